//! Jensen's two-pass photon mapping (`docs/language.md`): a pass of photons from the lights,
//! kept where they land after at least one bounce, in a k-d tree, its caustic photons taken
//! from a second pass aimed at the casters of caustics (a denser map of the same light:
//! `Projection`); then camera rays as `direct`
//! traces them, with indirect light at each vertex with a non-delta lobe estimated from the
//! `photon_k` nearest photons.
//!
//! Kernel: Jensen's cone filter over the disc of the k-th nearest photon's distance r_k
//! (`Kernel::Cone`), where the photons' powers Phi_p already share each light's power among the
//! photons it emitted.

use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

use std::time::Instant;

use super::direct::{Vertex, whitted};
use super::missed_light::MissedLight;
use super::{Integrator, SampleIntegrator, render_samples, stopped_before_a_pass};
use crate::film::Film;
use crate::geometry::Ray;
use crate::graph::IntegratorKind;
use crate::photon::{Arrival, Deposit, Emission, Photon, PhotonMap, Projection, trace_photon};
use crate::progress::{Progress, RenderStats};
use crate::region::Region;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Photons traced by one task between two looks at `Progress::should_abandon`.
pub const PHOTON_TASK: u32 = 4096;

/// The most memory a stored photon takes: the photon (28 bytes) twice while the tasks' photons
/// are joined, then the photon, its position (12), its place in the k-d tree's leaves (position
/// and index, 16) and what the tree's build sorts while the map is built, with a margin
/// (measured: 64.4 bytes a stored photon at the peak, 16 M photons in a closed room).
pub const STORED_PHOTON_BYTES: u64 = 72;

/// The pass of photons aimed at the casters of caustics (`Projection`), after pass 0.
const CAUSTIC_PASS: u64 = 1;

/// The most photons `scene`'s passes store: for `photon` one at each bounce after leaving the
/// light, up to `max_depth` per photon emitted (every photon, in a closed room of white walls),
/// and as many again from the caustic pass where the scene has casters; for `final_gather` one
/// more where each photon first lands, and the caustic pass's.
pub fn most_stored(scene: &Scene) -> u64 {
    let settings = &scene.settings;
    let emitted = u64::from(Emission::new(&scene.lights, settings.photons()).total());
    let depth = u64::from(settings.max_depth);
    let caustic = if Projection::of(scene).is_some() { emitted * depth } else { 0 };
    match settings.integrator {
        IntegratorKind::FinalGather => emitted * (depth + 1) + caustic,
        IntegratorKind::Photon => emitted * depth + caustic,
        IntegratorKind::Direct | IntegratorKind::Path | IntegratorKind::Sppm => emitted * depth,
    }
}

/// The caustic pass: `photons` photons aimed at the casters of caustics (`Projection`), kept
/// where they land after delta and near-specular bounces only (light -> specular -> here);
/// none in a scene without casters. `None` if `progress` asks to stop first.
pub(super) fn trace_caustics(scene: &Scene, progress: &dyn Progress) -> Option<Vec<Photon>> {
    let Some(projection) = Projection::of(scene) else { return Some(Vec::new()) };
    let aimed = Emission::aimed(&scene.lights, projection, scene.settings.photons());
    let caustic = |d: &Deposit| [d.arrival == Arrival::Caustic];
    let [caustics] = trace_pass(scene, &aimed, CAUSTIC_PASS, progress, caustic)?;
    Some(caustics)
}

/// Photon mapping with `k` photons in each density estimate, paths of at most `max_depth`
/// bounces (the photons' too).
pub struct PhotonMapping {
    pub max_depth: u32,
    pub k: usize,
}

impl Integrator for PhotonMapping {
    /// Traces the scene's photon pass (pass 0, `photons` photons) and its caustic pass, builds
    /// their map, then renders with it; a black film if `progress` asks to stop first. Photon mapping renders
    /// whole images: every pixel reads the same photons.
    fn render(
        &self,
        scene: &Scene,
        region: &Region,
        progress: &dyn Progress,
    ) -> (Film, RenderStats) {
        let start = Instant::now();
        let emission = Emission::new(&scene.lights, scene.settings.photons());
        // Direct light comes from next-event estimation, caustics from the caustic pass.
        let maps = |d: &Deposit| [d.arrival == Arrival::Indirect];
        let Some([mut photons]) = trace_pass(scene, &emission, 0, progress, maps) else {
            return stopped_before_a_pass(scene, start);
        };
        let Some(caustics) = trace_caustics(scene, progress) else {
            return stopped_before_a_pass(scene, start);
        };
        photons.extend(caustics);
        let map = PhotonMap::build(photons);
        let estimate = PhotonEstimate { mapping: self, map, missed: MissedLight::of(scene) };
        let (film, stats) = render_samples(scene, &estimate, region, progress);
        (film, RenderStats { seconds: start.elapsed().as_secs_f64(), ..stats })
    }

    fn samples_are_independent(&self) -> bool {
        false
    }
}

/// Camera rays as `direct` traces them, with indirect light from a photon map.
struct PhotonEstimate<'a> {
    mapping: &'a PhotonMapping,
    map: PhotonMap,
    missed: Option<MissedLight>,
}

impl PhotonEstimate<'_> {
    /// Light from other surfaces scattered towards `wo` by the gathered lobes at `vertex`, from
    /// the nearest photons, and the light they miss (`missed_light`).
    fn indirect(&self, scene: &Scene, vertex: &Vertex, sampler: &mut Sampler) -> Vec3 {
        let missed = (self.missed.as_ref())
            .map_or(Vec3::ZERO, |m| m.at(scene, vertex, self.mapping.max_depth, sampler));
        estimate(&self.map, vertex, self.mapping.k, Kernel::Cone) + missed
    }
}

/// How the photons of a density estimate are weighed against their distance d from the query,
/// r being the k-th nearest photon's distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Kernel {
    /// Uniform over the disc of radius r: L = Σ f(wo, wi_p) Φ_p / (π r²) (Jensen 2001, eq. 7.6).
    Uniform,
    /// Jensen's cone filter: a photon weighs 1 − d / (CONE r), and the sum is divided by
    /// (1 − 2 / (3 CONE)) π r², the weights' integral over the disc (Jensen 2001, eq. 7.7).
    /// Near photons count most, so a thin bright caustic spreads little light into its dark
    /// surroundings.
    Cone,
}

/// The cone filter's constant (`Kernel::Cone`): at 1 the k-th nearest photon weighs nothing.
const CONE: f32 = 1.0;

/// Light leaving `vertex` towards wo through its gathered lobes, from the `k` nearest photons
/// of `map` weighed by `kernel`: Σ f(wo, wi_p) Φ_p w(d_p) / (∫w over the disc of r_k).
pub(super) fn estimate(map: &PhotonMap, vertex: &Vertex, k: usize, kernel: Kernel) -> Vec3 {
    let Vertex { hit, wo, bsdf, gathered } = vertex;
    let found = map.nearest(hit.point, k);
    let Some(radius_squared) = found.last().map(|n| n.distance_squared) else {
        return Vec3::ZERO;
    };
    if radius_squared <= 0.0 {
        return Vec3::ZERO;
    }
    let radius = radius_squared.sqrt();
    let (weight, area) = match kernel {
        Kernel::Uniform => (None, PI * radius_squared),
        Kernel::Cone => (Some(CONE * radius), (1.0 - 2.0 / (3.0 * CONE)) * PI * radius_squared),
    };
    let flux: Vec3 = found
        .iter()
        .map(|n| {
            let photon = map.photon(n.index);
            let w = weight.map_or(1.0, |cone_radius| 1.0 - n.distance_squared.sqrt() / cone_radius);
            bsdf.eval_lobes(*wo, photon.wi(), *gathered) * photon.power * w
        })
        .sum();
    flux / area
}

impl SampleIntegrator for PhotonEstimate<'_> {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let indirect =
            |vertex: &Vertex, sampler: &mut Sampler| self.indirect(scene, vertex, sampler);
        whitted(scene, ray, sampler, self.mapping.max_depth, Some(&indirect))
    }
}

/// The photons of pass `pass` where they land, in `MAPS` maps: each map `m` keeps the deposits
/// `d` for which `maps(d)[m]`; in photon order whatever the thread count; `None` if `progress`
/// asks to stop first.
pub fn trace_pass<const MAPS: usize>(
    scene: &Scene,
    emission: &Emission,
    pass: u64,
    progress: &dyn Progress,
    maps: impl Fn(&Deposit) -> [bool; MAPS] + Sync,
) -> Option<[Vec<Photon>; MAPS]> {
    let total = emission.total();
    let tasks: Vec<Option<[Vec<Photon>; MAPS]>> = (0..total.div_ceil(PHOTON_TASK))
        .into_par_iter()
        .map(|task| {
            if progress.should_abandon() {
                return None;
            }
            let mut stored: [Vec<Photon>; MAPS] = std::array::from_fn(|_| Vec::new());
            let first = task * PHOTON_TASK;
            for index in first..(first + PHOTON_TASK).min(total) {
                trace_photon(scene, emission, scene.settings.max_depth, pass, index, |d| {
                    for (map, kept) in stored.iter_mut().zip(maps(d)) {
                        if kept {
                            map.push(Photon::new(d.hit.point, d.wi, d.power));
                        }
                    }
                });
            }
            // Only what is stored counts against the memory (`STORED_PHOTON_BYTES`).
            stored.iter_mut().for_each(Vec::shrink_to_fit);
            Some(stored)
        })
        .collect();
    let tasks: Vec<[Vec<Photon>; MAPS]> = tasks.into_iter().collect::<Option<_>>()?;
    Some(std::array::from_fn(|m| tasks.iter().flat_map(|t| t[m].iter().copied()).collect()))
}
