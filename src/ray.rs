//! Rays and the hits they find: below the acceleration structures that trace them and the
//! shapes that are hit (`geometry` re-exports them with its shapes).

use glam::{Vec3, Vec3A};

/// A ray `origin + t * dir` with `dir` of unit length. (`Vec3A`, written and read whole: the
/// traversals read a ray with 16-byte loads, which wait long for a `Vec3` written as three
/// floats, as the CPU cannot forward those stores to one load.)
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin: origin.into(), dir: dir.into() }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        (self.origin + t * self.dir).into()
    }
}

/// The closest intersection along a ray.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub t: f32,
    pub point: Vec3,
    /// Unit geometric normal in the shape's own orientation (outwards for closed solids,
    /// `edge1 x edge2` for planar shapes): it decides which side emits and which is "inside".
    pub normal: Vec3,
    /// Unit normal for shading (interpolated vertex normals of smooth meshes; otherwise
    /// `normal`), on the same side as `normal`.
    pub shading_normal: Vec3,
    /// A bound on the absolute error of `point`, per axis, used to offset spawned rays.
    pub error: f32,
    /// Index of the primitive hit, into `Scene::primitives`.
    pub primitive: u32,
}
