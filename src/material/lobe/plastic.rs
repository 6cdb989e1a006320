//! Plastic: a glossy dielectric coat over a Lambertian base (the `coat` of a material, POV-Ray's
//! highlights). The coat reflects off GGX microfacets (Walter et al. 2007) what Fresnel's
//! equations reflect at each microfacet; the base is Lambertian and sees only what the smooth
//! coat lets through (`CoatLayer`: 1 - h F, h = 1 for `.scn`'s coat, its strength for
//! POV-Ray's), on the way in and on the way out:
//!
//! f = coat F(o.m) D G / (4 |n.o| |n.i|) + base / pi (1 - h F(n.o)) (1 - h F(n.i)),
//!
//! the layered sum of pbrt-v3's `plastic` and Mitsuba's `roughplastic` without their light
//! reflected back down by the coat's inside (lost here: a few percent darker, never brighter).
//! It is reciprocal; with h = 1, f is linear in (coat, base) with at most 1 of light scattered
//! at (1, 1), so it scatters at most max(coat, base); with h = coat, at most 1 where base <= 1.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{LobeSample, mean, side_of};
use crate::geometry::on_side;
use crate::material::fresnel::fresnel_dielectric;
use crate::material::microfacet::Ggx;
use crate::material::{CoatLayer, LobeFlags};
use crate::sampling::cosine_hemisphere;

#[derive(Debug, Clone, Copy)]
pub struct Plastic {
    /// kd: the Lambertian base's reflectance.
    pub base: Vec3,
    /// The share of the coat's Fresnel reflection kept, in [0, 1] (1: a physical coat; Mitsuba's
    /// `specular_reflectance`).
    pub coat: f32,
    /// What the coat lets through to the base, and its index of refraction over the outside's.
    pub layer: CoatLayer,
    pub ggx: Ggx,
}

impl Plastic {
    pub const FLAGS: LobeFlags =
        LobeFlags::GLOSSY.union(LobeFlags::DIFFUSE).union(LobeFlags::REFLECTION);

    /// The coat's share coat F and the base's (1 - h F) kd seen from `wo`, by Fresnel at the
    /// macro-surface: what the lobe is chosen by, and how it chooses between its parts.
    #[inline]
    fn parts(&self, cos_o: f32) -> (f32, f32) {
        let f = fresnel_dielectric(cos_o.abs(), self.layer.ior);
        (self.coat * f, self.layer.through(cos_o) * mean(self.base))
    }

    pub fn albedo(&self, wo: Vec3) -> f32 {
        let (coat, base) = self.parts(wo.z);
        coat + base
    }

    /// The probability of sampling the coat rather than the base from `wo` (Mitsuba's
    /// `roughplastic`: in proportion to their shares).
    #[inline]
    fn coat_probability(&self, cos_o: f32) -> f32 {
        let (coat, base) = self.parts(cos_o);
        if coat + base > 0.0 { coat / (coat + base) } else { 1.0 }
    }

    /// f(wo, wi) as the module states, on wo's side; zero across the surface.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let side = side_of(wo);
        self.eval_turned(on_side(wo, side), on_side(wi, side))
    }

    /// `eval` of wo and wi already turned to wo's side.
    #[inline]
    fn eval_turned(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let m = (wo + wi).normalize();
        let fresnel = fresnel_dielectric(wo.dot(m), self.layer.ior);
        let masking = self.ggx.g1(wo) * self.ggx.g1(wi);
        let coat = self.coat * fresnel * self.ggx.d(m) * masking / (4.0 * wo.z * wi.z);
        Vec3::splat(coat) + self.base * (FRAC_1_PI * self.layer.beneath(wo, wi))
    }

    /// The coat's visible-normal density times the Jacobian 1 / (4 o.m) (Walter 2007, eq. 14)
    /// and the base's cosine density, each times the probability of sampling it.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let side = side_of(wo);
        let (wo, wi) = (on_side(wo, side), on_side(wi, side));
        self.pdf_turned(wo, wi)
    }

    /// `pdf` of wo and wi already turned to wo's side.
    #[inline]
    fn pdf_turned(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let p_coat = self.coat_probability(wo.z);
        let m = (wo + wi).normalize();
        let coat = self.ggx.visible_pdf(wo, m) / (4.0 * wo.dot(m));
        p_coat * coat + (1.0 - p_coat) * wi.z * FRAC_1_PI
    }

    /// The coat (a microfacet normal visible from wo, Heitz 2018, and the reflection about it)
    /// or the base (cosine-weighted), chosen by `u_split`; the weight is f cos / pdf with the
    /// density of both parts, so that either part's sample counts the other's.
    // Always inlined into `Lobe::sample` (see there).
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u_split: f32, u: Vec2) -> Option<LobeSample> {
        let side = side_of(wo);
        let wo = on_side(wo, side);
        if wo.z <= 0.0 {
            return None;
        }
        let coated = u_split < self.coat_probability(wo.z);
        let (wi, part) = if coated {
            let m = self.ggx.sample_visible(wo, u);
            (2.0 * wo.dot(m) * m - wo, LobeFlags::GLOSSY)
        } else {
            (cosine_hemisphere(u), LobeFlags::DIFFUSE)
        };
        let pdf = self.pdf_turned(wo, wi);
        if pdf <= 0.0 {
            return None;
        }
        Some(LobeSample {
            wi: on_side(wi, side),
            weight: self.eval_turned(wo, wi) * (wi.z / pdf),
            pdf,
            flags: part.union(LobeFlags::REFLECTION),
            eta: 1.0,
        })
    }
}
