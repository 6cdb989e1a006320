//! A shape sampled by the directions it fills as seen from a point, for next-event estimation:
//! a sphere seen from outside by the cone it subtends (pbrt-v4, 6.2.4), every other shape
//! uniformly by area with the density converted to solid angle.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::{Frame, Shape, SurfaceSample, sphere_error};
use crate::lanes::{Real, Vector};

/// A point on a shape drawn from `from`: the point, the shape's unit normal and error bound
/// there, the unit direction towards it and that direction's solid-angle density.
#[derive(Debug, Clone, Copy)]
pub struct DirectionSample {
    pub point: Vec3,
    pub normal: Vec3,
    pub error: f32,
    pub wi: Vec3,
    pub pdf: f32,
}

impl Shape {
    /// A point of the shape, of surface `area`, drawn by direction from `from`; `None` where
    /// the shape has no area sample. Always inlined for a planar shape (most area lights),
    /// the other shapes out of line: out of line, with every shape's sample in it, its call
    /// cost a planar light's sample a third of its instructions (callgrind, S3).
    #[inline(always)]
    pub fn sample_from(&self, from: Vec3, area: f32, u: Vec2) -> Option<DirectionSample> {
        match self {
            Shape::Planar(planar) => Some(by_area(planar.sample(u), from, area)),
            shape => shape.sample_curved_from(from, area, u),
        }
    }

    /// `sample_from` of a shape that is not planar.
    #[inline(never)]
    fn sample_curved_from(&self, from: Vec3, area: f32, u: Vec2) -> Option<DirectionSample> {
        match *self {
            Shape::Sphere { center, radius } if outside(center, radius, from) => {
                Some(sample_sphere_cone(center, radius, from, u))
            }
            ref shape => Some(by_area(shape.sample_area(u)?, from, area)),
        }
    }

    /// The solid-angle density with which `sample_from(from, area, ·)` returns the direction
    /// towards `point`, on the shape where its normal is `normal`.
    #[inline]
    pub fn pdf_from(&self, from: Vec3, area: f32, point: Vec3, normal: Vec3) -> f32 {
        match *self {
            Shape::Sphere { center, radius } if outside(center, radius, from) => {
                1.0 / cone_solid_angle(center, radius, from)
            }
            _ => {
                let to_point = point - from;
                let cos = normal.dot(to_point.normalize()).abs();
                to_point.length_squared() / (area * cos)
            }
        }
    }
}

/// Whether `from` is clearly outside the sphere, where its cone is sampled: a point on the
/// sphere itself (a two-sided emitter lighting its own inside) takes area sampling, which sees
/// the far side from within.
fn outside(center: Vec3, radius: f32, from: Vec3) -> bool {
    center.distance(from) > radius * (1.0 + 1e-4)
}

/// A point `s` drawn uniformly over a shape of surface `area`, seen from `from`: its direction
/// and that direction's density, the area density 1/A in solid angle, r^2 / (A cos).
#[inline(always)]
fn by_area(s: SurfaceSample, from: Vec3, area: f32) -> DirectionSample {
    let (wi, pdf) = towards_by_area(s.point.into(), s.normal.into(), from.into(), area);
    DirectionSample { point: s.point, normal: s.normal, error: s.error, wi: wi.into(), pdf }
}

/// `by_area` written once over `Real`: the unit direction from `from` to `point` (where the
/// normal is `normal`) and its density, for one point or a point per lane.
#[inline(always)]
pub fn towards_by_area<F: Real>(
    point: Vector<F>,
    normal: Vector<F>,
    from: Vector<F>,
    area: F,
) -> (Vector<F>, F) {
    let to_point = point - from;
    let distance_squared = to_point.length_squared();
    let wi = to_point / distance_squared.sqrt();
    (wi, distance_squared / (area * normal.dot(wi).abs()))
}

/// Solid angle of the cone of directions from `from` that meet the sphere:
/// 2 pi (1 - cos theta_max), with 1 - cos written as sin^2 / (1 + cos) for small cones.
fn cone_solid_angle(center: Vec3, radius: f32, from: Vec3) -> f32 {
    let sin2_max = radius * radius / center.distance_squared(from);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    2.0 * PI * sin2_max / (1.0 + cos_max)
}

/// A direction uniform in the cone the sphere subtends (pbrt-v4, 6.2.4), and the point it meets.
fn sample_sphere_cone(center: Vec3, radius: f32, from: Vec3, u: Vec2) -> DirectionSample {
    let axis = center - from;
    let distance = axis.length();
    let sin2_max = radius * radius / (distance * distance);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    let one_minus_cos_max = sin2_max / (1.0 + cos_max);
    let cos_theta = 1.0 - u.x * one_minus_cos_max;
    let sin2_theta = (1.0 - cos_theta * cos_theta).max(0.0);
    let phi = 2.0 * PI * u.y;
    let sin_theta = sin2_theta.sqrt();
    let wi = Frame::from_normal(axis / distance).to_world(Vec3::new(
        sin_theta * phi.cos(),
        sin_theta * phi.sin(),
        cos_theta,
    ));
    // Nearest intersection of from + t wi with the sphere; at the silhouette the root is 0.
    let t =
        distance * cos_theta - (radius * radius - distance * distance * sin2_theta).max(0.0).sqrt();
    let normal = (from + t * wi - center).normalize();
    let point = center + radius * normal;
    DirectionSample {
        point,
        normal,
        error: sphere_error(center, radius),
        wi: (point - from).normalize(),
        pdf: 1.0 / (2.0 * PI * one_minus_cos_max),
    }
}
