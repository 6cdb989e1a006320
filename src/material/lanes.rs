//! The Lambertian lobe four lanes at a time, as the path integrator's fast path computes it:
//! the same operations in the same order as `Bsdf`, so each lane gets exactly its result.

use std::f32::consts::FRAC_1_PI;

use glam::{BVec4A, Vec4};

use super::BsdfSample;
use crate::geometry::{Lane, Vec2x4, Vec3x4};
use crate::sampling::cosine_hemisphere_lanes;

/// `Frame::from_normal(n).to_world(local)` in four lanes, with `Vec3::any_orthonormal_pair`'s
/// operations in its order.
fn to_world_lanes(n: Vec3x4, local: Vec3x4) -> Vec3x4 {
    let sign = Vec4::ONE.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = Vec3x4 { x: 1.0 + sign * n.x * n.x * a, y: sign * b, z: -sign * n.x };
    let bitangent = Vec3x4 { x: b, y: sign + n.y * n.y * a, z: -n.y };
    local.x * t + local.y * bitangent + local.z * n
}

/// BSDF samples of four lanes, coordinate by coordinate: `BsdfSample`'s fields, held in the
/// lanes where `found` is set.
#[derive(Debug, Clone, Copy)]
pub struct BsdfSampleLanes {
    pub found: BVec4A,
    pub wi: Vec3x4,
    pub weight: Vec3x4,
    pub pdf: Vec4,
    pub delta: BVec4A,
    pub eta: Vec4,
}

impl BsdfSampleLanes {
    #[inline]
    pub fn set_lane(&mut self, lane: usize, sample: Option<BsdfSample>) {
        self.found.set_lane(lane, sample.is_some());
        if let Some(sample) = sample {
            self.wi.set_lane(lane, sample.wi);
            self.weight.set_lane(lane, sample.weight);
            self.pdf.set_lane(lane, sample.pdf);
            self.delta.set_lane(lane, sample.is_delta());
            self.eta.set_lane(lane, sample.eta);
        }
    }
}

/// `sample` in the lanes of `lambertian`, whose BSDFs are Lambertian (`Bsdf::is_lambertian`) with
/// reflectance `diffuse`: `Bsdf::sample`'s operations in its order, so each lane gets exactly
/// what `sample` returns.
pub fn sample_lambertian_lanes(
    lambertian: BVec4A,
    diffuse: Vec3x4,
    n: Vec3x4,
    wo: Vec3x4,
    u: Vec2x4,
) -> BsdfSampleLanes {
    // The lobe turns to wo's side: local z turned over below the normal (`frame::on_side`).
    let side = Vec4::select(n.dot(wo).cmplt(Vec4::ZERO), Vec4::NEG_ONE, Vec4::ONE);
    let mut local = cosine_hemisphere_lanes(u);
    // The lobe's probability is 1: pdf = 1 cos / pi, and the weight kd / 1 is kd.
    let pdf = local.z * FRAC_1_PI;
    local.z = side * local.z;
    BsdfSampleLanes {
        found: lambertian & pdf.cmpgt(Vec4::ZERO),
        wi: to_world_lanes(n, local),
        weight: diffuse,
        pdf,
        delta: BVec4A::FALSE,
        eta: Vec4::ONE,
    }
}

/// The diffuse lobe's `eval` (kd / pi) and `pdf` (p_diffuse (|cos| / pi)) in four lanes, both
/// zero where `wo` and `wi` lie on different sides.
pub fn eval_diffuse_lanes(
    n: Vec3x4,
    wo: Vec3x4,
    wi: Vec3x4,
    diffuse: Vec3x4,
    p_diffuse: Vec4,
) -> (Vec3x4, Vec4) {
    let same_side = (n.dot(wo) * n.dot(wi)).cmpgt(Vec4::ZERO);
    let f = Vec3x4::select(same_side, diffuse * Vec4::splat(FRAC_1_PI), Vec3x4::ZERO);
    let pdf = Vec4::select(same_side, p_diffuse * (n.dot(wi).abs() * FRAC_1_PI), Vec4::ZERO);
    (f, pdf)
}
