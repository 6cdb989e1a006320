//! Unidirectional path tracing of the full rendering equation: a loop over bounces with
//! next-event estimation towards one light chosen by power, BSDF sampling, multiple importance
//! sampling of the two (power heuristic, Veach 1997), and Russian roulette.

use glam::Vec3;

use super::Integrator;
use crate::accel::LANES;
use crate::geometry::{Hit, Ray, offset_origin};
use crate::light::ShadowRay;
use crate::material::Material;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Which estimators of direct light from area lights contribute. Point lights can only be
/// reached by next-event estimation and always are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Both, weighted by the power heuristic.
    Mis,
    /// Next-event estimation only; emitters hit by BSDF-sampled rays count only after a specular bounce.
    LightSampling,
    /// BSDF sampling only: emitters count when a sampled ray hits them.
    BsdfSampling,
}

pub struct Path {
    pub max_depth: u32,
    pub strategy: Strategy,
}

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

impl Integrator for Path {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut radiance = [Vec3::ZERO];
        self.radiance_of_all(scene, &mut std::iter::once((ray, sampler.clone())), &mut radiance);
        radiance[0]
    }

    /// Traces `LANES` paths at a time, bounce by bounce, so that their rays and their shadow
    /// rays meet the scene together (`Scene::intersect_lanes`); a finished path's lane takes
    /// the next camera sample.
    fn radiance_of_all(
        &self,
        scene: &Scene,
        samples: &mut dyn Iterator<Item = (Ray, Sampler)>,
        radiance: &mut [Vec3],
    ) {
        let mut samples = samples.enumerate();
        let mut lanes: [Option<PathState>; LANES] = Default::default();
        loop {
            for lane in lanes.iter_mut().filter(|lane| lane.is_none()) {
                *lane =
                    samples.next().map(|(slot, (ray, sampler))| PathState::new(slot, ray, sampler));
            }
            let active = lanes.each_ref().map(Option::is_some);
            if !active.contains(&true) {
                break;
            }
            let rays = lanes.each_ref().map(|lane| lane.as_ref().map_or(IDLE, |path| path.ray));
            let found = scene.intersect_lanes(&rays, active);
            let mut shadows = [None; LANES];
            let mut done = [false; LANES];
            for (lane, path) in lanes.iter_mut().enumerate() {
                if let Some(path) = path {
                    let hit = found[lane].map(|found| scene.hit(&path.ray, &found));
                    (shadows[lane], done[lane]) = self.bounce(scene, path, hit.as_ref());
                }
            }
            if shadows.iter().any(Option::is_some) {
                let rays = shadows.map(|shadow| shadow.map_or(IDLE, |s: Shadowed| s.ray.ray));
                let t_max = shadows.map(|shadow| shadow.map_or(0.0, |s| s.ray.t_max));
                let occluded = scene.occluded_lanes(&rays, t_max);
                for (lane, (path, shadow)) in lanes.iter_mut().zip(shadows).enumerate() {
                    if let (Some(path), Some(shadow)) = (path, shadow)
                        && occluded & (1 << lane) == 0
                    {
                        path.radiance += shadow.radiance;
                    }
                }
            }
            for (lane, done) in lanes.iter_mut().zip(done) {
                if done && let Some(path) = lane.take() {
                    radiance[path.slot] = path.radiance;
                }
            }
        }
    }
}

/// The ray of a lane with no path (never tested: its lane is inactive or its `t_max` is 0).
const IDLE: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::Z };

/// A path being traced: its next ray and what it has gathered so far.
struct PathState {
    /// Which camera sample it is: where its radiance goes.
    slot: usize,
    ray: Ray,
    sampler: Sampler,
    radiance: Vec3,
    beta: Vec3,
    /// Product of eta^2 over refractions: undoes their radiance scaling for Russian roulette,
    /// so paths through glass are not cut for a throughput drop that the exit restores.
    eta_scale: f32,
    /// The previous vertex and the solid-angle pdf of the direction sampled there (None for
    /// the camera ray and after specular bounces: no light sample could have found this path).
    previous: Option<(Hit, f32)>,
    bounces: u32,
}

impl PathState {
    fn new(slot: usize, ray: Ray, sampler: Sampler) -> Self {
        PathState {
            slot,
            ray,
            sampler,
            radiance: Vec3::ZERO,
            beta: Vec3::ONE,
            eta_scale: 1.0,
            previous: None,
            bounces: 0,
        }
    }
}

/// Radiance that next-event estimation found, counted if its shadow ray is unoccluded.
#[derive(Debug, Clone, Copy)]
struct Shadowed {
    ray: ShadowRay,
    radiance: Vec3,
}

impl Path {
    /// One bounce of a path at `hit` (`None`: the ray left the scene): emission found there,
    /// light from next-event estimation (returned, as it waits on its shadow ray), and the
    /// next ray. Returns whether the path ends here.
    fn bounce(
        &self,
        scene: &Scene,
        path: &mut PathState,
        hit: Option<&Hit>,
    ) -> (Option<Shadowed>, bool) {
        let Some(hit) = hit else {
            path.radiance += path.beta * scene.background();
            return (None, true);
        };
        let sampler = &mut path.sampler;
        let wo = -Vec3::from(path.ray.dir);
        let material = scene.material(hit);
        let emitted = material.emitted(hit.normal, wo);
        if emitted != Vec3::ZERO {
            let weight = self.emission_weight(scene, hit, path.previous.as_ref());
            path.radiance += path.beta * emitted * weight;
        }
        if path.bounces == self.max_depth {
            return (None, true);
        }
        let shadowed = if material.has_diffuse() {
            self.next_event(scene, hit, wo, &material, sampler)
                .map(|(ray, radiance)| Shadowed { ray, radiance: path.beta * radiance })
        } else {
            None
        };
        // Only a material with specular lobes has a lobe to choose.
        let u_lobe = sampler.next_1d_if(material.has_specular());
        let Some(sample) = material.sample(hit.shading_normal, wo, u_lobe, sampler.next_2d())
        else {
            return (shadowed, true);
        };
        path.beta *= sample.weight;
        path.eta_scale *= sample.eta * sample.eta;
        path.previous = (!sample.specular).then_some((*hit, sample.pdf));
        path.ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
        // Russian roulette: continue with probability tied to the throughput and divide by
        // it, so the estimate stays unbiased.
        let roulette = path.bounces + 1 >= ROULETTE_AFTER;
        let u = sampler.next_1d_if(roulette);
        if roulette {
            let survive = (path.beta * path.eta_scale).max_element().min(1.0);
            if u >= survive {
                return (shadowed, true);
            }
            path.beta /= survive;
        }
        path.bounces += 1;
        (shadowed, false)
    }

    /// The weight of emission found by a BSDF-sampled ray.
    fn emission_weight(&self, scene: &Scene, hit: &Hit, previous: Option<&(Hit, f32)>) -> f32 {
        let Some((from, bsdf_pdf)) = previous else {
            return 1.0; // seen by the camera or through specular bounces
        };
        let Some(light) = scene.primitives[hit.primitive as usize].light else {
            return 1.0; // no light sample can find this emitter
        };
        match self.strategy {
            Strategy::BsdfSampling => 1.0,
            Strategy::LightSampling => 0.0,
            Strategy::Mis => {
                let light_pdf = scene.light_probability(light as usize)
                    * scene.lights[light as usize].pdf(scene, from.point, hit);
                power_heuristic(*bsdf_pdf, light_pdf)
            }
        }
    }

    /// Light from one light chosen by power, weighted against BSDF sampling, if its shadow ray
    /// is unoccluded.
    fn next_event(
        &self,
        scene: &Scene,
        hit: &Hit,
        wo: Vec3,
        material: &Material,
        sampler: &mut Sampler,
    ) -> Option<(ShadowRay, Vec3)> {
        let u_select = sampler.next_1d_if(scene.lights.len() > 1);
        let u = sampler.next_2d();
        let (index, probability) = scene.choose_light(u_select)?;
        let light = &scene.lights[index];
        if !light.is_delta() && self.strategy == Strategy::BsdfSampling {
            return None;
        }
        let sample = light.sample(scene, hit, u)?;
        let f = material.eval(hit.shading_normal, wo, sample.wi);
        if f == Vec3::ZERO {
            return None;
        }
        let light_pdf = probability * sample.pdf;
        let weight = if sample.is_delta || self.strategy == Strategy::LightSampling {
            1.0
        } else {
            power_heuristic(light_pdf, material.pdf(hit.shading_normal, wo, sample.wi))
        };
        let radiance = f * sample.li * hit.shading_normal.dot(sample.wi).abs() * weight / light_pdf;
        Some((sample.shadow, radiance))
    }
}

/// Veach's power heuristic with exponent 2, for one sample from each strategy.
fn power_heuristic(pdf: f32, other: f32) -> f32 {
    let (a, b) = (pdf * pdf, other * other);
    if a + b == 0.0 { 0.0 } else { a / (a + b) }
}
