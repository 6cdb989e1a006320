//! The lobes a BSDF is made of, one file each. A lobe works in the shading frame's coordinates
//! (+z along the shading normal) and is the same seen from either side: it turns itself to the
//! side of `wo`.

mod ggx_conductor;
mod ggx_dielectric;
mod lambertian;
mod mirror;
mod plastic;
mod smooth_dielectric;

pub use ggx_conductor::GgxConductor;
pub use ggx_dielectric::GgxDielectric;
pub use lambertian::Lambertian;
pub use mirror::Mirror;
pub use plastic::Plastic;
pub use smooth_dielectric::SmoothDielectric;

use glam::{Vec2, Vec3};

use super::{LobeFlags, TransportMode};
use crate::lanes::Real;

/// A direction drawn from one lobe, in the shading frame. `weight` is f |cos| / pdf of the
/// lobe's own sampling (its choice between reflection and refraction included); `pdf` is in
/// solid angle, or for a delta lobe the probability of that choice.
#[derive(Debug, Clone, Copy)]
pub struct LobeSample {
    pub wi: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    /// The part of the lobe sampled: reflection or transmission, and its kind.
    pub flags: LobeFlags,
    /// eta_t / eta_i of the boundary crossed by a refracted `wi`; 1 for reflection.
    pub eta: f32,
}

#[derive(Debug, Clone, Copy)]
pub enum Lobe {
    Lambertian(Lambertian),
    Mirror(Mirror),
    SmoothDielectric(SmoothDielectric),
    GgxConductor(GgxConductor),
    GgxDielectric(GgxDielectric),
    Plastic(Plastic),
}

/// The dispatch over lobes is always inlined into the BSDF's methods: out of line, its call
/// and match cost as much as a Lambertian lobe's work (callgrind of S1–S7).
impl Lobe {
    #[inline(always)]
    pub fn flags(&self) -> LobeFlags {
        match self {
            Lobe::Lambertian(_) => Lambertian::FLAGS,
            Lobe::Mirror(_) => Mirror::FLAGS,
            Lobe::SmoothDielectric(_) => SmoothDielectric::FLAGS,
            Lobe::GgxConductor(_) => GgxConductor::FLAGS,
            Lobe::GgxDielectric(_) => GgxDielectric::FLAGS,
            Lobe::Plastic(_) => Plastic::FLAGS,
        }
    }

    /// The share of light from `wo` it scatters (mean over RGB), by which a BSDF chooses among
    /// its lobes (the course's per-bounce Russian roulette over kd, ks, kt).
    #[inline(always)]
    pub fn albedo(&self, wo: Vec3) -> f32 {
        match self {
            Lobe::Lambertian(lobe) => lobe.albedo(),
            Lobe::Mirror(lobe) => lobe.albedo(),
            Lobe::SmoothDielectric(lobe) => lobe.albedo(wo),
            Lobe::GgxConductor(lobe) => lobe.albedo(),
            Lobe::GgxDielectric(lobe) => lobe.albedo(),
            Lobe::Plastic(lobe) => lobe.albedo(wo),
        }
    }

    /// f(wo, wi); zero for delta lobes.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        self.eval_by(|v| v, wo, wi, mode)
    }

    /// `eval` of `local(wo)` and `local(wi)`, each arm taking the directions to the lobe's
    /// frame itself: what a lobe does not read of them is not computed (a Lambertian lobe
    /// reads only z; callgrind of S1–S7).
    #[inline(always)]
    pub fn eval_by(
        &self,
        local: impl Fn(Vec3) -> Vec3,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
    ) -> Vec3 {
        match self {
            Lobe::Lambertian(lobe) => lobe.eval(local(wo), local(wi)),
            Lobe::Mirror(_) | Lobe::SmoothDielectric(_) => Vec3::ZERO,
            Lobe::GgxConductor(lobe) => lobe.eval(local(wo), local(wi)),
            Lobe::GgxDielectric(lobe) => lobe.eval(local(wo), local(wi), mode),
            Lobe::Plastic(lobe) => lobe.eval(local(wo), local(wi)),
        }
    }

    /// Solid-angle density with which `sample` returns `wi`; zero for delta lobes.
    #[inline(always)]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_by(|v| v, wo, wi)
    }

    /// `pdf` of `local(wo)` and `local(wi)`, taken to the lobe's frame in each arm (`eval_by`).
    #[inline(always)]
    pub fn pdf_by(&self, local: impl Fn(Vec3) -> Vec3, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Lobe::Lambertian(lobe) => lobe.pdf(local(wo), local(wi)),
            Lobe::Mirror(_) | Lobe::SmoothDielectric(_) => 0.0,
            Lobe::GgxConductor(lobe) => lobe.pdf(local(wo), local(wi)),
            Lobe::GgxDielectric(lobe) => lobe.pdf(local(wo), local(wi)),
            Lobe::Plastic(lobe) => lobe.pdf(local(wo), local(wi)),
        }
    }

    /// A direction from the lobe: `u` draws it, `u_split` chooses between reflection and
    /// refraction, or coat and base, where the lobe has both. Every lobe's `sample` is always
    /// inlined here, as is `Bsdf::sample_among`: with one arm out of line, its returned
    /// `Option<LobeSample>` kept the result of every arm in memory, and the Lambertian lobe's
    /// sample, stored field by field, was copied out by wider loads that wait for those stores
    /// (store forwarding fails). Inlined, S2, S4, S5 and S7 took 4–22 % less CPU time in two
    /// alternated runs, S3 from 14 % less to 2 % more (docs/benchmarks.md).
    #[inline(always)]
    pub fn sample(
        &self,
        wo: Vec3,
        u_split: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<LobeSample> {
        match self {
            Lobe::Lambertian(lobe) => lobe.sample(wo, u),
            Lobe::Mirror(lobe) => Some(lobe.sample(wo)),
            Lobe::SmoothDielectric(lobe) => lobe.sample(wo, u_split, mode),
            Lobe::GgxConductor(lobe) => lobe.sample(wo, u),
            Lobe::GgxDielectric(lobe) => lobe.sample(wo, u_split, u, mode),
            Lobe::Plastic(lobe) => lobe.sample(wo, u_split, u),
        }
    }
}

/// +1 where `wo` (local) is on the normal's side, -1 below: the side a two-sided lobe turns to.
#[inline]
fn side_of(wo: Vec3) -> f32 {
    side_of_z(wo.z)
}

/// `side_of` a direction whose local z is `z`, written once over `Real`.
#[inline(always)]
fn side_of_z<F: Real>(z: F) -> F {
    F::select(z.lt(F::ZERO), -F::ONE, F::ONE)
}

/// The mirror direction of `wo` about the +z normal.
#[inline]
fn reflect(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}

/// Mean over RGB.
#[inline]
pub(super) fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// The probabilities of reflection and transmission from their mean shares.
#[inline]
fn shares((reflect, transmit): (Vec3, Vec3)) -> (f32, f32) {
    let (r, t) = (mean(reflect), mean(transmit));
    if r + t <= 0.0 {
        return (0.0, 0.0);
    }
    (r / (r + t), t / (r + t))
}
