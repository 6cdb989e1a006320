//! Unidirectional path tracing of the full rendering equation: a loop over bounces with
//! next-event estimation towards one light chosen by power, BSDF sampling, multiple importance
//! sampling of the two (power heuristic, Veach 1997), and Russian roulette.

use glam::{Vec2, Vec3};

use super::diffuse_lanes::{DiffuseLanes, DiffuseSamples, DiffuseVertex};
use super::{CameraSample, Lanes, SampleIntegrator, ShadowLanes, power_heuristic};
use crate::geometry::{Hit, Ray, offset_origin};
use crate::lanes::LANES;
use crate::light::{Light, ShadowRay};
use crate::material::lobe::Lambertian;
use crate::material::{Bsdf, LobeFlags, TransportMode};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Which estimators of direct light from area lights contribute. Point lights can only be
/// reached by next-event estimation and always are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Both, weighted by the power heuristic.
    Mis,
    /// Next-event estimation only; emitters hit by BSDF-sampled rays count only after a delta bounce.
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

/// A camera path between bounces: what the next bounce reads and updates.
pub(super) struct PathState {
    /// Its next ray.
    pub(super) ray: Ray,
    /// Radiance gathered so far.
    pub(super) radiance: Vec3,
    /// Throughput: the product of the BSDF (and medium) weights along the path.
    pub(super) beta: Vec3,
    /// Product of eta^2 over refractions: undoes their radiance scaling for Russian roulette,
    /// so paths through glass are not cut for a throughput drop that the exit restores.
    pub(super) eta_scale: f32,
    /// Where the last direction was sampled from a non-delta lobe (or a phase function), that
    /// vertex's point and the direction's solid-angle pdf (for MIS where the path meets an
    /// emitter).
    pub(super) previous: Option<(Vec3, f32)>,
    /// Whether every bounce so far was through a delta lobe: the camera sees what the path
    /// finds (POV-Ray's `background` too, which does not light).
    pub(super) seen: bool,
    pub(super) bounces: u32,
}

impl PathState {
    pub(super) fn new(ray: Ray) -> Self {
        PathState {
            ray,
            radiance: Vec3::ZERO,
            beta: Vec3::ONE,
            eta_scale: 1.0,
            previous: None,
            seen: true,
            bounces: 0,
        }
    }

    /// The rest of a bounce whose lone Lambertian lobe's sample was left to the lanes
    /// (`Path::bounce_by`), from `lane` of their samples: the next ray and roulette, as
    /// `Path::bounce` does after its BSDF sample. Whether the path goes on.
    #[inline(always)]
    pub(super) fn follow_diffuse(
        &mut self,
        sampled: &DiffuseSamples,
        lane: usize,
        sampler: &mut Sampler,
    ) -> bool {
        if !sampled.continues(lane) {
            return false;
        }
        let (ray, previous) = sampled.lane(lane);
        self.previous = Some(previous);
        self.seen = false;
        self.ray = ray;
        if !self.survives_roulette(sampler) {
            return false;
        }
        self.bounces += 1;
        true
    }

    /// Russian roulette before the next bounce: whether the path goes on, with probability tied
    /// to its throughput, which is divided by it so that the estimate stays unbiased.
    #[inline(always)]
    pub(super) fn survives_roulette(&mut self, sampler: &mut Sampler) -> bool {
        let roulette = self.bounces + 1 >= ROULETTE_AFTER;
        let survive = (self.beta * self.eta_scale).max_element().min(1.0);
        let u = sampler.next_1d_if(roulette);
        if roulette && u >= survive {
            return false;
        }
        if roulette {
            self.beta /= survive;
        }
        true
    }
}

/// What a bounce leaves to its caller: next-event estimation's shadow ray and the radiance it
/// brings if nothing is in the way, and whether the path goes on (along `PathState::ray`).
pub(super) struct Bounce {
    pub(super) shadowed: Option<(ShadowRay, Vec3)>,
    pub(super) continues: bool,
}

impl SampleIntegrator for Path {
    /// One path, one bounce at a time.
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        if scene.has_media() {
            return self.radiance_in_media(scene, ray, sampler);
        }
        let mut path = PathState::new(ray);
        loop {
            let hit = scene.intersect(&path.ray);
            let bounce = self.bounce(scene, &mut path, hit, sampler);
            if let Some((shadow, li)) = bounce.shadowed {
                path.radiance += li * scene.transmittance(&shadow.ray(), shadow.t_max());
            }
            if !bounce.continues {
                return path.radiance;
            }
        }
    }

    /// Traces `LANES` paths at a time, bounce by bounce, so that their rays and their shadow
    /// rays meet the scene together (`Scene::intersect_lanes`, `Scene::occluded_lanes`); each
    /// path's bounce is `bounce`, as for one path, but for the light and BSDF samples of a
    /// vertex on a lone Lambertian lobe, which the lanes with one take together (`DiffuseLanes`)
    /// by the same kernels, so each path gets the same radiance, bit for bit. A finished path's
    /// lane takes the next camera sample.
    fn radiance_of_all(&self, scene: &Scene, samples: &[CameraSample], radiance: &mut [Vec3]) {
        let samples = &mut samples.iter();
        if scene.has_media() {
            for CameraSample { slot, ray, sampler } in samples {
                radiance[*slot] = self.radiance_in_media(scene, *ray, &mut sampler.clone());
            }
            return;
        }
        let mut lanes: Lanes<PathState> = Lanes::new(PathState::new);
        while let Some(active) = lanes.fill(samples, PathState::new) {
            let rays = lanes.rays(|path| path.ray);
            let found = scene.intersect_lanes(&rays, active);
            let mut shadows = ShadowLanes::new();
            let mut diffuse = DiffuseLanes::new();
            let mut done = [false; LANES];
            let hits = found.hits();
            for (lane, path) in lanes.paths_mut() {
                let hit = hits[lane];
                let bounce = self.bounce_by(scene, &mut path.state, hit, &mut path.sampler, {
                    let diffuse = &mut diffuse;
                    move |vertex| diffuse.set_lane(scene, lane, vertex)
                });
                if let Some(shadowed) = bounce.shadowed {
                    shadows.set_lane(lane, shadowed);
                }
                done[lane] = !bounce.continues;
            }
            let set = diffuse.set();
            if set != 0 {
                let sampled = diffuse.scatter(scene, &found.hits, -rays.dir, &mut shadows);
                for (lane, path) in lanes.paths_mut().filter(|(lane, _)| set & (1 << lane) != 0) {
                    done[lane] = !path.state.follow_diffuse(&sampled, lane, &mut path.sampler);
                }
            }
            for (lane, reached) in shadows.reached(scene).into_iter().enumerate() {
                if let Some(path) = lanes.path_mut(lane) {
                    path.state.radiance += reached;
                }
            }
            for (lane, _) in done.iter().enumerate().filter(|(_, done)| **done) {
                if let Some(path) = lanes.end(lane) {
                    radiance[path.slot] = path.state.radiance;
                }
            }
        }
    }
}

impl Path {
    /// The path arrives where its ray meets the scene (`hit`), or leaves it: emission found
    /// there, weighted against next-event estimation; then, unless the path ends here, a light
    /// sample (its shadow ray left to the caller) and a BSDF sample for the next ray, and
    /// Russian roulette. Always inlined: out of line (volpath calls it too) its arguments and
    /// state cost a path vertex 5-10 % more instructions (callgrind, S2-S7).
    #[inline(always)]
    pub(super) fn bounce(
        &self,
        scene: &Scene,
        path: &mut PathState,
        hit: Option<Hit>,
        sampler: &mut Sampler,
    ) -> Bounce {
        self.bounce_by(scene, path, hit, sampler, |_| false)
    }

    /// `bounce`, but under multiple importance sampling a vertex on a lone Lambertian lobe
    /// (`Material::lone_lambertian`, without bump mapping) may be left to `defer`, with its
    /// light sample and its BSDF sample: where it takes it, the throughput is multiplied by kd
    /// and the bounce goes on, its next ray and roulette left to `PathState::follow_diffuse`.
    #[inline(always)]
    fn bounce_by(
        &self,
        scene: &Scene,
        path: &mut PathState,
        hit: Option<Hit>,
        sampler: &mut Sampler,
        defer: impl FnOnce(DiffuseVertex) -> bool,
    ) -> Bounce {
        let ends = Bounce { shadowed: None, continues: false };
        let Some(mut hit) = hit else {
            path.radiance += path.beta * self.beyond(scene, path);
            return ends;
        };
        let wo = -Vec3::from(path.ray.dir);
        let material = scene.material(hit.primitive, hit.point);
        let emitted = material.emitted(hit.normal, wo);
        if emitted != Vec3::ZERO {
            path.radiance += path.beta * emitted * self.emission_weight(scene, &hit, path.previous);
        }
        if path.bounces == self.max_depth {
            return ends;
        }
        // A lone Lambertian lobe without bump mapping, under MIS, may be left to `defer`, whose
        // lanes make its frame and samples: its BSDF is made only where it is not (made and
        // unread, it was 5–7 % of S3's samples in `perf`).
        let lone = match self.strategy {
            Strategy::Mis if !scene.is_bumped(hit.primitive) => material.lone_lambertian(),
            Strategy::Mis | Strategy::BsdfSampling | Strategy::LightSampling => None,
        };
        let mut bsdf = Bsdf::BLACK;
        let flags = match lone {
            Some(_) => Lambertian::FLAGS,
            None => {
                scene.shade(&mut bsdf, &mut hit, wo, &material, TransportMode::Radiance);
                bsdf.flags()
            }
        };
        let light = if flags.is_non_delta() { self.choose_light(scene, sampler) } else { None };
        let u_lobe = sampler.next_1d_if(flags.chooses_lobe());
        // Delta lobes read no direction sample.
        let u = sampler.next_2d_if(flags.is_non_delta());
        let beta = path.beta;
        if let Some(Lambertian { reflectance: kd }) = lone {
            if defer(DiffuseVertex { primitive: hit.primitive, kd, beta, light, u }) {
                path.beta *= kd;
                return Bounce { shadowed: None, continues: true };
            }
            // Its light is one the lanes do not sample: the vertex is traced here, as others.
            scene.shade(&mut bsdf, &mut hit, wo, &material, TransportMode::Radiance);
        }
        let shadowed = match light {
            Some((light, probability, u_light)) => self
                .next_event(scene, &hit, wo, &bsdf, (light, probability), u_light)
                .map(|(shadow, li)| (shadow, beta * li)),
            None => None,
        };
        let Some(sample) = bsdf.sample(wo, u_lobe, u, LobeFlags::ALL) else {
            return Bounce { shadowed, continues: false };
        };
        path.beta *= sample.weight;
        path.eta_scale *= sample.eta * sample.eta;
        // Light straight through the surface (`Material::passes_straight`) is a crossing, not
        // a bounce: shadow rays cross it too, so what the path finds beyond is weighed against
        // the light sample of the vertex before, as if the surface were not there.
        let crossed = sample.flags.contains(LobeFlags::TRANSMISSION)
            && sample.is_delta()
            && material.passes_straight();
        if !crossed {
            path.previous = (!sample.is_delta()).then_some((hit.point, sample.pdf));
        }
        path.seen &= sample.is_delta();
        path.ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
        if !path.survives_roulette(sampler) {
            return Bounce { shadowed, continues: false };
        }
        path.bounces += 1;
        Bounce { shadowed, continues: true }
    }

    /// Radiance the path finds where it leaves the scene: the environment's, weighted against
    /// next-event estimation, and the backdrop if the camera sees it.
    fn beyond(&self, scene: &Scene, path: &PathState) -> Vec3 {
        let dir = Vec3::from(path.ray.dir);
        let backdrop = if path.seen { scene.backdrop() } else { Vec3::ZERO };
        let Some((light, sky)) = scene.environment() else {
            return backdrop;
        };
        let weight = self.found_weight(scene, light, path.previous, |_, _| sky.pdf(dir));
        backdrop + sky.le(dir) * weight
    }

    /// The weight of emission found by a BSDF-sampled ray.
    fn emission_weight(&self, scene: &Scene, hit: &Hit, previous: Option<(Vec3, f32)>) -> f32 {
        let Some(light) = scene.primitives[hit.primitive as usize].light else {
            return 1.0; // no light sample can find this emitter
        };
        self.found_weight(scene, light as usize, previous, |light, from| light.pdf(from, hit))
    }

    /// The weight of light from `light` found by a ray sampled after `previous` (see
    /// `PathState::previous`); `light_pdf(light, from)` is the density with which a light
    /// sample from `from` finds the same direction.
    fn found_weight(
        &self,
        scene: &Scene,
        light: usize,
        previous: Option<(Vec3, f32)>,
        light_pdf: impl FnOnce(&Light, Vec3) -> f32,
    ) -> f32 {
        let Some((from, bsdf_pdf)) = previous else {
            return 1.0; // seen by the camera or through delta bounces
        };
        match self.strategy {
            Strategy::BsdfSampling => 1.0,
            Strategy::LightSampling => 0.0,
            Strategy::Mis => {
                let light_pdf =
                    scene.light_probability(light) * light_pdf(&scene.lights[light], from);
                power_heuristic(bsdf_pdf, light_pdf)
            }
        }
    }

    /// The light for next-event estimation, chosen by power, with the probability of that
    /// choice and the point that samples it; none if this strategy does not sample it. Always
    /// inlined, as `next_event` is: in `bounce`, grown by media and bump mapping, LLVM left both
    /// out of line, and their calls cost S1-S7 1-2 % more instructions (callgrind).
    #[inline(always)]
    pub(super) fn choose_light(
        &self,
        scene: &Scene,
        sampler: &mut Sampler,
    ) -> Option<(usize, f32, Vec2)> {
        let u_select = sampler.next_1d_if(scene.lights.len() > 1);
        let chosen = scene.choose_light(u_select);
        // A delta light (a point) reads no sample.
        let u =
            sampler.next_2d_if(chosen.is_some_and(|(index, _)| !scene.lights[index].is_delta()));
        let (index, probability) = chosen?;
        if !scene.lights[index].is_delta() && self.strategy == Strategy::BsdfSampling {
            return None;
        }
        Some((index, probability, u))
    }

    /// Light from `light`, chosen with `probability`, scattered by `bsdf` at one vertex,
    /// weighted against BSDF sampling, if its shadow ray is unoccluded.
    #[inline(always)]
    fn next_event(
        &self,
        scene: &Scene,
        hit: &Hit,
        wo: Vec3,
        bsdf: &Bsdf,
        (light, probability): (usize, f32),
        u: Vec2,
    ) -> Option<(ShadowRay, Vec3)> {
        let sample = scene.lights[light].sample(hit, u)?;
        let weighed = !sample.is_delta && self.strategy != Strategy::LightSampling;
        let (f, bsdf_pdf) = if weighed {
            bsdf.eval_pdf(wo, sample.wi, LobeFlags::ALL)
        } else {
            (bsdf.eval(wo, sample.wi), 0.0)
        };
        if f == Vec3::ZERO {
            return None;
        }
        let light_pdf = probability * sample.pdf;
        let weight = if weighed { power_heuristic(light_pdf, bsdf_pdf) } else { 1.0 };
        let radiance = f * sample.li * hit.shading_normal.dot(sample.wi).abs() * weight / light_pdf;
        Some((sample.shadow, radiance))
    }
}
