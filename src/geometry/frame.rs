//! An orthonormal frame with +z along a unit vector: the shading frame at a hit, built once
//! where the BSDF is made (lobes work in its coordinates), and the frames of directions sampled
//! around an axis.

use glam::Vec3;

#[derive(Debug, Clone, Copy)]
pub struct Frame {
    tangent: Vec3,
    bitangent: Vec3,
    normal: Vec3,
}

impl Frame {
    /// The world's own axes.
    pub const Z: Frame = Frame { tangent: Vec3::X, bitangent: Vec3::Y, normal: Vec3::Z };

    /// The frame around unit `n` (Duff et al. 2017: no branch but the sign of n.z).
    #[inline]
    pub fn from_normal(normal: Vec3) -> Self {
        let (tangent, bitangent) = normal.any_orthonormal_pair();
        Frame { tangent, bitangent, normal }
    }

    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.tangent), v.dot(self.bitangent), v.dot(self.normal))
    }

    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        v.x * self.tangent + v.y * self.bitangent + v.z * self.normal
    }
}

/// `v` (local) seen from the side of the surface that `z_sign` (+1 or -1) names: z turned over.
/// Lobes that are the same on both sides work on the side of `wo` with this.
#[inline]
pub fn on_side(v: Vec3, z_sign: f32) -> Vec3 {
    Vec3::new(v.x, v.y, z_sign * v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_and_world_round_trip_for_every_orientation() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            let frame = Frame::from_normal(n);
            assert!((frame.to_local(n) - Vec3::Z).length() < 1e-6, "{n}");
            for v in [Vec3::new(0.2, 0.4, -0.9).normalize(), Vec3::Y] {
                assert!((frame.to_world(frame.to_local(v)) - v).length() < 1e-6, "{n}, {v}");
            }
        }
    }
}
