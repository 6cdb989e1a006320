//! Acceleration structures: the BVH over bounded primitives and the set of unbounded planes.

mod bvh;
mod planes;

pub use bvh::Bvh;
pub use planes::Planes;
