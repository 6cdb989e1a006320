//! Unidirectional path tracing of the full rendering equation: a loop over bounces with
//! next-event estimation towards one light chosen by power, BSDF sampling, multiple importance
//! sampling of the two (power heuristic, Veach 1997), and Russian roulette.

use glam::{BVec4A, Vec2, Vec3, Vec4};

use super::{IDLE, Integrator, LanePath, LanePaths, Shadowed, fill_lanes};
use crate::accel::{Nearest, RayLanes};
use crate::geometry::{Hit, HitLanes, LANES, Lane, Ray, Vec2x4, Vec3x4, offset_origin};
use crate::light::{ShadowRay, sample_lanes};
use crate::material::{
    Bsdf, BsdfSampleLanes, LobeFlags, TransportMode, eval_diffuse_lanes, sample_lambertian_lanes,
};
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

impl Integrator for Path {
    /// The reference estimator: one path, one vertex at a time, through the scalar BSDFs and
    /// lights. `radiance_of_all` must give each path exactly this radiance.
    fn radiance(&self, scene: &Scene, mut ray: Ray, sampler: &mut Sampler) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let mut eta_scale = 1.0f32;
        // Where the last direction was sampled from a non-delta lobe, that vertex's point and
        // the direction's solid-angle pdf (for MIS where the path meets an emitter).
        let mut previous: Option<(Vec3, f32)> = None;
        for bounces in 0.. {
            let Some(hit) = scene.intersect(&ray) else {
                radiance += beta * scene.background();
                break;
            };
            let wo = -Vec3::from(ray.dir);
            let material = scene.material(hit.primitive, hit.point);
            let emitted = material.emitted(hit.normal, wo);
            if emitted != Vec3::ZERO {
                radiance += beta * emitted * self.emission_weight(scene, &hit, previous);
            }
            if bounces == self.max_depth {
                break;
            }
            let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
            let flags = bsdf.flags();
            let light = if flags.is_non_delta() { self.choose_light(scene, sampler) } else { None };
            let u_lobe = sampler.next_1d_if(flags.chooses_lobe());
            let u = sampler.next_2d();
            let shadowed = light.and_then(|(light, probability, u_light)| {
                let (shadow, li) =
                    self.next_event(scene, &hit, wo, &bsdf, (light, probability), u_light)?;
                Some((shadow, beta * li))
            });
            let sample = bsdf.sample(wo, u_lobe, u, LobeFlags::ALL);
            let continues = sample.is_some_and(|sample| {
                beta *= sample.weight;
                eta_scale *= sample.eta * sample.eta;
                previous = (!sample.is_delta()).then_some((hit.point, sample.pdf));
                ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
                let roulette = bounces + 1 >= ROULETTE_AFTER;
                let survive = (beta * eta_scale).max_element().min(1.0);
                let u = sampler.next_1d_if(roulette);
                if roulette && u >= survive {
                    return false;
                }
                if roulette {
                    beta /= survive;
                }
                true
            });
            if let Some((shadow, li)) = shadowed
                && !scene.occluded(&shadow.ray, shadow.t_max)
            {
                radiance += li;
            }
            if !continues {
                break;
            }
        }
        radiance
    }

    /// Traces `LANES` paths at a time, bounce by bounce, so that their rays and their shadow
    /// rays meet the scene together (`Scene::intersect_lanes`), and light and BSDF samples of
    /// the common kinds (point and planar lights, Lambertian lobes) and the throughput are
    /// computed side by side; a finished path's lane takes the next camera sample. Each path
    /// draws its sample values in the order `radiance` draws them and computes what it computes
    /// with the same operations, so it gets the same radiance, bit for bit.
    fn radiance_of_all(
        &self,
        scene: &Scene,
        samples: &mut dyn Iterator<Item = (Ray, Sampler)>,
        radiance: &mut [Vec3],
    ) {
        let mut samples = samples.enumerate();
        let mut lanes = PathLanes::new();
        while let Some(active) = fill_lanes(&mut lanes, &mut samples) {
            let found = scene.intersect_lanes(&lanes.rays, active);
            let mut vertices = Vertices::new();
            let mut emission = Emission::default();
            for lane in (0..LANES).filter(|&lane| active[lane]) {
                self.arrive(scene, &mut lanes, lane, &found, &mut emission, &mut vertices);
            }
            lanes.radiance = Vec3x4::select(
                emission.found,
                lanes.radiance + lanes.beta * emission.radiance * emission.weight,
                lanes.radiance,
            );
            // Lanes whose path ended on arrival hold values no one reads.
            let wo = -lanes.rays.dir;
            let shadowed = self.next_event_lanes(scene, &lanes, &vertices, &found, wo);
            let bsdf_samples = sample_bsdf_lanes(scene, &vertices, &found, wo);
            let done = lanes.leave(&found.hits, &bsdf_samples);
            if shadowed.found.any() {
                let t_max = Vec4::select(shadowed.found, shadowed.t_max, Vec4::ZERO);
                let open = !scene.occluded_lanes(&shadowed.rays, t_max);
                lanes.radiance = Vec3x4::select(
                    shadowed.found & open,
                    lanes.radiance + shadowed.radiance,
                    lanes.radiance,
                );
            }
            for lane in (0..LANES).filter(|&lane| done[lane]) {
                if let Some(path) = lanes.paths[lane].take() {
                    radiance[path.slot] = lanes.radiance.lane(lane);
                }
            }
        }
    }
}

/// Paths traced side by side, one per lane: what every bounce updates, coordinate by
/// coordinate, and per lane what only the path's own choices read.
struct PathLanes {
    paths: [Option<LanePath>; LANES],
    /// Each path's next ray.
    rays: RayLanes,
    /// Radiance gathered so far.
    radiance: Vec3x4,
    /// Throughput: the product of the BSDF weights along the path.
    beta: Vec3x4,
    /// Product of eta^2 over refractions: undoes their radiance scaling for Russian roulette,
    /// so paths through glass are not cut for a throughput drop that the exit restores.
    eta_scale: Vec4,
    /// Lanes whose last direction was sampled from a non-delta lobe, where a light sample
    /// could have found the path too (not the camera's), and there that vertex's point and
    /// the direction's solid-angle pdf.
    from_non_delta: BVec4A,
    previous_point: Vec3x4,
    previous_pdf: Vec4,
}

impl PathLanes {
    fn new() -> Self {
        PathLanes {
            paths: Default::default(),
            rays: RayLanes::new(&[IDLE; LANES]),
            radiance: Vec3x4::ZERO,
            beta: Vec3x4::ZERO,
            eta_scale: Vec4::ONE,
            from_non_delta: BVec4A::FALSE,
            previous_point: Vec3x4::ZERO,
            previous_pdf: Vec4::ZERO,
        }
    }

    /// Takes each path on along its BSDF sample, or ends it (no sample, or Russian roulette);
    /// returns the lanes whose path ends. (An ending path's lane keeps values that no one reads:
    /// `start` sets them anew.)
    fn leave(&mut self, hits: &HitLanes, samples: &BsdfSampleLanes) -> [bool; LANES] {
        self.beta = self.beta * samples.weight;
        self.eta_scale *= samples.eta * samples.eta;
        self.from_non_delta = !samples.delta;
        self.previous_point = hits.point;
        self.previous_pdf = samples.pdf;
        self.rays = RayLanes { origin: hits.offset_origin(samples.wi), dir: samples.wi };
        // Russian roulette: continue with probability tied to the throughput and divide by
        // it, so the estimate stays unbiased.
        let survive = (self.beta * self.eta_scale).max_element().min(Vec4::ONE);
        let mut divide = BVec4A::FALSE;
        let mut done = [false; LANES];
        for (lane, path) in self.paths.iter_mut().enumerate() {
            let Some(path) = path else { continue };
            if !samples.found.lane(lane) {
                done[lane] = true;
                continue;
            }
            let roulette = path.bounces + 1 >= ROULETTE_AFTER;
            let u = path.sampler.next_1d_if(roulette);
            if roulette && u >= survive.lane(lane) {
                done[lane] = true;
                continue;
            }
            divide.set_lane(lane, roulette);
            path.bounces += 1;
        }
        self.beta = Vec3x4::select(divide, self.beta / survive, self.beta);
        done
    }
}

impl LanePaths for PathLanes {
    fn is_free(&self, lane: usize) -> bool {
        self.paths[lane].is_none()
    }

    fn start(&mut self, lane: usize, slot: usize, ray: &Ray, sampler: Sampler) {
        self.paths[lane] = Some(LanePath { slot, sampler, bounces: 0 });
        self.rays.set_lane(lane, ray);
        self.radiance.set_lane(lane, Vec3::ZERO);
        self.beta.set_lane(lane, Vec3::ONE);
        self.eta_scale.set_lane(lane, 1.0);
        self.from_non_delta.set_lane(lane, false);
    }
}

/// Where the paths scatter this bounce, in the lanes of `found`, and the sample values for
/// their choices there: what sampling in lanes reads, so it gathers nothing. (What is sampled one
/// vertex at a time, BSDFs other than Lambertian and lights other than point and planar ones,
/// looks the material up again: keeping it here costs more.)
struct Vertices {
    found: BVec4A,
    /// The primitive hit (`u32::MAX` where there is no vertex).
    primitives: [u32; LANES],
    /// The BSDF's diffuse reflectance there; lanes whose BSDF is Lambertian alone (sampled in
    /// lanes), and lanes with a light whose non-delta lobes are Lambertian alone (evaluated in
    /// lanes).
    diffuse: Vec3x4,
    lambertian: BVec4A,
    diffuse_where_non_delta: [bool; LANES],
    /// For next-event estimation: the light chosen (`None`: none), the probability of that
    /// choice, the point of the unit square that samples it, and the probability of the
    /// diffuse lobe.
    lights: [Option<usize>; LANES],
    light_probability: Vec4,
    u_light: Vec2x4,
    p_diffuse: Vec4,
    u_lobe: [f32; LANES],
    u_direction: Vec2x4,
}

impl Vertices {
    fn new() -> Self {
        Vertices {
            found: BVec4A::FALSE,
            primitives: [u32::MAX; LANES],
            diffuse: Vec3x4::ZERO,
            lambertian: BVec4A::FALSE,
            diffuse_where_non_delta: [false; LANES],
            lights: [None; LANES],
            light_probability: Vec4::ONE,
            u_light: Vec2x4::ZERO,
            p_diffuse: Vec4::ZERO,
            u_lobe: [0.0; LANES],
            u_direction: Vec2x4::ZERO,
        }
    }
}

/// Emitted radiance the paths found where they arrived, in the lanes of `found`, to be
/// weighted by `weight` (multiple importance sampling) and the throughput.
#[derive(Default)]
struct Emission {
    found: BVec4A,
    radiance: Vec3x4,
    weight: Vec4,
}

impl Path {
    /// The path in `lane` arrives where its ray meets the scene (`found`), or leaves it, and
    /// finds the emission there; sets where it scatters next in `vertices`, unless it ends
    /// here. It reads the hit record's fields from their lanes: a whole `Hit` made here would
    /// be read back before its stores could be forwarded.
    fn arrive(
        &self,
        scene: &Scene,
        lanes: &mut PathLanes,
        lane: usize,
        found: &Nearest,
        emission: &mut Emission,
        vertices: &mut Vertices,
    ) {
        let Some(primitive) = found.names[lane] else {
            emission.found.set_lane(lane, true);
            emission.radiance.set_lane(lane, scene.background());
            emission.weight.set_lane(lane, 1.0);
            return;
        };
        let (hits, wo) = (&found.hits, -lanes.rays.dir.lane(lane));
        let material = scene.material(primitive, hits.point.lane(lane));
        let emitted = material.emitted(hits.normal.lane(lane), wo);
        if emitted != Vec3::ZERO {
            let hit = hits.lane(lane, primitive, found.t.lane(lane));
            let previous = lanes
                .from_non_delta
                .lane(lane)
                .then(|| (lanes.previous_point.lane(lane), lanes.previous_pdf.lane(lane)));
            emission.found.set_lane(lane, true);
            emission.radiance.set_lane(lane, emitted);
            emission.weight.set_lane(lane, self.emission_weight(scene, &hit, previous));
        }
        let Some(path) = lanes.paths[lane].as_mut() else { return };
        if path.bounces == self.max_depth {
            return;
        }
        let sampler = &mut path.sampler;
        let bsdf = material.bsdf(hits.shading_normal.lane(lane), TransportMode::Radiance);
        let flags = bsdf.flags();
        let light = if flags.is_non_delta() { self.choose_light(scene, sampler) } else { None };
        vertices.u_lobe[lane] = sampler.next_1d_if(flags.chooses_lobe());
        vertices.u_direction.set_lane(lane, sampler.next_2d());
        vertices.found.set_lane(lane, true);
        vertices.primitives[lane] = primitive;
        vertices.diffuse.set_lane(lane, material.diffuse);
        if let Some((light, probability, u)) = light {
            vertices.lights[lane] = Some(light);
            vertices.light_probability.set_lane(lane, probability);
            vertices.u_light.set_lane(lane, u);
            if flags.is_diffuse_where_non_delta() {
                vertices.p_diffuse.set_lane(lane, bsdf.diffuse_probability(wo));
                vertices.diffuse_where_non_delta[lane] = true;
            }
        }
        vertices.lambertian.set_lane(lane, flags.is_lambertian());
    }

    /// The weight of emission found by a BSDF-sampled ray.
    fn emission_weight(&self, scene: &Scene, hit: &Hit, previous: Option<(Vec3, f32)>) -> f32 {
        let Some((from, bsdf_pdf)) = previous else {
            return 1.0; // seen by the camera or through delta bounces
        };
        let Some(light) = scene.primitives[hit.primitive as usize].light else {
            return 1.0; // no light sample can find this emitter
        };
        match self.strategy {
            Strategy::BsdfSampling => 1.0,
            Strategy::LightSampling => 0.0,
            Strategy::Mis => {
                let light_pdf = scene.light_probability(light as usize)
                    * scene.lights[light as usize].pdf(from, hit);
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
    /// planar area lights seen from Lambertian lobes are sampled in lanes; other lights, and
    /// every light from other non-delta lobes, one vertex at a time.
    fn next_event_lanes(
        &self,
        scene: &Scene,
        lanes: &PathLanes,
        vertices: &Vertices,
        found: &Nearest,
        wo: Vec3x4,
    ) -> Shadowed {
        let (hits, lights) = (&found.hits, vertices.lights);
        let in_lanes = std::array::from_fn(|lane| {
            lights[lane].filter(|_| vertices.diffuse_where_non_delta[lane])
        });
        let sampled = sample_lanes(scene, hits, vertices.primitives, in_lanes, vertices.u_light);
        // Lanes without a shadow ray keep whatever ray: `found` leaves them untested.
        let mut shadowed = Shadowed {
            found: BVec4A::FALSE,
            rays: lanes.rays,
            t_max: Vec4::ZERO,
            radiance: Vec3x4::ZERO,
        };
        if let Some(sampled) = sampled.as_ref().filter(|s| s.found.any()) {
            let n = hits.shading_normal;
            let (f, bsdf_pdf) =
                eval_diffuse_lanes(n, wo, sampled.wi, vertices.diffuse, vertices.p_diffuse);
            let light_pdf = vertices.light_probability * sampled.pdf;
            let weight = match self.strategy {
                Strategy::LightSampling => Vec4::ONE,
                _ => Vec4::select(
                    sampled.is_delta,
                    Vec4::ONE,
                    power_heuristic_lanes(light_pdf, bsdf_pdf),
                ),
            };
            let radiance = f * sampled.li * n.dot(sampled.wi).abs() * weight / light_pdf;
            shadowed = Shadowed {
                found: sampled.found & !f.is_zero(),
                rays: RayLanes { origin: sampled.shadow_origin, dir: sampled.shadow_dir },
                t_max: sampled.shadow_t_max,
                radiance: lanes.beta * radiance,
            };
        }
        let handled = sampled.map_or(BVec4A::FALSE, |s| s.handled);
        for lane in (0..LANES).filter(|&lane| !handled.lane(lane)) {
            let Some(light) = lights[lane] else { continue };
            let Some(hit) = found.hit(lane) else { continue };
            let material = scene.material(hit.primitive, hit.point);
            let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
            let light = (light, vertices.light_probability.lane(lane));
            let u = vertices.u_light.lane(lane);
            if let Some((shadow, radiance)) =
                self.next_event(scene, &hit, wo.lane(lane), &bsdf, light, u)
            {
                shadowed.found.set_lane(lane, true);
                shadowed.rays.set_lane(lane, &shadow.ray);
                shadowed.t_max.set_lane(lane, shadow.t_max);
                shadowed.radiance.set_lane(lane, lanes.beta.lane(lane) * radiance);
            }
        }
        shadowed
    }

    /// Light from `light`, chosen with `probability`, scattered by `bsdf` at one vertex,
    /// weighted against BSDF sampling, if its shadow ray is unoccluded.
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
        let f = bsdf.eval(wo, sample.wi);
        if f == Vec3::ZERO {
            return None;
        }
        let light_pdf = probability * sample.pdf;
        let weight = if sample.is_delta || self.strategy == Strategy::LightSampling {
            1.0
        } else {
            power_heuristic(light_pdf, bsdf.pdf(wo, sample.wi, LobeFlags::ALL))
        };
        let radiance = f * sample.li * hit.shading_normal.dot(sample.wi).abs() * weight / light_pdf;
        Some((sample.shadow, radiance))
    }
}

/// Directions from the BSDFs at the lanes' vertices: Lambertian ones in lanes, the others one
/// vertex at a time.
fn sample_bsdf_lanes(
    scene: &Scene,
    vertices: &Vertices,
    found: &Nearest,
    wo: Vec3x4,
) -> BsdfSampleLanes {
    let (lambertian, n) = (vertices.lambertian, found.hits.shading_normal);
    let mut samples =
        sample_lambertian_lanes(lambertian, vertices.diffuse, n, wo, vertices.u_direction);
    for lane in (0..LANES).filter(|&lane| (vertices.found & !lambertian).lane(lane)) {
        let material = scene.material(vertices.primitives[lane], found.hits.point.lane(lane));
        let bsdf = material.bsdf(n.lane(lane), TransportMode::Radiance);
        let (u_lobe, u) = (vertices.u_lobe[lane], vertices.u_direction.lane(lane));
        let sample = bsdf.sample(wo.lane(lane), u_lobe, u, LobeFlags::ALL);
        samples.set_lane(lane, sample);
    }
    samples
}

/// `power_heuristic` in four lanes, with the same operations.
fn power_heuristic_lanes(pdf: Vec4, other: Vec4) -> Vec4 {
    let ratio = other / pdf;
    let weight = Vec4::ONE / (Vec4::ONE + ratio * ratio);
    let weight = Vec4::select(ratio.is_nan_mask(), Vec4::splat(0.5), weight);
    Vec4::select(pdf.cmpeq(Vec4::ZERO), Vec4::ZERO, weight)
}

/// Veach's power heuristic with exponent 2, for one sample from each strategy:
/// pdf² / (pdf² + other²), written as 1 / (1 + (other / pdf)²) because the squares overflow
/// where a pdf is huge (an area light seen edge-on from far away: a solid-angle pdf of 1e20),
/// and inf / inf is NaN. Both infinite: an even split.
fn power_heuristic(pdf: f32, other: f32) -> f32 {
    if pdf == 0.0 {
        return 0.0;
    }
    let ratio = other / pdf;
    if ratio.is_nan() { 0.5 } else { 1.0 / (1.0 + ratio * ratio) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The NaN of depth of field (a floor ray at a grazing angle sampling an area light 10^7
    /// units away: a light pdf near 1e20, squared to inf): every weight is a number in [0, 1],
    /// the two strategies' weights add up to 1, and the lanes give the same bits.
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
                let lanes = power_heuristic_lanes(Vec4::splat(a), Vec4::splat(b));
                assert_eq!(lanes.x.to_bits(), w.to_bits(), "lanes at ({a}, {b})");
            }
        }
    }
}
