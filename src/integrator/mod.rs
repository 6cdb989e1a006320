//! Integrators: estimators of the image. Each renders a region of it (`Integrator`); those that
//! estimate each camera sample on its own (`direct`, `path`, `photon`) do it through the
//! per-sample rung (`SampleIntegrator`, `render_samples`), and `sppm` renders by iterations of
//! its own.

mod direct;
mod final_gather;
mod path;
mod photon;
mod samples;
pub mod sppm;

pub use direct::Direct;
pub use final_gather::{CAUSTIC_K, FinalGather};
pub use path::{Path, Strategy};
pub use photon::{PHOTON_TASK, PhotonMapping, STORED_PHOTON_BYTES, most_stored, trace_pass};
pub use samples::{SampleIntegrator, TASK_SAMPLES, render_samples, stopped_before_a_pass};
pub use sppm::Sppm;

use glam::{Vec2, Vec3};

use crate::film::Film;
use crate::geometry::{Hit, Ray};
use crate::graph::{IntegratorKind, Settings};
use crate::lanes::{Floats, LANES, Lane, RayLanes, Wide};
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

/// Light from `light` scattered towards `wo` by the lobes of `bsdf` at `hit` that `mask` asks for
/// (those with a density among them), from
/// its sample at `u`, if the shadow ray turns out unoccluded: f Li |n . wi| / pdf (for a point
/// light exactly the course's Lab 4 p / r^2 f |n . wi|).
fn direct_from_light(
    light: &Light,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    mask: LobeFlags,
    u: Vec2,
) -> Option<(ShadowRay, Vec3)> {
    let sample = light.sample(hit, u)?;
    let f = bsdf.eval_lobes(wo, sample.wi, mask);
    Some((sample.shadow, f * sample.li * hit.shading_normal.dot(sample.wi).abs() / sample.pdf))
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
    paths: [Option<LanePath<S>>; LANES],
}

impl<S> Lanes<S> {
    fn new() -> Self {
        Lanes { paths: std::array::from_fn(|_| None) }
    }

    /// Gives each free lane the next camera sample (numbered by `samples`), its state made by
    /// `start` from the camera ray; the lanes with a path after that, or `None` when none has
    /// one: every sample is traced.
    fn fill(
        &mut self,
        samples: &mut impl Iterator<Item = (usize, (Ray, Sampler))>,
        start: impl Fn(Ray) -> S,
    ) -> Option<[bool; LANES]> {
        for path in self.paths.iter_mut().filter(|path| path.is_none()) {
            let Some((slot, (ray, sampler))) = samples.next() else { break };
            *path = Some(LanePath { slot, sampler, state: start(ray) });
        }
        let active = self.paths.each_ref().map(Option::is_some);
        active.contains(&true).then_some(active)
    }

    /// The paths' next rays, coordinate by coordinate (`IDLE` in free lanes).
    fn rays(&self, ray: impl Fn(&S) -> Ray) -> RayLanes {
        RayLanes::new(
            &self.paths.each_ref().map(|path| path.as_ref().map_or(IDLE, |p| ray(&p.state))),
        )
    }

    fn paths_mut(&mut self) -> impl Iterator<Item = (usize, &mut LanePath<S>)> {
        self.paths.iter_mut().enumerate().filter_map(|(lane, path)| Some((lane, path.as_mut()?)))
    }

    fn path_mut(&mut self, lane: usize) -> Option<&mut LanePath<S>> {
        self.paths[lane].as_mut()
    }

    /// Ends the path in `lane`, freeing the lane.
    fn take(&mut self, lane: usize) -> Option<LanePath<S>> {
        self.paths[lane].take()
    }
}

/// The ray of a lane with no path (never tested: its lane is inactive or its `t_max` is 0).
const IDLE: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::Z };

/// Shadow rays of next-event estimation, one per lane at most, tested together, and the
/// radiance each brings if it is unoccluded.
struct ShadowLanes {
    found: [bool; LANES],
    rays: [Ray; LANES],
    t_max: [f32; LANES],
    radiance: [Vec3; LANES],
}

impl ShadowLanes {
    fn new() -> Self {
        ShadowLanes {
            found: [false; LANES],
            rays: [IDLE; LANES],
            t_max: [0.0; LANES],
            radiance: [Vec3::ZERO; LANES],
        }
    }

    fn set_lane(&mut self, lane: usize, (shadow, radiance): (ShadowRay, Vec3)) {
        self.found[lane] = true;
        self.rays[lane] = shadow.ray;
        self.t_max[lane] = shadow.t_max;
        self.radiance[lane] = radiance;
    }

    /// The lanes whose shadow ray is unoccluded.
    fn open(&self, scene: &Scene) -> impl Iterator<Item = usize> + use<> {
        let mut open = [false; LANES];
        if self.found.contains(&true) {
            let t_max = Floats::from_fn(|lane| self.t_max[lane]);
            let occluded = scene.occluded_lanes(&RayLanes::new(&self.rays), t_max);
            open = std::array::from_fn(|lane| self.found[lane] && !occluded.lane(lane));
        }
        (0..LANES).filter(move |&lane| open[lane])
    }
}
