//! Jensen's projection map (Jensen 2001, 6.1.3): caustic photons aimed at the surfaces that
//! can start a caustic (a lobe photon mapping follows: mirror, glass, near-specular), so that
//! an open scene's caustic map is dense where the caustics are.
//!
//! Each such surface is bounded by a sphere. A photon from a point x of a light picks one of
//! the cones from x onto the spheres with probability proportional to its solid angle Ω_i and
//! a direction uniform in it, so its density is p(ω) = c(ω) / Σ Ω_i, c(ω) the number of cones
//! holding ω; it carries the light's Le cos / (p_A p(ω)) over the photons the light emits, as
//! unaimed photons carry it over theirs. A path light -> specular -> diffuse leaves the light
//! towards a caster, inside some cone, so the caustic photons' expected power is the unaimed
//! ones' (`projected_caustics_carry_the_power_of_unprojected_ones`).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::aabb::Aabb;
use crate::geometry::{Frame, Ray, Shape};
use crate::light::{EmissionSample, Light, emission_at};
use crate::material::TransportMode;
use crate::sampling::{concentric_disk, uniform_sphere};
use crate::scene::Scene;

/// Beyond this many casters, one sphere around them all: each photon tests every cone.
const MOST_SPHERES: usize = 32;

/// Where caustic photons are aimed.
#[derive(Debug, Clone)]
pub enum Projection {
    /// A caster has no bounds (a mirror plane): every direction may start a caustic.
    Everywhere,
    /// The bounding spheres (centre, radius) of the casters.
    Spheres(Vec<(Vec3, f32)>),
}

impl Projection {
    /// The projection onto `scene`'s casters: the traced primitives with a lobe photon mapping
    /// follows (for a CSG object, on any of its operands' surfaces); `None` if there is none,
    /// so the scene has no caustic.
    pub fn of(scene: &Scene) -> Option<Projection> {
        let follows = |primitive: usize| {
            let material = &scene.materials[scene.primitives[primitive].material as usize];
            let bsdf = material.bsdf(Vec3::Z, TransportMode::Importance);
            !bsdf.flags().is_in(bsdf.gathered_lobes())
        };
        let mut boxes = Vec::new();
        for (i, primitive) in scene.primitives[..scene.traced_primitives()].iter().enumerate() {
            let operands = match &primitive.shape {
                Shape::Csg(csg) => {
                    csg.surfaces as usize..csg.surfaces as usize + csg.operands.len()
                }
                _ => 0..0,
            };
            if follows(i) || operands.into_iter().any(follows) {
                let Some(bounds) = primitive.shape.bounds() else {
                    return Some(Projection::Everywhere);
                };
                boxes.push(bounds);
            }
        }
        if boxes.len() > MOST_SPHERES {
            let all = boxes.iter().fold(boxes[0], |all, b| all.union(*b));
            boxes = vec![all];
        }
        let sphere = |b: &Aabb| (b.centroid(), 0.5 * b.extent().length() * (1.0 + 1e-4));
        (!boxes.is_empty()).then(|| Projection::Spheres(boxes.iter().map(sphere).collect()))
    }

    /// The share of `light`'s photons that the projection keeps, for sharing a caustic pass's
    /// photons among the lights: the cones' solid angle over the sphere's from a point light or
    /// spotlight (summed, at most 1); from far away (a distant light, the sky), the casters'
    /// shadows' area over the disc the light's photons cross (Σ r_i² / R², at most 1); 1 for
    /// area lights and when a caster is unbounded.
    pub fn share_of(&self, light: &Light) -> f32 {
        let Projection::Spheres(spheres) = self else { return 1.0 };
        let from_far = |radius: f32| {
            (spheres.iter().map(|&(_, r)| r * r).sum::<f32>() / (radius * radius)).min(1.0)
        };
        match light {
            Light::Point { position, .. } => {
                (cones(spheres, *position).total / (4.0 * PI)).min(1.0)
            }
            Light::Spot(spot) => (cones(spheres, spot.position).total / (4.0 * PI)).min(1.0),
            Light::Distant { radius, .. } => from_far(*radius),
            Light::Environment(sky) => from_far(sky.sphere().1),
            Light::Modified { light, .. } => self.share_of(light),
            Light::Area { .. } => 1.0,
        }
    }

    /// One of `photons` caustic photons from `light`, aimed at the casters: from a point light,
    /// a spotlight and an area light, diffuse or beamed (from its point drawn by `u_point`),
    /// along a cone onto a caster (`u_cone` picks the cone); from a distant light and the sky,
    /// along the direction `Light::sample_emission` draws, across a caster's shadow
    /// (`across_casters`). When a caster is unbounded, as `Light::sample_emission` draws it.
    pub fn sample_emission(
        &self,
        light: &Light,
        photons: u32,
        u_cone: f32,
        u_point: Vec2,
        u_direction: Vec2,
    ) -> Option<EmissionSample> {
        let Projection::Spheres(spheres) = self else {
            return light.sample_emission(photons, u_point, u_direction);
        };
        let share = 1.0 / photons as f32;
        match light {
            &Light::Point { position, power } => {
                let (dir, pdf) = cones(spheres, position).sample(u_cone, u_direction)?;
                Some(EmissionSample { ray: Ray::new(position, dir), power: power / pdf * share })
            }
            Light::Spot(spot) => {
                let (dir, pdf) = cones(spheres, spot.position).sample(u_cone, u_direction)?;
                let power = spot.intensity_towards(dir) / pdf * share;
                Some(EmissionSample { ray: Ray::new(spot.position, dir), power })
            }
            Light::Area { shape, emission, pattern, beam: None, two_sided, area, .. } => {
                let s = shape.sample_area(u_point)?;
                let emission = emission_at(*emission, pattern.as_deref(), s.point);
                let (dir, pdf) = cones(spheres, s.point).sample(u_cone, u_direction)?;
                // Le cos / (p_A p(ω)), with p_A = 1 / A; the back side emits nothing unless
                // the emitter is two-sided.
                let side = if *two_sided && s.normal.dot(dir) < 0.0 { -s.normal } else { s.normal };
                let cos = side.dot(dir);
                if cos <= 0.0 {
                    return None;
                }
                let ray = Ray::new(s.point + side * s.error, dir);
                Some(EmissionSample { ray, power: emission * cos * *area / pdf * share })
            }
            Light::Area { shape, emission, pattern, beam: Some(beam), area, .. } => {
                // A point spotlight at each bit of area (`Light::sample_emission`), aimed.
                let s = shape.sample_area(u_point)?;
                let (dir, pdf) = cones(spheres, s.point).sample(u_cone, u_direction)?;
                let emission = emission_at(*emission, pattern.as_deref(), s.point);
                let intensity = *area * emission * beam.beam.towards(dir);
                if intensity == Vec3::ZERO {
                    return None;
                }
                let side = if s.normal.dot(dir) < 0.0 { -s.normal } else { s.normal };
                let ray = Ray::new(s.point + side * s.error, dir);
                Some(EmissionSample { ray, power: intensity / pdf * share })
            }
            &Light::Distant { centre, radius, .. } => {
                let unaimed = light.sample_emission(photons, u_point, u_direction)?;
                across_casters(spheres, (centre, radius), unaimed, u_cone, u_point)
            }
            Light::Environment(sky) => {
                let unaimed = light.sample_emission(photons, u_point, u_direction)?;
                across_casters(spheres, sky.sphere(), unaimed, u_cone, u_point)
            }
            Light::Modified { light, bulb, .. } => {
                let mut sample =
                    self.sample_emission(light, photons, u_cone, u_point, u_direction)?;
                if bulb.is_finite() {
                    sample.ray = Ray::new(sample.ray.at(*bulb), sample.ray.dir.into());
                }
                Some(sample)
            }
        }
    }
}

/// A photon from far away moved across the casters. Unaimed (`unaimed`), it crosses the disc of
/// radius R facing its direction, R upstream of `centre`, uniformly: density 1 / (π R²). Each
/// caster's sphere casts on that disc a shadow of its radius r_i around its centre's projection;
/// the photon picks one with probability r_i² / Σ r_j² (`u_disc`) and a point uniform in it
/// (`u_point`), of density c(x) / Σ π r_j², c(x) the number of shadows holding x; its power,
/// L π R² / (pdf_ω n) unaimed, becomes L / (pdf_ω p(x) n): times Σ r_j² / (c(x) R²). A line
/// through a caster crosses its shadow, and one outside the disc meets nothing (the disc
/// covers the scene), so the caustic photons' expected power is the unaimed ones'.
fn across_casters(
    spheres: &[(Vec3, f32)],
    (centre, radius): (Vec3, f32),
    unaimed: EmissionSample,
    u_disc: f32,
    u_point: Vec2,
) -> Option<EmissionSample> {
    let dir = Vec3::from(unaimed.ray.dir);
    let frame = Frame::from_normal(dir);
    let shadows: Vec<(Vec2, f32)> =
        spheres.iter().map(|&(c, r)| (frame.to_local(c - centre).truncate(), r)).collect();
    let total: f32 = spheres.iter().map(|&(_, r)| r * r).sum();
    let mut below = u_disc * total;
    let chosen = (shadows.iter())
        .position(|&(_, r)| {
            below -= r * r;
            below < 0.0
        })
        .unwrap_or(shadows.len() - 1);
    let (middle, r) = shadows[chosen];
    let across = middle + concentric_disk(u_point) * r;
    if across.length_squared() > radius * radius {
        return None;
    }
    // The shadow drawn counts whatever rounding says.
    let holding = (shadows.iter().enumerate())
        .filter(|&(i, &(o, r))| i != chosen && o.distance_squared(across) <= r * r)
        .count()
        + 1;
    let origin = centre + frame.to_world(across.extend(-radius));
    let power = unaimed.power * (total / (holding as f32 * radius * radius));
    Some(EmissionSample { ray: Ray::new(origin, dir), power })
}

/// The cones from a point onto the spheres: their solid angles and their sum.
struct Cones<'a> {
    from: Vec3,
    spheres: &'a [(Vec3, f32)],
    solid_angles: Vec<f32>,
    total: f32,
}

/// The cones from `from`: a sphere holding `from` fills every direction (4π).
fn cones(spheres: &[(Vec3, f32)], from: Vec3) -> Cones<'_> {
    let solid_angles: Vec<f32> = spheres
        .iter()
        .map(|&(centre, radius)| {
            let sin2_max = radius * radius / centre.distance_squared(from);
            if sin2_max >= 1.0 {
                4.0 * PI
            } else {
                // 2π (1 - cos θ_max), 1 - cos written as sin² / (1 + cos) for small cones.
                2.0 * PI * sin2_max / (1.0 + (1.0 - sin2_max).sqrt())
            }
        })
        .collect();
    let total = solid_angles.iter().sum();
    Cones { from, spheres, solid_angles, total }
}

impl Cones<'_> {
    /// Whether the ray from `from` along unit `dir` meets sphere `i`.
    fn holds(&self, i: usize, dir: Vec3) -> bool {
        let (centre, radius) = self.spheres[i];
        let to_centre = centre - self.from;
        let along = to_centre.dot(dir);
        let off_axis = to_centre.length_squared() - along * along;
        self.solid_angles[i] >= 4.0 * PI || (along > 0.0 && off_axis <= radius * radius)
    }

    /// A direction: cone i with probability Ω_i / Σ Ω (`u_cone`), uniform in it (`u`); and its
    /// density c(ω) / Σ Ω, the cone drawn counted whatever rounding says.
    fn sample(&self, u_cone: f32, u: Vec2) -> Option<(Vec3, f32)> {
        if self.total.is_nan() || self.total <= 0.0 {
            return None;
        }
        let mut below = u_cone * self.total;
        let chosen = (self.solid_angles.iter())
            .position(|&omega| {
                below -= omega;
                below < 0.0
            })
            .unwrap_or(self.spheres.len() - 1);
        let (centre, radius) = self.spheres[chosen];
        let dir = if self.solid_angles[chosen] >= 4.0 * PI {
            uniform_sphere(u)
        } else {
            Shape::Sphere { center: centre, radius }.sample_from(self.from, 1.0, u)?.wi
        };
        let others = (0..self.spheres.len()).filter(|&i| i != chosen && self.holds(i, dir));
        Some((dir, (1 + others.count()) as f32 / self.total))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// Two overlapping spheres and one the point sits in, seen from a point: for each sphere,
    /// the mean of 1{ω meets it} / p(ω) over aimed directions is its cone's solid angle, in
    /// closed form (2π (1 - cos θ_max), 4π from inside), within 4 standard errors; and no
    /// direction misses every cone.
    #[test]
    fn aimed_directions_weigh_each_cone_as_its_solid_angle() {
        let from = Vec3::new(0.2, -0.1, 0.3);
        for spheres in [
            vec![(Vec3::new(0.0, 2.0, 0.0), 0.5), (Vec3::new(0.3, 2.2, 0.1), 0.4)],
            vec![(Vec3::new(3.0, 0.0, 0.0), 1.0), (Vec3::new(0.0, 0.0, 0.0), 0.5)],
        ] {
            let cones = cones(&spheres, from);
            let n = 200_000;
            let mut sums = vec![(0.0f64, 0.0f64); spheres.len()];
            for i in 0..n {
                let mut s = Sampler::new(3, 0, i);
                let (dir, pdf) = cones.sample(s.next_1d(), s.next_2d()).unwrap();
                assert!((0..spheres.len()).any(|j| cones.holds(j, dir)), "{dir} misses");
                for (j, sum) in sums.iter_mut().enumerate() {
                    let x = if cones.holds(j, dir) { 1.0 / f64::from(pdf) } else { 0.0 };
                    *sum = (sum.0 + x, sum.1 + x * x);
                }
            }
            for (j, &(centre, radius)) in spheres.iter().enumerate() {
                let d = f64::from(centre.distance(from));
                let r = f64::from(radius);
                let expected = if d <= r {
                    4.0 * std::f64::consts::PI
                } else {
                    2.0 * std::f64::consts::PI * (1.0 - (1.0 - r * r / (d * d)).sqrt())
                };
                let mean = sums[j].0 / n as f64;
                let error = ((sums[j].1 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - expected).abs() < 4.0 * error + 1e-9,
                    "sphere {j}: {mean} +- {error} against {expected}"
                );
            }
        }
    }

    /// The mean power per photon that meets each of `spheres` (the casters' bounds), aimed by
    /// the projection onto them and unaimed, with their standard errors: (aimed, its error,
    /// unaimed, its error) per sphere.
    fn power_towards_casters(light: &Light, spheres: &[(Vec3, f32)], n: u64) -> Vec<[f64; 4]> {
        let projection = Projection::Spheres(spheres.to_vec());
        let meets = |ray: &Ray, (centre, radius): (Vec3, f32)| {
            let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
            let along = (centre - o).dot(d);
            along > 0.0 && (centre - o).length_squared() - along * along <= radius * radius
        };
        let mean_and_error = |aimed: bool, sphere: (Vec3, f32)| {
            let (mut sum, mut squares) = (0.0f64, 0.0f64);
            for i in 0..n {
                let mut s = Sampler::new(5, u64::from(aimed), i);
                let (u_cone, u_point, u_direction) = (s.next_1d(), s.next_2d(), s.next_2d());
                let photon = if aimed {
                    projection.sample_emission(light, 1, u_cone, u_point, u_direction)
                } else {
                    light.sample_emission(1, u_point, u_direction)
                };
                let x = (photon.filter(|p| meets(&p.ray, sphere)))
                    .map_or(0.0, |p| f64::from(p.power.x));
                (sum, squares) = (sum + x, squares + x * x);
            }
            let mean = sum / n as f64;
            (mean, ((squares / n as f64 - mean * mean) / n as f64).sqrt())
        };
        (spheres.iter())
            .map(|&sphere| {
                let (aimed, aimed_error) = mean_and_error(true, sphere);
                let (unaimed, unaimed_error) = mean_and_error(false, sphere);
                [aimed, aimed_error, unaimed, unaimed_error]
            })
            .collect()
    }

    /// `light`'s aimed photons carry, towards each caster, the power its unaimed photons carry
    /// there, within 4 standard errors, with less noise.
    fn assert_aimed_photons_carry_the_unaimed_power(light: &Light, spheres: &[(Vec3, f32)]) {
        for (i, [aimed, aimed_error, unaimed, unaimed_error]) in
            power_towards_casters(light, spheres, 50_000).into_iter().enumerate()
        {
            let figures = format!(
                "sphere {i}: aimed {aimed} +- {aimed_error}, unaimed {unaimed} +- {unaimed_error}"
            );
            assert!(unaimed > 0.0, "{figures}");
            assert!((aimed - unaimed).abs() < 4.0 * aimed_error.hypot(unaimed_error), "{figures}");
            assert!(aimed_error < unaimed_error, "aiming must lower the noise: {figures}");
        }
    }

    /// Two overlapping casters, off the scene's centre.
    const CASTERS: [(Vec3, f32); 2] =
        [(Vec3::new(0.5, 1.0, 0.0), 0.4), (Vec3::new(0.7, 1.2, 0.2), 0.3)];

    /// A spherical area light's aimed photons carry the power its unaimed ones carry (Le cos A
    /// over the cosine-weighted hemisphere: π A Le).
    #[test]
    fn aimed_area_photons_carry_the_unaimed_power_towards_casters() {
        let light = Light::Area {
            shape: Shape::Sphere { center: Vec3::ZERO, radius: 0.3 },
            emission: Vec3::ONE,
            pattern: None,
            beam: None,
            two_sided: false,
            area: 4.0 * PI * 0.09,
            primitive: 0,
        };
        assert_aimed_photons_carry_the_unaimed_power(&light, &CASTERS);
    }

    /// So do a beamed area light's (a point spotlight at each bit of area), a distant light's
    /// and the sky's (across a disc covering the scene; the casters off the disc's centre, so
    /// their shadows move with the direction).
    #[test]
    fn aimed_beamed_distant_and_sky_photons_carry_the_unaimed_power_towards_casters() {
        use crate::light::{Beam, BeamSampler, Environment, SpotProfile};
        let beam = Beam { axis: Vec3::Y, profile: SpotProfile::from_degrees(30.0, 60.0, 1.0) };
        let beamed = Light::Area {
            shape: Shape::Sphere { center: Vec3::ZERO, radius: 0.3 },
            emission: Vec3::ONE,
            pattern: None,
            beam: Some(BeamSampler::new(beam)),
            two_sided: false,
            area: 4.0 * PI * 0.09,
            primitive: 0,
        };
        assert_aimed_photons_carry_the_unaimed_power(&beamed, &CASTERS);
        let (centre, radius) = (Vec3::new(0.2, 0.5, -0.1), 2.0);
        let direction = Vec3::new(-0.3, -1.0, 0.2).normalize();
        let distant = Light::Distant { direction, irradiance: Vec3::ONE, centre, radius };
        assert_aimed_photons_carry_the_unaimed_power(&distant, &CASTERS);
        let sky = Light::Environment(Box::new(Environment::constant(Vec3::ONE, centre, radius)));
        assert_aimed_photons_carry_the_unaimed_power(&sky, &CASTERS);
    }
}
