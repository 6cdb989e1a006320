//! Rays, hits and the shapes they hit.

mod aabb;
mod ray;
mod shape;

pub use aabb::Aabb;
pub use ray::{Hit, Ray, offset_origin};
pub use shape::{PlanarKind, QuadricFrame, QuadricKind, Shape, SurfaceSample, sphere_error};
