//! The course's Lab 4 integrator: emission seen directly, direct light at surfaces with lobes
//! that have a density (diffuse, glossy) with shadow rays (from point lights, area lights and
//! the background), delta lobes (perfect mirrors and refraction) followed Whitted-style; no
//! indirect light otherwise.

use glam::{BVec4A, Vec3, Vec4};

use super::{
    IDLE, Integrator, LanePath, LanePaths, Shadowed, direct_from_all_lights, direct_from_light,
    fill_lanes,
};
use crate::accel::{Nearest, RayLanes};
use crate::geometry::{Hit, LANES, Lane, Ray, Vec2x4, Vec3x4, offset_origin};
use crate::light::sample_lanes;
use crate::material::{Bsdf, LobeFlags, TransportMode, eval_diffuse_lanes};
use crate::sampling::Sampler;
use crate::scene::Scene;

pub struct Direct {
    /// Longest path in bounces (scattering events); 0 shows only what the camera sees emit.
    pub max_depth: u32,
}

/// Light of the background (an environment of constant radiance L all around) reflected towards
/// `wo` by the non-delta lobes: one direction sampled from them with a shadow ray to infinity,
/// whose estimate is f L cos / pdf (kd L for a diffuse lobe) where the sky is seen. A black
/// background draws no sample, so the course's Lab 4 scenes render as they always have.
pub(super) fn direct_from_background(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    sampler: &mut Sampler,
) -> Vec3 {
    let background = scene.background();
    if background == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let u_lobe = sampler.next_1d_if(bsdf.flags().contains(LobeFlags::GLOSSY));
    let Some(sample) = bsdf.sample_non_delta(wo, u_lobe, sampler.next_2d()) else {
        return Vec3::ZERO;
    };
    let ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
    if scene.occluded(&ray, f32::INFINITY) { Vec3::ZERO } else { sample.weight * background }
}

impl Integrator for Direct {
    /// The reference estimator: one path at a time (`whitted`). `radiance_of_all` must give
    /// each path exactly this radiance.
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        whitted(scene, ray, sampler, self.max_depth, None)
    }

    /// Traces `LANES` paths at a time, bounce by bounce, as `Path::radiance_of_all` does: their
    /// rays meet the scene together, and so do the shadow rays towards each light in turn,
    /// with point and planar lights sampled and Lambertian lobes evaluated side by side. Each
    /// path draws its sample values in the order `whitted` draws them and adds up the same
    /// terms in the same order, so it gets the same radiance, bit for bit.
    fn radiance_of_all(
        &self,
        scene: &Scene,
        samples: &mut dyn Iterator<Item = (Ray, Sampler)>,
        radiance: &mut [Vec3],
    ) {
        let mut samples = samples.enumerate();
        let mut lanes = WhittedLanes::new();
        let mut vertices = Vertices::new(scene.lights.len());
        while let Some(active) = fill_lanes(&mut lanes, &mut samples) {
            let found = scene.intersect_lanes(&lanes.rays, active);
            let wo = -lanes.rays.dir;
            vertices.clear();
            for lane in (0..LANES).filter(|&lane| active[lane]) {
                self.arrive(scene, &mut lanes, lane, &found, &mut vertices);
            }
            let arrived = BVec4A::from_array(active);
            lanes.radiance = Vec3x4::select(
                arrived,
                lanes.radiance + lanes.beta * vertices.emitted,
                lanes.radiance,
            );
            let lit = direct_from_all_lights_lanes(scene, &vertices, &found, wo);
            let non_delta = vertices.non_delta;
            lanes.radiance =
                Vec3x4::select(non_delta, lanes.radiance + lanes.beta * lit, lanes.radiance);
            lanes.radiance = Vec3x4::select(
                non_delta,
                lanes.radiance + lanes.beta * vertices.from_background,
                lanes.radiance,
            );
            lanes.beta = lanes.beta * vertices.delta_weight;
            lanes.rays = vertices.next_rays;
            for lane in (0..LANES).filter(|&lane| active[lane] && !vertices.goes_on[lane]) {
                if let Some(path) = lanes.paths[lane].take() {
                    radiance[path.slot] = lanes.radiance.lane(lane);
                }
            }
        }
    }
}

impl Direct {
    /// The path in `lane` arrives where its ray meets the scene (`found`), or leaves it: it
    /// finds the emission there, draws its sample values for the vertex in `whitted`'s order,
    /// gathers light from the background and follows a delta lobe one path at a time (both
    /// rare), and leaves in `vertices` what next-event estimation in lanes reads.
    fn arrive(
        &self,
        scene: &Scene,
        lanes: &mut WhittedLanes,
        lane: usize,
        found: &Nearest,
        vertices: &mut Vertices,
    ) {
        let Some(primitive) = found.names[lane] else {
            vertices.emitted.set_lane(lane, scene.background());
            return;
        };
        // The hit's fields are read from their lanes; a whole `Hit` is made only where the rare
        // cases need one (see `Path::arrive`).
        let (hits, wo) = (&found.hits, -lanes.rays.dir.lane(lane));
        let hit = || hits.lane(lane, primitive, found.t.lane(lane));
        let material = scene.material(primitive, hits.point.lane(lane));
        vertices.emitted.set_lane(lane, material.emitted(hits.normal.lane(lane), wo));
        let Some(path) = lanes.paths[lane].as_mut() else { return };
        if path.bounces == self.max_depth {
            return;
        }
        let sampler = &mut path.sampler;
        let bsdf = material.bsdf(hits.shading_normal.lane(lane), TransportMode::Radiance);
        let flags = bsdf.flags();
        if flags.is_non_delta() {
            for u in &mut vertices.u_lights {
                u.set_lane(lane, sampler.next_2d());
            }
            if scene.background() != Vec3::ZERO {
                let background = direct_from_background(scene, &hit(), wo, &bsdf, sampler);
                vertices.from_background.set_lane(lane, background);
            }
            vertices.non_delta.set_lane(lane, true);
            vertices.primitives[lane] = primitive;
            vertices.diffuse.set_lane(lane, material.diffuse);
            vertices.diffuse_where_non_delta[lane] = flags.is_diffuse_where_non_delta();
        }
        if !flags.is_delta() {
            return;
        }
        let Some(sample) = bsdf.sample_delta(wo, sampler.next_1d()) else { return };
        path.bounces += 1;
        vertices.goes_on[lane] = true;
        vertices.delta_weight.set_lane(lane, sample.weight);
        vertices.next_rays.set_lane(lane, &Ray::new(offset_origin(&hit(), sample.wi), sample.wi));
    }
}

/// `whitted`'s paths traced side by side, one per lane.
struct WhittedLanes {
    paths: [Option<LanePath>; LANES],
    /// Each path's next ray.
    rays: RayLanes,
    /// Radiance gathered so far.
    radiance: Vec3x4,
    /// Throughput: the product of the delta lobes' weights so far.
    beta: Vec3x4,
}

impl WhittedLanes {
    fn new() -> Self {
        WhittedLanes {
            paths: Default::default(),
            rays: RayLanes::new(&[IDLE; LANES]),
            radiance: Vec3x4::ZERO,
            beta: Vec3x4::ZERO,
        }
    }
}

impl LanePaths for WhittedLanes {
    fn is_free(&self, lane: usize) -> bool {
        self.paths[lane].is_none()
    }

    fn start(&mut self, lane: usize, slot: usize, ray: &Ray, sampler: Sampler) {
        self.paths[lane] = Some(LanePath { slot, sampler, bounces: 0 });
        self.rays.set_lane(lane, ray);
        self.radiance.set_lane(lane, Vec3::ZERO);
        self.beta.set_lane(lane, Vec3::ONE);
    }
}

/// What the paths found where they arrived this bounce, in lanes: what `whitted` adds there
/// and where it goes on.
struct Vertices {
    /// Emission seen (or the background, where the ray left the scene).
    emitted: Vec3x4,
    /// Lanes whose vertex has lobes with a density (next-event estimation there), their
    /// primitives, diffuse reflectance, whether those lobes are Lambertian alone, and the
    /// light from the background they reflect.
    non_delta: BVec4A,
    primitives: [u32; LANES],
    diffuse: Vec3x4,
    diffuse_where_non_delta: [bool; LANES],
    from_background: Vec3x4,
    /// Per light, each lane's point of the unit square that samples it.
    u_lights: Vec<Vec2x4>,
    /// Paths that follow a delta lobe, its weight (1 elsewhere) and their next rays.
    goes_on: [bool; LANES],
    delta_weight: Vec3x4,
    next_rays: RayLanes,
}

impl Vertices {
    fn new(lights: usize) -> Self {
        Vertices {
            emitted: Vec3x4::ZERO,
            non_delta: BVec4A::FALSE,
            primitives: [u32::MAX; LANES],
            diffuse: Vec3x4::ZERO,
            diffuse_where_non_delta: [false; LANES],
            from_background: Vec3x4::ZERO,
            u_lights: vec![Vec2x4::ZERO; lights],
            goes_on: [false; LANES],
            delta_weight: Vec3x4::splat(Vec3::ONE),
            next_rays: RayLanes::new(&[IDLE; LANES]),
        }
    }

    /// Ready for the next bounce (the lights' sample values are all drawn anew).
    fn clear(&mut self) {
        let u_lights = std::mem::take(&mut self.u_lights);
        *self = Vertices { u_lights, ..Vertices::new(0) };
    }
}

/// `direct_from_all_lights` at the lanes' vertices with lobes of a density: one sample of every
/// light, in order, their shadow rays traced together. Point and planar lights seen from
/// Lambertian lobes are sampled in lanes; other lights, and every light from other lobes, one
/// vertex at a time.
fn direct_from_all_lights_lanes(
    scene: &Scene,
    vertices: &Vertices,
    found: &Nearest,
    wo: Vec3x4,
) -> Vec3x4 {
    let (hits, n) = (&found.hits, found.hits.shading_normal);
    let mut radiance = Vec3x4::ZERO;
    for (light, &u) in vertices.u_lights.iter().enumerate() {
        let non_delta = |lane: usize| vertices.non_delta.lane(lane);
        let in_lanes = std::array::from_fn(|lane| {
            (non_delta(lane) && vertices.diffuse_where_non_delta[lane]).then_some(light)
        });
        let mut shadowed = Shadowed {
            found: BVec4A::FALSE,
            rays: RayLanes::new(&[IDLE; LANES]),
            t_max: Vec4::ZERO,
            radiance: Vec3x4::ZERO,
        };
        let sampled = sample_lanes(scene, hits, vertices.primitives, in_lanes, u);
        if let Some(sampled) = sampled.as_ref().filter(|s| s.found.any()) {
            let no_pdf = Vec4::ZERO; // only f is read
            let (f, _) = eval_diffuse_lanes(n, wo, sampled.wi, vertices.diffuse, no_pdf);
            shadowed = Shadowed {
                found: sampled.found & !f.is_zero(),
                rays: RayLanes { origin: sampled.shadow_origin, dir: sampled.shadow_dir },
                t_max: sampled.shadow_t_max,
                radiance: f * sampled.li * n.dot(sampled.wi).abs() / sampled.pdf,
            };
        }
        let handled = sampled.map_or(BVec4A::FALSE, |s| s.handled);
        for lane in (0..LANES).filter(|&lane| non_delta(lane) && !handled.lane(lane)) {
            let Some(hit) = found.hit(lane) else { continue };
            let material = scene.material(hit.primitive, hit.point);
            let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
            let (light, u) = (&scene.lights[light], u.lane(lane));
            let Some((shadow, reflected)) = direct_from_light(light, &hit, wo.lane(lane), &bsdf, u)
            else {
                continue;
            };
            shadowed.found.set_lane(lane, true);
            shadowed.rays.set_lane(lane, &shadow.ray);
            shadowed.t_max.set_lane(lane, shadow.t_max);
            shadowed.radiance.set_lane(lane, reflected);
        }
        if shadowed.found.any() {
            let t_max = Vec4::select(shadowed.found, shadowed.t_max, Vec4::ZERO);
            let open = shadowed.found & !scene.occluded_lanes(&shadowed.rays, t_max);
            radiance = Vec3x4::select(open, radiance + shadowed.radiance, radiance);
        }
    }
    radiance
}

/// Light from other surfaces scattered towards `wo` by `bsdf` at a hit, from some estimator
/// (a photon map's).
pub(super) type Indirect<'a> = dyn Fn(&Hit, Vec3, &Bsdf) -> Vec3 + 'a;

/// `Direct`'s estimate along `ray`, plus any `indirect(hit, wo, bsdf)` (light from other surfaces)
/// at each vertex with a non-delta lobe: emission seen on the way, next-event estimation at
/// those vertices, delta lobes followed, for at most `max_depth` bounces.
pub(super) fn whitted(
    scene: &Scene,
    mut ray: Ray,
    sampler: &mut Sampler,
    max_depth: u32,
    indirect: Option<&Indirect>,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    // Path throughput: the product of specular weights so far.
    let mut beta = Vec3::ONE;
    for bounces in 0.. {
        let Some(hit) = scene.intersect(&ray) else {
            radiance += beta * scene.background();
            break;
        };
        let wo = -Vec3::from(ray.dir);
        let material = scene.material(hit.primitive, hit.point);
        radiance += beta * material.emitted(hit.normal, wo);
        if bounces == max_depth {
            break;
        }
        let bsdf = material.bsdf(hit.shading_normal, TransportMode::Radiance);
        let flags = bsdf.flags();
        if flags.is_non_delta() {
            radiance += beta * direct_from_all_lights(scene, &hit, wo, &bsdf, sampler);
            radiance += beta * direct_from_background(scene, &hit, wo, &bsdf, sampler);
            if let Some(indirect) = indirect {
                radiance += beta * indirect(&hit, wo, &bsdf);
            }
        }
        // With both mirror and refraction one of them is followed, chosen at random with
        // its weight divided by its probability: one ray, no branching, no bias.
        if !flags.is_delta() {
            break;
        }
        let Some(sample) = bsdf.sample_delta(wo, sampler.next_1d()) else {
            break;
        };
        beta *= sample.weight;
        ray = Ray::new(offset_origin(&hit, sample.wi), sample.wi);
    }
    radiance
}
