//! Scenes: `build` turns the graph `lang` produces (`crate::graph`) into a render-ready `Scene`:
//! world-space primitives in flat arrays under a BVH, materials, lights and the camera.

mod build;
mod sky;
mod surface;

pub use build::build;
pub use surface::SurfaceTexture;

use std::borrow::Cow;
use std::ops::Range;

use glam::{Affine3A, Vec3};

use crate::aabb::Aabb;
use crate::accel::{Bvh, Planes};
use crate::camera::Camera;
use crate::geometry::{Csg, FewShapes, Hit, Intersection, Nearest, Ray, Shape, offset_origin};
use crate::graph::Settings;
use crate::lanes::{Floats, LANES, Lane, Mask, RayLanes, Wide};
use crate::light::{Environment, Light};
use crate::material::{Bsdf, Material, TransportMode};
use crate::medium::Medium;
use crate::sampling::{PixelSampler, Sampler};
use crate::texture::{Bump, tilt};

/// The most surfaces a ray may cross in a row without scattering (surfaces that only bound a
/// medium, or let light straight through): more is a ray caught between coincident surfaces,
/// which ends (a bound, not a cut of any real scene's paths).
pub const MOST_CROSSINGS: u32 = 256;

#[derive(Debug, Clone)]
pub struct Primitive {
    pub shape: Shape,
    pub material: u32,
    /// Index into `Scene::frames`: the object's own space, where textures are evaluated.
    pub frame: u32,
    /// Its index in `Scene::lights` when it is an emitter sampled as an area light.
    pub light: Option<u32>,
}

/// Where a ray meets a primitive, before its hit record is made.
#[derive(Debug, Clone, Copy)]
struct Found {
    primitive: u32,
    at: Intersection,
}

#[derive(Debug)]
pub struct Scene {
    pub settings: Settings,
    pub camera: Camera,
    /// Bounded primitives first, in BVH order, then the unbounded planes, then other unbounded
    /// primitives, then the surfaces of CSG operands (not traced: a hit on a CSG primitive is
    /// named by its operand's surface).
    pub primitives: Vec<Primitive>,
    bounded: usize,
    bvh: Bvh,
    /// The unbounded planes, `primitives[bounded..]`, in the same order, four to a group for
    /// one ray at a time.
    planes: Planes,
    /// Unbounded primitives other than planes (CSG objects without bounds), after the planes:
    /// tested by every ray.
    others: Range<usize>,
    /// For rays traced in lanes: the planes, and the simple bounded primitives too when they
    /// are few and the others fewer still (`few_holds_bounded`: the BVH is then not traversed).
    few: FewShapes,
    few_holds_bounded: bool,
    /// Where `few_holds_bounded`, the bounded primitives it does not take, which rays traced in
    /// lanes meet one lane at a time, in the order of `alone_bvh`'s leaves; else none.
    alone: Vec<usize>,
    alone_bvh: Bvh,
    pub materials: Vec<Material>,
    /// Per material, what of it varies over the surface, if anything.
    textures: Vec<Option<SurfaceTexture>>,
    /// Whether some material lets light straight through somewhere (`transmittance`).
    see_through: bool,
    /// Per material, its bump mapping, if any.
    bumps: Vec<Option<Bump>>,
    /// World to object space of each object, for textures.
    frames: Vec<Affine3A>,
    pub lights: Vec<Light>,
    /// The index in `lights` of the environment light, if there is one.
    environment: Option<usize>,
    /// What rays the camera sees through delta bounces only find where they leave a scene
    /// without an environment light: POV-Ray's `background`, which does not light.
    backdrop: Vec3,
    /// Cumulative distribution for choosing a light: half by power, half uniform
    /// (`build::light_selection_cdf`).
    light_cdf: Vec<f32>,
    /// The participating media: objects' interiors and the atmosphere (none in most scenes).
    pub media: Vec<Medium>,
    /// Per material, the index in `media` of the medium inside objects made of it.
    interiors: Vec<Option<u32>>,
    /// The index in `media` of the medium filling the scene outside objects with one.
    atmosphere: Option<u32>,
    /// Things the user should know that are not errors (e.g. the camera's aspect ratio).
    pub warnings: Vec<String>,
}

impl Scene {
    /// The closest surface along the ray.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let bounded = &self.primitives[..self.bounded];
        let mut closest = None;
        let test = |i: usize, t_max| {
            let at = bounded[i].shape.intersection(ray, t_max)?;
            closest = Some(Found { primitive: i as u32, at });
            Some(at.t)
        };
        let mut t_max = self.bvh.closest(ray, f32::INFINITY, test, |leaf| self.preload(leaf));
        for i in self.others.clone() {
            if let Some(at) = self.primitives[i].shape.intersection(ray, t_max) {
                closest = Some(Found { primitive: i as u32, at });
                t_max = at.t;
            }
        }
        if let Some((k, t)) = self.planes.closest(ray, t_max) {
            closest = Some(Found { primitive: (self.bounded + k) as u32, at: Intersection::at(t) });
        }
        Some(self.hit(ray, &closest?))
    }

    /// The closest primitive along each ray whose lane is active (none in the others), and
    /// its hit record.
    // Inlined into both integrators' loops over lanes, as when `Path` alone called it: once
    // `Direct` called it too, LLVM kept it and the tests under it out of line, which cost S3
    // 6% more instructions (callgrind).
    #[inline(always)]
    pub fn intersect_lanes(&self, rays: &RayLanes, active: [bool; LANES]) -> Nearest {
        let mut closest = [None; LANES];
        let mut t_max = active.map(|active| if active { f32::INFINITY } else { 0.0 });
        if !self.few_holds_bounded || !self.alone.is_empty() {
            let bounded = &self.primitives[..self.bounded];
            for lane in (0..LANES).filter(|&lane| active[lane]) {
                let ray = &rays.lane(lane);
                let mut test = |i: usize, t_max| {
                    let at = bounded[i].shape.intersection(ray, t_max)?;
                    closest[lane] = Some(Found { primitive: i as u32, at });
                    Some(at.t)
                };
                t_max[lane] = if self.few_holds_bounded {
                    let test = |k: usize, t_max| test(self.alone[k], t_max);
                    self.alone_bvh.closest(ray, t_max[lane], test, |_| ())
                } else {
                    self.bvh.closest(ray, t_max[lane], test, |leaf| self.preload(leaf))
                };
            }
        }
        if !self.others.is_empty() {
            self.closest_others(rays, active, &mut closest, &mut t_max);
        }
        let mut nearest = self.few.closest(rays, Floats::from_fn(|lane| t_max[lane]));
        for (lane, found) in closest.iter().enumerate() {
            if nearest.names[lane].is_none()
                && let Some(found) = found
            {
                let hit = self.hit(&rays.lane(lane), found);
                nearest.names[lane] = Some(hit.primitive);
                nearest.t.set_lane(lane, hit.t);
                nearest.hits.set_lane(lane, &hit);
            }
        }
        nearest
    }

    /// The closest of the unbounded primitives other than planes along each active lane's ray,
    /// nearer than what was found so far.
    #[cold]
    fn closest_others(
        &self,
        rays: &RayLanes,
        active: [bool; LANES],
        closest: &mut [Option<Found>; LANES],
        t_max: &mut [f32; LANES],
    ) {
        for lane in (0..LANES).filter(|&lane| active[lane]) {
            let ray = &rays.lane(lane);
            for i in self.others.clone() {
                if let Some(at) = self.primitives[i].shape.intersection(ray, t_max[lane]) {
                    closest[lane] = Some(Found { primitive: i as u32, at });
                    t_max[lane] = at.t;
                }
            }
        }
    }

    /// The hit record of the primitive `ray` was found to meet. (Made only for the closest.)
    fn hit(&self, ray: &Ray, found: &Found) -> Hit {
        let primitive = &self.primitives[found.primitive as usize];
        // A CSG surface is named by its operand's surface, which has its material.
        let name = match &primitive.shape {
            Shape::Csg(csg) => csg.surfaces + Csg::operand(&found.at),
            _ => found.primitive,
        };
        Hit { primitive: name, ..primitive.shape.hit(ray, &found.at) }
    }

    /// The fraction of light that travels the shadow ray from `t_max` to its origin: 0 where a
    /// surface stops it, else the product of the transmissions of the surfaces that light
    /// crosses straight (`Material::passes_straight`: POV-Ray's filter and transmit), each at
    /// the point crossed. Paths cross them too without a bounce of their own (`Path::bounce`),
    /// so the two estimators meet the same light.
    pub fn transmittance(&self, ray: &Ray, t_max: f32) -> Vec3 {
        if !self.see_through {
            return if self.occluded(ray, t_max) { Vec3::ZERO } else { Vec3::ONE };
        }
        let dir = Vec3::from(ray.dir);
        let (mut ray, mut left, mut reached) = (*ray, t_max, Vec3::ONE);
        for _ in 0..=MOST_CROSSINGS {
            let Some(hit) = self.intersect(&ray).filter(|hit| hit.t < left) else {
                return reached;
            };
            reached *= self.passes(&hit, dir);
            if reached == Vec3::ZERO {
                return reached;
            }
            let origin = offset_origin(&hit, dir);
            left -= (origin - Vec3::from(ray.origin)).length();
            ray = Ray::new(origin, dir);
        }
        Vec3::ZERO
    }

    /// The light `hit`'s surface lets straight through there, crossed by `dir`
    /// (`Material::straight_through` where it `passes_straight`), else none.
    pub fn passes(&self, hit: &Hit, dir: Vec3) -> Vec3 {
        let material = self.material(hit.primitive, hit.point);
        if !material.passes_straight() {
            return Vec3::ZERO;
        }
        material.straight_through(dir.dot(hit.shading_normal))
    }

    /// Whether some material lets light straight through (`transmittance` then follows shadow
    /// rays through the surfaces they cross).
    pub fn has_see_through(&self) -> bool {
        self.see_through
    }

    /// Whether any surface lies along the ray before `t_max` (shadow rays).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let bounded = &self.primitives[..self.bounded];
        let occludes = |i: usize| bounded[i].shape.occludes(ray, t_max);
        self.planes.any(ray, t_max)
            || self.others.clone().any(|i| self.primitives[i].shape.occludes(ray, t_max))
            || self.bvh.any(ray, t_max, occludes, |leaf| self.preload(leaf))
    }

    /// Per lane, whether any surface lies along the ray before its `t_max`; a
    /// lane with `t_max` 0 is never occluded.
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    pub fn occluded_lanes(&self, rays: &RayLanes, t_max: Floats) -> Mask {
        let mut occluded = self.few.any(rays, t_max);
        if !self.others.is_empty() {
            let open = occluded;
            for lane in (0..LANES).filter(|&lane| !open.lane(lane) && t_max.lane(lane) > 0.0) {
                let (ray, t_max) = (&rays.lane(lane), t_max.lane(lane));
                if self.others.clone().any(|i| self.primitives[i].shape.occludes(ray, t_max)) {
                    occluded.set_lane(lane, true);
                }
            }
        }
        if !self.few_holds_bounded || !self.alone.is_empty() {
            let bounded = &self.primitives[..self.bounded];
            let open = occluded;
            for lane in (0..LANES).filter(|&lane| !open.lane(lane) && t_max.lane(lane) > 0.0) {
                let (ray, t_max) = (&rays.lane(lane), t_max.lane(lane));
                let occludes = |i: usize| bounded[i].shape.occludes(ray, t_max);
                let met = if self.few_holds_bounded {
                    self.alone_bvh.any(ray, t_max, |k| occludes(self.alone[k]), |_| ())
                } else {
                    self.bvh.any(ray, t_max, occludes, |leaf| self.preload(leaf))
                };
                if met {
                    occluded.set_lane(lane, true);
                }
            }
        }
        occluded
    }

    /// How many primitives rays are traced against (the surfaces of CSG operands, which only
    /// name hits, are not counted).
    pub fn traced_primitives(&self) -> usize {
        self.others.end
    }

    /// The box around every surface rays meet; `None` when one of them is unbounded.
    pub fn bounds(&self) -> Option<Aabb> {
        let traced = &self.primitives[..self.others.end];
        traced.iter().try_fold(Aabb::EMPTY, |bounds, p| Some(bounds.union(p.shape.bounds()?)))
    }

    /// Whether `p` is inside one of the scene's solids.
    pub fn contains(&self, p: Vec3) -> bool {
        self.primitives[..self.others.end].iter().any(|primitive| primitive.shape.contains(p))
    }

    /// Starts loading primitives a traversal may test soon (see `Bvh::closest`).
    fn preload(&self, leaf: Range<usize>) {
        crate::accel::prefetch(&self.primitives[leaf.start]);
    }

    /// The material of `primitive` at `point` on it, with what varies over its surface (a
    /// textured `diffuse`, a POV-Ray pigment's transparency) evaluated there in the object's
    /// own space (so patterns move with their objects); the scene's own where nothing varies
    /// (most materials), so that a path vertex copies none of it. Always inlined, the texture's
    /// part out of line: every path vertex calls it, and out of line (as LLVM left it once the
    /// texture could make see-through shares) it cost a vertex about 90 instructions
    /// (callgrind, S2: 6 %).
    #[inline(always)]
    pub fn material(&self, primitive: u32, point: Vec3) -> Cow<'_, Material> {
        let primitive = &self.primitives[primitive as usize];
        let index = primitive.material as usize;
        match &self.textures[index] {
            None => Cow::Borrowed(&self.materials[index]),
            Some(texture) => Cow::Owned(self.textured(index, texture, primitive.frame, point)),
        }
    }

    /// Material `index` with `texture` applied at `point`, in the object space `frame`.
    #[inline(never)]
    fn textured(
        &self,
        index: usize,
        texture: &SurfaceTexture,
        frame: u32,
        point: Vec3,
    ) -> Material {
        let mut material = self.materials[index].clone();
        texture.apply(&mut material, self.frames[frame as usize].transform_point3(point));
        material
    }

    /// Makes in `bsdf` the BSDF of `material` (`Scene::material`'s at `hit`) seen from `wo`,
    /// with `hit`'s shading normal bumped by the material's bump mapping, if any, and then kept
    /// consistent with the geometric normal (`texture::tilt`, `Bsdf::face`). Without bump
    /// mapping, `material.bsdf(hit.shading_normal, mode)` and the hit as it is. Always inlined,
    /// the BSDF built once in place, where the caller keeps it: every path vertex calls it, and
    /// a BSDF returned (or built on two branches) is moved through memory, its wide loads
    /// waiting on the narrower stores that made it (perf of S1, S3).
    #[inline(always)]
    pub fn shade(
        &self,
        bsdf: &mut Bsdf,
        hit: &mut Hit,
        wo: Vec3,
        material: &Material,
        mode: TransportMode,
    ) {
        let primitive = &self.primitives[hit.primitive as usize];
        let tilted = match &self.bumps[primitive.material as usize] {
            Some(bump) => self.bumped(bump, primitive.frame, hit, wo),
            None => None,
        };
        if let Some(shading_normal) = tilted {
            hit.shading_normal = shading_normal;
        }
        material.bsdf_in(bsdf, hit.shading_normal, mode);
        if tilted.is_some() {
            bsdf.face(hit.normal);
        }
    }

    /// Whether the material of `primitive` has bump mapping (`shade` may tilt its normals).
    #[inline]
    pub fn is_bumped(&self, primitive: u32) -> bool {
        self.bumps[self.primitives[primitive as usize].material as usize].is_some()
    }

    /// The shading normal of `hit` tilted by `bump` (in object space `frame`), seen from `wo`;
    /// none where it does not tilt (amount 0, a flat stretch): exactly the surface without
    /// bumps there.
    fn bumped(&self, bump: &Bump, frame: u32, hit: &Hit, wo: Vec3) -> Option<Vec3> {
        let to_object = &self.frames[frame as usize];
        // The object's transform is the pattern's outermost one (POV-Ray transforms textures
        // with their objects): the normal goes to object space by the inverse transpose of
        // world-to-object's linear part B, unit there, and its tilt back by B^T, times the
        // normal's length there (`Bump::perturbation`).
        let tilt_to_world = glam::Mat3::from(to_object.matrix3).transpose();
        let normal = tilt_to_world.inverse() * hit.shading_normal;
        let length = normal.length();
        let by = bump.perturbation(to_object.transform_point3(hit.point), normal / length);
        let shading_normal = tilt(hit.shading_normal, tilt_to_world * by * length, hit.normal, wo);
        (shading_normal != hit.shading_normal).then_some(shading_normal)
    }

    /// Whether any medium fills part of the scene (`integrator::Path` then follows its paths
    /// through media).
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// The medium filling the scene outside objects with a medium of their own: where camera
    /// rays start.
    pub fn atmosphere(&self) -> Option<u32> {
        self.atmosphere
    }

    /// The medium a ray leaving `hit` along `dir` travels in: the interior of the object hit
    /// where `dir` goes into it and it has one, the atmosphere otherwise (media do not nest:
    /// `docs/limits.md`).
    pub fn medium_towards(&self, hit: &Hit, dir: Vec3) -> Option<u32> {
        let material = self.primitives[hit.primitive as usize].material as usize;
        let inwards = hit.normal.dot(dir) < 0.0;
        if inwards { self.interiors[material].or(self.atmosphere) } else { self.atmosphere }
    }

    /// Whether the surface hit only bounds a medium: it lets light straight through (all
    /// transmission, `ior 1`, nothing else), so paths and shadow rays cross it as if it were
    /// not there (pbrt's interface material).
    pub fn only_bounds(&self, hit: &Hit) -> bool {
        let primitive = &self.primitives[hit.primitive as usize];
        let index = primitive.material as usize;
        let m = &self.materials[index];
        self.textures[index].is_none()
            && m.diffuse == Vec3::ZERO
            && m.specular == Vec3::ZERO
            && m.transmission == Vec3::ONE
            && m.ior == 1.0
            && m.emission == Vec3::ZERO
            && m.coat.is_none()
    }

    /// Whether the scene has unbounded primitives (planes): they reach beyond any sphere
    /// around the others.
    pub fn has_unbounded(&self) -> bool {
        self.others.end > self.bounded
    }

    /// The environment light, if the scene has one, and its index in `lights`.
    pub fn environment(&self) -> Option<(usize, &Environment)> {
        let index = self.environment?;
        let Light::Environment(sky) = &self.lights[index] else { return None };
        Some((index, sky))
    }

    /// Radiance found along direction `dir` by a ray that leaves the scene: the environment's,
    /// and the backdrop if the camera sees the ray through delta bounces only (`seen`).
    pub fn beyond(&self, dir: Vec3, seen: bool) -> Vec3 {
        let backdrop = if seen { self.backdrop } else { Vec3::ZERO };
        backdrop + self.environment().map_or(Vec3::ZERO, |(_, sky)| sky.le(dir))
    }

    /// What rays the camera sees through delta bounces only find beyond a scene without an
    /// environment light (`beyond`'s part that does not light).
    pub fn backdrop(&self) -> Vec3 {
        self.backdrop
    }

    /// A light chosen half by power, half uniformly among those that emit, and the probability
    /// of that choice.
    pub fn choose_light(&self, u: f32) -> Option<(usize, f32)> {
        if self.light_cdf.len() == 1 {
            return Some((0, 1.0)); // the only light (`light_probability` is c / c = 1)
        }
        let total = *self.light_cdf.last()?;
        let index = self.light_cdf.partition_point(|&c| c <= u * total).min(self.lights.len() - 1);
        Some((index, self.light_probability(index)))
    }

    /// The probability that `choose_light` returns light `index`.
    pub fn light_probability(&self, index: usize) -> f32 {
        let total = self.light_cdf.last().copied().unwrap_or(0.0);
        let below = if index == 0 { 0.0 } else { self.light_cdf[index - 1] };
        (self.light_cdf[index] - below) / total
    }
}

/// Camera sample `index` of pixel (x, y) of the image: its ray (`None` where the camera's
/// projection leaves the film dark: no light arrives there), and the sampler its path goes on
/// drawing from.
pub fn camera_sample(scene: &Scene, x: usize, y: usize, index: u32) -> (Option<Ray>, Sampler) {
    camera_samples(scene, x, y).sample(index)
}

/// The camera samples of pixel (x, y) by index (`PixelSamples::sample`), the hash their
/// samplers share made once (`PixelSampler`).
pub fn camera_samples(scene: &Scene, x: usize, y: usize) -> PixelSamples<'_> {
    let (width, height) = (scene.settings.width as usize, scene.settings.height as usize);
    let pixel = PixelSampler::new(scene.settings.seed, (y * width + x) as u64);
    // Converted once for the pixel's samples: from `usize`, each conversion costs about ten
    // instructions (callgrind of S1).
    let (x, y, width, height) = (x as f32, y as f32, width as f32, height as f32);
    PixelSamples { scene, pixel, x, y, width, height }
}

/// The camera samples of one pixel (`camera_samples`).
pub struct PixelSamples<'a> {
    scene: &'a Scene,
    pixel: PixelSampler,
    x: f32,
    y: f32,
    width: f32,
    height: f32,
}

impl PixelSamples<'_> {
    /// Camera sample `index` (`camera_sample`). Always inlined: returned from a call (a closure
    /// LLVM left out of line), the ray and sampler went through memory, and the copy into a
    /// task's buffer waited on the narrower stores that had written them (perf of S1).
    #[inline(always)]
    pub fn sample(&self, index: u32) -> (Option<Ray>, Sampler) {
        let camera = &self.scene.camera;
        let mut sampler = self.pixel.sample(u64::from(index));
        let jitter = sampler.next_2d();
        // A pinhole camera needs no lens sample.
        let lens = if camera.aperture > 0.0 { sampler.next_2d() } else { glam::Vec2::ZERO };
        let (u, v) = ((self.x + jitter.x) / self.width, (self.y + jitter.y) / self.height);
        let ray = camera.sees(u, v).then(|| camera.ray(u, v, lens));
        (ray, sampler)
    }
}
