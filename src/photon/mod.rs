//! Photon mapping's parts: photons shared out among the lights (`emission`), aimed at the
//! casters of caustics for a caustic pass (`projection`), traced through the scene (`trace`),
//! stored in a k-d tree for k-nearest queries (`kd_tree`), and the hash grid of visible points
//! that progressive photon mapping splats photons into (`hash_grid`).

mod emission;
mod hash_grid;
mod kd_tree;
mod projection;
mod trace;

pub use emission::{Emission, MAX_PHOTONS};
pub use hash_grid::HashGrid;
pub use kd_tree::{Neighbour, PhotonMap};
pub use projection::Projection;
pub use trace::{Arrival, Deposit, trace_photon};

use glam::{Vec2, Vec3};

/// A stored photon: where it landed, the direction back towards where it came from (`wi` at
/// that point, octahedral-encoded in 2 x 16 bits, the axes and zero exact), and the power it carries. 28 bytes.
#[derive(Debug, Clone, Copy)]
pub struct Photon {
    pub position: Vec3,
    pub power: Vec3,
    direction: u32,
}

impl Photon {
    pub fn new(position: Vec3, wi: Vec3, power: Vec3) -> Self {
        Photon { position, power, direction: encode_direction(wi) }
    }

    /// Unit direction towards where the photon came from.
    pub fn wi(&self) -> Vec3 {
        decode_direction(self.direction)
    }
}

/// A unit vector as 2 x 16 bits: the octahedral map (Meyer et al. 2010; Cigolle et al. 2014),
/// within 1e-4 radians of the original.
fn encode_direction(d: Vec3) -> u32 {
    let p = Vec2::new(d.x, d.y) / (d.x.abs() + d.y.abs() + d.z.abs());
    let p = if d.z < 0.0 { (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign(p) } else { p };
    let quantise = |v: f32| ((v.clamp(-1.0, 1.0) * 0.5 + 0.5) * 65534.0).round() as u32;
    quantise(p.x) | (quantise(p.y) << 16)
}

fn decode_direction(bits: u32) -> Vec3 {
    let unquantise = |v: u32| (v & 0xffff) as f32 / 65534.0 * 2.0 - 1.0;
    let p = Vec2::new(unquantise(bits), unquantise(bits >> 16));
    let z = 1.0 - p.x.abs() - p.y.abs();
    let xy = if z < 0.0 { (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign(p) } else { p };
    Vec3::new(xy.x, xy.y, z).normalize()
}

/// +-1 per component, +1 at zero (unlike `signum`, which keeps -0's sign).
fn sign(v: Vec2) -> Vec2 {
    Vec2::new(if v.x >= 0.0 { 1.0 } else { -1.0 }, if v.y >= 0.0 { 1.0 } else { -1.0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Sampler, uniform_sphere};

    #[test]
    fn directions_survive_encoding() {
        for i in 0..10_000 {
            let d = uniform_sphere(Sampler::new(1, 2, i).next_2d());
            let back = Photon::new(Vec3::ZERO, d, Vec3::ONE).wi();
            assert!(back.dot(d) > 0.0 && back.cross(d).length() < 1e-4, "{d} came back as {back}");
        }
        for d in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
            assert!(Photon::new(Vec3::ZERO, d, Vec3::ONE).wi().distance(d) < 1e-6, "{d}");
        }
    }

    #[test]
    fn a_photon_takes_28_bytes() {
        assert_eq!(std::mem::size_of::<Photon>(), 28);
    }
}
