//! Lights: point lights and emissive primitives (area lights), each holding what it emits from;
//! sampled towards a point (next-event estimation) and for emission (photon tracing).

use std::f32::consts::PI;

use glam::{BVec4A, Vec2, Vec3, Vec4};

use crate::geometry::{
    Hit, HitLanes, LANES, Lane, PlanarKind, Ray, Shape, Vec2x4, Vec3x4, offset_origin,
    planar_coordinates, planar_error, sphere_error,
};
use crate::material::to_world;
use crate::sampling::{cosine_hemisphere, uniform_sphere};
use crate::scene::Scene;

#[derive(Debug, Clone)]
pub enum Light {
    /// `power` acts as radiant intensity: irradiance power / r^2 (the course's Lab 4 formula).
    Point { position: Vec3, power: Vec3 },
    /// An emissive primitive: its shape, the radiance it emits towards its normal, its surface
    /// area, and its index in `Scene::primitives` (which names hits on it).
    Area { shape: Shape, emission: Vec3, area: f32, primitive: u32 },
}

/// Incident light at a point from one sampled light position, if nothing is in the way.
#[derive(Debug, Clone, Copy)]
pub struct LightSample {
    pub wi: Vec3,
    /// Incident radiance (for a point light, intensity / r^2: irradiance on a normal surface).
    pub li: Vec3,
    /// Solid-angle density of `wi`; 1 for a point light (a delta distribution).
    pub pdf: f32,
    pub is_delta: bool,
    /// The segment towards the light that must be free of surfaces for the light to arrive.
    pub shadow: ShadowRay,
}

/// A segment from a surface towards a light: `ray` up to `t_max`.
#[derive(Debug, Clone, Copy)]
pub struct ShadowRay {
    pub ray: Ray,
    pub t_max: f32,
}

impl Light {
    pub fn is_delta(&self) -> bool {
        matches!(self, Light::Point { .. })
    }

    /// Emitted power (mean over RGB), for choosing lights in proportion to it: 4 pi I for a
    /// point light, pi A Le for a one-sided diffuse emitter.
    pub fn power(&self) -> f32 {
        self.power_rgb().element_sum() / 3.0
    }

    /// Emitted power per channel: 4 pi I for a point light, pi A Le for a one-sided diffuse
    /// emitter (Le cos integrated over the hemisphere is pi Le).
    pub fn power_rgb(&self) -> Vec3 {
        match self {
            Light::Point { power, .. } => 4.0 * PI * *power,
            Light::Area { emission, area, .. } => PI * *area * *emission,
        }
    }

    /// Samples light arriving at `hit` from this light, unless something is in the way (see
    /// `LightSample::shadow`); `None` if it arrives from behind the emitter or carries nothing.
    pub fn sample(&self, hit: &Hit, u: Vec2) -> Option<LightSample> {
        let (target, wi, li, pdf, is_delta) = match self {
            &Light::Point { position, power } => {
                let to_light = position - hit.point;
                let distance_squared = to_light.length_squared();
                let wi = to_light / distance_squared.sqrt();
                (position, wi, power / distance_squared, 1.0, true)
            }
            // Every emitter shape but the torus is convex or emits outwards only: it never
            // lights itself (and a sample from its own surface would be degenerate).
            Light::Area { primitive, shape, .. }
                if *primitive == hit.primitive && !matches!(shape, Shape::Torus(_)) =>
            {
                return None;
            }
            &Light::Area { ref shape, emission, area, .. } => {
                let (point, normal, error, wi, pdf) = match *shape {
                    Shape::Sphere { center, radius } if center.distance(hit.point) > radius => {
                        let (point, normal, error, pdf) =
                            sample_sphere_cone(center, radius, hit.point, u);
                        (point, normal, error, (point - hit.point).normalize(), pdf)
                    }
                    ref shape => {
                        let s = shape.sample_area(u)?;
                        let to_light = s.point - hit.point;
                        let distance_squared = to_light.length_squared();
                        let wi = to_light / distance_squared.sqrt();
                        // Area density 1/A in solid angle: r^2 / (A cos).
                        let pdf = distance_squared / (area * s.normal.dot(wi).abs());
                        (s.point, s.normal, s.error, wi, pdf)
                    }
                };
                let le = emitted(emission, normal, -wi);
                if le == Vec3::ZERO || !(pdf.is_finite() && pdf > 0.0) {
                    return None;
                }
                // Aim just off the light's surface, on the side we see, so it does not shadow itself.
                (point + normal * error, wi, le, pdf, false)
            }
        };
        let shadow = shadow_ray(hit, target, wi);
        Some(LightSample { wi, li, pdf, is_delta, shadow })
    }

    /// The solid-angle density with which `sample` from `from` returns the direction towards
    /// `on_light`, a hit on this (area) light.
    pub fn pdf(&self, from: Vec3, on_light: &Hit) -> f32 {
        let Light::Area { ref shape, area, .. } = *self else {
            return 0.0;
        };
        match *shape {
            Shape::Sphere { center, radius } if center.distance(from) > radius => {
                1.0 / cone_solid_angle(center, radius, from)
            }
            _ => {
                let to_light = on_light.point - from;
                let cos_light = on_light.normal.dot(to_light.normalize()).abs();
                to_light.length_squared() / (area * cos_light)
            }
        }
    }
}

/// A photon's start: where it leaves its light, in which direction, and the power it carries.
#[derive(Debug, Clone, Copy)]
pub struct EmissionSample {
    pub ray: Ray,
    /// The light's power divided by the number of photons it emits: Le cos / (pdf_A pdf_w)
    /// over them, which for these emitters is the same for every photon.
    pub power: Vec3,
}

impl Light {
    /// One of `photons` photons from this light: a point light's uniform over the sphere
    /// (4 pi I / n each), an area light's from a point uniform by area, cosine-weighted over
    /// the hemisphere its emitting side faces (Le cos / (1/A cos/pi) = pi A Le, / n each). So
    /// `photons` photons carry exactly `power_rgb`. `None` where the shape has no sample.
    pub fn sample_emission(
        &self,
        photons: u32,
        u_point: Vec2,
        u_direction: Vec2,
    ) -> Option<EmissionSample> {
        let share = 1.0 / photons as f32;
        match self {
            &Light::Point { position, power } => {
                let ray = Ray::new(position, uniform_sphere(u_direction));
                Some(EmissionSample { ray, power: 4.0 * PI * power * share })
            }
            Light::Area { shape, emission, area, .. } => {
                let s = shape.sample_area(u_point)?;
                let dir = to_world(s.normal, cosine_hemisphere(u_direction));
                // Leave just off the surface, on the side that emits.
                let ray = Ray::new(s.point + s.normal * s.error, dir);
                Some(EmissionSample { ray, power: PI * *area * *emission * share })
            }
        }
    }
}

/// Radiance an emitter sends towards `wo` from a point with normal `n`: `Material::emitted`'s
/// one-sided rule, towards the normal.
fn emitted(emission: Vec3, n: Vec3, wo: Vec3) -> Vec3 {
    if n.dot(wo) > 0.0 { emission } else { Vec3::ZERO }
}

/// Samples of four lanes' lights, from `sample_lanes`.
#[derive(Debug, Clone, Copy)]
pub struct LightSampleLanes {
    /// Lanes whose light is a point light or a planar area light: the others are left to
    /// `Light::sample`.
    pub handled: BVec4A,
    /// Lanes with a sample (where `Light::sample` returns one); the fields below hold it.
    pub found: BVec4A,
    /// Lanes whose light is a point light (a delta distribution, beyond MIS).
    pub is_delta: BVec4A,
    pub wi: Vec3x4,
    pub li: Vec3x4,
    pub pdf: Vec4,
    pub shadow_origin: Vec3x4,
    pub shadow_dir: Vec3x4,
    pub shadow_t_max: Vec4,
}

/// A light as `sample_lanes` reads it, gathered once per scene: a planar area light, or a
/// point light as one of no extent (its position as `origin`, edges and normal zero, its
/// intensity as `emission`).
#[derive(Debug, Clone, Copy)]
pub struct LaneLight {
    /// The emitter's primitive and shape; `None` for a point light.
    pub planar: Option<(u32, PlanarKind)>,
    pub origin: Vec3,
    pub edge1: Vec3,
    pub edge2: Vec3,
    pub normal: Vec3,
    pub emission: Vec3,
    pub area: f32,
    /// The error bound of points on it (`planar_error`).
    pub error: f32,
}

impl Light {
    /// Its form for `sample_lanes`, if it is a point light or a planar area light.
    pub fn in_lanes(&self) -> Option<LaneLight> {
        let (primitive, shape, emission, area) = match self {
            &Light::Point { position, power } => {
                return Some(LaneLight {
                    planar: None,
                    origin: position,
                    edge1: Vec3::ZERO,
                    edge2: Vec3::ZERO,
                    normal: Vec3::ZERO,
                    emission: power,
                    area: 1.0,
                    error: 0.0,
                });
            }
            Light::Area { primitive, shape, emission, area } => {
                (*primitive, shape, *emission, *area)
            }
        };
        let Shape::Planar { kind, origin, edge1, edge2, normal } = *shape else { return None };
        Some(LaneLight {
            planar: Some((primitive, kind)),
            origin,
            edge1,
            edge2,
            normal,
            emission,
            area,
            error: planar_error(origin, edge1, edge2),
        })
    }
}

/// `Light::sample` for four lanes at once, where a lane's light is a point light or a planar
/// area light (quad, disk, triangle): the same operations in the same order, side by side, so
/// each lane gets exactly what `sample` returns. `lights` holds each lane's light (`None`:
/// nothing to sample) and `u` its point of the unit square, `primitives` the primitive each
/// lane's hit is on. `None` if no lane's light is of these kinds.
// Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
#[inline(always)]
pub fn sample_lanes(
    scene: &Scene,
    hits: &HitLanes,
    primitives: [u32; LANES],
    lights: [Option<usize>; LANES],
    u: Vec2x4,
) -> Option<LightSampleLanes> {
    let lanes = lights.map(|l| scene.lights_in_lanes[l?].as_ref());
    let first = *lanes.iter().flatten().next()?;
    // Lanes mostly share a light (always, in a scene of one): its values are spread, not gathered.
    let shared = lanes.iter().flatten().all(|light| std::ptr::eq(*light, first));
    let vectors = |value: fn(&LaneLight) -> Vec3| {
        if shared {
            Vec3x4::splat(value(first))
        } else {
            Vec3x4::from_lanes(lanes.map(|l| l.map_or(Vec3::ZERO, value)))
        }
    };
    let (origin, edge1, edge2) =
        (vectors(|l| l.origin), vectors(|l| l.edge1), vectors(|l| l.edge2));
    let (normal, emission) = (vectors(|l| l.normal), vectors(|l| l.emission));
    let scalars =
        |value: fn(&LaneLight) -> f32| Vec4::from_array(lanes.map(|l| l.map_or(1.0, value)));
    let (area, error) = (scalars(|l| l.area), scalars(|l| l.error));
    // Coordinates along the edges: a quad's are u itself (`planar_coordinates`); point
    // lights' lanes keep u, unread.
    let mut st = u;
    for (lane, light) in lanes.iter().enumerate() {
        if let Some(LaneLight { planar: Some((_, kind)), .. }) = light
            && !matches!(kind, PlanarKind::Quad)
        {
            st.set_lane(lane, planar_coordinates(*kind, u.lane(lane)));
        }
    }
    let (s, t) = (st.x, st.y);
    let handled = BVec4A::from_array(lanes.map(|l| l.is_some()));
    let is_point = BVec4A::from_array(lanes.map(|l| l.is_some_and(|l| l.planar.is_none())));
    let own = BVec4A::from_array(std::array::from_fn(|lane| {
        lanes[lane].is_some_and(|l| l.planar.is_some_and(|(p, _)| p == primitives[lane]))
    }));

    let point = Vec3x4::select(is_point, origin, origin + s * edge1 + t * edge2);
    let to_light = point - hits.point;
    let distance_squared = to_light.length_squared();
    let wi = to_light / distance_squared.sqrt();
    // A point light's intensity / r^2; an area light's emission (`Material::emitted`:
    // one-sided, towards the normal) with the area density in solid angle, r^2 / (A cos).
    let emitted = Vec3x4::select(normal.dot(-wi).cmpgt(Vec4::ZERO), emission, Vec3x4::ZERO);
    let li = Vec3x4::select(is_point, emission / distance_squared, emitted);
    let pdf = Vec4::select(is_point, Vec4::ONE, distance_squared / (area * normal.dot(wi).abs()));
    let area_found = !own & !li.is_zero() & pdf.cmpgt(Vec4::ZERO) & pdf.cmplt(Vec4::INFINITY);
    // `shadow_ray` towards the light, or the point just off its surface.
    let target = Vec3x4::select(is_point, point, point + normal * error);
    let shadow_origin = hits.offset_origin(wi);
    let to_target = target - shadow_origin;
    let distance = to_target.length_squared().sqrt();
    Some(LightSampleLanes {
        handled,
        found: handled & (is_point | area_found),
        is_delta: is_point,
        wi,
        li,
        pdf,
        shadow_origin,
        shadow_dir: to_target / distance,
        shadow_t_max: distance * (1.0 - 1e-4),
    })
}

/// Solid angle of the cone of directions from `from` that meet the sphere:
/// 2 pi (1 - cos theta_max), with 1 - cos written as sin^2 / (1 + cos) for small cones.
fn cone_solid_angle(center: Vec3, radius: f32, from: Vec3) -> f32 {
    let sin2_max = radius * radius / center.distance_squared(from);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    2.0 * PI * sin2_max / (1.0 + cos_max)
}

/// A direction uniform in the cone the sphere subtends (pbrt-v4, 6.2.4), and the point it meets.
/// Returns point, outward normal, error bound and solid-angle pdf.
fn sample_sphere_cone(center: Vec3, radius: f32, from: Vec3, u: Vec2) -> (Vec3, Vec3, f32, f32) {
    let axis = center - from;
    let distance = axis.length();
    let sin2_max = radius * radius / (distance * distance);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    let one_minus_cos_max = sin2_max / (1.0 + cos_max);
    let cos_theta = 1.0 - u.x * one_minus_cos_max;
    let sin2_theta = (1.0 - cos_theta * cos_theta).max(0.0);
    let phi = 2.0 * PI * u.y;
    let sin_theta = sin2_theta.sqrt();
    let wi = to_world(
        axis / distance,
        Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta),
    );
    // Nearest intersection of from + t wi with the sphere; at the silhouette the root is 0.
    let t =
        distance * cos_theta - (radius * radius - distance * distance * sin2_theta).max(0.0).sqrt();
    let normal = (from + t * wi - center).normalize();
    let point = center + radius * normal;
    (point, normal, sphere_error(center, radius), 1.0 / (2.0 * PI * one_minus_cos_max))
}

/// The segment from `hit` to `target`.
fn shadow_ray(hit: &Hit, target: Vec3, wi: Vec3) -> ShadowRay {
    let origin = offset_origin(hit, wi);
    let to_target = target - origin;
    let distance = to_target.length();
    // Stop just short of the target so that the light's own surface does not occlude it.
    ShadowRay { ray: Ray::new(origin, to_target / distance), t_max: distance * (1.0 - 1e-4) }
}
