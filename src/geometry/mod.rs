//! The shapes rays hit. Rays, hits and boxes live below the acceleration structures (`ray`,
//! `aabb`), which the meshes here build on, and are re-exported here with the shapes they meet.

mod algebraic;
mod arc_solid;
mod blob;
mod cone;
mod crossings;
mod csg;
mod cuboid;
mod few_shapes;
mod frame;
mod isosurface;
mod julia;
mod lathe;
mod parametric;
mod planar;
mod polygon;
mod polynomial;
mod prism;
mod quadratic;
mod quadric;
mod shape;
mod solid_angle;
mod sor;
mod spline;
mod superellipsoid;
mod torus;
mod triangle_mesh;

pub use crate::aabb::Aabb;
pub use crate::lanes::offset_origin;
pub use crate::ray::{Hit, Ray};
pub use algebraic::{Algebraic, Term, pov_ray_term_count, pov_ray_terms};
pub use arc_solid::{ArcSolid, lemon_min_inner_radius};
pub use blob::{Blob, BlobComponent, ComponentShape};
pub use cone::Cone;
pub use crossings::{Crossing, Crossings, MAX_CROSSINGS};
pub use csg::{Csg, CsgNode, CsgOp};
pub use cuboid::Cuboid;
pub use few_shapes::{FewShapes, Nearest};
pub use frame::{Frame, on_side};
pub use isosurface::{Container, Isosurface, IsosurfaceDesc, ScalarField};
pub use julia::{
    Algebra, Julia, JuliaDesc, JuliaFunction, MAX_JULIA_ITERATIONS, MAX_JULIA_PRECISION,
};
pub use lathe::Lathe;
pub use parametric::{Parametric, ParametricDesc};
pub use planar::{Planar, PlanarKind, planar_coordinates, planar_coordinates_of, planar_error};
pub use polygon::{Polygon, close_outlines, outline_normal};
pub use polynomial::{MAX_DEGREE, polynomial_roots};
pub use prism::{Prism, Sweep};
pub use quadric::{QuadricFrame, QuadricKind};
pub use shape::{Intersection, Shape, SurfaceSample, similarity_scale, sphere_error};
pub use solid_angle::{DirectionSample, towards_by_area};
pub use sor::{Sor, SorError, SorPiece, sor_pieces};
pub use spline::{Segment, SplineError, SplineKind, open_spline_segments, spline_segments};
pub use superellipsoid::Superellipsoid;
pub use torus::Torus;
pub use triangle_mesh::{Placement, TriangleMesh};
