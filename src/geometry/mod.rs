//! Rays, hits and the shapes they hit.

mod aabb;
mod cone;
mod crossings;
mod csg;
mod cuboid;
mod lanes;
mod planar;
mod quadratic;
mod quadric;
mod ray;
mod shape;
mod torus;
mod triangle_mesh;

pub use aabb::Aabb;
pub use cone::Cone;
pub use crossings::{Crossing, Crossings, MAX_CROSSINGS};
pub use csg::{Csg, CsgNode, CsgOp};
pub use cuboid::Cuboid;
pub use lanes::{HitLanes, LANES, Lane, Vec3x4};
pub use planar::{Planar, PlanarKind, planar_coordinates, planar_error};
pub use quadric::{QuadricFrame, QuadricKind};
pub use ray::{Hit, Ray, offset_origin};
pub(crate) use shape::REL_ERROR;
pub use shape::{Intersection, Shape, SurfaceSample, similarity_scale, sphere_error};
pub use torus::{Torus, polynomial_roots};
pub use triangle_mesh::{Placement, TriangleMesh};
