//! The BSDF at a surface point, built from its material (pbrt-v4's `Material::GetBSDF`): its
//! lobes' flags, which the integrators read to decide where light sampling applies, and
//! `eval` / `pdf` / `sample` over its lobes.
//!
//! Directions follow pbrt: `wo` points towards the viewer, `wi` towards the light, both unit.

use std::f32::consts::FRAC_1_PI;
use std::ops::BitOr;

use glam::{Vec2, Vec3};

use super::fresnel::{fresnel_dielectric, reflects_totally, refract};
use super::microfacet::Ggx;
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
    #[inline]
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether some flag of `other` is set.
    #[inline]
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

    /// Whether it is a diffuse lobe alone, which `sample_lambertian_lanes` samples.
    pub fn is_lambertian(self) -> bool {
        self == LobeFlags::DIFFUSE | LobeFlags::REFLECTION
    }

    /// Whether its lobes with a density are Lambertian alone (`eval_diffuse_lanes` evaluates
    /// them), whatever its delta lobes.
    pub fn is_diffuse_where_non_delta(self) -> bool {
        self.contains(LobeFlags::DIFFUSE) && !self.contains(LobeFlags::GLOSSY)
    }

    /// Whether `Bsdf::sample` reads its `u_lobe`: there are lobes besides a diffuse one.
    pub fn chooses_lobe(self) -> bool {
        self.intersects(LobeFlags::DELTA | LobeFlags::GLOSSY)
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
/// refraction: a Lambertian lobe `diffuse`, and a reflection lobe `specular` and a refraction
/// lobe `transmission` (split by Fresnel's equations with `fresnel`), both perfect (delta) where
/// `roughness` is 0, else GGX microfacet lobes of that alpha (glossy).
#[derive(Debug, Clone, Copy)]
pub struct Bsdf<'m> {
    n: Vec3,
    material: &'m Material,
    mode: TransportMode,
    /// Its lobes, found once where it is made.
    flags: LobeFlags,
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
    #[inline]
    pub fn bsdf(&self, n: Vec3, mode: TransportMode) -> Bsdf<'_> {
        let mut flags = LobeFlags::NONE;
        if self.diffuse.max_element() > 0.0 {
            flags = flags | LobeFlags::DIFFUSE | LobeFlags::REFLECTION;
        }
        if self.specular.max_element() > 0.0 || self.transmission.max_element() > 0.0 {
            let kind = if self.roughness > 0.0 { LobeFlags::GLOSSY } else { LobeFlags::DELTA };
            // Refraction reflects totally beyond the critical angle: a reflection lobe too.
            flags = flags | kind | LobeFlags::REFLECTION;
            if self.transmission.max_element() > 0.0 || self.fresnel {
                flags = flags | LobeFlags::TRANSMISSION;
            }
        }
        Bsdf { n, material: self, mode, flags }
    }
}

impl Bsdf<'_> {
    /// The kinds of lobes it has.
    #[inline]
    pub fn flags(&self) -> LobeFlags {
        self.flags
    }

    fn is_glossy(&self) -> bool {
        self.flags.contains(LobeFlags::GLOSSY)
    }

    /// Whether `sample` reads its `u_lobe`: it has lobes other than the diffuse one.
    fn chooses_lobe(&self) -> bool {
        self.flags.chooses_lobe()
    }

    fn has_diffuse(&self) -> bool {
        self.flags.contains(LobeFlags::DIFFUSE)
    }

    /// The non-delta part of f(wo, wi): Lambert's kd / pi, reflection only (both sides), and
    /// the glossy lobes.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let diffuse =
            if same_side(self.n, wo, wi) { self.material.diffuse * FRAC_1_PI } else { Vec3::ZERO };
        if !self.is_glossy() {
            return diffuse;
        }
        diffuse + self.eval_glossy(wo, wi)
    }

    /// Solid-angle density with which `sample` returns `wi` through its non-delta lobes.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p_diffuse = self.diffuse_probability(wo);
        let diffuse = if same_side(self.n, wo, wi) {
            p_diffuse * self.n.dot(wi).abs() * FRAC_1_PI
        } else {
            0.0
        };
        if !self.is_glossy() {
            return diffuse;
        }
        diffuse + (1.0 - p_diffuse) * self.glossy_pdf(wo, wi)
    }

    /// The probability with which `sample` chooses the diffuse lobe, seen from `wo`: with
    /// glossy lobes, from kd against ks + kt (which reflection and transmission share at
    /// every microfacet).
    #[inline]
    pub fn diffuse_probability(&self, wo: Vec3) -> f32 {
        if self.is_glossy() {
            let d = mean(self.material.diffuse);
            d / (d + mean(self.material.specular + self.material.transmission))
        } else if self.chooses_lobe() {
            self.lobe_probabilities(&self.delta_lobes(wo))[0]
        } else if self.has_diffuse() {
            1.0
        } else {
            0.0
        }
    }

    /// Chooses a lobe with probability from its reflectance (the course's per-bounce Russian
    /// roulette over kd, ks, kt), then a direction from it: cosine-weighted for the diffuse lobe;
    /// for glossy lobes a visible microfacet normal, then reflection or refraction there.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !self.chooses_lobe() {
            // Lambertian alone (the common case): no lobe to choose.
            return if self.has_diffuse() { self.sample_diffuse(wo, 1.0, u) } else { None };
        }
        if self.is_glossy() {
            let p_diffuse = self.diffuse_probability(wo);
            if u_lobe < p_diffuse {
                // Its weight is the diffuse lobe's, its pdf that of every non-delta lobe (MIS).
                let sample = self.sample_diffuse(wo, p_diffuse, u)?;
                let pdf = self.pdf(wo, sample.wi);
                return (pdf > 0.0).then_some(BsdfSample { pdf, ..sample });
            }
            let u_split = (u_lobe - p_diffuse) / (1.0 - p_diffuse);
            return self.sample_glossy(wo, 1.0 - p_diffuse, u_split, u);
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

    /// A direction from the lobes with a density alone, for estimators that follow delta lobes
    /// apart: the diffuse lobe's, cosine-weighted on wo's side, where the others are delta.
    /// `u_lobe` is read only with glossy lobes.
    pub fn sample_non_delta(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if self.is_glossy() { self.sample(wo, u_lobe, u) } else { self.sample_diffuse(wo, 1.0, u) }
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
            weight: self.material.diffuse / p_diffuse,
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

    /// The frame of the glossy lobes seen from `wo`: +z along the normal on wo's side, and
    /// eta = eta_t / eta_i for a direction crossing the boundary from that side.
    fn glossy_frame(&self, wo: Vec3) -> GlossyFrame {
        let cos_o = self.n.dot(wo);
        let (facing, eta) = if cos_o >= 0.0 {
            (self.n, self.material.ior)
        } else {
            (-self.n, 1.0 / self.material.ior)
        };
        let (tangent, bitangent) = facing.any_orthonormal_pair();
        GlossyFrame { tangent, bitangent, facing, eta, ggx: Ggx { alpha: self.material.roughness } }
    }

    /// Reflectance and transmittance at a microfacet seen at cosine `cos_om` from wo: with
    /// `fresnel`, F (ks + kt) and (1 - F)(ks + kt); else ks and kt, where kt goes to reflection
    /// if the microfacet reflects totally.
    fn microfacet_split(&self, cos_om: f32, eta: f32) -> (Vec3, Vec3) {
        let total = self.material.specular + self.material.transmission;
        if self.material.fresnel {
            let f = fresnel_dielectric(cos_om, eta);
            (f * total, (1.0 - f) * total)
        } else if reflects_totally(cos_om, eta) {
            (total, Vec3::ZERO)
        } else {
            (self.material.specular, self.material.transmission)
        }
    }

    /// The glossy lobes' f(wo, wi): reflection ks D G / (4 |n.o| |n.i|) at the half vector (Walter
    /// 2007, eq. 20) and transmission kt D G |i.m| |o.m| / (|n.i| |n.o| (i.m + o.m / eta)^2) at the
    /// refraction half vector (eq. 21, pbrt-v4's form), divided by eta^2 for radiance; G is
    /// Smith's G1(o) G1(i).
    fn eval_glossy(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let frame = self.glossy_frame(wo);
        let (wo, wi) = (frame.to_local(wo), frame.to_local(wi));
        if wo.z <= 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        let ggx = frame.ggx;
        let masking = ggx.g1(wo) * ggx.g1(wi);
        if wi.z > 0.0 {
            let m = (wo + wi).normalize();
            let (reflect, _) = self.microfacet_split(wo.dot(m), frame.eta);
            return reflect * (ggx.d(m) * masking / (4.0 * wo.z * wi.z));
        }
        let Some(m) = transmission_half_vector(wo, wi, frame.eta) else {
            return Vec3::ZERO;
        };
        let (cos_om, cos_im) = (wo.dot(m), wi.dot(m));
        if cos_om <= 0.0 || cos_im >= 0.0 {
            return Vec3::ZERO;
        }
        let (_, transmit) = self.microfacet_split(cos_om, frame.eta);
        let denominator = cos_im + cos_om / frame.eta;
        let f = ggx.d(m) * masking * -cos_im * cos_om / (wo.z * -wi.z * denominator * denominator);
        self.carried(transmit * f, frame.eta)
    }

    /// Density of `sample_glossy`'s directions: the visible normal's density D_wo(m) times the
    /// Jacobian of m to wi, 1 / (4 o.m) for reflection and |i.m| / (i.m + o.m / eta)^2 for
    /// refraction (Walter 2007, eqs. 14, 17), times the probability of the choice at m.
    fn glossy_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let frame = self.glossy_frame(wo);
        let (wo, wi) = (frame.to_local(wo), frame.to_local(wi));
        if wo.z <= 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        if wi.z > 0.0 {
            let m = (wo + wi).normalize();
            let cos_om = wo.dot(m);
            let (p_reflect, _) = shares(self.microfacet_split(cos_om, frame.eta));
            return p_reflect * frame.ggx.visible_pdf(wo, m) / (4.0 * cos_om);
        }
        let Some(m) = transmission_half_vector(wo, wi, frame.eta) else {
            return 0.0;
        };
        let (cos_om, cos_im) = (wo.dot(m), wi.dot(m));
        if cos_om <= 0.0 || cos_im >= 0.0 {
            return 0.0;
        }
        let (_, p_transmit) = shares(self.microfacet_split(cos_om, frame.eta));
        let denominator = cos_im + cos_om / frame.eta;
        p_transmit * frame.ggx.visible_pdf(wo, m) * -cos_im / (denominator * denominator)
    }

    /// The glossy lobes, chosen with probability `p_glossy`: a microfacet normal m visible from
    /// wo (Heitz 2018), then reflection or refraction about m with probability from their
    /// shares at m (`u_split`). The weight f |cos| / pdf reduces to k G1(wi) / p, k the lobe's
    /// reflectance at m and p the probability of choosing it.
    fn sample_glossy(&self, wo: Vec3, p_glossy: f32, u_split: f32, u: Vec2) -> Option<BsdfSample> {
        let frame = self.glossy_frame(wo);
        let wo_local = frame.to_local(wo);
        if wo_local.z <= 0.0 {
            return None;
        }
        let m = frame.ggx.sample_visible(wo_local, u);
        let cos_om = wo_local.dot(m);
        let (reflect, transmit) = self.microfacet_split(cos_om, frame.eta);
        let (p_reflect, p_transmit) = shares((reflect, transmit));
        let reflected = u_split < p_reflect;
        let (wi, weight, eta) = if reflected {
            let wi = 2.0 * cos_om * m - wo_local;
            (wi, reflect / (p_glossy * p_reflect), 1.0)
        } else {
            let wi = refract(wo_local, m, frame.eta)?;
            (wi, self.carried(transmit, frame.eta) / (p_glossy * p_transmit), frame.eta)
        };
        // A reflection below the surface or a refraction above it leaves the lobe.
        if (wi.z > 0.0) != reflected || wi.z == 0.0 {
            return None;
        }
        let weight = weight * frame.ggx.g1(wi);
        let wi = to_world(frame.facing, wi);
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then_some(BsdfSample { wi, weight, pdf, delta: false, eta })
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
        let eta = if cos_o >= 0.0 { self.material.ior } else { 1.0 / self.material.ior };
        let has_transmission = self.material.transmission.max_element() > 0.0;
        let transmit_dir =
            if has_transmission || self.material.fresnel { refract(wo, facing, eta) } else { None };
        let (mut reflect, mut transmit) = if self.material.fresnel {
            let f = fresnel_dielectric(cos_o.abs(), eta);
            let total = self.material.specular + self.material.transmission;
            (f * total, (1.0 - f) * total)
        } else {
            (self.material.specular, self.material.transmission)
        };
        if transmit_dir.is_none() {
            reflect += transmit;
            transmit = Vec3::ZERO;
        }
        DeltaLobes { reflect, transmit, eta, reflect_dir, transmit_dir }
    }

    /// Probabilities of the diffuse, reflection and transmission lobes, from their mean energy.
    fn lobe_probabilities(&self, lobes: &DeltaLobes) -> [f32; 3] {
        let d = mean(self.material.diffuse);
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

/// A frame with +z along the normal on wo's side, the relative index of refraction eta_t /
/// eta_i from that side, and the distribution of microfacet normals.
struct GlossyFrame {
    tangent: Vec3,
    bitangent: Vec3,
    facing: Vec3,
    eta: f32,
    ggx: Ggx,
}

impl GlossyFrame {
    fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.tangent), v.dot(self.bitangent), v.dot(self.facing))
    }
}

/// The microfacet normal that refracts `wo` into `wi` (local, wo above, wi below): the
/// normalised wo + eta wi turned to the +z side (Walter 2007, eq. 16).
fn transmission_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<Vec3> {
    let m = (wo + eta * wi).try_normalize()?;
    Some(if m.z < 0.0 { -m } else { m })
}

/// The probabilities of reflection and transmission at a microfacet, from their mean shares.
fn shares((reflect, transmit): (Vec3, Vec3)) -> (f32, f32) {
    let (r, t) = (mean(reflect), mean(transmit));
    if r + t <= 0.0 {
        return (0.0, 0.0);
    }
    (r / (r + t), t / (r + t))
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
