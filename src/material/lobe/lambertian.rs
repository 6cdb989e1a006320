//! Lambert's diffuse reflection: f = kd / pi on the side of `wo`, sampled cosine-weighted.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{LobeSample, mean, side_of};
use crate::geometry::on_side;
use crate::material::LobeFlags;
use crate::sampling::cosine_hemisphere;

#[derive(Debug, Clone, Copy)]
pub struct Lambertian {
    /// kd.
    pub reflectance: Vec3,
}

impl Lambertian {
    pub const FLAGS: LobeFlags = LobeFlags::DIFFUSE.union(LobeFlags::REFLECTION);

    #[inline]
    pub fn albedo(&self) -> f32 {
        mean(self.reflectance)
    }

    /// kd / pi where `wo` and `wi` are on the same side (reflection only, from both sides).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z * wi.z > 0.0 { self.reflectance * FRAC_1_PI } else { Vec3::ZERO }
    }

    /// |cos| / pi on wo's side.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z > 0.0 { wi.z.abs() * FRAC_1_PI } else { 0.0 }
    }

    /// Cosine-weighted on wo's side: f |cos| / pdf = (kd / pi) cos / (cos / pi) = kd.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<LobeSample> {
        let local = cosine_hemisphere(u);
        let pdf = local.z * FRAC_1_PI;
        (pdf > 0.0).then(|| LobeSample {
            wi: on_side(local, side_of(wo)),
            weight: self.reflectance,
            pdf,
            flags: Self::FLAGS,
            eta: 1.0,
        })
    }
}
