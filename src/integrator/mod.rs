//! Integrators: estimators of the image. Each renders a region of it (`Integrator`); those that
//! estimate each camera sample on its own (`direct`, `path`, `photon`) do it through the
//! per-sample rung (`SampleIntegrator`, `render_samples`), and `sppm` renders by iterations of
//! its own.

mod diffuse_lanes;
mod direct;
mod final_gather;
mod missed_light;
mod path;
mod photon;
mod samples;
pub mod sppm;
mod volpath;

pub use direct::Direct;
pub use final_gather::{CAUSTIC_K, FinalGather};
pub use path::{Path, Strategy};
pub use photon::{PHOTON_TASK, PhotonMapping, STORED_PHOTON_BYTES, most_stored, trace_pass};
pub use samples::{
    CameraSample, SampleIntegrator, TASK_SAMPLES, render_samples, stopped_before_a_pass,
};
pub use sppm::Sppm;

use glam::{Vec2, Vec3};

use crate::film::Film;
use crate::geometry::{Hit, Ray};
use crate::graph::{IntegratorKind, Settings};
use crate::lanes::{Floats, LANES, Lane, Mask, MaskLanes, RayLanes, Real, Vec3Lanes};
use crate::light::{Light, ShadowRay};
use crate::material::{Bsdf, LobeFlags};
use crate::progress::{Progress, RenderStats};
use crate::region::Region;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// An estimator of the image: it renders a region (a crop of the image and a share of its
/// samples) into a film.
pub trait Integrator: Sync {
    fn render(
        &self,
        scene: &Scene,
        region: &Region,
        progress: &dyn Progress,
    ) -> (Film, RenderStats);

    /// Whether the image is a mean of independent pixel samples, each a pure function of (seed,
    /// pixel, sample index): then disjoint shares of the samples rendered apart merge into the
    /// render of all of them (`--part`), and a render's per-pixel variance is what `snapshot`
    /// tests with. An integrator whose pixels share work across samples (a photon map built per
    /// pass, SPPM's shrinking radii) answers false: `render --part` refuses it and `snapshot`
    /// says it cannot snapshot it.
    fn samples_are_independent(&self) -> bool;
}

/// Integrators of each camera sample on its own render through the per-sample rung.
impl<I: SampleIntegrator> Integrator for I {
    fn render(
        &self,
        scene: &Scene,
        region: &Region,
        progress: &dyn Progress,
    ) -> (Film, RenderStats) {
        render_samples(scene, self, region, progress)
    }

    fn samples_are_independent(&self) -> bool {
        true
    }
}

/// The integrator `settings` name, with their parameters.
pub fn of(settings: &Settings) -> Box<dyn Integrator> {
    let max_depth = settings.max_depth;
    match settings.integrator {
        IntegratorKind::Direct => Box::new(Direct { max_depth }),
        IntegratorKind::Path => Box::new(Path { max_depth, strategy: Strategy::Mis }),
        IntegratorKind::Photon => {
            Box::new(PhotonMapping { max_depth, k: settings.photon_k as usize })
        }
        IntegratorKind::FinalGather => {
            Box::new(FinalGather { max_depth, k: settings.photon_k as usize })
        }
        IntegratorKind::Sppm => Box::new(Sppm),
    }
}

/// Light from `light` scattered towards `wo` by the lobes of `bsdf` at `hit` that `gathered`
/// and `followed` ask for (those with a density among them), from its sample at `u`, if the
/// shadow ray turns out unoccluded: f Li |n . wi| / pdf (for a point light exactly the course's
/// Lab 4 p / r^2 f |n . wi|). Through `gathered` the environment's sample is weighted against the
/// BSDF's sample of it (`direct::direct_from_environment`) by the power heuristic; through
/// `followed` (the lobes a photon-mapping path goes on by, `Vertex::followed`) every light but a
/// point light is weighted against the ray sampled from them finding it (`WhittedPath::found`).
/// A point light takes its whole sample: no ray finds it. Always inlined into `direct`'s loop
/// over lights, with the light's sample.
#[inline(always)]
fn direct_from_light(
    light: &Light,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    (gathered, followed): (LobeFlags, LobeFlags),
    u: Vec2,
) -> Option<(ShadowRay, Vec3)> {
    let sample = light.sample(hit, u)?;
    let cos = hit.shading_normal.dot(sample.wi).abs();
    if sample.is_delta {
        let f = bsdf.eval_lobes(wo, sample.wi, gathered | followed);
        return Some((sample.shadow, f * sample.li * cos / sample.pdf));
    }
    let f = bsdf.eval_lobes(wo, sample.wi, gathered);
    let weight = if matches!(light, Light::Environment(_)) {
        power_heuristic(sample.pdf, bsdf.pdf(wo, sample.wi, gathered))
    } else {
        1.0
    };
    let mut lit = f * sample.li * cos * weight / sample.pdf;
    if followed.is_non_delta() {
        let f = bsdf.eval_lobes(wo, sample.wi, followed);
        let weight = power_heuristic(sample.pdf, bsdf.pdf(wo, sample.wi, followed));
        lit += f * sample.li * cos * weight / sample.pdf;
    }
    Some((sample.shadow, lit))
}

/// Veach's power heuristic with exponent 2, for one sample from each strategy:
/// pdf² / (pdf² + other²), written as 1 / (1 + (other / pdf)²) because the squares overflow
/// where a pdf is huge (an area light seen edge-on from far away: a solid-angle pdf of 1e20),
/// and inf / inf is NaN. Both infinite: an even split.
pub(super) fn power_heuristic(pdf: f32, other: f32) -> f32 {
    power_heuristic_of(pdf, other)
}

/// `power_heuristic` written once over `Real`: for one sample or a sample per lane.
#[inline(always)]
fn power_heuristic_of<F: Real>(pdf: F, other: F) -> F {
    let ratio = other / pdf;
    let is_nan = ratio.ne(ratio);
    let weight = F::select(is_nan, F::splat(0.5), F::ONE / (F::ONE + ratio * ratio));
    F::select(pdf.eq(F::ZERO), F::ZERO, weight)
}

/// A path traced in a lane: which camera sample it is (where its radiance goes), its own
/// sample values, and the integrator's state of it.
struct LanePath<S> {
    slot: usize,
    sampler: Sampler,
    state: S,
}

/// Paths traced side by side, one per lane: the rays of a bounce meet the scene together, and
/// each path's bounce is computed alone, by the same code as one path at a time (pbrt-v4's
/// wavefront way: ray queries batched, kernels written once).
struct Lanes<S> {
    /// Each lane's path; a free lane's (see `traced`) is stale and not read.
    paths: [LanePath<S>; LANES],
    /// The lanes whose path is being traced.
    traced: [bool; LANES],
}

impl<S> Lanes<S> {
    /// Free lanes, for paths whose state `start` makes from their camera ray.
    fn new(start: impl Fn(Ray) -> S) -> Self {
        let idle = || LanePath { slot: 0, sampler: Sampler::new(0, 0, 0), state: start(IDLE) };
        Lanes { paths: std::array::from_fn(|_| idle()), traced: [false; LANES] }
    }

    /// Gives each free lane the next camera sample, its state made by `start` from the camera
    /// ray; the lanes with a path after that, or `None` when none has one: every sample is
    /// traced.
    fn fill(
        &mut self,
        samples: &mut std::slice::Iter<CameraSample>,
        start: impl Fn(Ray) -> S,
    ) -> Option<[bool; LANES]> {
        let free = self.paths.iter_mut().zip(&mut self.traced).filter(|(_, traced)| !**traced);
        for (path, traced) in free {
            let Some(CameraSample { slot, ray, sampler }) = samples.next() else { break };
            // Assigned to the lane's fields: a whole `Option<LanePath>` made aside and moved in
            // was read back by wider loads than the stores that had made it, which waited for
            // them (perf of S3; LLVM still makes the state aside, 1–2 % of S3's samples).
            path.slot = *slot;
            path.sampler = sampler.clone();
            path.state = start(*ray);
            *traced = true;
        }
        self.traced.contains(&true).then_some(self.traced)
    }

    /// The paths' next rays, coordinate by coordinate (`IDLE` in free lanes).
    fn rays(&self, ray: impl Fn(&S) -> Ray) -> RayLanes {
        RayLanes::new(&std::array::from_fn(|lane| {
            if self.traced[lane] { ray(&self.paths[lane].state) } else { IDLE }
        }))
    }

    fn paths_mut(&mut self) -> impl Iterator<Item = (usize, &mut LanePath<S>)> {
        let traced = self.traced;
        self.paths.iter_mut().enumerate().filter(move |(lane, _)| traced[*lane])
    }

    fn path_mut(&mut self, lane: usize) -> Option<&mut LanePath<S>> {
        self.traced[lane].then(|| &mut self.paths[lane])
    }

    /// Ends the path in `lane`, freeing the lane: the path as it ended.
    fn end(&mut self, lane: usize) -> Option<&LanePath<S>> {
        std::mem::take(&mut self.traced[lane]).then(|| &self.paths[lane])
    }
}

/// The ray of a lane with no path (never tested: its lane is inactive or its `t_max` is 0).
const IDLE: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::Z };

/// Shadow rays of next-event estimation, one per lane at most, tested together, and the
/// radiance each brings if it is unoccluded. Held in lanes as they are set, so testing them
/// transposes nothing.
struct ShadowLanes {
    found: Mask,
    rays: RayLanes,
    /// Each ray's `t_max`; 0 in lanes without one (never occluded).
    t_max: Floats,
    radiance: [Vec3; LANES],
}

impl ShadowLanes {
    fn new() -> Self {
        ShadowLanes {
            found: Mask::none(),
            rays: RayLanes {
                origin: Vec3Lanes::splat(IDLE.origin.into()),
                dir: Vec3Lanes::splat(IDLE.dir.into()),
            },
            t_max: Floats::ZERO,
            radiance: [Vec3::ZERO; LANES],
        }
    }

    fn set_lane(&mut self, lane: usize, (shadow, radiance): (ShadowRay, Vec3)) {
        self.found.set_lane(lane, true);
        self.rays.set_lane(lane, &shadow.ray());
        self.t_max.set_lane(lane, shadow.t_max());
        self.radiance[lane] = radiance;
    }

    /// Sets the lanes of `lanes`: shadow rays from `origin` along `dir` up to `t_max`, each
    /// bringing its lane of `radiance` if unoccluded.
    #[inline(always)]
    fn set_lanes(
        &mut self,
        lanes: Mask,
        (origin, dir, t_max): (Vec3Lanes, Vec3Lanes, Floats),
        radiance: Vec3Lanes,
    ) {
        self.found = self.found | lanes;
        self.rays.origin = Vec3Lanes::select(lanes, origin, self.rays.origin);
        self.rays.dir = Vec3Lanes::select(lanes, dir, self.rays.dir);
        self.t_max = <Floats as Real>::select(lanes, t_max, self.t_max);
        for lane in (0..LANES).filter(|&lane| lanes.lane(lane)) {
            self.radiance[lane] = radiance.lane(lane);
        }
    }

    /// The radiance each lane's shadow ray brings: its light sample's, times the fraction that
    /// reaches it (`Scene::transmittance`); nothing for a lane without one. Always inlined, the
    /// see-through surfaces' part out of line: out of line (as LLVM left it), its call and
    /// returned array cost S1 4 % more instructions (callgrind).
    #[inline(always)]
    fn reached(&self, scene: &Scene) -> [Vec3; LANES] {
        let mut reached = [Vec3::ZERO; LANES];
        if !self.found.any() {
            return reached;
        }
        if scene.has_see_through() {
            return self.reached_through(scene);
        }
        let open = !scene.occluded_lanes(&self.rays, self.t_max);
        for lane in (0..LANES).filter(|&lane| self.found.lane(lane) && open.lane(lane)) {
            reached[lane] = self.radiance[lane];
        }
        reached
    }

    /// `reached` in a scene with see-through surfaces: each lane's shadow ray followed through
    /// them.
    #[inline(never)]
    fn reached_through(&self, scene: &Scene) -> [Vec3; LANES] {
        let mut reached = [Vec3::ZERO; LANES];
        for lane in (0..LANES).filter(|&lane| self.found.lane(lane)) {
            let ray = self.rays.lane(lane);
            reached[lane] = self.radiance[lane] * scene.transmittance(&ray, self.t_max.lane(lane));
        }
        reached
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The NaN of depth of field (a floor ray at a grazing angle sampling an area light 10^7
    /// units away: a light pdf near 1e20, squared to inf): every weight is a number in [0, 1],
    /// and the two strategies' weights add up to 1.
    #[test]
    fn power_heuristic_weights_are_numbers_for_any_pdfs() {
        assert_eq!(power_heuristic(1e20, 1.0), 1.0);
        assert_eq!(power_heuristic(1.0, 1e20), 0.0);
        let pdfs = [0.0, 1e-30, 1e-3, 0.5, 1.0, 3.0, 1e19, 1e20, 1e30, f32::MAX, f32::INFINITY];
        for a in pdfs {
            for b in pdfs {
                let (w, v) = (power_heuristic(a, b), power_heuristic(b, a));
                assert!((0.0..=1.0).contains(&w), "w({a}, {b}) = {w}");
                if a > 0.0 || b > 0.0 {
                    assert!((w + v - 1.0).abs() < 1e-6, "w({a}, {b}) + w({b}, {a}) = {}", w + v);
                }
            }
        }
    }
}
