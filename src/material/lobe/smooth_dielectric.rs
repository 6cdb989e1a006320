//! A smooth boundary between two media: perfect reflection and Snell refraction, sharing what
//! arrives by Fresnel's equations or by the course's fixed ks and kt (`Split`).

use glam::Vec3;

use super::{LobeSample, mean, reflect, side_of};
use crate::material::fresnel::{Split, refract};
use crate::material::{LobeFlags, TransportMode};

#[derive(Debug, Clone, Copy)]
pub struct SmoothDielectric {
    pub split: Split,
    /// Index of refraction inside (on the side opposite the normal) over outside.
    pub ior: f32,
}

/// What the boundary does with light from one `wo`.
struct Boundary {
    reflect: Vec3,
    /// Energy carried through; `None` for the direction under total internal reflection
    /// (then `reflect` holds everything).
    transmit: Vec3,
    transmit_dir: Option<Vec3>,
    /// eta_t / eta_i for a direction crossing from wo's side.
    eta: f32,
}

impl SmoothDielectric {
    pub const FLAGS: LobeFlags =
        LobeFlags::DELTA.union(LobeFlags::REFLECTION).union(LobeFlags::TRANSMISSION);

    #[inline]
    fn boundary(&self, wo: Vec3) -> Boundary {
        let cos_o = wo.z;
        let eta = if cos_o >= 0.0 { self.ior } else { 1.0 / self.ior };
        let transmit_dir = refract(wo, Vec3::new(0.0, 0.0, side_of(wo)), eta);
        let (reflect, transmit) = self.split.at(cos_o.abs(), eta);
        Boundary { reflect, transmit, transmit_dir, eta }
    }

    /// Reflected and transmitted together, seen from `wo`.
    pub fn albedo(&self, wo: Vec3) -> f32 {
        let boundary = self.boundary(wo);
        mean(boundary.reflect) + mean(boundary.transmit)
    }

    /// Reflection or refraction, chosen by `u_split` with probability from their mean energy.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_split: f32, mode: TransportMode) -> Option<LobeSample> {
        let boundary = self.boundary(wo);
        let (r, t) = (mean(boundary.reflect), mean(boundary.transmit));
        let total = r + t;
        if total <= 0.0 {
            return None;
        }
        let p_reflect = r / total;
        match boundary.transmit_dir {
            Some(wi) if u_split >= p_reflect => {
                let p_transmit = 1.0 - p_reflect;
                Some(LobeSample {
                    wi,
                    weight: mode.carried(boundary.transmit, boundary.eta) / p_transmit,
                    pdf: p_transmit,
                    flags: LobeFlags::DELTA.union(LobeFlags::TRANSMISSION),
                    eta: boundary.eta,
                })
            }
            _ => Some(LobeSample {
                wi: reflect(wo),
                weight: boundary.reflect / p_reflect,
                pdf: p_reflect,
                flags: LobeFlags::DELTA.union(LobeFlags::REFLECTION),
                eta: 1.0,
            }),
        }
    }
}
