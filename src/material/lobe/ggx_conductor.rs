//! Rough reflection of reflectance ks off GGX microfacets (Walter et al. 2007), the same whatever
//! the angle: the course's `specular` with `roughness`.

use glam::{Vec2, Vec3};

use super::{LobeSample, mean, side_of};
use crate::geometry::on_side;
use crate::material::LobeFlags;
use crate::material::microfacet::Ggx;

#[derive(Debug, Clone, Copy)]
pub struct GgxConductor {
    /// ks.
    pub reflectance: Vec3,
    pub ggx: Ggx,
}

impl GgxConductor {
    pub const FLAGS: LobeFlags = LobeFlags::GLOSSY.union(LobeFlags::REFLECTION);

    pub fn albedo(&self) -> f32 {
        mean(self.reflectance)
    }

    /// ks D G / (4 |n.o| |n.i|) at the half vector (Walter 2007, eq. 20), on wo's side; G is
    /// Smith's G1(o) G1(i).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let side = side_of(wo);
        let (wo, wi) = (on_side(wo, side), on_side(wi, side));
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let m = (wo + wi).normalize();
        let masking = self.ggx.g1(wo) * self.ggx.g1(wi);
        self.reflectance * (self.ggx.d(m) * masking / (4.0 * wo.z * wi.z))
    }

    /// The visible normal's density D_wo(m) times the Jacobian 1 / (4 o.m) of m to wi (Walter
    /// 2007, eq. 14).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let side = side_of(wo);
        let (wo, wi) = (on_side(wo, side), on_side(wi, side));
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let m = (wo + wi).normalize();
        self.ggx.visible_pdf(wo, m) / (4.0 * wo.dot(m))
    }

    /// A microfacet normal visible from wo (Heitz 2018), and the reflection about it: f |cos|
    /// / pdf reduces to ks G1(wi).
    // Always inlined into `Lobe::sample` (see there).
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<LobeSample> {
        let side = side_of(wo);
        let wo = on_side(wo, side);
        if wo.z <= 0.0 {
            return None;
        }
        let m = self.ggx.sample_visible(wo, u);
        let cos_om = wo.dot(m);
        let wi = 2.0 * cos_om * m - wo;
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.ggx.visible_pdf(wo, m) / (4.0 * cos_om);
        Some(LobeSample {
            wi: on_side(wi, side),
            weight: self.reflectance * self.ggx.g1(wi),
            pdf,
            flags: Self::FLAGS,
            eta: 1.0,
        })
    }
}
