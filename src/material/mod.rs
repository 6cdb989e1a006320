//! Materials of the course's model — Lambertian `diffuse` (kd), mirror `specular` (ks),
//! refractive `transmission` (kt) with `ior`, `emission`, and `roughness` that makes the mirror
//! and refraction GGX microfacet lobes, and a glossy `coat` over the diffuse base (plastic; over
//! the mirror and transmission too for POV-Ray's highlights, `Covers`) — and the BSDF each
//! makes at a hit (`Material::bsdf`):
//! its lobes (`lobe/`, one file each) in a shading frame, `eval`, `sample`, `pdf` under a mask
//! of lobes.

mod bsdf;
mod coat;
mod flags;
mod fresnel;
pub mod lobe;
mod microfacet;
mod pov_shares;

pub use bsdf::{Bsdf, BsdfSample, NEAR_SPECULAR_ROUGHNESS, NO_DIRECTION, TransportMode};
pub use coat::{Coat, CoatLayer};
pub use flags::LobeFlags;
pub use fresnel::{Split, fresnel_dielectric, refract};
pub use pov_shares::{Shares, pov_shares};

use glam::Vec3;

use crate::graph::{MaterialDesc, Pattern};
use crate::light::{Beam, SpotProfile, emitted};
use lobe::{Lambertian, Lobe, Plastic};
use microfacet::Ggx;

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub transmission: Vec3,
    pub ior: f32,
    pub emission: Vec3,
    /// `emission` leaves both sides (`emitted`).
    pub two_sided: bool,
    /// Split `specular + transmission` between reflection and refraction by Fresnel's equations.
    pub fresnel: bool,
    /// GGX alpha of the `specular` and `transmission` lobes; 0: perfect mirror and refraction.
    pub roughness: f32,
    /// A glossy coat over `diffuse`, if any.
    pub coat: Option<Coat>,
    /// The beam that shapes `emission` (an area spotlight's), if any (`emitted`).
    pub beam: Option<Beam>,
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
            two_sided: false,
            fresnel: false,
            roughness: 0.0,
            coat: None,
            beam: None,
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
            two_sided: d.two_sided,
            fresnel: d.fresnel,
            roughness: d.roughness,
            coat: (d.coat > 0.0).then_some(Coat {
                strength: d.coat,
                roughness: d.coat_roughness,
                covers: d.coat_covers,
            }),
            beam: d.beam.map(|b| Beam {
                axis: b.axis,
                profile: SpotProfile::from_degrees(b.cone.radius, b.cone.falloff, b.cone.tightness),
            }),
        }
    }
}

impl Material {
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// The lobe of `diffuse` and `coat`: Lambertian, or plastic under a coat (even over a black
    /// base); none where neither reflects.
    #[inline]
    fn base_lobe(&self) -> Option<Lobe> {
        match self.coat {
            Some(coat) => Some(Lobe::Plastic(Plastic {
                base: self.diffuse,
                coat: coat.strength,
                layer: coat.layer(),
                ggx: Ggx { alpha: coat.roughness },
            })),
            None if self.diffuse.max_element() > 0.0 => {
                Some(Lobe::Lambertian(Lambertian { reflectance: self.diffuse }))
            }
            None => None,
        }
    }

    /// Whether light crosses it straight, unbent, where it transmits: a smooth transmission at
    /// ior 1 (POV-Ray's filter and transmit without an interior's ior; pbrt's interface
    /// material). Shadow rays cross it, weighted by `straight_through` (`Scene::transmittance`).
    #[inline]
    pub fn passes_straight(&self) -> bool {
        self.ior == 1.0 && self.roughness == 0.0 && !self.fresnel
    }

    /// The light it lets straight through where it `passes_straight`, crossed at cosine `cos`
    /// to the normal: `transmission`, under a coat over it what the coat lets through of that
    /// (`CoatLayer::beneath`, as the BSDF's transmission).
    #[inline]
    pub fn straight_through(&self, cos: f32) -> Vec3 {
        match self.coat.and_then(|coat| coat.over_all()) {
            Some(layer) => self.transmission * layer.through(cos),
            None => self.transmission,
        }
    }

    /// Takes the lobes' shares at a point (a POV-Ray pigment's, `pov_shares`).
    #[inline]
    pub fn share(&mut self, shares: Shares) {
        self.diffuse = shares.diffuse;
        self.specular = shares.specular;
        self.transmission = shares.transmission;
        if let Some(coat) = &mut self.coat {
            coat.strength = shares.coat;
        }
    }

    /// Radiance emitted towards `wo` from a point with normal `n` (`light::emitted`).
    #[inline]
    pub fn emitted(&self, n: Vec3, wo: Vec3) -> Vec3 {
        emitted(self.emission, self.beam.as_ref(), self.two_sided, n, wo)
    }
}
