//! The BSDF at a surface point, built from its material (pbrt-v4's `Material::GetBSDF`): its
//! lobes' flags, which the integrators read to decide where light sampling applies, and
//! `eval` / `pdf` / `sample` over its lobes.
//!
//! Directions follow pbrt: `wo` points towards the viewer, `wi` towards the light, both unit.

use std::f32::consts::FRAC_1_PI;
use std::ops::BitOr;

use glam::{Vec2, Vec3};

use super::fresnel::{fresnel_dielectric, refract};
use super::{Material, to_world};
use crate::sampling::cosine_hemisphere;

/// What a path carries: radiance (camera paths) or importance (photons, light paths). They
/// differ only in the 1/eta^2 that refraction applies to radiance (pbrt-v4, 9.5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// The kinds of lobes a BSDF has (pbrt-v4's `BxDFFlags`): reflection and/or transmission,
/// each diffuse, glossy or delta (a perfect mirror or refraction, which no light sample can
/// meet).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LobeFlags(u8);

impl LobeFlags {
    pub const NONE: Self = LobeFlags(0);
    pub const REFLECTION: Self = LobeFlags(1);
    pub const TRANSMISSION: Self = LobeFlags(2);
    pub const DIFFUSE: Self = LobeFlags(4);
    pub const GLOSSY: Self = LobeFlags(8);
    pub const DELTA: Self = LobeFlags(16);

    /// Whether every flag of `other` is set.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether some flag of `other` is set.
    pub fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether some lobe has a density: next-event estimation and MIS apply there.
    pub fn is_non_delta(self) -> bool {
        self.intersects(LobeFlags::DIFFUSE | LobeFlags::GLOSSY)
    }

    pub fn is_delta(self) -> bool {
        self.contains(LobeFlags::DELTA)
    }
}

impl BitOr for LobeFlags {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        LobeFlags(self.0 | rhs.0)
    }
}

/// A direction drawn from a BSDF. `weight` is f |cos| / pdf, including the probability of the
/// lobe chosen; `pdf` is in solid angle (for a delta lobe, the discrete probability of the lobe).
#[derive(Debug, Clone, Copy)]
pub struct BsdfSample {
    pub wi: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    /// Drawn from a delta lobe (a light sample could not have found `wi`).
    pub delta: bool,
    /// eta_t / eta_i of the boundary crossed by a refracted `wi`; 1 for reflection.
    pub eta: f32,
}

/// The BSDF of a material at a point with shading normal `n`, whose side is "outside" for
/// refraction: a Lambertian lobe `diffuse`, and a mirror `specular` and refraction `transmission`
/// lobe (split by Fresnel's equations with `fresnel`).
#[derive(Debug, Clone)]
pub struct Bsdf {
    n: Vec3,
    diffuse: Vec3,
    specular: Vec3,
    transmission: Vec3,
    ior: f32,
    fresnel: bool,
    mode: TransportMode,
}

/// The reflectance of each delta lobe seen from one `wo`, and where they send light.
struct DeltaLobes {
    reflect: Vec3,
    /// Energy carried through the boundary; the radiance it carries is `transmit / eta^2`.
    transmit: Vec3,
    /// eta_t / eta_i for a direction crossing the boundary from wo's side.
    eta: f32,
    reflect_dir: Vec3,
    /// `None` under total internal reflection (its share then goes to `reflect`).
    transmit_dir: Option<Vec3>,
}

impl Material {
    /// The BSDF of this material where the shading normal is `n`, for `mode` transport.
    pub fn bsdf(&self, n: Vec3, mode: TransportMode) -> Bsdf {
        Bsdf {
            n,
            diffuse: self.diffuse,
            specular: self.specular,
            transmission: self.transmission,
            ior: self.ior,
            fresnel: self.fresnel,
            mode,
        }
    }
}

impl Bsdf {
    /// The kinds of lobes it has.
    pub fn flags(&self) -> LobeFlags {
        let mut flags = LobeFlags::NONE;
        if self.has_diffuse() {
            flags = flags | LobeFlags::DIFFUSE | LobeFlags::REFLECTION;
        }
        if self.chooses_lobe() {
            // Refraction reflects totally beyond the critical angle: a reflection lobe too.
            flags = flags | LobeFlags::DELTA | LobeFlags::REFLECTION;
            if self.transmission.max_element() > 0.0 || self.fresnel {
                flags = flags | LobeFlags::TRANSMISSION;
            }
        }
        flags
    }

    /// Whether it is a diffuse lobe alone, which `sample_lambertian_lanes` samples.
    pub fn is_lambertian(&self) -> bool {
        self.flags() == LobeFlags::DIFFUSE | LobeFlags::REFLECTION
    }

    /// Whether its lobes with a density are Lambertian alone (`eval_diffuse_lanes` evaluates
    /// them), whatever its delta lobes.
    pub fn is_diffuse_where_non_delta(&self) -> bool {
        self.has_diffuse()
    }

    /// Whether `sample` reads its `u_lobe`: it has lobes other than the diffuse one.
    pub fn chooses_lobe(&self) -> bool {
        self.specular.max_element() > 0.0 || self.transmission.max_element() > 0.0
    }

    fn has_diffuse(&self) -> bool {
        self.diffuse.max_element() > 0.0
    }

    /// The non-delta part of f(wo, wi): Lambert's kd / pi, reflection only (both sides).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if same_side(self.n, wo, wi) { self.diffuse * FRAC_1_PI } else { Vec3::ZERO }
    }

    /// Solid-angle density with which `sample` returns `wi` through its non-delta lobes.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !same_side(self.n, wo, wi) {
            return 0.0;
        }
        self.diffuse_probability(wo) * self.n.dot(wi).abs() * FRAC_1_PI
    }

    /// The probability with which `sample` chooses the diffuse lobe, seen from `wo`.
    #[inline]
    pub fn diffuse_probability(&self, wo: Vec3) -> f32 {
        if self.chooses_lobe() {
            self.lobe_probabilities(&self.delta_lobes(wo))[0]
        } else if self.has_diffuse() {
            1.0
        } else {
            0.0
        }
    }

    /// Chooses a lobe with probability from its reflectance (the course's per-bounce Russian
    /// roulette over kd, ks, kt), then a direction from it: cosine-weighted for the diffuse lobe.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !self.chooses_lobe() {
            // Lambertian alone (the common case): no lobe to choose.
            return if self.has_diffuse() { self.sample_diffuse(wo, 1.0, u) } else { None };
        }
        let lobes = self.delta_lobes(wo);
        let [p_diffuse, p_reflect, _] = self.lobe_probabilities(&lobes);
        if u_lobe < p_diffuse {
            self.sample_diffuse(wo, p_diffuse, u)
        } else if u_lobe < p_diffuse + p_reflect {
            Some(delta_sample(lobes.reflect_dir, lobes.reflect, p_reflect, 1.0))
        } else {
            let wi = lobes.transmit_dir?;
            let p_transmit = 1.0 - p_diffuse - p_reflect;
            (p_transmit > 0.0).then(|| self.transmission_sample(&lobes, wi, p_transmit))
        }
    }

    /// A direction from the lobes with a density alone (the diffuse one), for estimators that
    /// follow delta lobes apart: cosine-weighted on wo's side.
    pub fn sample_non_delta(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        self.sample_diffuse(wo, 1.0, u)
    }

    /// The diffuse lobe, chosen with probability `p_diffuse`: cosine-weighted on wo's side.
    fn sample_diffuse(&self, wo: Vec3, p_diffuse: f32, u: Vec2) -> Option<BsdfSample> {
        let facing = if self.n.dot(wo) < 0.0 { -self.n } else { self.n };
        let local = cosine_hemisphere(u);
        let wi = to_world(facing, local);
        let pdf = p_diffuse * local.z * FRAC_1_PI;
        // f |cos| / pdf = (kd / pi) cos / (p cos / pi) = kd / p
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.diffuse / p_diffuse,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }

    /// Samples only the delta lobes (mirror, refraction), with probabilities from their
    /// reflectances; `None` if it has none. Used by Whitted-style integrators.
    pub fn sample_delta(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let lobes = self.delta_lobes(wo);
        let reflect = mean(lobes.reflect);
        let transmit = mean(lobes.transmit);
        let total = reflect + transmit;
        if total <= 0.0 {
            return None;
        }
        let p_reflect = reflect / total;
        match lobes.transmit_dir {
            Some(wi) if u_lobe >= p_reflect => {
                Some(self.transmission_sample(&lobes, wi, 1.0 - p_reflect))
            }
            _ => Some(delta_sample(lobes.reflect_dir, lobes.reflect, p_reflect, 1.0)),
        }
    }

    /// What refraction carries of energy `transmitted` across a boundary of relative index `eta`:
    /// radiance is compressed by 1 / eta^2 on entering a denser medium; importance is not
    /// (pbrt-v4, 9.5.2).
    fn carried(&self, transmitted: Vec3, eta: f32) -> Vec3 {
        match self.mode {
            TransportMode::Radiance => transmitted / (eta * eta),
            TransportMode::Importance => transmitted,
        }
    }

    fn delta_lobes(&self, wo: Vec3) -> DeltaLobes {
        let n = self.n;
        let cos_o = n.dot(wo);
        let facing = if cos_o < 0.0 { -n } else { n };
        let reflect_dir = 2.0 * cos_o * n - wo;
        // Relative index of refraction eta = eta_t / eta_i across the boundary crossed by wi.
        let eta = if cos_o >= 0.0 { self.ior } else { 1.0 / self.ior };
        let has_transmission = self.transmission.max_element() > 0.0;
        let transmit_dir =
            if has_transmission || self.fresnel { refract(wo, facing, eta) } else { None };
        let (mut reflect, mut transmit) = if self.fresnel {
            let f = fresnel_dielectric(cos_o.abs(), eta);
            let total = self.specular + self.transmission;
            (f * total, (1.0 - f) * total)
        } else {
            (self.specular, self.transmission)
        };
        if transmit_dir.is_none() {
            reflect += transmit;
            transmit = Vec3::ZERO;
        }
        DeltaLobes { reflect, transmit, eta, reflect_dir, transmit_dir }
    }

    /// Probabilities of the diffuse, reflection and transmission lobes, from their mean energy.
    fn lobe_probabilities(&self, lobes: &DeltaLobes) -> [f32; 3] {
        let d = mean(self.diffuse);
        let r = mean(lobes.reflect);
        let t = mean(lobes.transmit);
        let total = d + r + t;
        if total <= 0.0 {
            return [0.0; 3];
        }
        [d / total, r / total, t / total]
    }

    fn transmission_sample(&self, lobes: &DeltaLobes, wi: Vec3, probability: f32) -> BsdfSample {
        delta_sample(wi, self.carried(lobes.transmit, lobes.eta), probability, lobes.eta)
    }
}

fn delta_sample(wi: Vec3, reflectance: Vec3, probability: f32, eta: f32) -> BsdfSample {
    BsdfSample { wi, weight: reflectance / probability, pdf: probability, delta: true, eta }
}

fn same_side(n: Vec3, wo: Vec3, wi: Vec3) -> bool {
    n.dot(wo) * n.dot(wi) > 0.0
}

fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}
