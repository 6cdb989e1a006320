//! Unidirectional path tracing of the full rendering equation: a loop over bounces with
//! next-event estimation towards one light chosen by power, BSDF sampling, multiple importance
//! sampling of the two (power heuristic, Veach 1997), and Russian roulette.

use glam::Vec3;

use super::Integrator;
use crate::geometry::{Hit, Ray, offset_origin};
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
    fn radiance(&self, scene: &Scene, mut ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        // Product of eta^2 over refractions: undoes their radiance scaling for Russian roulette,
        // so paths through glass are not cut for a throughput drop that the exit restores.
        let mut eta_scale = 1.0;
        // The previous vertex and the solid-angle pdf of the direction sampled there (None for
        // the camera ray and after specular bounces: no light sample could have found this path).
        let mut previous: Option<(Hit, f32)> = None;
        for bounces in 0.. {
            let Some(hit) = scene.intersect(&ray) else {
                radiance += beta * scene.background();
                break;
            };
            let wo = -Vec3::from(ray.dir);
            let material = scene.material(&hit);
            let emitted = material.emitted(hit.normal, wo);
            if emitted != Vec3::ZERO {
                radiance += beta * emitted * self.emission_weight(scene, &hit, previous.as_ref());
            }
            if bounces == self.max_depth {
                break;
            }
            if material.has_diffuse() {
                radiance += beta * self.next_event(scene, &hit, wo, &material, sampler);
            }
            // Only a material with specular lobes has a lobe to choose.
            let u_lobe = sampler.next_1d_if(material.has_specular());
            let Some(sample) = material.sample(hit.shading_normal, wo, u_lobe, sampler.next_2d())
            else {
                break;
            };
            beta *= sample.weight;
            eta_scale *= sample.eta * sample.eta;
            previous = (!sample.specular).then_some((hit, sample.pdf));
            ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
            // Russian roulette: continue with probability tied to the throughput and divide by
            // it, so the estimate stays unbiased.
            let roulette = bounces + 1 >= ROULETTE_AFTER;
            let u = sampler.next_1d_if(roulette);
            if roulette {
                let survive = (beta * eta_scale).max_element().min(1.0);
                if u >= survive {
                    break;
                }
                beta /= survive;
            }
        }
        radiance
    }
}

impl Path {
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

    /// Light from one light chosen by power, weighted against BSDF sampling.
    fn next_event(
        &self,
        scene: &Scene,
        hit: &Hit,
        wo: Vec3,
        material: &Material,
        sampler: &mut Sampler,
    ) -> Vec3 {
        let u_select = sampler.next_1d_if(scene.lights.len() > 1);
        let u = sampler.next_2d();
        let Some((index, probability)) = scene.choose_light(u_select) else {
            return Vec3::ZERO;
        };
        let light = &scene.lights[index];
        if !light.is_delta() && self.strategy == Strategy::BsdfSampling {
            return Vec3::ZERO;
        }
        let Some(sample) = light.sample(scene, hit, u) else {
            return Vec3::ZERO;
        };
        let f = material.eval(hit.shading_normal, wo, sample.wi);
        if f == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let light_pdf = probability * sample.pdf;
        let weight = if sample.is_delta || self.strategy == Strategy::LightSampling {
            1.0
        } else {
            power_heuristic(light_pdf, material.pdf(hit.shading_normal, wo, sample.wi))
        };
        f * sample.li * hit.shading_normal.dot(sample.wi).abs() * weight / light_pdf
    }
}

/// Veach's power heuristic with exponent 2, for one sample from each strategy.
fn power_heuristic(pdf: f32, other: f32) -> f32 {
    let (a, b) = (pdf * pdf, other * other);
    if a + b == 0.0 { 0.0 } else { a / (a + b) }
}
