//! A light sampled at a bounce's hits together, one per lane, by the kernels `Light::sample`
//! runs for one hit: each lane's sample is that one's, bit for bit.

use glam::Vec3;

use super::{Light, LightSample, ShadowRay, aim, faces, point_towards, shadow_segment, usable_pdf};
use crate::geometry::{Ray, Shape, planar_coordinates_of, towards_by_area};
use crate::lanes::{Floats, HitLanes, Lane, Mask, MaskLanes, Vec3Lanes};

/// `Light::sample` in each lane (`Light::sample_lanes`).
pub struct LightLanes {
    wi: Vec3Lanes,
    li: Vec3Lanes,
    pdf: Floats,
    is_delta: bool,
    /// The lanes with a sample.
    found: Mask,
    /// The shadow rays: from `origin` along `dir` up to `t_max`.
    origin: Vec3Lanes,
    dir: Vec3Lanes,
    t_max: Floats,
    /// A one-sided emitter's primitive, which never lights itself.
    itself: Option<u32>,
}

impl LightLanes {
    /// The sample of `lane`, whose hit is on `primitive`.
    #[inline(always)]
    pub fn lane(&self, lane: usize, primitive: u32) -> Option<LightSample> {
        if !self.found.lane(lane) || self.itself == Some(primitive) {
            return None;
        }
        let ray = Ray::new(self.origin.lane(lane), self.dir.lane(lane));
        Some(LightSample {
            wi: self.wi.lane(lane),
            li: self.li.lane(lane),
            pdf: self.pdf.lane(lane),
            is_delta: self.is_delta,
            shadow: ShadowRay { ray, t_max: self.t_max.lane(lane) },
        })
    }
}

impl Light {
    /// `sample` at each lane's hit of `hits`, from that lane's point `(u_x, u_y)`, where the
    /// light's sample is written over lanes: a point light's, and an area light's without a
    /// beam on a triangle or a quad. `None` for the others (a disk's warp takes sines and
    /// cosines, which lanes do not round as `f32` does), sampled one lane at a time.
    #[inline(always)]
    pub fn sample_lanes(
        &self,
        hits: &HitLanes,
        (u_x, u_y): (Floats, Floats),
    ) -> Option<LightLanes> {
        let from = hits.point;
        let (target, wi, li, pdf, found, is_delta, itself) = match *self {
            Light::Point { position, power } => {
                let position = Vec3Lanes::splat(position);
                let (wi, li) = point_towards(position, Vec3Lanes::splat(power), from);
                (position, wi, li, Floats::ONE, !Mask::none(), true, None)
            }
            Light::Area {
                shape: Shape::Planar(ref planar),
                emission,
                beam: None,
                two_sided,
                area,
                primitive,
            } if emission != Vec3::ZERO => {
                let (s, t) = planar_coordinates_of(planar.kind, u_x, u_y)?;
                let point = planar.point_at(s, t);
                let normal = Vec3Lanes::splat(planar.normal);
                let (wi, pdf) = towards_by_area(point, normal, from, Floats::splat(area));
                let found = faces(two_sided, normal.dot(-wi)) & usable_pdf(pdf);
                let target = aim(point, normal, Floats::splat(planar.error()), wi);
                let itself = (!two_sided).then_some(primitive);
                (target, wi, Vec3Lanes::splat(emission), pdf, found, false, itself)
            }
            _ => return None,
        };
        let origin = hits.offset_origin(wi);
        let (dir, t_max) = shadow_segment(origin, target);
        Some(LightLanes { wi, li, pdf, is_delta, found, origin, dir, t_max, itself })
    }
}
