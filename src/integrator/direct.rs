//! The course's Lab 4 integrator: emission seen directly, direct light at non-specular surfaces
//! with shadow rays, perfect mirrors and refraction followed Whitted-style; no indirect diffuse.

use glam::Vec3;

use super::{Integrator, direct_from_all_lights};
use crate::geometry::{Ray, offset_origin};
use crate::sampling::Sampler;
use crate::scene::Scene;

pub struct Direct {
    /// Longest path in bounces (scattering events); 0 shows only what the camera sees emit.
    pub max_depth: u32,
}

impl Integrator for Direct {
    fn radiance(&self, scene: &Scene, mut ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        // Path throughput: the product of specular weights so far.
        let mut beta = Vec3::ONE;
        for bounces in 0.. {
            let Some(hit) = scene.intersect(&ray) else {
                radiance += beta * scene.background();
                break;
            };
            let wo = -Vec3::from(ray.dir);
            let material = scene.material(hit.primitive, hit.point);
            radiance += beta * material.emitted(hit.normal, wo);
            if bounces == self.max_depth {
                break;
            }
            if material.has_diffuse() {
                radiance += beta * direct_from_all_lights(scene, &hit, wo, &material, sampler);
            }
            // With both mirror and refraction one of them is followed, chosen at random with
            // its weight divided by its probability: one ray, no branching, no bias.
            if !material.has_specular() {
                break;
            }
            let Some(sample) = material.sample_specular(hit.shading_normal, wo, sampler.next_1d())
            else {
                break;
            };
            beta *= sample.weight;
            ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
        }
        radiance
    }
}
