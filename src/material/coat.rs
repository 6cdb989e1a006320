//! A glossy dielectric coat (the `coat` of a material, POV-Ray's highlights) and what it lets
//! through to what lies beneath it.

use glam::Vec3;

use super::fresnel::fresnel_dielectric;
use crate::graph::Covers;

/// A glossy dielectric coat over the diffuse base (the plastic lobe, `lobe::Plastic`), and over
/// the mirror and transmission too where it `covers` them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coat {
    /// The share of the coat's Fresnel reflection kept, in (0, 1]; 1 is a physical coat.
    pub strength: f32,
    /// GGX alpha of its microfacets, in (0, 1].
    pub roughness: f32,
    pub covers: Covers,
}

impl Coat {
    /// Index of refraction of every coat: a typical plastic or varnish (F = 0.04 head-on).
    pub const IOR: f32 = 1.5;

    /// What it lets through to its base.
    #[inline]
    pub fn layer(&self) -> CoatLayer {
        let held = match self.covers {
            Covers::Base => 1.0,
            Covers::Everything => self.strength,
        };
        CoatLayer { held, ior: Coat::IOR }
    }

    /// What it lets through to the mirror and transmission, where it covers them.
    #[inline]
    pub fn over_all(&self) -> Option<CoatLayer> {
        match self.covers {
            Covers::Base => None,
            Covers::Everything => Some(self.layer()),
        }
    }
}

/// A smooth coat seen by what lies beneath it: at each crossing it lets through 1 - `held` F(θ)
/// of the light, F Fresnel's reflectance of index `ior` at θ from the normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatLayer {
    /// The share of Fresnel's reflection the coat holds back, in [0, 1].
    pub held: f32,
    pub ior: f32,
}

impl CoatLayer {
    /// What one crossing at cosine `cos` to the normal lets through.
    #[inline]
    pub fn through(&self, cos: f32) -> f32 {
        1.0 - self.held * fresnel_dielectric(cos.abs(), self.ior)
    }

    /// What a lobe beneath carries from `wi` to `wo` (shading frame) through the coat: in and
    /// out for a reflection; once, at the angle of the direction on the normal's (the coat's)
    /// side, for a transmission. Symmetric in `wo` and `wi`, so the lobe stays reciprocal.
    #[inline]
    pub fn beneath(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z > 0.0 {
            self.through(wo.z) * self.through(wi.z)
        } else {
            self.through(wo.z.max(wi.z))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A coat of weight c over a clear transmission: what it reflects head-on (c F) and what
    /// passes sum to 1, whatever c; `.scn`'s coat holds back all of F from its base.
    #[test]
    fn a_layered_coat_passes_what_it_does_not_reflect() {
        let f = fresnel_dielectric(1.0, Coat::IOR);
        for strength in [0.1, 0.5, 1.0] {
            let coat = Coat { strength, roughness: 0.1, covers: Covers::Everything };
            let layer = coat.over_all().unwrap();
            let passed = layer.beneath(Vec3::Z, -Vec3::Z);
            assert!((strength * f + passed - 1.0).abs() < 1e-6, "{strength}: {passed}");
            let base = Coat { covers: Covers::Base, ..coat };
            assert_eq!(base.over_all(), None);
            assert!((base.layer().through(1.0) - (1.0 - f)).abs() < 1e-6);
        }
    }
}
