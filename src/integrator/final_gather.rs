//! Jensen's photon mapping with a caustic map and final gathering (`docs/language.md`,
//! `final_gather`; Jensen 2001, 9.1). Two passes of photons fill two maps: the global map,
//! every photon of the first where it lands on a gathered lobe, and the caustic map, the photons
//! of a second pass aimed at the casters of caustics (`Projection`) that came from a light
//! through delta and near-specular bounces only. Camera rays go as `photon`'s do; at
//! each vertex with gathered lobes the light arriving there is split four ways:
//! - emission and direct light: next-event estimation, as `direct`;
//! - caustics (light -> specular -> here): the caustic map's `CAUSTIC_K` nearest photons,
//!   weighted by a cone filter, which keeps thin bright caustics from spreading a halo into
//!   their dark surroundings (Jensen 2001, eq. 7.7);
//! - the rest, light reflected by other gathered lobes: one final-gather ray sampled from the
//!   gathered lobes, followed through delta and near-specular lobes to a vertex with gathered
//!   lobes, where the global map's `photon_k` nearest photons estimate the light leaving it.
//!
//! The global estimate's blur is seen only through a bounce, so `photon_k` may be large; the
//! caustic estimate is seen directly, so it is kept small and sharp.

use glam::Vec3;
use std::time::Instant;

use super::direct::{Vertex, WhittedPath, arrive, follow, whitted};
use super::missed_light::MissedLight;
use super::photon::{Kernel, estimate, trace_caustics, trace_pass};
use super::{Integrator, SampleIntegrator, render_samples, stopped_before_a_pass};
use crate::film::Film;
use crate::geometry::{Ray, offset_origin};
use crate::photon::{Emission, PhotonMap};
use crate::progress::{Progress, RenderStats};
use crate::region::Region;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Photons in each caustic estimate.
pub const CAUSTIC_K: usize = 20;

/// Photon mapping with a caustic map and final gathering from a global map of `k` photons an
/// estimate, paths of at most `max_depth` bounces (the photons' and the gather rays' too).
pub struct FinalGather {
    pub max_depth: u32,
    pub k: usize,
}

impl Integrator for FinalGather {
    /// Traces the scene's photon pass (pass 0) into the global map and its caustic pass into
    /// the caustic map, then renders with them; a black film if `progress` asks to stop first.
    fn render(
        &self,
        scene: &Scene,
        region: &Region,
        progress: &dyn Progress,
    ) -> (Film, RenderStats) {
        let start = Instant::now();
        let emission = Emission::new(&scene.lights, scene.settings.photons());
        let Some([global]) = trace_pass(scene, &emission, 0, progress, |_| [true]) else {
            return stopped_before_a_pass(scene, start);
        };
        let Some(caustic) = trace_caustics(scene, progress) else {
            return stopped_before_a_pass(scene, start);
        };
        let estimate = GatherEstimate {
            gather: self,
            caustic: PhotonMap::build(caustic),
            global: PhotonMap::build(global),
            missed: MissedLight::of(scene),
        };
        let (film, stats) = render_samples(scene, &estimate, region, progress);
        (film, RenderStats { seconds: start.elapsed().as_secs_f64(), ..stats })
    }

    fn samples_are_independent(&self) -> bool {
        false
    }
}

struct GatherEstimate<'a> {
    gather: &'a FinalGather,
    caustic: PhotonMap,
    global: PhotonMap,
    missed: Option<MissedLight>,
}

impl GatherEstimate<'_> {
    /// Caustic light scattered towards wo by the gathered lobes at `vertex`: the cone-filtered
    /// estimate from the caustic map.
    fn caustic(&self, vertex: &Vertex) -> Vec3 {
        estimate(&self.caustic, vertex, CAUSTIC_K, Kernel::Cone)
    }

    /// Light leaving `vertex` towards wo through its gathered lobes, all of it: the global
    /// map's estimate (Jensen 2001, eq. 7.6).
    fn global(&self, vertex: &Vertex) -> Vec3 {
        estimate(&self.global, vertex, self.gather.k, Kernel::Uniform)
    }

    /// Light from other gathered lobes scattered towards wo by the gathered lobes at `vertex`:
    /// one ray sampled from them, followed through delta and near-specular lobes to a vertex
    /// with gathered lobes, where the global map tells the light leaving it. Emission met on the
    /// way is direct light or a caustic, both estimated elsewhere: it is left out. Where both
    /// kinds of lobe are met, the ray stops at the gathered ones with their probability p and
    /// goes on otherwise, each divided by its probability.
    fn final_gather(&self, scene: &Scene, vertex: &Vertex, sampler: &mut Sampler) -> Vec3 {
        let Vertex { hit, wo, bsdf, gathered } = vertex;
        let (u_lobe, u) = (sampler.next_1d(), sampler.next_2d());
        let Some(sample) = bsdf.sample(*wo, u_lobe, u, *gathered) else {
            return Vec3::ZERO;
        };
        let mut path =
            WhittedPath::photon_mapping(Ray::new(offset_origin(hit, sample.wi), sample.wi));
        path.beta = sample.weight;
        loop {
            let hit = scene.intersect(&path.ray);
            let Some(next) = arrive(scene, &mut path, hit, self.gather.max_depth) else { break };
            let followed = next.followed();
            if !next.gathered.is_empty() {
                let p = if followed.is_empty() {
                    1.0
                } else {
                    next.bsdf.probability_of(next.wo, next.gathered)
                };
                if sampler.next_1d_if(!followed.is_empty()) < p {
                    return path.beta / p * self.global(&next);
                }
                path.beta /= 1.0 - p;
            }
            if !follow(&mut path, &next, sampler) {
                break;
            }
        }
        Vec3::ZERO
    }
}

impl SampleIntegrator for GatherEstimate<'_> {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let indirect = |vertex: &Vertex, sampler: &mut Sampler| {
            let max_depth = self.gather.max_depth;
            let missed = (self.missed.as_ref())
                .map_or(Vec3::ZERO, |m| m.at(scene, vertex, max_depth, sampler));
            self.caustic(vertex) + self.final_gather(scene, vertex, sampler) + missed
        };
        whitted(scene, ray, sampler, self.gather.max_depth, Some(&indirect))
    }
}
