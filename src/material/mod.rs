//! Materials of the course's model — Lambertian `diffuse` (kd), mirror `specular` (ks),
//! refractive `transmission` (kt) with `ior`, `emission` — and their BSDF: `eval`, `sample`, `pdf`.
//!
//! Directions follow pbrt: `wo` points towards the viewer, `wi` towards the light, both unit.
//! `n` is the shape's geometric normal; its side is "outside" for refraction.

mod fresnel;

pub use fresnel::{fresnel_dielectric, refract};

use std::f32::consts::FRAC_1_PI;

use glam::{BVec4A, Vec2, Vec3, Vec4};

use crate::geometry::{Lane, Vec2x4, Vec3x4};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_lanes};
use crate::scene::graph::{MaterialDesc, Pattern};

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub transmission: Vec3,
    pub ior: f32,
    pub emission: Vec3,
    /// Split `specular + transmission` between reflection and refraction by Fresnel's equations.
    pub fresnel: bool,
}

/// The language's defaults: black, reflecting nothing, `ior 1` (POV-Ray's default pigment is
/// black too).
impl Default for Material {
    fn default() -> Self {
        Material {
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
            transmission: Vec3::ZERO,
            ior: 1.0,
            emission: Vec3::ZERO,
            fresnel: false,
        }
    }
}

/// The material of a description; a textured `diffuse` is left black here and filled in per
/// hit (`Scene::material`).
impl From<&MaterialDesc> for Material {
    fn from(d: &MaterialDesc) -> Self {
        Material {
            diffuse: match d.diffuse.pattern {
                Pattern::Solid(c) => c,
                _ => Vec3::ZERO,
            },
            specular: d.specular,
            transmission: d.transmission,
            ior: d.ior,
            emission: d.emission,
            fresnel: d.fresnel,
        }
    }
}

/// A direction drawn from a BSDF. `weight` is f |cos| / pdf, including the probability of the
/// lobe chosen; `pdf` is in solid angle (for a specular lobe, the discrete probability of the lobe).
#[derive(Debug, Clone, Copy)]
pub struct BsdfSample {
    pub wi: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    pub specular: bool,
    /// eta_t / eta_i of the boundary crossed by a refracted `wi`; 1 for reflection.
    pub eta: f32,
}

/// The reflectance of each lobe seen from one `wo`, and where the specular ones send light.
struct Lobes {
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
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether it has a mirror or refraction lobe.
    pub fn has_specular(&self) -> bool {
        self.specular.max_element() > 0.0 || self.transmission.max_element() > 0.0
    }

    pub fn has_diffuse(&self) -> bool {
        self.diffuse.max_element() > 0.0
    }

    /// Radiance emitted towards `wo`: emission is one-sided, towards the normal.
    pub fn emitted(&self, n: Vec3, wo: Vec3) -> Vec3 {
        if n.dot(wo) > 0.0 { self.emission } else { Vec3::ZERO }
    }

    /// The non-specular part of f(wo, wi): Lambert's kd / pi, reflection only (both sides).
    pub fn eval(&self, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
        if same_side(n, wo, wi) { self.diffuse * FRAC_1_PI } else { Vec3::ZERO }
    }

    /// Solid-angle density with which `sample` returns `wi` through its non-specular lobe.
    pub fn pdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        if !same_side(n, wo, wi) {
            return 0.0;
        }
        self.diffuse_probability(n, wo) * n.dot(wi).abs() * FRAC_1_PI
    }

    /// The probability with which `sample` chooses the diffuse lobe, seen from `wo`.
    #[inline]
    pub fn diffuse_probability(&self, n: Vec3, wo: Vec3) -> f32 {
        if self.has_specular() {
            self.lobe_probabilities(&self.lobes(n, wo))[0]
        } else if self.has_diffuse() {
            1.0
        } else {
            0.0
        }
    }

    /// Whether it is a diffuse lobe alone, which `sample_lambertian_lanes` samples.
    pub fn is_lambertian(&self) -> bool {
        self.has_diffuse() && !self.has_specular()
    }

    /// Chooses a lobe with probability from its reflectance (the course's per-bounce Russian
    /// roulette over kd, ks, kt), then a direction from it: cosine-weighted for the diffuse lobe.
    pub fn sample(&self, n: Vec3, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !self.has_specular() {
            // Lambertian alone (the common case): no lobe to choose.
            return if self.has_diffuse() { self.sample_diffuse(n, wo, 1.0, u) } else { None };
        }
        let lobes = self.lobes(n, wo);
        let [p_diffuse, p_reflect, _] = self.lobe_probabilities(&lobes);
        if u_lobe < p_diffuse {
            self.sample_diffuse(n, wo, p_diffuse, u)
        } else if u_lobe < p_diffuse + p_reflect {
            Some(specular_sample(lobes.reflect_dir, lobes.reflect, p_reflect, 1.0))
        } else {
            let wi = lobes.transmit_dir?;
            let p_transmit = 1.0 - p_diffuse - p_reflect;
            (p_transmit > 0.0).then(|| lobes.transmission_sample(wi, p_transmit))
        }
    }

    /// The diffuse lobe, chosen with probability `p_diffuse`: cosine-weighted on wo's side.
    pub fn sample_diffuse(&self, n: Vec3, wo: Vec3, p_diffuse: f32, u: Vec2) -> Option<BsdfSample> {
        let facing = if n.dot(wo) < 0.0 { -n } else { n };
        let local = cosine_hemisphere(u);
        let wi = to_world(facing, local);
        self.diffuse_sample(wi, p_diffuse * local.z * FRAC_1_PI, p_diffuse)
    }

    /// The sample of direction `wi` drawn from the diffuse lobe with density `pdf`; none where
    /// the density is not positive.
    fn diffuse_sample(&self, wi: Vec3, pdf: f32, p_diffuse: f32) -> Option<BsdfSample> {
        // f |cos| / pdf = (kd / pi) cos / (p cos / pi) = kd / p
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: self.diffuse / p_diffuse,
            pdf,
            specular: false,
            eta: 1.0,
        })
    }

    /// Samples only the specular lobes (mirror, refraction), with probabilities from their
    /// reflectances; `None` if the material has none. Used by Whitted-style integrators.
    pub fn sample_specular(&self, n: Vec3, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let lobes = self.lobes(n, wo);
        let reflect = mean(lobes.reflect);
        let transmit = mean(lobes.transmit);
        let total = reflect + transmit;
        if total <= 0.0 {
            return None;
        }
        let p_reflect = reflect / total;
        match lobes.transmit_dir {
            Some(wi) if u_lobe >= p_reflect => Some(lobes.transmission_sample(wi, 1.0 - p_reflect)),
            _ => Some(specular_sample(lobes.reflect_dir, lobes.reflect, p_reflect, 1.0)),
        }
    }

    fn lobes(&self, n: Vec3, wo: Vec3) -> Lobes {
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
        Lobes { reflect, transmit, eta, reflect_dir, transmit_dir }
    }

    /// Probabilities of the diffuse, reflection and transmission lobes, from their mean energy.
    fn lobe_probabilities(&self, lobes: &Lobes) -> [f32; 3] {
        let d = mean(self.diffuse);
        let r = mean(lobes.reflect);
        let t = mean(lobes.transmit);
        let total = d + r + t;
        if total <= 0.0 {
            return [0.0; 3];
        }
        [d / total, r / total, t / total]
    }
}

impl Lobes {
    /// Radiance is compressed by 1 / eta^2 on entering a denser medium (pbrt-v4, 9.5.2).
    fn transmission_sample(&self, wi: Vec3, probability: f32) -> BsdfSample {
        specular_sample(wi, self.transmit / (self.eta * self.eta), probability, self.eta)
    }
}

fn specular_sample(wi: Vec3, reflectance: Vec3, probability: f32, eta: f32) -> BsdfSample {
    BsdfSample { wi, weight: reflectance / probability, pdf: probability, specular: true, eta }
}

fn same_side(n: Vec3, wo: Vec3, wi: Vec3) -> bool {
    n.dot(wo) * n.dot(wi) > 0.0
}

fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Maps a direction from a frame with +z along `n` to the world (Duff et al. 2017).
pub fn to_world(n: Vec3, local: Vec3) -> Vec3 {
    let (t, b) = n.any_orthonormal_pair();
    local.x * t + local.y * b + local.z * n
}

/// `to_world` in four lanes, with `Vec3::any_orthonormal_pair`'s operations in its order.
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
    pub specular: BVec4A,
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
            self.specular.set_lane(lane, sample.specular);
            self.eta.set_lane(lane, sample.eta);
        }
    }
}

/// `sample` in the lanes of `lambertian`, whose materials are Lambertian (`is_lambertian`) with
/// reflectance `diffuse`: `sample_diffuse`'s operations in its order, so each lane gets exactly
/// what `sample` returns.
pub fn sample_lambertian_lanes(
    lambertian: BVec4A,
    diffuse: Vec3x4,
    n: Vec3x4,
    wo: Vec3x4,
    u: Vec2x4,
) -> BsdfSampleLanes {
    let facing = Vec3x4::select(n.dot(wo).cmplt(Vec4::ZERO), -n, n);
    let local = cosine_hemisphere_lanes(u);
    // The lobe's probability is 1: pdf = 1 cos / pi, and the weight kd / 1 is kd.
    let pdf = local.z * FRAC_1_PI;
    BsdfSampleLanes {
        found: lambertian & pdf.cmpgt(Vec4::ZERO),
        wi: to_world_lanes(facing, local),
        weight: diffuse,
        pdf,
        specular: BVec4A::FALSE,
        eta: Vec4::ONE,
    }
}

/// The diffuse lobe's `eval` (kd / pi) and `pdf` (p_diffuse |cos| / pi) in four lanes, both
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
    let pdf = Vec4::select(same_side, p_diffuse * n.dot(wi).abs() * FRAC_1_PI, Vec4::ZERO);
    (f, pdf)
}
