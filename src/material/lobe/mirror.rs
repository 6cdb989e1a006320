//! A perfect mirror of reflectance ks, the same whatever the angle (the course's `specular`).

use glam::Vec3;

use super::{LobeSample, mean, reflect};
use crate::material::LobeFlags;

#[derive(Debug, Clone, Copy)]
pub struct Mirror {
    /// ks.
    pub reflectance: Vec3,
}

impl Mirror {
    pub const FLAGS: LobeFlags = LobeFlags::DELTA.union(LobeFlags::REFLECTION);

    pub fn albedo(&self) -> f32 {
        mean(self.reflectance)
    }

    /// The one direction it reflects `wo` to, with weight ks.
    #[inline]
    pub fn sample(&self, wo: Vec3) -> LobeSample {
        LobeSample {
            wi: reflect(wo),
            weight: self.reflectance,
            pdf: 1.0,
            flags: Self::FLAGS,
            eta: 1.0,
        }
    }
}
