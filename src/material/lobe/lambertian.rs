//! Lambert's diffuse reflection: f = kd / pi on the side of `wo`, sampled cosine-weighted.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{LobeSample, mean, side_of_z};
use crate::lanes::{Real, Vector};
use crate::material::LobeFlags;
use crate::sampling::cosine_hemisphere_of;

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
        Self::eval_of(self.reflectance.into(), wo.z, wi.z).into()
    }

    /// |cos| / pi on wo's side.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Self::pdf_of(wo.z, wi.z)
    }

    /// `eval` of reflectance `kd` where the local z of `wo` and `wi` are `wo_z` and `wi_z`,
    /// written once over `Real`: for one vertex or a vertex per lane.
    #[inline(always)]
    pub fn eval_of<F: Real>(kd: Vector<F>, wo_z: F, wi_z: F) -> Vector<F> {
        Vector::select((wo_z * wi_z).gt(F::ZERO), kd * F::splat(FRAC_1_PI), Vector::ZERO)
    }

    /// `pdf` where the local z of `wo` and `wi` are `wo_z` and `wi_z`, written once over `Real`.
    #[inline(always)]
    pub fn pdf_of<F: Real>(wo_z: F, wi_z: F) -> F {
        F::select((wo_z * wi_z).gt(F::ZERO), wi_z.abs() * F::splat(FRAC_1_PI), F::ZERO)
    }

    /// Cosine-weighted on wo's side: f |cos| / pdf = (kd / pi) cos / (cos / pi) = kd.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<LobeSample> {
        let (wi, pdf) = Self::direction(wo.z, u.x, u.y);
        (pdf > 0.0).then(|| LobeSample {
            wi: wi.into(),
            weight: self.reflectance,
            pdf,
            flags: Self::FLAGS,
            eta: 1.0,
        })
    }

    /// `sample`'s direction (local) on the side of a `wo` of local z `wo_z`, and its density
    /// cos / pi, written once over `Real`: for one vertex or a vertex per lane.
    #[inline(always)]
    pub fn direction<F: Real>(wo_z: F, ux: F, uy: F) -> (Vector<F>, F) {
        let local = cosine_hemisphere_of(ux, uy);
        let pdf = local.z * F::splat(FRAC_1_PI);
        (Vector { z: side_of_z(wo_z) * local.z, ..local }, pdf)
    }
}
