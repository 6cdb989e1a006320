//! The BSDF at a surface point, built from its material (pbrt-v4's `Material::GetBSDF`): the
//! shading frame, built once, and the lobes; `eval` / `pdf` / `sample` over the lobes a caller's
//! mask asks for (pbrt-v4's sample flags, Mitsuba's `BSDFContext`).
//!
//! Directions follow pbrt: `wo` points towards the viewer, `wi` towards the light, both unit.

use arrayvec::ArrayVec;
use glam::{Vec2, Vec3};

use super::fresnel::Split;
use super::lobe::{GgxConductor, GgxDielectric, Lambertian, Lobe, Mirror, SmoothDielectric};
use super::microfacet::Ggx;
use super::{CoatLayer, LobeFlags, Material};
use crate::geometry::Frame;

/// What a path carries: radiance (camera paths) or importance (photons, light paths). They
/// differ only in the 1/eta^2 that refraction applies to radiance (pbrt-v4, 9.5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

impl TransportMode {
    /// What refraction carries of energy `transmitted` across a boundary of relative index
    /// `eta`: radiance is compressed by 1 / eta^2 on entering a denser medium; importance is not.
    #[inline]
    pub fn carried(self, transmitted: Vec3, eta: f32) -> Vec3 {
        match self {
            TransportMode::Radiance => transmitted / (eta * eta),
            TransportMode::Importance => transmitted,
        }
    }
}

/// A direction drawn from a BSDF. `weight` is f |cos| / pdf of the lobe taken, including the
/// probability of taking it; `pdf` is in solid angle, that of every lobe with a density that the
/// mask let take part (for multiple importance sampling), or for a delta lobe the discrete
/// probability of the choice.
#[derive(Debug, Clone, Copy)]
pub struct BsdfSample {
    pub wi: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    /// The lobe sampled: reflection or transmission, diffuse, glossy or delta.
    pub flags: LobeFlags,
    /// eta_t / eta_i of the boundary crossed by a refracted `wi`; 1 for reflection.
    pub eta: f32,
}

impl BsdfSample {
    /// Drawn from a delta lobe: a light sample could not have found `wi`.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.flags.is_delta()
    }
}

/// The direction sample to pass `Bsdf::sample` under a mask of delta lobes alone, which read
/// none.
pub const NO_DIRECTION: Vec2 = Vec2::ZERO;

/// GGX alpha (`roughness`) below which photon mapping treats a glossy lobe as near-specular: its
/// light is not estimated from photons (a density estimate blurs a lobe narrower than the
/// gather disc into blotches) but followed by sampling the lobe, as a delta lobe is
/// (`Bsdf::gathered_lobes`, `docs/language.md`). 0.2 follows rough.scn's blotched lobes (0.02
/// and 0.1 gold, 0.08 copper, 0.15 frosted glass) and gathers its 0.3 and 0.7 gold, whose
/// lobes are broader than the gather discs.
pub const NEAR_SPECULAR_ROUGHNESS: f32 = 0.2;

/// The most lobes a material makes: a diffuse (or coated) base and one specular or glossy lobe.
const MAX_LOBES: usize = 2;

/// The lobes of a material at a point, in its shading frame, for one kind of transport.
#[derive(Debug, Clone)]
pub struct Bsdf {
    frame: Frame,
    lobes: ArrayVec<Lobe, MAX_LOBES>,
    mode: TransportMode,
    /// Its lobes' flags together.
    flags: LobeFlags,
    /// The coat over the lobes other than its own (POV-Ray's highlight over a mirror or a
    /// transmission, `Covers::Everything`), if any: they carry what it lets through.
    beneath: Option<CoatLayer>,
    /// The geometric normal, where bump mapping tilted the shading normal away from it
    /// (`face`); `None` otherwise.
    geometric: Option<Vec3>,
}

impl Material {
    /// The BSDF of this material where the shading normal is `n`, for `mode` transport: a
    /// Lambertian lobe of `diffuse` (plastic under a `coat`); and `specular` and `transmission`
    /// as a mirror (no transmission, no Fresnel) or a smooth dielectric, or where `roughness`
    /// > 0 their GGX forms, a conductor or a dielectric, under the coat where it covers them.
    ///
    /// Always inlined, as are the BSDF's `sample` and `pdf`: made and used once per vertex, out
    /// of line they cost their calls and a copy of the BSDF (callgrind of S1–S7).
    #[inline(always)]
    pub fn bsdf(&self, n: Vec3, mode: TransportMode) -> Bsdf {
        let mut bsdf = Bsdf::BLACK;
        self.bsdf_in(&mut bsdf, n, mode);
        bsdf
    }

    /// The lobe of its BSDF where that is its one lobe, a Lambertian one that scatters light
    /// (kd > 0): `Bsdf::sample` then gives `Lambertian::direction` in the frame of the shading
    /// normal, weighted by kd, and never ends a path for a leak where bump mapping did not tilt
    /// that normal (`Bsdf::face`).
    #[inline(always)]
    pub fn lone_lambertian(&self) -> Option<Lambertian> {
        match self.base_lobe() {
            Some(Lobe::Lambertian(lobe)) if !self.has_specular_lobe() && lobe.albedo() > 0.0 => {
                Some(lobe)
            }
            _ => None,
        }
    }

    /// Whether its BSDF has a specular or transmission lobe beside the base (`bsdf_in`).
    #[inline(always)]
    fn has_specular_lobe(&self) -> bool {
        self.specular.max_element() > 0.0 || self.transmission.max_element() > 0.0
    }

    /// `bsdf` made in place in `bsdf`, whatever it held.
    #[inline(always)]
    pub fn bsdf_in(&self, bsdf: &mut Bsdf, n: Vec3, mode: TransportMode) {
        bsdf.frame = Frame::from_normal(n);
        bsdf.lobes.clear();
        if let Some(base) = self.base_lobe() {
            bsdf.lobes.push(base);
        }
        if self.has_specular_lobe() {
            let (ks, kt) = (self.specular, self.transmission);
            let dielectric = kt.max_element() > 0.0 || self.fresnel;
            let split = if self.fresnel {
                Split::Fresnel { total: ks + kt }
            } else {
                Split::Fixed { reflect: ks, transmit: kt }
            };
            let (ior, ggx) = (self.ior, Ggx { alpha: self.roughness });
            bsdf.lobes.push(match (self.roughness > 0.0, dielectric) {
                (false, false) => Lobe::Mirror(Mirror { reflectance: ks }),
                (false, true) => Lobe::SmoothDielectric(SmoothDielectric { split, ior }),
                (true, false) => Lobe::GgxConductor(GgxConductor { reflectance: ks, ggx }),
                (true, true) => Lobe::GgxDielectric(GgxDielectric { split, ior, ggx }),
            });
        }
        bsdf.flags = bsdf.lobes.iter().fold(LobeFlags::NONE, |flags, lobe| flags | lobe.flags());
        bsdf.beneath = self.coat.and_then(|coat| coat.over_all());
        bsdf.mode = mode;
        bsdf.geometric = None;
    }
}

impl Bsdf {
    /// A BSDF of no lobes, for `Material::bsdf_in` to fill.
    pub const BLACK: Bsdf = Bsdf {
        frame: Frame::Z,
        lobes: ArrayVec::new_const(),
        mode: TransportMode::Radiance,
        flags: LobeFlags::NONE,
        beneath: None,
        geometric: None,
    };

    /// Puts this BSDF on a surface of geometric normal `geometric` (bump mapping's tilted shading
    /// frame): a pair of directions that the geometric surface and the shading frame see on
    /// different sides (one reflects where the other transmits) carries nothing, so no light
    /// leaks through the surface and none reaches it from below.
    #[inline]
    pub fn face(&mut self, geometric: Vec3) {
        self.geometric = Some(geometric);
    }

    /// Whether `wo` and `wi` (world) cross the surface differently in the shading frame than
    /// geometrically (always false without `face`).
    #[inline]
    fn leaks(&self, wo: Vec3, wi: Vec3) -> bool {
        let Some(n) = self.geometric else { return false };
        let shading = self.frame.to_local(wo).z * self.frame.to_local(wi).z > 0.0;
        (wo.dot(n) * wi.dot(n) > 0.0) != shading
    }

    /// The kinds of lobes it has.
    #[inline]
    pub fn flags(&self) -> LobeFlags {
        self.flags
    }

    /// The lobes photon mapping estimates from photons here: the diffuse (or coated) lobe, and
    /// a glossy one at least `NEAR_SPECULAR_ROUGHNESS` rough. The others (delta and near-specular lobes)
    /// photon mapping follows by sampling, and photons are stored only where this is not empty.
    #[inline]
    pub fn gathered_lobes(&self) -> LobeFlags {
        let broad = |lobe: &Lobe| match lobe {
            // A coated base is gathered whole, its coat too: the coat's highlight of lights is
            // next-event estimation's, only its reflection of other surfaces is the photons'.
            Lobe::Lambertian(_) | Lobe::Plastic(_) => true,
            Lobe::Mirror(_) | Lobe::SmoothDielectric(_) => false,
            Lobe::GgxConductor(GgxConductor { ggx, .. })
            | Lobe::GgxDielectric(GgxDielectric { ggx, .. }) => {
                ggx.alpha >= NEAR_SPECULAR_ROUGHNESS
            }
        };
        let gathered = self.lobes.iter().filter(|lobe| broad(lobe));
        gathered.fold(LobeFlags::NONE, |flags, lobe| flags | lobe.flags())
    }

    /// f(wo, wi) of the lobes with a density. Always inlined, as are `eval_lobes` and
    /// `eval_pdf`: next-event estimation calls one per light sample, and out of line (as LLVM
    /// left them) each call cost a Lambertian vertex about 110 instructions (callgrind, S1–S3).
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.leaks(wo, wi) {
            return Vec3::ZERO;
        }
        self.eval_world(wo, wi, LobeFlags::ALL)
    }

    /// f(wo, wi) of the lobes with a density that `mask` asks for.
    #[inline(always)]
    pub fn eval_lobes(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> Vec3 {
        if self.leaks(wo, wi) {
            return Vec3::ZERO;
        }
        self.eval_world(wo, wi, mask)
    }

    /// `eval_lobes` of world directions, without the check for leaks. Always inlined:
    /// next-event estimation calls it once per light sample, and out of line its call costs as
    /// much as a Lambertian lobe's work. A lone lobe (every material of S1–S7) is evaluated
    /// without the walk over lobes, which would give the same sum of one term, and takes the
    /// directions to the shading frame itself (`Lobe::eval_by`): a Lambertian lobe's cosines
    /// alone are computed. (A lone lobe is under no coat: a coat makes a lobe of its own.)
    #[inline(always)]
    fn eval_world(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> Vec3 {
        let local = |v| self.frame.to_local(v);
        if let [lobe] = self.lobes.as_slice() {
            let taken = lobe.flags().is_in(mask);
            return if taken { lobe.eval_by(local, wo, wi, self.mode) } else { Vec3::ZERO };
        }
        self.eval_local(local(wo), local(wi), mask)
    }

    /// `eval_lobes` in the shading frame, over any number of lobes.
    #[inline(always)]
    fn eval_local(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> Vec3 {
        let taking = self.lobes.iter().filter(|lobe| lobe.flags().is_in(mask));
        let mut f =
            taking.map(|lobe| lobe.eval(wo, wi, self.mode) * self.through_coat(lobe, wo, wi));
        let first = f.next().unwrap_or(Vec3::ZERO);
        f.fold(first, |f, lobe| f + lobe)
    }

    /// Solid-angle density with which `sample` under `mask` returns `wi` through its lobes with
    /// a density: each lobe's, times the probability of taking it.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> f32 {
        self.pdf_world(wo, wi, mask)
    }

    /// `eval` and `pdf` together (next-event estimation weighs the light sample by both): the
    /// directions taken to the shading frame once.
    #[inline(always)]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> (Vec3, f32) {
        if self.leaks(wo, wi) {
            return (Vec3::ZERO, 0.0);
        }
        (self.eval_world(wo, wi, LobeFlags::ALL), self.pdf_world(wo, wi, mask))
    }

    /// `pdf` of world directions: for a lone lobe, its own density where it is taken
    /// (`pdf_local` with the choice of one lobe, bit for bit), the directions taken to the
    /// shading frame by the lobe (`Lobe::pdf_by`, as `eval_world`).
    #[inline(always)]
    fn pdf_world(&self, wo: Vec3, wi: Vec3, mask: LobeFlags) -> f32 {
        let local = |v| self.frame.to_local(v);
        match self.lobes.as_slice() {
            [lobe] => {
                let taken = lobe.flags().is_in(mask) && lobe.albedo(local(wo)) > 0.0;
                let with_density = taken && lobe.flags().is_non_delta();
                if with_density { 0.0 + lobe.pdf_by(local, wo, wi) } else { 0.0 }
            }
            _ => {
                let wo = local(wo);
                self.pdf_local(wo, local(wi), &self.choice(wo, mask))
            }
        }
    }

    fn pdf_local(&self, wo: Vec3, wi: Vec3, choice: &[f32; MAX_LOBES]) -> f32 {
        let mut pdf = 0.0;
        for (lobe, &p) in self.lobes.iter().zip(choice) {
            if p > 0.0 && lobe.flags().is_non_delta() {
                pdf += p * lobe.pdf(wo, wi);
            }
        }
        pdf
    }

    /// The probability with which `sample` over every lobe takes one of those `mask` asks
    /// for, seen from `wo`.
    #[inline]
    pub fn probability_of(&self, wo: Vec3, mask: LobeFlags) -> f32 {
        let choice = self.choice(self.frame.to_local(wo), LobeFlags::ALL);
        let taking = self.lobes.iter().zip(choice).filter(|(lobe, _)| lobe.flags().is_in(mask));
        taking.map(|(_, p)| p).sum()
    }

    /// The coat over `lobe`, if it lies under one (`beneath`; never the coat's own lobe).
    #[inline(always)]
    fn coat_over(&self, lobe: &Lobe) -> Option<CoatLayer> {
        match lobe {
            Lobe::Plastic(_) => None,
            Lobe::Lambertian(_)
            | Lobe::Mirror(_)
            | Lobe::SmoothDielectric(_)
            | Lobe::GgxConductor(_)
            | Lobe::GgxDielectric(_) => self.beneath,
        }
    }

    /// The share of `lobe`'s light from `wi` to `wo` (local) that the coat over it lets
    /// through (`CoatLayer::beneath`); 1 where no coat covers it.
    #[inline(always)]
    fn through_coat(&self, lobe: &Lobe, wo: Vec3, wi: Vec3) -> f32 {
        self.coat_over(lobe).map_or(1.0, |coat| coat.beneath(wo, wi))
    }

    /// The probability of taking each lobe under `mask`, seen from `wo` (local): in proportion
    /// to its albedo (the course's per-bounce Russian roulette over kd, ks, kt), a lobe under a
    /// coat's times what the coat lets in; 1 for the only lobe taking part.
    #[inline]
    fn choice(&self, wo: Vec3, mask: LobeFlags) -> [f32; MAX_LOBES] {
        let mut albedo = [0.0; MAX_LOBES];
        let mut taking = 0;
        for (a, lobe) in albedo.iter_mut().zip(&self.lobes) {
            if lobe.flags().is_in(mask) {
                *a = lobe.albedo(wo) * self.coat_over(lobe).map_or(1.0, |coat| coat.through(wo.z));
                taking += 1;
            }
        }
        if taking == 1 {
            return albedo.map(|a| if a > 0.0 { 1.0 } else { 0.0 });
        }
        let total: f32 = albedo.iter().sum();
        if total <= 0.0 {
            return [0.0; MAX_LOBES];
        }
        albedo.map(|a| a / total)
    }

    /// Takes one of the lobes `mask` asks for with `u_lobe` (`choice`), then a direction from
    /// it, the rest of `u_lobe` choosing between reflection and refraction within it. Delta
    /// lobes read no `u`.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2, mask: LobeFlags) -> Option<BsdfSample> {
        let local = self.frame.to_local(wo);
        let sample = match self.lobes.as_slice() {
            [lobe] => self.sample_lone(lobe, local, u_lobe, u, mask),
            _ => self.sample_among(local, u_lobe, u, mask),
        }?;
        let wi = self.frame.to_world(sample.wi);
        // A direction that leaks through the surface ends the path (its light is lost, never
        // gained).
        if self.leaks(wo, wi) {
            return None;
        }
        Some(BsdfSample { wi, ..sample })
    }

    /// `sample_among` for a BSDF of one lobe (most materials), without the choice among lobes:
    /// it is taken with probability 1 where `mask` asks for it and it scatters light, and all of
    /// `u_lobe` is left for its own choices; the same result, bit for bit (tested).
    #[inline(always)]
    fn sample_lone(
        &self,
        lobe: &Lobe,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mask: LobeFlags,
    ) -> Option<BsdfSample> {
        if !(lobe.flags().is_in(mask) && lobe.albedo(wo) > 0.0) {
            return None;
        }
        let sample = lobe.sample(wo, u_lobe.clamp(0.0, ONE_MINUS_EPSILON), u, self.mode)?;
        (sample.pdf > 0.0).then_some(BsdfSample {
            wi: sample.wi,
            weight: sample.weight,
            pdf: sample.pdf,
            flags: sample.flags,
            eta: sample.eta,
        })
    }

    /// `sample` in the shading frame (`wi` too), over any number of lobes. Always inlined, as
    /// the lobes' `sample`s are (`Lobe::sample`): out of line, the BSDF sample it returns kept
    /// the lone lobe's in memory too.
    #[inline(always)]
    fn sample_among(&self, wo: Vec3, u_lobe: f32, u: Vec2, mask: LobeFlags) -> Option<BsdfSample> {
        let choice = self.choice(wo, mask);
        let (index, u_split) = take(&choice, u_lobe)?;
        let (lobe, p) = (&self.lobes[index], choice[index]);
        let sample = lobe.sample(wo, u_split, u, self.mode)?;
        // With another lobe of a density taking part, the direction's density is theirs
        // together (one-sample MIS over the lobes); the weight stays the lobe's own.
        let others_with_density = self
            .lobes
            .iter()
            .zip(&choice)
            .enumerate()
            .any(|(i, (l, &q))| i != index && q > 0.0 && l.flags().is_non_delta());
        let pdf = if sample.flags.is_delta() || !others_with_density {
            p * sample.pdf
        } else {
            self.pdf_local(wo, sample.wi, &choice)
        };
        (pdf > 0.0).then_some(BsdfSample {
            wi: sample.wi,
            weight: sample.weight * self.through_coat(lobe, wo, sample.wi) / p,
            pdf,
            flags: sample.flags,
            eta: sample.eta,
        })
    }
}

/// The lobe `u` takes from probabilities `choice` (0 for lobes not taking part), and what is
/// left of `u` for the lobe's own choices, rescaled to [0, 1).
#[inline]
fn take(choice: &[f32; MAX_LOBES], u: f32) -> Option<(usize, f32)> {
    let last = choice.iter().rposition(|&p| p > 0.0)?;
    let mut start = 0.0;
    for (index, &p) in choice.iter().enumerate().take(last) {
        if p > 0.0 && u < start + p {
            return Some((index, ((u - start) / p).min(ONE_MINUS_EPSILON)));
        }
        start += p;
    }
    Some((last, ((u - start) / choice[last]).clamp(0.0, ONE_MINUS_EPSILON)))
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// Materials of one lobe each: Lambertian, mirror, smooth and rough dielectrics (fixed
    /// split and Fresnel's), rough conductor.
    fn lone_lobe_materials() -> Vec<Material> {
        let kd = Vec3::new(0.7, 0.2, 0.4);
        let base = Material::default();
        vec![
            Material { diffuse: kd, ..base.clone() },
            Material { specular: kd, ..base.clone() },
            Material { transmission: kd, ior: 1.5, ..base.clone() },
            Material { specular: kd, transmission: kd, ior: 1.3, fresnel: true, ..base.clone() },
            Material { specular: kd, roughness: 0.3, ..base.clone() },
            Material { transmission: Vec3::ONE, ior: 1.5, fresnel: true, roughness: 0.2, ..base },
        ]
    }

    /// A fixed spread of unit directions and sample values (a low-discrepancy walk).
    fn spread(i: u32) -> (Vec3, Vec3, f32, Vec2) {
        let f = |k: f32| (i as f32 * k).fract();
        let dir = |a: f32, b: f32| {
            let z = 1.0 - 2.0 * a;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * b;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        };
        let wo = dir(f(0.618_034), f(0.754_877_7));
        let wi = dir(f(0.569_840_3), f(0.314_159_3));
        (wo, wi, f(0.414_213_6), Vec2::new(f(0.732_050_8), f(0.236_068)))
    }

    fn bits(s: Option<BsdfSample>) -> Option<([u32; 7], f32, LobeFlags)> {
        s.map(|s| {
            let (wi, w) =
                (s.wi.to_array().map(f32::to_bits), s.weight.to_array().map(f32::to_bits));
            ([wi[0], wi[1], wi[2], w[0], w[1], w[2], s.pdf.to_bits()], s.eta, s.flags)
        })
    }

    /// The lone lobe's short ways through `sample` and `pdf` give what the choice among lobes
    /// gives, bit for bit, under every mask.
    #[test]
    fn a_lone_lobe_samples_and_weighs_as_the_choice_among_lobes() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let masks = [
            LobeFlags::ALL,
            LobeFlags::NON_DELTA,
            LobeFlags::DELTA,
            LobeFlags::DIFFUSE,
            LobeFlags::GLOSSY,
        ];
        for material in lone_lobe_materials() {
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                let bsdf = material.bsdf(n, mode);
                assert_eq!(bsdf.lobes.len(), 1, "{material:?}");
                for i in 0..2000 {
                    let (wo, wi, u_lobe, u) = spread(i);
                    for mask in masks {
                        let among = bsdf
                            .sample_among(bsdf.frame.to_local(wo), u_lobe, u, mask)
                            .map(|s| BsdfSample { wi: bsdf.frame.to_world(s.wi), ..s });
                        assert_eq!(bits(bsdf.sample(wo, u_lobe, u, mask)), bits(among));
                        let lone = bsdf.pdf(wo, wi, mask);
                        let (wo, wi) = (bsdf.frame.to_local(wo), bsdf.frame.to_local(wi));
                        let choice = bsdf.choice(wo, mask);
                        let pdf = bsdf.pdf_local(wo, wi, &choice);
                        assert_eq!(lone.to_bits(), pdf.to_bits());
                    }
                }
            }
        }
    }
}
