//! Integrators: estimators of the radiance arriving along a camera ray.

mod direct;
mod path;
mod photon;
pub mod sppm;

pub use direct::Direct;
pub use path::{Path, Strategy};
pub use photon::{PHOTON_TASK, PhotonMapping, trace_pass};

use glam::{BVec4A, Vec2, Vec3, Vec4};

use crate::accel::RayLanes;
use crate::geometry::{Hit, LANES, Ray, Vec3x4};
use crate::light::{Light, ShadowRay};
use crate::material::Bsdf;
use crate::sampling::Sampler;
use crate::scene::Scene;

pub trait Integrator: Sync {
    /// An estimate of the radiance arriving at the ray's origin from along `-ray.dir`.
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3;

    /// The radiance of each camera sample, in order, into `radiance` (as long as the samples).
    /// Integrators that trace several paths at once override this.
    fn radiance_of_all(
        &self,
        scene: &Scene,
        samples: &mut dyn Iterator<Item = (Ray, Sampler)>,
        radiance: &mut [Vec3],
    ) {
        for (out, (ray, mut sampler)) in radiance.iter_mut().zip(samples) {
            *out = self.radiance(scene, ray, &mut sampler);
        }
    }
}

/// Light scattered towards `wo` by the non-delta lobes of `bsdf` at `hit`, one sample from
/// every light.
fn direct_from_all_lights(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    sampler: &mut Sampler,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    for light in &scene.lights {
        let u = sampler.next_2d();
        let Some((shadow, reflected)) = direct_from_light(light, hit, wo, bsdf, u) else {
            continue;
        };
        if !scene.occluded(&shadow.ray, shadow.t_max) {
            radiance += reflected;
        }
    }
    radiance
}

/// Light from `light` scattered towards `wo` by the non-delta lobes of `bsdf` at `hit`, from
/// its sample at `u`, if the shadow ray turns out unoccluded: f Li |n . wi| / pdf (for a point
/// light exactly the course's Lab 4 p / r^2 f |n . wi|).
fn direct_from_light(
    light: &Light,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    u: Vec2,
) -> Option<(ShadowRay, Vec3)> {
    let sample = light.sample(hit, u)?;
    let f = bsdf.eval(wo, sample.wi);
    Some((sample.shadow, f * sample.li * hit.shading_normal.dot(sample.wi).abs() / sample.pdf))
}

/// What only a path traced in a lane reads: its own choices.
struct LanePath {
    /// Which camera sample it is: where its radiance goes.
    slot: usize,
    sampler: Sampler,
    bounces: u32,
}

/// Paths traced side by side, one per lane, as the integrators' `radiance_of_all` trace them.
trait LanePaths {
    /// Whether `lane` has no path (never had one, or its path ended).
    fn is_free(&self, lane: usize) -> bool;
    /// Starts the path of camera sample `slot` in `lane`.
    fn start(&mut self, lane: usize, slot: usize, ray: &Ray, sampler: Sampler);
}

/// Gives each free lane the next camera sample (numbered by `samples`); the lanes with a path
/// after that, or `None` when none has one: every sample is traced.
fn fill_lanes(
    lanes: &mut impl LanePaths,
    samples: &mut impl Iterator<Item = (usize, (Ray, Sampler))>,
) -> Option<[bool; LANES]> {
    for lane in 0..LANES {
        if lanes.is_free(lane)
            && let Some((slot, (ray, sampler))) = samples.next()
        {
            lanes.start(lane, slot, &ray, sampler);
        }
    }
    let active = std::array::from_fn(|lane| !lanes.is_free(lane));
    active.contains(&true).then_some(active)
}

/// The ray of a lane with no path (never tested: its lane is inactive or its `t_max` is 0).
const IDLE: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::Z };

/// Shadow rays of next-event estimation, in the lanes of `found`, and the radiance each brings if
/// it is unoccluded.
struct Shadowed {
    found: BVec4A,
    rays: RayLanes,
    t_max: Vec4,
    radiance: Vec3x4,
}
