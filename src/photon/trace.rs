//! Photon tracing: photon `index` of pass `pass` leaves its light (`Emission`) and scatters
//! through the scene by BSDF sampling in importance mode, with Russian roulette on its
//! throughput, depositing where it lands on a surface with gathered lobes (diffuse, or glossy and
//! not near-specular: `Bsdf::gathered_lobes`) after at least one bounce. Its random numbers are a pure function of (seed, pass, index).

use glam::Vec3;

use super::Emission;
use crate::geometry::{Hit, Ray, offset_origin};
use crate::material::{Bsdf, LobeFlags, TransportMode};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Photon streams draw from `Sampler`s keyed by this plus the pass in place of a pixel: above
/// every pixel index (images have at most 2^32 pixels), so no photon shares a camera sample's
/// numbers.
const PHOTON_STREAMS: u64 = 1 << 40;

/// Where a photon landed: the hit, the direction back towards where it came from, its power
/// there, and the way it came.
#[derive(Debug, Clone, Copy)]
pub struct Deposit {
    pub hit: Hit,
    pub wi: Vec3,
    pub power: Vec3,
    pub arrival: Arrival,
}

/// The bounces a photon took from its light to where it lands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrival {
    /// None: the light lit the surface directly.
    Direct,
    /// Delta and near-specular ones only (light -> specular -> here): a caustic.
    Caustic,
    /// At least one on a gathered lobe (diffuse or broad glossy).
    Indirect,
}

/// Traces photon `index` of pass `pass`, calling `deposit` at every surface with gathered lobes
/// it reaches (straight from the light too: callers keep the arrivals they estimate from), for
/// at most `max_depth` bounces.
pub fn trace_photon(
    scene: &Scene,
    emission: &Emission,
    max_depth: u32,
    pass: u64,
    index: u32,
    mut deposit: impl FnMut(&Deposit),
) {
    let (light, photons) = emission.light_of(index);
    let mut sampler = Sampler::new(scene.settings.seed, PHOTON_STREAMS + pass, u64::from(index));
    let Some(start) = emission.start(&scene.lights[light], photons, &mut sampler) else {
        return;
    };
    let (mut ray, mut power, mut arrival) = (start.ray, start.power, Arrival::Direct);
    if scene.lights[light].photon_sphere().is_some() {
        // A photon from infinitely far away (the sky, a distant light) starts on a disc across
        // the sphere around the bounded objects, which lie all downstream of it; an unbounded
        // object (a floor) may cross the disc, and where it lies upstream it stops that light
        // before the disc: the sky below the horizon lit the objects above a floor.
        let upstream = Ray::new(start.ray.origin.into(), -Vec3::from(start.ray.dir));
        power *= scene.transmittance(&upstream, f32::INFINITY);
        if power == Vec3::ZERO {
            return;
        }
    }
    for bounces in 0.. {
        let Some(mut hit) = scene.intersect(&ray) else { break };
        let wo = -Vec3::from(ray.dir);
        let material = scene.material(hit.primitive, hit.point);
        let mut bsdf = Bsdf::BLACK;
        scene.shade(&mut bsdf, &mut hit, wo, &material, TransportMode::Importance);
        let gathered = bsdf.gathered_lobes();
        if !gathered.is_empty() {
            deposit(&Deposit { hit, wi: wo, power, arrival });
        }
        if bounces == max_depth {
            break;
        }
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let Some(sample) = bsdf.sample(wo, u_lobe, u, LobeFlags::ALL) else { break };
        let scattered = power * sample.weight;
        // Russian roulette: go on with probability max(scattered) / max(power), divided by it,
        // so that a photon's power stays about what it left with (pbrt-v4's SPPM).
        let survive = (scattered.max_element() / power.max_element()).min(1.0);
        if survive.is_nan() || survive <= 0.0 || sampler.next_1d() >= survive {
            break;
        }
        power = scattered / survive;
        arrival = match arrival {
            Arrival::Direct | Arrival::Caustic if !sample.flags.is_in(gathered) => Arrival::Caustic,
            Arrival::Direct | Arrival::Caustic | Arrival::Indirect => Arrival::Indirect,
        };
        ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
    }
}
