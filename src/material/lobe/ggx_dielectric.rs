//! A rough boundary between two media: reflection and refraction at GGX microfacets (Walter et
//! al. 2007), sharing what arrives at each microfacet by Fresnel's equations or by the course's
//! fixed ks and kt (`Split`).

use glam::{Vec2, Vec3};

use super::{LobeSample, mean, shares, side_of};
use crate::geometry::on_side;
use crate::material::fresnel::{Split, refract};
use crate::material::microfacet::Ggx;
use crate::material::{LobeFlags, TransportMode};

#[derive(Debug, Clone, Copy)]
pub struct GgxDielectric {
    pub split: Split,
    /// Index of refraction inside (on the side opposite the normal) over outside.
    pub ior: f32,
    pub ggx: Ggx,
}

impl GgxDielectric {
    pub const FLAGS: LobeFlags =
        LobeFlags::GLOSSY.union(LobeFlags::REFLECTION).union(LobeFlags::TRANSMISSION);

    pub fn albedo(&self) -> f32 {
        mean(self.split.total())
    }

    /// wo and wi turned to wo's side, and eta = eta_t / eta_i for a direction crossing the
    /// boundary from there.
    #[inline]
    fn turned_to_wo(&self, wo: Vec3, wi: Vec3) -> (Vec3, Vec3, f32) {
        let side = side_of(wo);
        let eta = if side > 0.0 { self.ior } else { 1.0 / self.ior };
        (on_side(wo, side), on_side(wi, side), eta)
    }

    /// Reflection ks D G / (4 |n.o| |n.i|) at the half vector (Walter 2007, eq. 20) and
    /// transmission kt D G |i.m| |o.m| / (|n.i| |n.o| (i.m + o.m / eta)^2) at the refraction
    /// half vector (eq. 21, pbrt-v4's form), divided by eta^2 for radiance; G is Smith's
    /// G1(o) G1(i).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        let (wo, wi, eta) = self.turned_to_wo(wo, wi);
        if wo.z <= 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        let masking = self.ggx.g1(wo) * self.ggx.g1(wi);
        if wi.z > 0.0 {
            let m = (wo + wi).normalize();
            let (reflect, _) = self.split.at(wo.dot(m), eta);
            return reflect * (self.ggx.d(m) * masking / (4.0 * wo.z * wi.z));
        }
        let Some(m) = transmission_half_vector(wo, wi, eta) else {
            return Vec3::ZERO;
        };
        let (cos_om, cos_im) = (wo.dot(m), wi.dot(m));
        if cos_om <= 0.0 || cos_im >= 0.0 {
            return Vec3::ZERO;
        }
        let (_, transmit) = self.split.at(cos_om, eta);
        let denominator = cos_im + cos_om / eta;
        let f =
            self.ggx.d(m) * masking * -cos_im * cos_om / (wo.z * -wi.z * denominator * denominator);
        mode.carried(transmit * f, eta)
    }

    /// The visible normal's density D_wo(m) times the Jacobian of m to wi, 1 / (4 o.m) for
    /// reflection and |i.m| / (i.m + o.m / eta)^2 for refraction (Walter 2007, eqs. 14, 17),
    /// times the probability of the choice at m.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi, eta) = self.turned_to_wo(wo, wi);
        self.pdf_turned(wo, wi, eta)
    }

    /// `pdf` of wo and wi already turned to wo's side, eta from there.
    #[inline]
    fn pdf_turned(&self, wo: Vec3, wi: Vec3, eta: f32) -> f32 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        if wi.z > 0.0 {
            let m = (wo + wi).normalize();
            let cos_om = wo.dot(m);
            let (p_reflect, _) = shares(self.split.at(cos_om, eta));
            return p_reflect * self.ggx.visible_pdf(wo, m) / (4.0 * cos_om);
        }
        let Some(m) = transmission_half_vector(wo, wi, eta) else {
            return 0.0;
        };
        let (cos_om, cos_im) = (wo.dot(m), wi.dot(m));
        if cos_om <= 0.0 || cos_im >= 0.0 {
            return 0.0;
        }
        let (_, p_transmit) = shares(self.split.at(cos_om, eta));
        let denominator = cos_im + cos_om / eta;
        p_transmit * self.ggx.visible_pdf(wo, m) * -cos_im / (denominator * denominator)
    }

    /// A microfacet normal m visible from wo (Heitz 2018), then reflection or refraction about
    /// m with probability from their shares at m (`u_split`). The weight f |cos| / pdf reduces
    /// to k G1(wi) / p, k the share chosen at m and p the probability of choosing it.
    // Always inlined into `Lobe::sample` (see there).
    #[inline(always)]
    pub fn sample(
        &self,
        wo: Vec3,
        u_split: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<LobeSample> {
        let side = side_of(wo);
        let (wo, _, eta) = self.turned_to_wo(wo, Vec3::ZERO);
        if wo.z <= 0.0 {
            return None;
        }
        let m = self.ggx.sample_visible(wo, u);
        let cos_om = wo.dot(m);
        let (reflect, transmit) = self.split.at(cos_om, eta);
        let (p_reflect, p_transmit) = shares((reflect, transmit));
        let reflected = u_split < p_reflect;
        let sample = if reflected {
            let wi = 2.0 * cos_om * m - wo;
            (wi, reflect / p_reflect, 1.0, LobeFlags::REFLECTION)
        } else {
            let wi = refract(wo, m, eta)?;
            (wi, mode.carried(transmit, eta) / p_transmit, eta, LobeFlags::TRANSMISSION)
        };
        let (wi, weight, crossed_eta, part) = sample;
        // A reflection below the surface or a refraction above it leaves the lobe.
        if (wi.z > 0.0) != reflected || wi.z == 0.0 {
            return None;
        }
        Some(LobeSample {
            wi: on_side(wi, side),
            weight: weight * self.ggx.g1(wi),
            pdf: self.pdf_turned(wo, wi, eta),
            flags: LobeFlags::GLOSSY.union(part),
            eta: crossed_eta,
        })
    }
}

/// The microfacet normal that refracts `wo` into `wi` (local, wo above, wi below): the
/// normalised wo + eta wi turned to the +z side (Walter 2007, eq. 16).
fn transmission_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<Vec3> {
    let m = (wo + eta * wi).try_normalize()?;
    Some(if m.z < 0.0 { -m } else { m })
}
