//! Lights: point lights and emissive primitives (area lights), each holding what it emits from;
//! sampled towards a point (next-event estimation) and for emission (photon tracing).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::geometry::{DirectionSample, Frame, Hit, Ray, Shape, offset_origin};
use crate::sampling::{cosine_hemisphere, uniform_sphere};

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
    #[inline]
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
                let DirectionSample { point, normal, error, wi, pdf } =
                    shape.sample_from(hit.point, area, u)?;
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
        shape.pdf_from(from, area, on_light.point, on_light.normal)
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
                let dir = Frame::from_normal(s.normal).to_world(cosine_hemisphere(u_direction));
                // Leave just off the surface, on the side that emits.
                let ray = Ray::new(s.point + s.normal * s.error, dir);
                Some(EmissionSample { ray, power: PI * *area * *emission * share })
            }
        }
    }
}

/// Radiance an emitter sends towards `wo` from a point with normal `n`: `Material::emitted`'s
/// one-sided rule, towards the normal.
#[inline]
fn emitted(emission: Vec3, n: Vec3, wo: Vec3) -> Vec3 {
    if n.dot(wo) > 0.0 { emission } else { Vec3::ZERO }
}

/// The segment from `hit` to `target`.
#[inline]
fn shadow_ray(hit: &Hit, target: Vec3, wi: Vec3) -> ShadowRay {
    let origin = offset_origin(hit, wi);
    let to_target = target - origin;
    let distance = to_target.length();
    // Stop just short of the target so that the light's own surface does not occlude it.
    ShadowRay { ray: Ray::new(origin, to_target / distance), t_max: distance * (1.0 - 1e-4) }
}
