//! The shapes rays hit. Rays, hits and boxes live below the acceleration structures (`ray`,
//! `aabb`), which the meshes here build on, and are re-exported here with the shapes they meet.

mod csg;
mod lanes;
mod shape;
mod solid;
mod torus;
mod triangle_mesh;

pub use crate::aabb::Aabb;
pub use crate::ray::{Hit, Ray, offset_origin};
pub use csg::{Csg, CsgNode, CsgOp};
pub use lanes::{HitLanes, LANES, Lane, Vec2x4, Vec3x4};
pub(crate) use shape::REL_ERROR;
pub use shape::{
    Intersection, PlanarKind, QuadricFrame, QuadricKind, Shape, SurfaceSample, planar_coordinates,
    planar_error, similarity_scale, sphere_error,
};
pub use solid::{Cone, Crossing, Crossings, Cuboid, Face, MAX_CROSSINGS};
pub use torus::{Torus, polynomial_roots};
pub use triangle_mesh::{Placement, TriangleMesh};
