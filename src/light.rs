//! Lights: point lights, spotlights, distant lights, emissive primitives (area lights) and the
//! environment, each holding what it emits from; sampled towards a point (next-event
//! estimation) and for emission (photon tracing).

mod environment;
mod lanes;
mod spot;

pub use environment::Environment;
pub use lanes::{LanesLight, LightLanes};
pub use spot::{Beam, BeamSampler, Spot, SpotDirection, SpotProfile};

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{Affine3A, Vec2, Vec3, Vec3A, Vec4};

use crate::geometry::{DirectionSample, Frame, Hit, Ray, Shape, offset_origin};
use crate::lanes::{Real, Vector};
use crate::sampling::{concentric_disk, cosine_hemisphere, uniform_sphere};
use crate::texture::Texture;

#[derive(Debug, Clone)]
pub enum Light {
    /// `power` acts as radiant intensity: irradiance power / r^2 (the course's Lab 4 formula).
    Point { position: Vec3, power: Vec3 },
    /// An emissive primitive: its shape, its material's `emission` (a glowing pattern's
    /// brightest, where `pattern` makes it at each point), the beam that shapes it, if any, and
    /// whether it leaves both sides (`light::emitted`), its surface area, and its index in
    /// `Scene::primitives` (which names hits on it).
    Area {
        shape: Shape,
        emission: Vec3,
        pattern: Option<Box<GlowPattern>>,
        beam: Option<BeamSampler>,
        two_sided: bool,
        area: f32,
        primitive: u32,
    },
    /// Radiance arriving from infinitely far away (a sky): rays that leave the scene find it.
    Environment(Box<Environment>),
    /// A point light with an angular profile (`light::spot`).
    Spot(Spot),
    /// A light from infinitely far away, travelling along unit `direction`, giving `irradiance`
    /// on a surface facing it; its photons leave a disk covering the sphere (`centre`,
    /// `radius`) that bounds the scene's finite objects.
    Distant { direction: Vec3, irradiance: Vec3, centre: Vec3, radius: f32 },
    /// A delta light with POV-Ray's modifiers: what lies within `bulb` of it (`looks_like`'s
    /// object) does not block it, so shadow rays stop and photons start that far from it; a
    /// `shadowless` light's direct light is never blocked.
    Modified { light: Box<Light>, bulb: f32, shadowless: bool },
}

/// A glow that varies over an area light (pbrt-v4's `DiffuseAreaLight` with an image): its
/// emission at a point is `pov_glow` of `glow`, `colour` and `through` (grey) there, in the
/// object's own space (`to_object` takes world points there). The light is sampled uniformly
/// by area all the same, as pbrt's is: the density is the shape's, each sample's radiance the
/// pattern's at its point.
#[derive(Debug, Clone)]
pub struct GlowPattern {
    pub glow: Vec3,
    pub colour: Arc<Texture>,
    pub through: Arc<Texture>,
    pub to_object: Affine3A,
}

/// An area light's emission at `point` on it: `emission`, or its pattern's there.
#[inline]
pub fn emission_at(emission: Vec3, pattern: Option<&GlowPattern>, point: Vec3) -> Vec3 {
    match pattern {
        None => emission,
        Some(p) => {
            let q = p.to_object.transform_point3(point);
            pov_glow(p.glow, p.colour.eval(q), p.through.grey(q))
        }
    }
}

/// POV-Ray's glow (`emission`, and `ambient` over `diffuse 0`) where its pigment has `colour`
/// and lets `through` of the light through (filter + transmit): `glow` times the colour, faded
/// as POV-Ray fades it, by 1 − f − t (`rgbt <1, 1, 1, 0.8>` glows 0.2).
#[inline]
pub fn pov_glow(glow: Vec3, colour: Vec3, through: f32) -> Vec3 {
    glow * colour * (1.0 - through).max(0.0)
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

/// A segment from a surface towards a light: a ray up to `t_max`.
#[derive(Debug, Clone, Copy)]
pub struct ShadowRay {
    origin: Vec3A,
    /// The unit direction in x, y, z and `t_max` in w, written by one 16-byte store: a `t_max`
    /// of its own, 4 bytes before 12 of padding, was read back as 16 when the light sample was
    /// copied, a load that cannot be forwarded from the narrower store (11 % of S1's render loop).
    dir_t_max: Vec4,
}

impl ShadowRay {
    #[inline]
    pub fn new(ray: Ray, t_max: f32) -> Self {
        ShadowRay { origin: ray.origin, dir_t_max: ray.dir.extend(t_max) }
    }

    #[inline]
    pub fn ray(&self) -> Ray {
        Ray { origin: self.origin, dir: Vec3A::from_vec4(self.dir_t_max) }
    }

    #[inline]
    pub fn t_max(&self) -> f32 {
        self.dir_t_max.w
    }
}

impl Light {
    pub fn is_delta(&self) -> bool {
        match self {
            Light::Point { .. } | Light::Spot(_) | Light::Distant { .. } => true,
            Light::Area { .. } | Light::Environment(_) => false,
            Light::Modified { light, .. } => light.is_delta(),
        }
    }

    /// The sphere (centre, radius) across which the light's photons leave a disc upstream, for
    /// a light from infinitely far away (a distant light, the environment); `None` for a
    /// light whose photons leave it in every direction it shines, which reach everything it lights.
    pub fn photon_sphere(&self) -> Option<(Vec3, f32)> {
        match self {
            &Light::Distant { centre, radius, .. } => Some((centre, radius)),
            Light::Environment(sky) => Some(sky.sphere()),
            Light::Point { .. } | Light::Area { .. } | Light::Spot(_) => None,
            Light::Modified { light, .. } => light.photon_sphere(),
        }
    }

    /// Emitted power (mean over RGB), for choosing lights in proportion to it (`power_rgb`).
    pub fn power(&self) -> f32 {
        self.power_rgb().element_sum() / 3.0
    }

    /// Emitted power per channel: 4 pi I for a point light, pi A Le for a one-sided diffuse
    /// emitter (Le cos integrated over the hemisphere is pi Le), twice that for a two-sided
    /// one, a spotlight's intensity
    /// integrated over its beam (for a beamed emitter, of intensity A times its emission).
    /// A glowing pattern's is reckoned from its brightest emission: a bound, for choosing
    /// lights and sharing photons (each photon carries the emission where it leaves).
    pub fn power_rgb(&self) -> Vec3 {
        match self {
            Light::Point { power, .. } => 4.0 * PI * *power,
            Light::Area { emission, beam: None, two_sided, area, .. } => {
                let sides = if *two_sided { 2.0 } else { 1.0 };
                sides * PI * *area * *emission
            }
            Light::Area { emission, beam: Some(beam), area, .. } => {
                beam.solid_angle() * *area * *emission
            }
            Light::Environment(sky) => sky.power_rgb(),
            Light::Spot(spot) => spot.power_rgb(),
            Light::Distant { irradiance, radius, .. } => PI * radius * radius * *irradiance,
            Light::Modified { light, .. } => light.power_rgb(),
        }
    }

    /// Samples light arriving at `hit` from this light, unless something is in the way (see
    /// `LightSample::shadow`); `None` if it arrives from behind the emitter or carries nothing.
    /// Always inlined into next-event estimation: out of line, its call and the copy of its
    /// result cost a tenth of its work.
    #[inline(always)]
    pub fn sample(&self, hit: &Hit, u: Vec2) -> Option<LightSample> {
        let (target, wi, li, pdf, is_delta) = match self {
            &Light::Point { position, power } => {
                let (wi, li) = point_towards(position.into(), power.into(), hit.point.into());
                (position, wi.into(), li.into(), 1.0, true)
            }
            Light::Area { .. } if self.never_lights(hit.primitive) => return None,
            &Light::Area {
                ref shape, emission, ref pattern, ref beam, two_sided, area, ..
            } => {
                let DirectionSample { point, normal, error, wi, pdf } =
                    shape.sample_from(hit.point, area, u)?;
                let emission = emission_at(emission, pattern.as_deref(), point);
                let le = emitted(emission, beam.as_ref().map(|b| &b.beam), two_sided, normal, -wi);
                if le == Vec3::ZERO || !usable_pdf(pdf) {
                    return None;
                }
                (aim(point.into(), normal.into(), error, wi.into()).into(), wi, le, pdf, false)
            }
            Light::Environment(sky) => {
                let s = sky.sample(u).filter(|s| s.le != Vec3::ZERO)?;
                let ray = Ray::new(offset_origin(hit, s.wi), s.wi);
                let shadow = ShadowRay::new(ray, f32::INFINITY);
                return Some(LightSample {
                    wi: s.wi,
                    li: s.le,
                    pdf: s.pdf,
                    is_delta: false,
                    shadow,
                });
            }
            Light::Spot(spot) => {
                let to_light = spot.position - hit.point;
                let distance_squared = to_light.length_squared();
                let wi = to_light / distance_squared.sqrt();
                let li = spot.intensity_towards(-wi) / distance_squared;
                if li == Vec3::ZERO {
                    return None;
                }
                (spot.position, wi, li, 1.0, true)
            }
            &Light::Distant { direction, irradiance, .. } => {
                let wi = -direction;
                let ray = Ray::new(offset_origin(hit, wi), wi);
                let shadow = ShadowRay::new(ray, f32::INFINITY);
                return Some(LightSample { wi, li: irradiance, pdf: 1.0, is_delta: true, shadow });
            }
            Light::Modified { light, bulb, shadowless } => {
                return modified_sample(light, *bulb, *shadowless, hit, u);
            }
        };
        let shadow = shadow_ray(hit, target, wi);
        Some(LightSample { wi, li, pdf, is_delta, shadow })
    }

    /// Whether this is an emitter that never lights a point of `primitive`: a one-sided emitter
    /// of any shape but the torus is convex or emits outwards only, so it never lights itself
    /// (and a sample from its own surface would be degenerate). A two-sided sphere lights its
    /// own inside.
    #[inline(always)]
    pub fn never_lights(&self, primitive: u32) -> bool {
        match self {
            Light::Area { primitive: own, shape, two_sided, .. } => {
                !two_sided && *own == primitive && !matches!(shape, Shape::Torus(_))
            }
            Light::Point { .. }
            | Light::Spot(_)
            | Light::Distant { .. }
            | Light::Environment(_)
            | Light::Modified { .. } => false,
        }
    }

    /// The solid-angle density with which `sample` from `from` returns the direction towards
    /// `on_light`, a hit on this (area) light. (The environment's is `Environment::pdf`, of a
    /// direction.)
    pub fn pdf(&self, from: Vec3, on_light: &Hit) -> f32 {
        match self {
            Light::Area { shape, area, .. } => {
                shape.pdf_from(from, *area, on_light.point, on_light.normal)
            }
            Light::Point { .. }
            | Light::Spot(_)
            | Light::Distant { .. }
            | Light::Environment(_) => 0.0,
            Light::Modified { light, .. } => light.pdf(from, on_light),
        }
    }
}

/// A photon's start: where it leaves its light, in which direction, and the power it carries.
#[derive(Debug, Clone, Copy)]
pub struct EmissionSample {
    pub ray: Ray,
    /// Le cos / (pdf_A pdf_w) over the number of photons the light emits: its power over that
    /// number, the same for every photon but a spotlight's and an area spotlight's (whose
    /// density follows the profile bin by bin) and a textured sky's, whose mean it is.
    pub power: Vec3,
}

impl Light {
    /// One of `photons` photons from this light: a point light's uniform over the sphere
    /// (4 pi I / n each), an area light's from a point uniform by area, cosine-weighted over
    /// the hemisphere its emitting side faces (Le cos / (1/A cos/pi) = pi A Le, / n each; a
    /// two-sided one's side chosen with probability 1/2, 2 pi A Le). So
    /// `photons` photons carry exactly `power_rgb`; a spotlight's leave with density following
    /// its profile (an area spotlight's from a point uniform by area, then so), a distant light's from a disk across the scene's bounding sphere, the
    /// environment's from a disc facing a direction it samples (`Environment::sample_photon`).
    /// `None` where the shape or profile has no sample.
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
            &Light::Area {
                ref shape, emission, ref pattern, beam: None, two_sided, area, ..
            } => {
                let s = shape.sample_area(u_point)?;
                let emission = emission_at(emission, pattern.as_deref(), s.point);
                // A two-sided emitter's side: the first half of u.x the front, the second the
                // back, each half stretched back to [0, 1).
                let (side, sides, u) = match two_sided {
                    true if u_direction.x >= 0.5 => {
                        (-s.normal, 2.0, Vec2::new(2.0 * u_direction.x - 1.0, u_direction.y))
                    }
                    true => (s.normal, 2.0, Vec2::new(2.0 * u_direction.x, u_direction.y)),
                    false => (s.normal, 1.0, u_direction),
                };
                let dir = Frame::from_normal(side).to_world(cosine_hemisphere(u));
                // Leave just off the surface, on the side that emits.
                let ray = Ray::new(s.point + side * s.error, dir);
                Some(EmissionSample { ray, power: sides * PI * area * emission * share })
            }
            Light::Area { shape, emission, pattern, beam: Some(beam), area, .. } => {
                // Each bit of area is a point spotlight: Le |cos| / (pdf_A pdf_w) is
                // A emission P / pdf_w, the point spotlight's weight times A.
                let s = shape.sample_area(u_point)?;
                let sampled = beam.sample(u_direction)?;
                let dir = sampled.direction;
                let side = if s.normal.dot(dir) < 0.0 { -s.normal } else { s.normal };
                let ray = Ray::new(s.point + side * s.error, dir);
                let emission = emission_at(*emission, pattern.as_deref(), s.point);
                let intensity = *area * emission * beam.beam.towards(dir);
                Some(EmissionSample { ray, power: intensity / sampled.pdf * share })
            }
            Light::Environment(sky) => {
                let (origin, dir, power) = sky.sample_photon(u_point, u_direction, share)?;
                Some(EmissionSample { ray: Ray::new(origin, dir), power })
            }
            Light::Spot(spot) => {
                let sampled = spot.sample_direction(u_direction)?;
                let ray = Ray::new(spot.position, sampled.direction);
                let power = spot.intensity_towards(sampled.direction) / sampled.pdf * share;
                Some(EmissionSample { ray, power })
            }
            &Light::Distant { direction, irradiance, centre, radius } => {
                let across = concentric_disk(u_point) * radius;
                let frame = Frame::from_normal(direction);
                // Upstream of the bounding sphere: the disk is outside it.
                let origin = centre + frame.to_world(across.extend(-radius));
                let power = PI * radius * radius * irradiance * share;
                Some(EmissionSample { ray: Ray::new(origin, direction), power })
            }
            Light::Modified { light, bulb, .. } => {
                let mut sample = light.sample_emission(photons, u_point, u_direction)?;
                // An unbounded object (a plane) has no outside to start from.
                if bulb.is_finite() {
                    sample.ray = Ray::new(sample.ray.at(*bulb), sample.ray.dir.into());
                }
                Some(sample)
            }
        }
    }
}

/// `Light::sample` of a light with POV-Ray's modifiers (`Light::Modified`): its own light's
/// sample, the shadow ray shortened by `bulb`, or never blocked where `shadowless`. Never
/// inlined: were `sample` to call itself, it could not be inlined anywhere.
#[inline(never)]
fn modified_sample(
    light: &Light,
    bulb: f32,
    shadowless: bool,
    hit: &Hit,
    u: Vec2,
) -> Option<LightSample> {
    let mut sample = light.sample(hit, u)?;
    let t_max = if shadowless { 0.0 } else { (sample.shadow.t_max() - bulb).max(0.0) };
    sample.shadow = ShadowRay::new(sample.shadow.ray(), t_max);
    Some(sample)
}

/// Radiance an emitter sends towards unit `wo` from a point with normal `n`. Without a beam,
/// `emission` towards the normal's side only (a diffuse emitter), or towards both sides where
/// `two_sided` (POV-Ray's glow). With one, each bit of area dA
/// is a point spotlight of intensity `emission` dA on the beam's axis, shining both ways:
/// `emission` · P(wo) / |wo · n|, so that a flat emitter of area A has the intensity A ·
/// `emission` · P of a point spotlight, whatever its size (POV-Ray's area spotlight, a grid of
/// point spotlights, `docs/povray.md`).
#[inline]
pub fn emitted(emission: Vec3, beam: Option<&Beam>, two_sided: bool, n: Vec3, wo: Vec3) -> Vec3 {
    let cos = n.dot(wo);
    match beam {
        None if faces(two_sided, cos) => emission,
        None => Vec3::ZERO,
        Some(beam) => {
            let share = beam.towards(wo);
            if share > 0.0 && cos != 0.0 { emission * (share / cos.abs()) } else { Vec3::ZERO }
        }
    }
}

/// The segment from `hit` to `target`.
#[inline]
fn shadow_ray(hit: &Hit, target: Vec3, wi: Vec3) -> ShadowRay {
    let origin = offset_origin(hit, wi);
    let (dir, t_max) = shadow_segment(origin.into(), target.into());
    ShadowRay::new(Ray::new(origin, dir.into()), t_max)
}

// The kernels of a light sample, written once over `Real`: `Light::sample` computes them for one
// point, `LanesLight::sample` for a point per lane.

/// A point light at `position` of intensity `power` seen from `from`: the unit direction
/// towards it and the radiance arriving, intensity / r^2.
#[inline(always)]
fn point_towards<F: Real>(
    position: Vector<F>,
    power: Vector<F>,
    from: Vector<F>,
) -> (Vector<F>, Vector<F>) {
    let to_light = position - from;
    let distance_squared = to_light.length_squared();
    (to_light / distance_squared.sqrt(), power / distance_squared)
}

/// Whether a diffuse emitter whose normal makes cosine `cos` with a direction emits that way:
/// towards its normal's side, or either side where `two_sided` (`emitted`).
#[inline(always)]
fn faces<F: Real>(two_sided: bool, cos: F) -> F::Mask {
    let front = cos.gt(F::ZERO);
    if two_sided { front | cos.lt(F::ZERO) } else { front }
}

/// Whether a solid-angle density can weigh a sample: a positive finite number.
#[inline(always)]
fn usable_pdf<F: Real>(pdf: F) -> F::Mask {
    pdf.gt(F::ZERO) & pdf.lt(F::splat(f32::INFINITY))
}

/// Where a shadow ray aims at a point of an emitter (`normal`, error bound `error`) it meets
/// along `wi`: just off the surface, on the side seen, so that it does not shadow itself.
#[inline(always)]
fn aim<F: Real>(point: Vector<F>, normal: Vector<F>, error: F, wi: Vector<F>) -> Vector<F> {
    let seen = Vector::select(normal.dot(wi).lt(F::ZERO), normal, -normal);
    point + seen * error
}

/// The segment from `origin` to `target`: its unit direction and its length, stopped just short
/// of the target so that the light's own surface does not occlude it.
#[inline(always)]
fn shadow_segment<F: Real>(origin: Vector<F>, target: Vector<F>) -> (Vector<F>, F) {
    let to_target = target - origin;
    let distance = to_target.length_squared().sqrt();
    (to_target / distance, distance * F::splat(1.0 - 1e-4))
}

/// Whether photons leaving a disc of radius `radius` at distance `radius` from `centre` towards
/// it (`Light::photon_sphere`) reach `point` from direction `wi` (towards the light) when
/// nothing is in the way: the line through `point` along `wi` must cross the disc, upstream of
/// `point`. Inside the sphere every direction does.
pub fn photons_reach(centre: Vec3, radius: f32, point: Vec3, wi: Vec3) -> bool {
    let offset = point - centre;
    let along = offset.dot(wi);
    along < radius && (offset - along * wi).length_squared() < radius * radius
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// Every photon of a distant light and of the sky reaches the points along its ray from
    /// where it starts, by `photons_reach`; a point outside the sphere is reached from the
    /// directions that cross it and not from those that miss it.
    #[test]
    fn photons_reach_where_the_lights_photons_go() {
        let (centre, radius) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        let distant = Light::Distant {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            irradiance: Vec3::ONE,
            centre,
            radius,
        };
        let sky = Light::Environment(Box::new(Environment::constant(Vec3::ONE, centre, radius)));
        for light in [distant, sky] {
            assert_eq!(light.photon_sphere(), Some((centre, radius)));
            for i in 0..1000 {
                let mut s = Sampler::new(1, i, 0);
                let photon = light.sample_emission(1000, s.next_2d(), s.next_2d()).unwrap();
                for t in [0.01, 1.0, 3.0, 10.0] {
                    let point = photon.ray.at(t);
                    let wi = -Vec3::from(photon.ray.dir);
                    assert!(photons_reach(centre, radius, point, wi), "{point} from {wi}");
                }
            }
        }
        let outside = centre + Vec3::new(5.0, 0.0, 0.0);
        assert!(photons_reach(centre, radius, outside, -Vec3::X), "a line through the sphere");
        assert!(!photons_reach(centre, radius, outside, Vec3::X), "the disc is downstream");
        assert!(!photons_reach(centre, radius, outside, Vec3::Y), "a line beside the sphere");
        assert!(photons_reach(centre, radius, centre + Vec3::splat(0.5), -Vec3::Y), "inside");
    }

    /// A unit sphere glowing in checkers of red and blue (one colour to each octant, so half
    /// its area each): its photons, each carrying the radiance where it leaves, carry π A times
    /// the mean radiance, π 4π <1, 0, 1>, not its brightest, π 4π <2, 0, 2>.
    #[test]
    fn a_patterned_glow_s_photons_carry_its_mean_radiance() {
        use crate::graph::{Pattern, TextureNode};
        let (red, blue) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
        let checker = TextureNode {
            pattern: Pattern::Checker(
                Box::new(TextureNode::solid(red)),
                Box::new(TextureNode::solid(blue)),
            ),
            transforms: Vec::new(),
        };
        let colour = Texture::new(&checker, &mut |_| unreachable!("no image")).unwrap();
        let area = 4.0 * PI;
        let light = Light::Area {
            shape: Shape::Sphere { center: Vec3::ZERO, radius: 1.0 },
            emission: red + blue,
            pattern: Some(Box::new(GlowPattern {
                glow: Vec3::ONE,
                colour: Arc::new(colour),
                through: Arc::new(
                    Texture::new(&TextureNode::solid(Vec3::ZERO), &mut |_| {
                        unreachable!("no image")
                    })
                    .unwrap(),
                ),
                to_object: Affine3A::IDENTITY,
            })),
            beam: None,
            two_sided: false,
            area,
            primitive: 0,
        };
        let photons = 16384;
        let carried: Vec3 = (0..photons)
            .map(|i| {
                let mut s = Sampler::new(1, 0, u64::from(i));
                light.sample_emission(photons, s.next_2d(), s.next_2d()).unwrap().power
            })
            .sum();
        let expected = PI * area * Vec3::new(1.0, 0.0, 1.0);
        assert!((carried - expected).abs().max_element() < 0.03 * expected.x, "{carried}");
    }
}
