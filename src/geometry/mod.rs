//! Rays, hits and the shapes they hit.

mod aabb;
mod csg;
mod lanes;
mod quadratic;
mod ray;
mod shape;
mod solid;
mod torus;
mod triangle_mesh;

pub use aabb::Aabb;
pub use csg::{Csg, CsgNode, CsgOp};
pub use lanes::{HitLanes, LANES, Lane, Vec2x4, Vec3x4};
pub use ray::{Hit, Ray, offset_origin};
pub(crate) use shape::REL_ERROR;
pub use shape::{
    Intersection, PlanarKind, QuadricFrame, QuadricKind, Shape, SurfaceSample, planar_coordinates,
    planar_error, similarity_scale, sphere_error,
};
pub use solid::{Cone, Crossing, Crossings, Cuboid, Face, MAX_CROSSINGS};
pub use torus::{Torus, polynomial_roots};
pub use triangle_mesh::{Placement, TriangleMesh};
