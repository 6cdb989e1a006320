//! Integrators: estimators of the radiance arriving along a camera ray.

mod direct;
mod path;

pub use direct::Direct;
pub use path::{Path, Strategy};

use glam::Vec3;

use crate::geometry::{Hit, Ray};
use crate::material::Material;
use crate::sampling::Sampler;
use crate::scene::Scene;

pub trait Integrator: Sync {
    /// An estimate of the radiance arriving at the ray's origin from along `-ray.dir`.
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3;
}

/// Light reflected towards `wo` by the non-specular part of `material` at `hit`, one sample
/// from every light (point lights exactly: the seed's p / r^2 f |n . wi|).
fn direct_from_all_lights(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    material: &Material,
    sampler: &mut Sampler,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    for light in &scene.lights {
        let u = sampler.next_2d();
        if let Some(sample) = light.sample(scene, hit, u) {
            let f = material.eval(hit.shading_normal, wo, sample.wi);
            radiance += f * sample.li * hit.shading_normal.dot(sample.wi).abs() / sample.pdf;
        }
    }
    radiance
}
