//! A light sampled from a point per lane at once, by the kernels `Light::sample` runs for one
//! point: each lane's sample is that one's, bit for bit. Point lights and area lights of one
//! emission on a triangle, a quad or a disk without a hole.

use glam::Vec3;

use super::{Light, aim, faces, point_towards, shadow_segment, usable_pdf};
use crate::geometry::{Planar, Shape, planar_coordinates_of, towards_by_area};
use crate::lanes::{Floats, Mask, MaskLanes, Vec3Lanes, offset_point};

/// A light whose sample is written over lanes (`Light::in_lanes`).
#[derive(Clone, Copy)]
pub enum LanesLight<'a> {
    Point {
        position: Vec3,
        power: Vec3,
    },
    /// An area light without a pattern or a beam, whose emission is not zero.
    Planar {
        planar: &'a Planar,
        emission: Vec3,
        two_sided: bool,
        area: f32,
    },
}

/// `Light::sample` in each lane: where it found one (`found`), the direction, radiance and
/// density, and the shadow ray from `origin` along `dir` up to `t_max`.
pub struct LightLanes {
    pub found: Mask,
    pub wi: Vec3Lanes,
    pub li: Vec3Lanes,
    pub pdf: Floats,
    pub is_delta: bool,
    pub origin: Vec3Lanes,
    pub dir: Vec3Lanes,
    pub t_max: Floats,
}

impl Light {
    /// This light as one whose sample is written over lanes, if it is one.
    #[inline(always)]
    pub fn in_lanes(&self) -> Option<LanesLight<'_>> {
        match *self {
            Light::Point { position, power } => Some(LanesLight::Point { position, power }),
            Light::Area {
                shape: Shape::Planar(ref planar),
                emission,
                pattern: None,
                beam: None,
                two_sided,
                area,
                ..
            } if emission != Vec3::ZERO
                // Not a disk with a hole, whose ring is sampled one point at a time.
                && planar_coordinates_of(planar.kind, planar.hole, 0.0, 0.0).is_some() =>
            {
                Some(LanesLight::Planar { planar, emission, two_sided, area })
            }
            Light::Area { .. }
            | Light::Environment(_)
            | Light::Spot(_)
            | Light::Distant { .. }
            | Light::Modified { .. } => None,
        }
    }
}

impl LanesLight<'_> {
    /// `Light::sample` at each lane's point (of geometric `normal` and error bound `error`),
    /// drawn by that lane's `u`: what `sample` gives where `found` is set, for a point that the
    /// light may light (`Light::never_lights`).
    #[inline(always)]
    pub fn sample(
        self,
        point: Vec3Lanes,
        normal: Vec3Lanes,
        error: Floats,
        (u_x, u_y): (Floats, Floats),
    ) -> LightLanes {
        let (target, wi, li, pdf, found, is_delta) = match self {
            LanesLight::Point { position, power } => {
                let position = Vec3Lanes::splat(position);
                let (wi, li) = point_towards(position, Vec3Lanes::splat(power), point);
                (position, wi, li, Floats::ONE, !Mask::none(), true)
            }
            LanesLight::Planar { planar, emission, two_sided, area } => {
                // (A disk with a hole, which `in_lanes` leaves out, would find none: NaN.)
                let (s, t) = planar_coordinates_of(planar.kind, planar.hole, u_x, u_y)
                    .unwrap_or((Floats::NAN, Floats::NAN));
                let on_light = planar.point_at(s, t);
                let light_normal = Vec3Lanes::splat(planar.normal);
                let (wi, pdf) = towards_by_area(on_light, light_normal, point, Floats::splat(area));
                let found = faces(two_sided, light_normal.dot(-wi)) & usable_pdf(pdf);
                let target = aim(on_light, light_normal, Floats::splat(planar.error()), wi);
                (target, wi, Vec3Lanes::splat(emission), pdf, found, false)
            }
        };
        let origin = offset_point(point, normal, error, wi);
        let (dir, t_max) = shadow_segment(origin, target);
        LightLanes { found, wi, li, pdf, is_delta, origin, dir, t_max }
    }
}
