//! Unidirectional path tracing of the full rendering equation: a loop over bounces with
//! next-event estimation towards one light chosen by power, BSDF sampling, multiple importance
//! sampling of the two (power heuristic, Veach 1997), and Russian roulette.

use glam::{BVec4A, Vec2, Vec3, Vec4};

use super::Integrator;
use crate::geometry::{Hit, HitLanes, LANES, Ray, Vec3x4, offset_origin};
use crate::light::{ShadowRay, sample_lanes};
use crate::material::{BsdfSample, Material, eval_diffuse_lanes, sample_lambertian_lanes};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Which estimators of direct light from area lights contribute. Point lights can only be
/// reached by next-event estimation and always are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Both, weighted by the power heuristic.
    Mis,
    /// Next-event estimation only; emitters hit by BSDF-sampled rays count only after a specular bounce.
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

impl Integrator for Path {
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut radiance = [Vec3::ZERO];
        self.radiance_of_all(scene, &mut std::iter::once((ray, sampler.clone())), &mut radiance);
        radiance[0]
    }

    /// Traces `LANES` paths at a time, bounce by bounce, so that their rays and their shadow
    /// rays meet the scene together (`Scene::intersect_lanes`), and light and BSDF samples of
    /// the common kinds (point and planar lights, Lambertian materials) are computed side by side;
    /// a finished path's lane takes the next camera sample. Each path draws its sample values in
    /// the order it would alone, so it gets the same radiance.
    fn radiance_of_all(
        &self,
        scene: &Scene,
        samples: &mut dyn Iterator<Item = (Ray, Sampler)>,
        radiance: &mut [Vec3],
    ) {
        let mut samples = samples.enumerate();
        let mut lanes: [Option<PathState>; LANES] = Default::default();
        loop {
            for lane in lanes.iter_mut().filter(|lane| lane.is_none()) {
                *lane =
                    samples.next().map(|(slot, (ray, sampler))| PathState::new(slot, ray, sampler));
            }
            let active = lanes.each_ref().map(Option::is_some);
            if !active.contains(&true) {
                break;
            }
            let rays = lanes.each_ref().map(|lane| lane.as_ref().map_or(IDLE, |path| path.ray));
            let found = scene.intersect_lanes(&rays, active);
            let mut vertices: [Option<Vertex>; LANES] = Default::default();
            let mut done = [false; LANES];
            for (lane, path) in lanes.iter_mut().enumerate() {
                if let Some(path) = path {
                    let hit = found[lane].map(|found| scene.hit(&path.ray, &found));
                    vertices[lane] = self.arrive(scene, path, hit);
                    done[lane] = vertices[lane].is_none();
                }
            }
            let hits = HitLanes::new(vertices.each_ref().map(|v| v.as_ref().map(|v| &v.hit)));
            let wo = Vec3x4::from_lanes(
                vertices.each_ref().map(|v| v.as_ref().map_or(Vec3::Z, |v| v.wo)),
            );
            let shadowed = self.next_event_lanes(scene, &lanes, &vertices, &hits, wo);
            let bsdf_samples = sample_bsdf_lanes(&vertices, &hits, wo);
            for (lane, path) in lanes.iter_mut().enumerate() {
                if let (Some(path), Some(vertex)) = (path, &vertices[lane]) {
                    done[lane] = self.leave(path, &vertex.hit, bsdf_samples[lane]);
                }
            }
            if shadowed.iter().any(Option::is_some) {
                let rays = shadowed.map(|shadow| shadow.map_or(IDLE, |s: Shadowed| s.ray.ray));
                let t_max = shadowed.map(|shadow| shadow.map_or(0.0, |s| s.ray.t_max));
                let occluded = scene.occluded_lanes(&rays, t_max);
                for (lane, (path, shadow)) in lanes.iter_mut().zip(shadowed).enumerate() {
                    if let (Some(path), Some(shadow)) = (path, shadow)
                        && occluded & (1 << lane) == 0
                    {
                        path.radiance += shadow.radiance;
                    }
                }
            }
            for (lane, done) in lanes.iter_mut().zip(done) {
                if done && let Some(path) = lane.take() {
                    radiance[path.slot] = path.radiance;
                }
            }
        }
    }
}

/// The ray of a lane with no path (never tested: its lane is inactive or its `t_max` is 0).
const IDLE: Ray = Ray { origin: glam::Vec3A::ZERO, dir: glam::Vec3A::Z };

/// A path being traced: its next ray and what it has gathered so far.
struct PathState {
    /// Which camera sample it is: where its radiance goes.
    slot: usize,
    ray: Ray,
    sampler: Sampler,
    radiance: Vec3,
    beta: Vec3,
    /// Product of eta^2 over refractions: undoes their radiance scaling for Russian roulette,
    /// so paths through glass are not cut for a throughput drop that the exit restores.
    eta_scale: f32,
    /// The previous vertex's point and the solid-angle pdf of the direction sampled there
    /// (None for the camera ray and after specular bounces: no light sample could have found
    /// this path).
    previous: Option<(Vec3, f32)>,
    bounces: u32,
}

impl PathState {
    fn new(slot: usize, ray: Ray, sampler: Sampler) -> Self {
        PathState {
            slot,
            ray,
            sampler,
            radiance: Vec3::ZERO,
            beta: Vec3::ONE,
            eta_scale: 1.0,
            previous: None,
            bounces: 0,
        }
    }
}

/// Where a path scatters this bounce, and the sample values for its choices there.
struct Vertex {
    hit: Hit,
    wo: Vec3,
    material: Material,
    /// For next-event estimation: the light chosen, the probability of that choice, and the
    /// point of the unit square that samples it.
    light: Option<(usize, f32, Vec2)>,
    u_lobe: f32,
    u_direction: Vec2,
}

/// Radiance that next-event estimation found, counted if its shadow ray is unoccluded.
#[derive(Debug, Clone, Copy)]
struct Shadowed {
    ray: ShadowRay,
    radiance: Vec3,
}

impl Path {
    /// A path arrives at `hit` (`None`: its ray left the scene) and takes the emission found
    /// there; returns where it scatters next, or `None` if it ends here.
    fn arrive(&self, scene: &Scene, path: &mut PathState, hit: Option<Hit>) -> Option<Vertex> {
        let Some(hit) = hit else {
            path.radiance += path.beta * scene.background();
            return None;
        };
        let wo = -Vec3::from(path.ray.dir);
        let material = scene.material(&hit);
        let emitted = material.emitted(hit.normal, wo);
        if emitted != Vec3::ZERO {
            let weight = self.emission_weight(scene, &hit, path.previous);
            path.radiance += path.beta * emitted * weight;
        }
        if path.bounces == self.max_depth {
            return None;
        }
        let sampler = &mut path.sampler;
        let light = if material.has_diffuse() { self.choose_light(scene, sampler) } else { None };
        // Only a material with specular lobes has a lobe to choose.
        let u_lobe = sampler.next_1d_if(material.has_specular());
        let u_direction = sampler.next_2d();
        Some(Vertex { hit, wo, material, light, u_lobe, u_direction })
    }

    /// Takes a path on along its BSDF sample, or ends it (`None`, or Russian roulette);
    /// returns whether it ends here.
    fn leave(&self, path: &mut PathState, hit: &Hit, sample: Option<BsdfSample>) -> bool {
        let Some(sample) = sample else {
            return true;
        };
        path.beta *= sample.weight;
        path.eta_scale *= sample.eta * sample.eta;
        path.previous = (!sample.specular).then_some((hit.point, sample.pdf));
        path.ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
        // Russian roulette: continue with probability tied to the throughput and divide by
        // it, so the estimate stays unbiased.
        let roulette = path.bounces + 1 >= ROULETTE_AFTER;
        let u = path.sampler.next_1d_if(roulette);
        if roulette {
            let survive = (path.beta * path.eta_scale).max_element().min(1.0);
            if u >= survive {
                return true;
            }
            path.beta /= survive;
        }
        path.bounces += 1;
        false
    }

    /// The weight of emission found by a BSDF-sampled ray.
    fn emission_weight(&self, scene: &Scene, hit: &Hit, previous: Option<(Vec3, f32)>) -> f32 {
        let Some((from, bsdf_pdf)) = previous else {
            return 1.0; // seen by the camera or through specular bounces
        };
        let Some(light) = scene.primitives[hit.primitive as usize].light else {
            return 1.0; // no light sample can find this emitter
        };
        match self.strategy {
            Strategy::BsdfSampling => 1.0,
            Strategy::LightSampling => 0.0,
            Strategy::Mis => {
                let light_pdf = scene.light_probability(light as usize)
                    * scene.lights[light as usize].pdf(scene, from, hit);
                power_heuristic(bsdf_pdf, light_pdf)
            }
        }
    }

    /// The light for next-event estimation, chosen by power, with the probability of that
    /// choice and the point that samples it; none if this strategy does not sample it.
    fn choose_light(&self, scene: &Scene, sampler: &mut Sampler) -> Option<(usize, f32, Vec2)> {
        let u_select = sampler.next_1d_if(scene.lights.len() > 1);
        let u = sampler.next_2d();
        let (index, probability) = scene.choose_light(u_select)?;
        if !scene.lights[index].is_delta() && self.strategy == Strategy::BsdfSampling {
            return None;
        }
        Some((index, probability, u))
    }

    /// Next-event estimation at the lanes' vertices: light from each vertex's chosen light,
    /// weighted against BSDF sampling, if its shadow ray turns out unoccluded. Point lights and
    /// planar area lights are sampled in lanes, other lights one vertex at a time.
    fn next_event_lanes(
        &self,
        scene: &Scene,
        paths: &[Option<PathState>; LANES],
        vertices: &[Option<Vertex>; LANES],
        hits: &HitLanes,
        wo: Vec3x4,
    ) -> [Option<Shadowed>; LANES] {
        let lights = vertices.each_ref().map(|v| v.as_ref().and_then(|v| v.light));
        let primitives =
            vertices.each_ref().map(|v| v.as_ref().map_or(u32::MAX, |v| v.hit.primitive));
        let sampled =
            sample_lanes(scene, hits, primitives, lights.map(|l| l.map(|(i, _, u)| (i, u))));
        let mut shadowed = [None; LANES];
        if let Some(sampled) = sampled.filter(|s| s.found.any()) {
            let diffuse = Vec3x4::from_lanes(
                vertices.each_ref().map(|v| v.as_ref().map_or(Vec3::ZERO, |v| v.material.diffuse)),
            );
            let p_diffuse = Vec4::from_array(std::array::from_fn(|lane| match &vertices[lane] {
                Some(v) if sampled.found.test(lane) => {
                    v.material.diffuse_probability(v.hit.shading_normal, v.wo)
                }
                _ => 0.0,
            }));
            let n = hits.shading_normal;
            let (f, bsdf_pdf) = eval_diffuse_lanes(n, wo, sampled.wi, diffuse, p_diffuse);
            let probability = Vec4::from_array(lights.map(|l| l.map_or(1.0, |(_, p, _)| p)));
            let light_pdf = probability * sampled.pdf;
            let weight = match self.strategy {
                Strategy::LightSampling => Vec4::ONE,
                _ => Vec4::select(
                    sampled.is_delta,
                    Vec4::ONE,
                    power_heuristic_lanes(light_pdf, bsdf_pdf),
                ),
            };
            let radiance = f * sampled.li * n.dot(sampled.wi).abs() * weight / light_pdf;
            let beta = Vec3x4::from_lanes(
                paths.each_ref().map(|p| p.as_ref().map_or(Vec3::ZERO, |p| p.beta)),
            );
            let radiance = beta * radiance;
            let found = sampled.found & !f.is_zero();
            for lane in (0..LANES).filter(|&lane| found.test(lane)) {
                shadowed[lane] =
                    Some(Shadowed { ray: sampled.shadow(lane), radiance: radiance.lane(lane) });
            }
        }
        let handled = sampled.map_or(BVec4A::FALSE, |s| s.handled);
        for lane in (0..LANES).filter(|&lane| !handled.test(lane)) {
            if let (Some(path), Some(vertex)) = (&paths[lane], &vertices[lane])
                && let Some((light, probability, u)) = vertex.light
            {
                shadowed[lane] = self
                    .next_event(scene, vertex, light, probability, u)
                    .map(|(ray, radiance)| Shadowed { ray, radiance: path.beta * radiance });
            }
        }
        shadowed
    }

    /// Light from `light`, chosen with `probability`, at one vertex, weighted against BSDF
    /// sampling, if its shadow ray is unoccluded.
    fn next_event(
        &self,
        scene: &Scene,
        vertex: &Vertex,
        light: usize,
        probability: f32,
        u: Vec2,
    ) -> Option<(ShadowRay, Vec3)> {
        let Vertex { hit, wo, material, .. } = vertex;
        let sample = scene.lights[light].sample(scene, hit, u)?;
        let f = material.eval(hit.shading_normal, *wo, sample.wi);
        if f == Vec3::ZERO {
            return None;
        }
        let light_pdf = probability * sample.pdf;
        let weight = if sample.is_delta || self.strategy == Strategy::LightSampling {
            1.0
        } else {
            power_heuristic(light_pdf, material.pdf(hit.shading_normal, *wo, sample.wi))
        };
        let radiance = f * sample.li * hit.shading_normal.dot(sample.wi).abs() * weight / light_pdf;
        Some((sample.shadow, radiance))
    }
}

/// Directions from the BSDFs at the lanes' vertices: Lambertian ones in lanes, the others one
/// vertex at a time.
fn sample_bsdf_lanes(
    vertices: &[Option<Vertex>; LANES],
    hits: &HitLanes,
    wo: Vec3x4,
) -> [Option<BsdfSample>; LANES] {
    let lambertian = vertices.each_ref().map(|v| v.as_ref().filter(|v| v.material.is_lambertian()));
    let mut samples = if lambertian.iter().any(Option::is_some) {
        let u = vertices.each_ref().map(|v| v.as_ref().map_or(Vec2::ZERO, |v| v.u_direction));
        sample_lambertian_lanes(
            lambertian.map(|v| v.map(|v| &v.material)),
            hits.shading_normal,
            wo,
            u,
        )
    } else {
        [None; LANES]
    };
    for (lane, vertex) in vertices.iter().enumerate() {
        if let (Some(v), None) = (vertex, lambertian[lane]) {
            samples[lane] = v.material.sample(v.hit.shading_normal, v.wo, v.u_lobe, v.u_direction);
        }
    }
    samples
}

/// `power_heuristic` in four lanes.
fn power_heuristic_lanes(pdf: Vec4, other: Vec4) -> Vec4 {
    let (a, b) = (pdf * pdf, other * other);
    Vec4::select((a + b).cmpeq(Vec4::ZERO), Vec4::ZERO, a / (a + b))
}

/// Veach's power heuristic with exponent 2, for one sample from each strategy.
fn power_heuristic(pdf: f32, other: f32) -> f32 {
    let (a, b) = (pdf * pdf, other * other);
    if a + b == 0.0 { 0.0 } else { a / (a + b) }
}
