//! The light photon mapping's photons cannot carry, estimated by paths from the camera's side.
//! A distant light's and the sky's photons leave a disc across the sphere around the scene's
//! bounded objects and the camera (`Light::photon_sphere`), so they reach a point outside that
//! sphere (on an infinite floor, far away) only along lines that cross it: the light such a
//! point receives along other lines, and all it lights after, is in no photon map. Yet the
//! camera sees it, in the floor's light on the objects. At a vertex where photon mapping
//! gathers, a path goes on (BSDF sampling, Russian roulette, as `path`'s) and adds that light
//! only: at each vertex after the gathering one, those lights' samples from directions their
//! photons miss, weighted by the power heuristic against the BSDF-sampled rays that find the
//! sky there. Photon paths carry the rest of the light, and next-event estimation the direct
//! light at the gathering vertex, so the three split the light between them without overlap:
//! the sum stays unbiased however little of the floor the sphere covers.
//!
//! A scene without unbounded objects, or without such lights, draws nothing here: every point
//! is inside the sphere, and its images are unchanged.

use glam::Vec3;

use super::direct::Vertex;
use super::path::PathState;
use super::power_heuristic;
use crate::geometry::{Ray, offset_origin};
use crate::light::photons_reach;
use crate::material::{Bsdf, LobeFlags, TransportMode};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// The lights whose photons leave a disc across a sphere, in a scene where some surface lies
/// outside it: each one's index in `Scene::lights` and its sphere.
pub(super) struct MissedLight {
    lights: Vec<(usize, Vec3, f32)>,
}

impl MissedLight {
    /// `None` where photons carry all the light: no unbounded object, or no light from
    /// infinitely far away.
    pub(super) fn of(scene: &Scene) -> Option<Self> {
        if !scene.has_unbounded() {
            return None;
        }
        let lights: Vec<_> = (scene.lights.iter().enumerate())
            .filter_map(|(i, light)| light.photon_sphere().map(|(centre, r)| (i, centre, r)))
            .collect();
        (!lights.is_empty()).then_some(MissedLight { lights })
    }

    /// Whether the photons of the light `light` (one of ours) miss `point` from `wi`.
    fn misses(&self, light: usize, point: Vec3, wi: Vec3) -> bool {
        (self.lights.iter())
            .any(|&(i, centre, radius)| i == light && !photons_reach(centre, radius, point, wi))
    }

    /// Whether `point` lies inside every light's sphere, where its photons reach from anywhere.
    fn inside(&self, point: Vec3) -> bool {
        self.lights
            .iter()
            .all(|&(_, centre, radius)| point.distance_squared(centre) < radius * radius)
    }

    /// Light the photons miss, scattered towards wo by the gathered lobes at `vertex`: one path
    /// sampled from those lobes, of at most `max_depth` bounces more.
    pub(super) fn at(
        &self,
        scene: &Scene,
        vertex: &Vertex,
        max_depth: u32,
        sampler: &mut Sampler,
    ) -> Vec3 {
        let Vertex { hit, wo, bsdf, gathered } = vertex;
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let Some(sample) = bsdf.sample(*wo, u_lobe, u, *gathered) else {
            return Vec3::ZERO;
        };
        let mut path = PathState::new(Ray::new(offset_origin(hit, sample.wi), sample.wi));
        path.beta = sample.weight;
        path.bounces = 1;
        // The vertex the path last scattered at and its sample's density (`None` through a
        // delta lobe), where it is not the gathering vertex: the sky found from there is ours.
        let mut from: Option<(Vec3, Option<f32>)> = None;
        loop {
            let Some(mut hit) = scene.intersect(&path.ray) else {
                path.radiance += path.beta * self.sky_found(scene, from, path.ray.dir.into());
                return path.radiance;
            };
            if path.bounces >= max_depth {
                return path.radiance;
            }
            let wo = -Vec3::from(path.ray.dir);
            let material = scene.material(hit.primitive, hit.point);
            let mut bsdf = Bsdf::BLACK;
            scene.shade(&mut bsdf, &mut hit, wo, &material, TransportMode::Radiance);
            let flags = bsdf.flags();
            if flags.is_non_delta() && !self.inside(hit.point) {
                for &(light, ..) in &self.lights {
                    let Some(sample) = scene.lights[light].sample(&hit, sampler.next_2d()) else {
                        continue;
                    };
                    if self.misses(light, hit.point, sample.wi) {
                        let (f, bsdf_pdf) = bsdf.eval_pdf(wo, sample.wi, LobeFlags::ALL);
                        let weight = if sample.is_delta {
                            1.0
                        } else {
                            power_heuristic(sample.pdf, bsdf_pdf)
                        };
                        let cos = hit.shading_normal.dot(sample.wi).abs();
                        let li = f * sample.li * cos * weight / sample.pdf;
                        if li != Vec3::ZERO {
                            let reached =
                                scene.transmittance(&sample.shadow.ray(), sample.shadow.t_max());
                            path.radiance += path.beta * li * reached;
                        }
                    }
                }
            }
            let u_lobe = sampler.next_1d_if(flags.chooses_lobe());
            let Some(sample) = bsdf.sample(wo, u_lobe, sampler.next_2d(), LobeFlags::ALL) else {
                return path.radiance;
            };
            path.beta *= sample.weight;
            path.eta_scale *= sample.eta * sample.eta;
            from = Some((hit.point, (!sample.is_delta()).then_some(sample.pdf)));
            path.ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
            if !path.survives_roulette(sampler) {
                return path.radiance;
            }
            path.bounces += 1;
        }
    }

    /// The sky's light found along `dir` from `from` if its photons miss it there, weighted
    /// against the sky's own sample where the direction was sampled from a lobe with a density.
    fn sky_found(&self, scene: &Scene, from: Option<(Vec3, Option<f32>)>, dir: Vec3) -> Vec3 {
        let (Some((point, bsdf_pdf)), Some((light, sky))) = (from, scene.environment()) else {
            return Vec3::ZERO;
        };
        if !self.misses(light, point, dir) {
            return Vec3::ZERO;
        }
        let weight = bsdf_pdf.map_or(1.0, |pdf| power_heuristic(pdf, sky.pdf(dir)));
        sky.le(dir) * weight
    }
}
