//! The course's Lab 4 integrator: emission seen directly, direct light at surfaces with lobes
//! that have a density (diffuse, glossy) with shadow rays (from point lights, area lights and
//! the background), delta lobes (perfect mirrors and refraction) followed Whitted-style; no
//! indirect light otherwise.

use glam::Vec3;

use super::{Integrator, direct_from_all_lights};
use crate::geometry::{Hit, Ray, offset_origin};
use crate::material::{Bsdf, LobeFlags, TransportMode};
use crate::sampling::Sampler;
use crate::scene::Scene;

pub struct Direct {
    /// Longest path in bounces (scattering events); 0 shows only what the camera sees emit.
    pub max_depth: u32,
}

/// Light of the background (an environment of constant radiance L all around) reflected towards
/// `wo` by the non-delta lobes: one direction sampled from them with a shadow ray to infinity,
/// whose estimate is f L cos / pdf (kd L for a diffuse lobe) where the sky is seen. A black
/// background draws no sample, so the seed's scenes render as they always have.
pub(super) fn direct_from_background(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    sampler: &mut Sampler,
) -> Vec3 {
    let background = scene.background();
    if background == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let u_lobe = sampler.next_1d_if(bsdf.flags().contains(LobeFlags::GLOSSY));
    let Some(sample) = bsdf.sample_non_delta(wo, u_lobe, sampler.next_2d()) else {
        return Vec3::ZERO;
    };
    let ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
    if scene.occluded(&ray, f32::INFINITY) { Vec3::ZERO } else { sample.weight * background }
}

impl Integrator for Direct {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        whitted(scene, ray, sampler, self.max_depth, None)
    }
}

/// Light from other surfaces scattered towards `wo` by `bsdf` at a hit, from some estimator
/// (a photon map's).
pub(super) type Indirect<'a> = dyn Fn(&Hit, Vec3, &Bsdf) -> Vec3 + 'a;

/// `Direct`'s estimate along `ray`, plus any `indirect(hit, wo, bsdf)` (light from other surfaces)
/// at each vertex with a non-delta lobe: emission seen on the way, next-event estimation at
/// those vertices, delta lobes followed, for at most `max_depth` bounces.
pub(super) fn whitted(
    scene: &Scene,
    mut ray: Ray,
    sampler: &mut Sampler,
    max_depth: u32,
    indirect: Option<&Indirect>,
) -> Vec3 {
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
        if bounces == max_depth {
            break;
        }
        let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
        let flags = bsdf.flags();
        if flags.is_non_delta() {
            radiance += beta * direct_from_all_lights(scene, &hit, wo, &bsdf, sampler);
            radiance += beta * direct_from_background(scene, &hit, wo, &bsdf, sampler);
            if let Some(indirect) = indirect {
                radiance += beta * indirect(&hit, wo, &bsdf);
            }
        }
        // With both mirror and refraction one of them is followed, chosen at random with
        // its weight divided by its probability: one ray, no branching, no bias.
        if !flags.is_delta() {
            break;
        }
        let Some(sample) = bsdf.sample_delta(wo, sampler.next_1d()) else {
            break;
        };
        beta *= sample.weight;
        ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
    }
    radiance
}
