//! Path tracing through participating media (Mitsuba's `volpath`, pbrt-v3's
//! `VolPathIntegrator`): `Path` follows its paths here when the scene has a medium.
//!
//! Along each segment in a medium the path gathers the medium's emission (its integral against
//! the transmittance, in closed form), then free-flight sampling either stops it at a scattering
//! point, where next-event estimation and a phase-function sample (weighted by the power
//! heuristic) take over from the BSDF's, or lets it reach the surface with the transmittance's
//! weight. Surfaces are `Path::bounce`'s, except that shadow rays carry the transmittance of
//! the media they cross, and surfaces that only bound a medium (`Scene::only_bounds`) are
//! crossed as if absent.

use glam::Vec3;

use super::path::PathState;
use super::{Path, Strategy, power_heuristic};
use crate::geometry::{Hit, Ray, offset_origin};
use crate::light::ShadowRay;
use crate::medium::Flight;
use crate::sampling::Sampler;
use crate::scene::{MOST_CROSSINGS, Scene};

impl Path {
    /// The radiance arriving along `ray` in a scene with media; camera rays start in the
    /// atmosphere.
    pub(super) fn radiance_in_media(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut path = PathState::new(ray);
        let mut medium = scene.atmosphere();
        let mut crossings = 0;
        loop {
            let hit = scene.intersect(&path.ray);
            if let Some(index) = medium {
                let m = &scene.media[index as usize];
                let length = hit.map_or(f32::INFINITY, |hit| hit.t);
                path.radiance += path.beta * m.emitted(&path.ray, length);
                let (u_channel, u) =
                    if m.scatters() { (sampler.next_1d(), sampler.next_1d()) } else { (0.0, 0.0) };
                match m.sample_flight(&path.ray, length, u_channel, u) {
                    Flight::Scattered { t, weight } => {
                        path.beta *= weight;
                        if !self.scatter(scene, &mut path, index, t, sampler) {
                            return path.radiance;
                        }
                        crossings = 0;
                        continue;
                    }
                    Flight::Crossed { weight } => path.beta *= weight,
                }
                if path.beta == Vec3::ZERO {
                    return path.radiance;
                }
            }
            let dir = Vec3::from(path.ray.dir);
            if let Some(hit) = hit.filter(|hit| scene.only_bounds(hit)) {
                crossings += 1;
                if crossings > MOST_CROSSINGS {
                    return path.radiance;
                }
                medium = scene.medium_towards(&hit, dir);
                path.ray = Ray::new(offset_origin(&hit, dir), dir);
                continue;
            }
            crossings = 0;
            let bounce = self.bounce(scene, &mut path, hit, sampler);
            if let (Some((shadow, li)), Some(hit)) = (bounce.shadowed, hit) {
                let towards = scene.medium_towards(&hit, shadow.ray().dir.into());
                path.radiance += li * transmittance(scene, &shadow, towards);
            }
            match hit {
                Some(hit) if bounce.continues => {
                    medium = scene.medium_towards(&hit, path.ray.dir.into());
                }
                _ => return path.radiance,
            }
        }
    }

    /// The path scatters in medium `index` at distance `t` along its ray: light sampled there
    /// through the phase function, weighted against phase sampling, and the next direction
    /// drawn from the phase function; whether the path goes on.
    fn scatter(
        &self,
        scene: &Scene,
        path: &mut PathState,
        index: u32,
        t: f32,
        sampler: &mut Sampler,
    ) -> bool {
        if path.bounces == self.max_depth {
            return false;
        }
        let phase = scene.media[index as usize].phase;
        let point = path.ray.at(t);
        let wo = -Vec3::from(path.ray.dir);
        if let Some((light, probability, u)) = self.choose_light(scene, sampler) {
            // A vertex of no surface: no primitive, no offset.
            let vertex =
                Hit { t, point, normal: wo, shading_normal: wo, error: 0.0, primitive: u32::MAX };
            if let Some(sample) = scene.lights[light].sample(&vertex, u) {
                let f = phase.eval(wo, sample.wi);
                let light_pdf = probability * sample.pdf;
                let weighed = !sample.is_delta && self.strategy != Strategy::LightSampling;
                let weight = if weighed { power_heuristic(light_pdf, f) } else { 1.0 };
                let li = f * sample.li * weight / light_pdf;
                if li != Vec3::ZERO {
                    let reached = transmittance(scene, &sample.shadow, Some(index));
                    path.radiance += path.beta * li * reached;
                }
            }
        }
        let (wi, pdf) = phase.sample(wo, sampler.next_2d());
        path.previous = Some((point, pdf));
        path.seen = false;
        path.ray = Ray::new(point, wi);
        if !path.survives_roulette(sampler) {
            return false;
        }
        path.bounces += 1;
        true
    }
}

/// The fraction of light that travels the shadow ray from its end to its origin, which lies
/// in `medium`: zero if an opaque surface is in the way, else the product of the
/// transmittances of the media along it and of the surfaces that let light straight through
/// (`Scene::passes`: those that only bound a medium pass all).
fn transmittance(scene: &Scene, shadow: &ShadowRay, mut medium: Option<u32>) -> Vec3 {
    let dir = Vec3::from(shadow.ray().dir);
    let mut ray = shadow.ray();
    let mut left = shadow.t_max();
    let mut reached = Vec3::ONE;
    for _ in 0..=MOST_CROSSINGS {
        let hit = scene.intersect(&ray).filter(|hit| hit.t < left);
        if let Some(index) = medium {
            let medium = &scene.media[index as usize];
            reached *= medium.transmittance(&ray, hit.map_or(left, |hit| hit.t));
        }
        let Some(hit) = hit else { return reached };
        reached *= scene.passes(&hit, dir);
        if reached == Vec3::ZERO {
            return reached;
        }
        medium = scene.medium_towards(&hit, dir);
        let origin = offset_origin(&hit, dir);
        left -= (origin - Vec3::from(ray.origin)).length();
        ray = Ray::new(origin, dir);
    }
    Vec3::ZERO
}
