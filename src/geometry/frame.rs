//! An orthonormal frame with +z along a unit vector: the shading frame at a hit, built once
//! where the BSDF is made (lobes work in its coordinates), and the frames of directions sampled
//! around an axis.

use glam::Vec3;

use crate::lanes::{Real, Vector};

/// Written once over `Real`: one frame (`f32`, the default), or a frame per lane.
#[derive(Debug, Clone, Copy)]
pub struct Frame<F = f32> {
    tangent: Vector<F>,
    bitangent: Vector<F>,
    normal: Vector<F>,
}

impl Frame {
    /// The world's own axes.
    pub const Z: Frame = Frame {
        tangent: Vector { x: 1.0, y: 0.0, z: 0.0 },
        bitangent: Vector { x: 0.0, y: 1.0, z: 0.0 },
        normal: Vector { x: 0.0, y: 0.0, z: 1.0 },
    };

    /// The frame around unit `n`.
    #[inline]
    pub fn from_normal(normal: Vec3) -> Self {
        Frame::around(normal.into())
    }

    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        self.local(v.into()).into()
    }

    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.world(v.into()).into()
    }
}

impl<F: Real> Frame<F> {
    /// The frame around unit `n` (Duff et al. 2017: no branch but the sign of n.z), as glam's
    /// `Vec3::any_orthonormal_pair` computes it.
    #[inline(always)]
    pub fn around(n: Vector<F>) -> Self {
        let sign = n.z.signum();
        let a = -F::ONE / (sign + n.z);
        let b = n.x * n.y * a;
        let tangent = Vector { x: F::ONE + sign * n.x * n.x * a, y: sign * b, z: -sign * n.x };
        let bitangent = Vector { x: b, y: sign + n.y * n.y * a, z: -n.y };
        Frame { tangent, bitangent, normal: n }
    }

    #[inline(always)]
    pub fn local(&self, v: Vector<F>) -> Vector<F> {
        Vector { x: v.dot(self.tangent), y: v.dot(self.bitangent), z: v.dot(self.normal) }
    }

    #[inline(always)]
    pub fn world(&self, v: Vector<F>) -> Vector<F> {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
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
    use crate::lanes::{LANES, Lane, Vec3Lanes};

    /// The lanes' frames are each normal's own, bit for bit, a normal of z = -0 (whose sign
    /// picks the frame) among them.
    #[test]
    fn frames_in_lanes_are_each_normal_s() {
        let normals = [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 0.0, -0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(-0.6, 0.0, -0.8),
            Vec3::new(0.48, 0.6, 0.64),
            Vec3::new(-0.0, 0.6, -0.8),
        ];
        let lanes =
            Frame::around(Vec3Lanes::from_lanes(std::array::from_fn::<_, LANES, _>(|lane| {
                normals[lane % normals.len()]
            })));
        let v = Vec3::new(0.2, 0.4, -0.9);
        let (world, local) = (lanes.world(Vec3Lanes::splat(v)), lanes.local(Vec3Lanes::splat(v)));
        for lane in 0..LANES {
            let one = Frame::from_normal(normals[lane % normals.len()]);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(world.lane(lane)), bits(one.to_world(v)), "lane {lane}");
            assert_eq!(bits(local.lane(lane)), bits(one.to_local(v)), "lane {lane}");
        }
    }

    #[test]
    fn local_and_world_round_trip_for_every_orientation() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            let frame = Frame::from_normal(n);
            let (tangent, bitangent) = n.any_orthonormal_pair();
            assert_eq!(frame.to_world(Vec3::X), tangent, "glam's frame, bit for bit");
            assert_eq!(frame.to_world(Vec3::Y), bitangent);
            assert!((frame.to_local(n) - Vec3::Z).length() < 1e-6, "{n}");
            for v in [Vec3::new(0.2, 0.4, -0.9).normalize(), Vec3::Y] {
                assert!((frame.to_world(frame.to_local(v)) - v).length() < 1e-6, "{n}, {v}");
            }
        }
    }
}
