//! Path vertices on a lone Lambertian lobe (`Bsdf::lone_lambertian`), their BSDF samples
//! computed for all lanes at once: the shading frame, the cosine-weighted direction and its
//! density, and the next ray. Each lane is set with what the sample reads, as its bounce leaves
//! it, and computes by the kernels one path runs (`Frame`, `Lambertian::direction`,
//! `offset_point`), so a lane's sample is that path's, bit for bit.

use glam::{Vec2, Vec3};

use crate::geometry::{Frame, Hit, Ray};
use crate::lanes::{Floats, Lane, Mask, MaskLanes, Real, Vec3Lanes, offset_point};
use crate::material::lobe::Lambertian;

/// The lanes' vertices, coordinate by coordinate, and which lanes have one.
pub(super) struct DiffuseLanes {
    set: Mask,
    point: Vec3Lanes,
    normal: Vec3Lanes,
    error: Floats,
    shading_normal: Vec3Lanes,
    wo: Vec3Lanes,
    u: (Floats, Floats),
}

/// The lanes' samples: where a lane's path goes on (`continues`), its next ray, and the
/// vertex and the direction's density (`PathState::previous`).
pub(super) struct DiffuseSamples {
    continues: Mask,
    point: Vec3Lanes,
    origin: Vec3Lanes,
    wi: Vec3Lanes,
    pdf: Floats,
}

impl DiffuseLanes {
    pub(super) fn new() -> Self {
        DiffuseLanes {
            set: Mask::none(),
            point: Vec3Lanes::ZERO,
            normal: Vec3Lanes::ZERO,
            error: Floats::ZERO,
            shading_normal: Vec3Lanes::splat(Vec3::Z),
            wo: Vec3Lanes::splat(Vec3::Z),
            u: (Floats::ZERO, Floats::ZERO),
        }
    }

    /// Sets `lane`'s vertex: `hit` (after shading), seen from `wo`, its direction to be drawn
    /// by `u`.
    #[inline(always)]
    pub(super) fn set_lane(&mut self, lane: usize, hit: &Hit, wo: Vec3, u: Vec2) {
        self.set.set_lane(lane, true);
        self.point.set_lane(lane, hit.point);
        self.normal.set_lane(lane, hit.normal);
        self.error.set_lane(lane, hit.error);
        self.shading_normal.set_lane(lane, hit.shading_normal);
        self.wo.set_lane(lane, wo);
        self.u.0.set_lane(lane, u.x);
        self.u.1.set_lane(lane, u.y);
    }

    /// The lanes set.
    #[inline(always)]
    pub(super) fn set(&self) -> u32 {
        self.set.bitmask()
    }

    /// Every set lane's sample (`Bsdf::sample` of its lone Lambertian lobe).
    #[inline(always)]
    pub(super) fn sample(&self) -> DiffuseSamples {
        let frame = Frame::around(self.shading_normal);
        let wo_z = frame.local(self.wo).z;
        let (local, pdf) = Lambertian::direction(wo_z, self.u.0, self.u.1);
        let wi = frame.world(local);
        let origin = offset_point(self.point, self.normal, self.error, wi);
        let continues = pdf.gt(Floats::ZERO);
        DiffuseSamples { continues, point: self.point, origin, wi, pdf }
    }
}

impl DiffuseSamples {
    /// Whether `lane`'s path goes on.
    #[inline(always)]
    pub(super) fn continues(&self, lane: usize) -> bool {
        self.continues.lane(lane)
    }

    /// `lane`'s next ray, and its vertex and the ray's density.
    #[inline(always)]
    pub(super) fn lane(&self, lane: usize) -> (Ray, (Vec3, f32)) {
        let ray = Ray::new(self.origin.lane(lane), self.wi.lane(lane));
        (ray, (self.point.lane(lane), self.pdf.lane(lane)))
    }
}
