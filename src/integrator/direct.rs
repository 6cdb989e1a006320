//! The course's Lab 4 integrator: emission seen directly, direct light at surfaces with lobes
//! that have a density (diffuse, glossy) with shadow rays (from point lights, area lights and
//! the environment, by both its sample and the BSDF's), delta lobes (perfect mirrors and
//! refraction) followed Whitted-style; no indirect light otherwise.

use glam::Vec3;

use super::{
    CameraSample, Lanes, SampleIntegrator, ShadowLanes, direct_from_light, power_heuristic,
};
use crate::geometry::{Hit, Ray, offset_origin};
use crate::lanes::LANES;
use crate::light::{Light, ShadowRay};
use crate::material::{Bsdf, LobeFlags, NO_DIRECTION, TransportMode};
use crate::sampling::Sampler;
use crate::scene::Scene;

pub struct Direct {
    /// Longest path in bounces (scattering events); 0 shows only what the camera sees emit.
    pub max_depth: u32,
}

/// Light of the environment reflected towards `wo` by the lobes with a density that `mask` asks
/// for, found by one direction sampled from them with a shadow ray to infinity: f L cos / pdf
/// where the sky is seen, weighted against the environment's own sample (`direct_from_light`)
/// by the power heuristic. A scene without an environment draws no sample, so the course's Lab
/// 4 scenes render as they always have. Always inlined: most scenes have no environment, and
/// out of line the call costs more than finding that out.
#[inline(always)]
pub(super) fn direct_from_environment(
    scene: &Scene,
    hit: &Hit,
    wo: Vec3,
    bsdf: &Bsdf,
    mask: LobeFlags,
    sampler: &mut Sampler,
) -> Vec3 {
    let Some((_, sky)) = scene.environment() else {
        return Vec3::ZERO;
    };
    let u_lobe = sampler.next_1d_if(bsdf.flags().contains(LobeFlags::GLOSSY));
    let Some(sample) = bsdf.sample(wo, u_lobe, sampler.next_2d(), mask & LobeFlags::NON_DELTA)
    else {
        return Vec3::ZERO;
    };
    let ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
    let reached = scene.transmittance(&ray, f32::INFINITY);
    reached * sample.weight * sky.le(sample.wi) * power_heuristic(sample.pdf, sky.pdf(sample.wi))
}

impl SampleIntegrator for Direct {
    /// One path at a time (`whitted`).
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3 {
        whitted(scene, ray, sampler, self.max_depth, None)
    }

    /// Traces `LANES` paths at a time, bounce by bounce: their rays meet the scene together,
    /// and so do the shadow rays towards each light in turn. Each path's vertex is `arrive`,
    /// a sample of each light (`light_sample`) and `leave`, as in `whitted`, with the lights' contributions added in
    /// the same order, so it gets the same radiance, bit for bit.
    fn radiance_of_all(&self, scene: &Scene, samples: &[CameraSample], radiance: &mut [Vec3]) {
        let samples = &mut samples.iter();
        let mut lanes: Lanes<WhittedPath> = Lanes::new(WhittedPath::new);
        // Each lane's vertex, made in place by each bounce (`arrive_in`) where its path
        // `scatters`.
        let mut vertices = [Vertex::UNSET; LANES];
        let mut scatters = [false; LANES];
        while let Some(active) = lanes.fill(samples, WhittedPath::new) {
            let found = scene.intersect_lanes(&lanes.rays(|path| path.ray), active);
            let hits = found.hits();
            for (lane, path) in lanes.paths_mut() {
                let hit = hits[lane];
                let vertex = &mut vertices[lane];
                scatters[lane] = arrive_in(scene, &mut path.state, hit, self.max_depth, vertex);
            }
            // Each light in turn, sampled at every lit vertex: a lane's sampler draws for the
            // lights in their order, as in `light_samples`.
            let mut lit = [Vec3::ZERO; LANES];
            for light in &scene.lights {
                let mut shadows = ShadowLanes::new();
                for (lane, path) in lanes.paths_mut() {
                    let vertex = &vertices[lane];
                    if !(scatters[lane] && vertex.is_lit()) {
                        continue;
                    }
                    let sampler = &mut path.sampler;
                    if let Some(shadowed) = light_sample(light, vertex, LobeFlags::ALL, sampler) {
                        shadows.set_lane(lane, shadowed);
                    }
                }
                for (lane, reached) in shadows.reached(scene).into_iter().enumerate() {
                    lit[lane] += reached;
                }
            }
            for (lane, lit) in lit.into_iter().enumerate() {
                let Some(path) = lanes.path_mut(lane) else { continue };
                let (vertex, sampler) = (&vertices[lane], &mut path.sampler);
                let continues =
                    scatters[lane] && leave(scene, &mut path.state, vertex, lit, sampler, None);
                if !continues && let Some(path) = lanes.end(lane) {
                    radiance[path.slot] = path.state.radiance;
                }
            }
        }
    }
}

/// A path of `whitted` (or of sppm's camera pass) between bounces.
pub(super) struct WhittedPath {
    /// Whether it follows near-specular lobes as it does delta lobes, and gathers only at the
    /// others (photon mapping's glossy rule, `Bsdf::gathered_lobes`).
    follows_near_specular: bool,
    /// Its next ray.
    pub ray: Ray,
    /// Radiance gathered so far.
    pub radiance: Vec3,
    /// Throughput: the product of the followed lobes' weights so far.
    pub beta: Vec3,
    /// Where the last followed direction was sampled from a near-specular lobe, that vertex's
    /// point and the direction's density: light the ray finds is weighted against that
    /// vertex's light samples (`found_weight`).
    previous: Option<(Vec3, f32)>,
    bounces: u32,
}

impl WhittedPath {
    /// A path of `direct`: it gathers light at every lobe with a density.
    pub fn new(ray: Ray) -> Self {
        WhittedPath {
            follows_near_specular: false,
            ray,
            radiance: Vec3::ZERO,
            beta: Vec3::ONE,
            previous: None,
            bounces: 0,
        }
    }

    /// A camera path of photon mapping: it follows near-specular lobes too.
    pub fn photon_mapping(ray: Ray) -> Self {
        WhittedPath { follows_near_specular: true, ..WhittedPath::new(ray) }
    }

    /// The weight of light the path's ray finds with density `light_pdf(from)` of the light's
    /// own sample at the vertex it left, `from`: the power heuristic where a near-specular lobe
    /// sampled the ray (every light is sampled at that vertex, through that lobe too:
    /// `direct_from_light`), 1 after a delta lobe or the camera (no light sample finds it).
    fn found_weight(&self, light_pdf: impl FnOnce(Vec3) -> f32) -> f32 {
        self.previous.map_or(1.0, |(from, pdf)| power_heuristic(pdf, light_pdf(from)))
    }
}

/// Where a path of `whitted` scatters.
pub(super) struct Vertex {
    pub hit: Hit,
    pub wo: Vec3,
    pub bsdf: Bsdf,
    /// The lobes whose light is estimated here (light samples, the background, a photon
    /// map's estimate); the path follows the others.
    pub gathered: LobeFlags,
}

impl Vertex {
    /// A vertex slot before `arrive_in` fills it.
    const UNSET: Vertex = Vertex {
        hit: Hit {
            t: 0.0,
            point: Vec3::ZERO,
            normal: Vec3::Z,
            shading_normal: Vec3::Z,
            error: 0.0,
            primitive: 0,
        },
        wo: Vec3::Z,
        bsdf: Bsdf::BLACK,
        gathered: LobeFlags::NONE,
    };

    /// Whether it has lobes with a density, which light samples light.
    fn is_lit(&self) -> bool {
        self.bsdf.flags().is_non_delta()
    }

    /// The lobes the path follows onward: delta lobes, and near-specular ones under the
    /// glossy rule.
    pub fn followed(&self) -> LobeFlags {
        (self.bsdf.flags() & (LobeFlags::NON_DELTA | LobeFlags::DELTA)).without(self.gathered)
    }
}

/// The path arrives where its ray meets the scene (`hit`), or leaves it, and adds the emission
/// seen there (what lies beyond where it leaves); the vertex where it scatters, unless it ends.
/// `arrive`, `leave` and `follow` are always inlined: a vertex is made and read in place, not
/// copied out of a call (callgrind of S1).
#[inline(always)]
pub(super) fn arrive(
    scene: &Scene,
    path: &mut WhittedPath,
    hit: Option<Hit>,
    max_depth: u32,
) -> Option<Vertex> {
    let mut vertex = Vertex::UNSET;
    arrive_in(scene, path, hit, max_depth, &mut vertex).then_some(vertex)
}

/// `arrive` with the vertex made in place in `vertex` (whatever it held; meaningful only where
/// the path scatters, which it returns). The lanes keep a vertex per lane this way: returned
/// and moved into its lane, a vertex was copied three times, and those copies' wide loads
/// waited on the narrower stores that made it (a fifth of S1's time, perf).
#[inline(always)]
fn arrive_in(
    scene: &Scene,
    path: &mut WhittedPath,
    hit: Option<Hit>,
    max_depth: u32,
    vertex: &mut Vertex,
) -> bool {
    let Some(mut hit) = hit else {
        // Only followed lobes lead here: the camera sees what lies beyond.
        let dir = Vec3::from(path.ray.dir);
        let beyond = match scene.environment() {
            Some((_, sky)) if path.previous.is_some() => {
                scene.backdrop() + sky.le(dir) * path.found_weight(|_| sky.pdf(dir))
            }
            _ => scene.beyond(dir, true),
        };
        path.radiance += path.beta * beyond;
        return false;
    };
    let wo = -Vec3::from(path.ray.dir);
    let material = scene.material(hit.primitive, hit.point);
    let emitted = material.emitted(hit.normal, wo);
    if emitted != Vec3::ZERO {
        let light = scene.primitives[hit.primitive as usize].light;
        let found = |from| light.map_or(0.0, |l| scene.lights[l as usize].pdf(from, &hit));
        path.radiance += path.beta * emitted * path.found_weight(found);
    }
    if path.bounces == max_depth {
        return false;
    }
    scene.shade(&mut vertex.bsdf, &mut hit, wo, &material, TransportMode::Radiance);
    vertex.gathered = if path.follows_near_specular {
        vertex.bsdf.gathered_lobes()
    } else {
        vertex.bsdf.flags() & LobeFlags::NON_DELTA
    };
    vertex.hit = hit;
    vertex.wo = wo;
    true
}

/// A sample of every light at a lit vertex, in order: its shadow ray and the light it reflects
/// towards wo through the lobes `mask` asks for, if unoccluded (`light_sample`).
fn light_samples<'a>(
    scene: &'a Scene,
    vertex: &'a Vertex,
    mask: LobeFlags,
    sampler: &'a mut Sampler,
) -> impl Iterator<Item = Option<(ShadowRay, Vec3)>> + 'a {
    scene.lights.iter().map(move |light| light_sample(light, vertex, mask, sampler))
}

/// A sample of `light` at a lit vertex through the lobes `mask` asks for: its gathered lobes
/// among them, and its followed ones (`Vertex::followed`) if `mask` asks for one with a density,
/// weighted against the ray the path follows (`direct_from_light`); from the sampler's next
/// point, drawn where no lobe is asked for too (each light's draws stay in place). Always
/// inlined: out of line (as LLVM left it), its call and returned sample cost S1's light sample
/// about 40 of its 325 instructions (callgrind).
#[inline(always)]
fn light_sample(
    light: &Light,
    vertex: &Vertex,
    mask: LobeFlags,
    sampler: &mut Sampler,
) -> Option<(ShadowRay, Vec3)> {
    let u = sampler.next_2d_if(!light.is_delta());
    let gathered = vertex.gathered & mask;
    let followed = vertex.followed();
    let followed = if (followed & mask).is_non_delta() { followed } else { LobeFlags::NONE };
    if gathered.is_empty() && followed.is_empty() {
        return None;
    }
    direct_from_light(light, &vertex.hit, vertex.wo, &vertex.bsdf, (gathered, followed), u)
}

/// The path leaves its vertex: at a lit one it adds `lit` (the light samples found unoccluded),
/// where it gathers the environment's light found by BSDF sampling and any `indirect` light; it
/// follows a delta (or near-specular) lobe if there is one. Whether it goes on.
#[inline(always)]
fn leave(
    scene: &Scene,
    path: &mut WhittedPath,
    vertex: &Vertex,
    lit: Vec3,
    sampler: &mut Sampler,
    indirect: Option<&Indirect>,
) -> bool {
    let Vertex { hit, wo, bsdf, gathered } = vertex;
    path.radiance += path.beta * lit;
    if !gathered.is_empty() {
        let environment = direct_from_environment(scene, hit, *wo, bsdf, *gathered, sampler);
        path.radiance += path.beta * environment;
        if let Some(indirect) = indirect {
            path.radiance += path.beta * indirect(vertex, sampler);
        }
    }
    follow(path, vertex, sampler)
}

/// The path goes on through the vertex's followed lobes (`Vertex::followed`), if it has some:
/// with both reflection and refraction one of them is followed, chosen at random with its
/// weight divided by its probability (one ray, no branching, no bias). Whether it goes on.
#[inline(always)]
pub(super) fn follow(path: &mut WhittedPath, vertex: &Vertex, sampler: &mut Sampler) -> bool {
    let Vertex { hit, wo, bsdf, .. } = vertex;
    let followed = vertex.followed();
    if followed.is_empty() {
        return false;
    }
    let u_lobe = sampler.next_1d();
    // Delta lobes read no direction sample: `direct` draws none.
    let u = if followed.is_non_delta() { sampler.next_2d() } else { NO_DIRECTION };
    let Some(sample) = bsdf.sample(*wo, u_lobe, u, followed) else {
        return false;
    };
    path.beta *= sample.weight;
    path.previous = (!sample.is_delta()).then_some((hit.point, sample.pdf));
    path.ray = Ray::new(offset_origin(hit, sample.wi), sample.wi);
    path.bounces += 1;
    true
}

/// Light from every light reflected towards wo at a lit vertex through the lobes `mask` asks
/// for (`light_sample`), each sample's shadow ray traced at once: what the lanes of `Direct`
/// find together, one path at a time.
pub(super) fn lit_one_at_a_time(
    scene: &Scene,
    vertex: &Vertex,
    mask: LobeFlags,
    sampler: &mut Sampler,
) -> Vec3 {
    let mut lit = Vec3::ZERO;
    for (shadow, reflected) in light_samples(scene, vertex, mask, sampler).flatten() {
        lit += reflected * scene.transmittance(&shadow.ray(), shadow.t_max());
    }
    lit
}

/// Light from other surfaces scattered towards `wo` by the gathered lobes at a vertex, from
/// some estimator (a photon map's).
pub(super) type Indirect<'a> = dyn Fn(&Vertex, &mut Sampler) -> Vec3 + 'a;

/// `Direct`'s estimate along `ray`, plus any `indirect(vertex)` (light from other surfaces) at
/// each vertex with gathered lobes: emission seen on the way, next-event estimation at those
/// vertices, delta lobes followed, for at most `max_depth` bounces. With `indirect`, a photon
/// map's, the path follows near-specular lobes too (`WhittedPath::photon_mapping`).
pub(super) fn whitted(
    scene: &Scene,
    ray: Ray,
    sampler: &mut Sampler,
    max_depth: u32,
    indirect: Option<&Indirect>,
) -> Vec3 {
    let mut path =
        if indirect.is_some() { WhittedPath::photon_mapping(ray) } else { WhittedPath::new(ray) };
    loop {
        let hit = scene.intersect(&path.ray);
        let Some(vertex) = arrive(scene, &mut path, hit, max_depth) else { break };
        let lit = if vertex.is_lit() {
            lit_one_at_a_time(scene, &vertex, LobeFlags::ALL, sampler)
        } else {
            Vec3::ZERO
        };
        if !leave(scene, &mut path, &vertex, lit, sampler, indirect) {
            break;
        }
    }
    path.radiance
}
