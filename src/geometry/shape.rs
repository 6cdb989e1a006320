//! World-space shapes: what a ray meets, bounds, area and uniform area sampling, and for
//! solids where a ray crosses them and what is inside. Each kind's own code is in its file;
//! here every query is dispatched over every kind.

use std::sync::Arc;

use glam::{Affine3A, Mat3A, Vec2, Vec3};

use super::algebraic::Algebraic;
use super::arc_solid::ArcSolid;
use super::blob::Blob;
use super::cone::Cone;
use super::crossings::Crossings;
use super::csg::Csg;
use super::cuboid::Cuboid;
use super::isosurface::Isosurface;
use super::julia::Julia;
use super::lathe::Lathe;
use super::parametric::Parametric;
use super::planar::Planar;
use super::polygon::Polygon;
use super::prism::Prism;
use super::quadratic::quadratic_roots_in_lanes;
use super::quadric::{QuadricFrame, QuadricKind};
use super::sor::Sor;
use super::superellipsoid::Superellipsoid;
use super::torus::Torus;
use super::triangle_mesh::{Placement, TriangleMesh};
use super::{Aabb, Hit, Ray};
use crate::lanes::{Real, Vector};
use crate::sampling::uniform_sphere;

/// Relative error allowance for computed hit points: a few hundred ulps of the coordinates'
/// magnitude, so that spawned rays clear the surface at any scene scale.
pub(crate) const REL_ERROR: f32 = 256.0 * f32::EPSILON;

#[derive(Debug, Clone)]
pub enum Shape {
    /// Points p with `normal . p + offset = 0`, `normal` of unit length. Unbounded.
    Plane {
        normal: Vec3,
        offset: f32,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// A triangle, quad or disk.
    Planar(Planar),
    /// The unit sphere, or the open tube x^2 + y^2 = 1, 0 <= z <= 1, under an affine map
    /// (a sphere under non-uniform scale, the side of a cylinder).
    Quadric {
        kind: QuadricKind,
        frame: Box<QuadricFrame>,
    },
    /// A triangle mesh, shared by its instances, each placed by its own transform (`None`: the
    /// mesh's space is the world).
    Mesh {
        mesh: Arc<TriangleMesh>,
        placement: Option<Box<Placement>>,
    },
    /// A box kept whole: its six faces, and its inside.
    Box(Box<Cuboid>),
    /// A cone or cylinder, closed by its end disks unless open.
    Cone(Box<Cone>),
    /// POV-Ray's torus under an affine map.
    Torus(Box<Torus>),
    /// The surface P(x, y, z) = 0 of a polynomial under an affine map (POV-Ray's `quadric`,
    /// `cubic`, `quartic`, `poly`), solid where P < 0. Unbounded.
    Algebraic(Box<Algebraic>),
    /// POV-Ray's blob: spheres and capsules summed into a field, under an affine map.
    Blob(Box<Blob>),
    /// POV-Ray's prism under an affine map.
    Prism(Box<Prism>),
    /// POV-Ray's lathe under an affine map.
    Lathe(Box<Lathe>),
    /// POV-Ray's surface of revolution (`sor`) under an affine map.
    Sor(Box<Sor>),
    /// POV-Ray's ovus or lemon (arcs turned about an axis) under an affine map.
    ArcSolid(Box<ArcSolid>),
    /// POV-Ray's polygon (not a solid), in world space.
    Polygon(Box<Polygon>),
    /// POV-Ray's superellipsoid under an affine map.
    Superellipsoid(Box<Superellipsoid>),
    /// POV-Ray's julia_fractal under an affine map.
    Julia(Box<Julia>),
    /// A CSG solid: one primitive whose surfaces belong to its operands.
    Csg(Box<Csg>),
    /// POV-Ray's isosurface under an affine map.
    Isosurface(Box<Isosurface>),
    /// POV-Ray's parametric surface (not a solid) under an affine map.
    Parametric(Box<Parametric>),
}

/// A point on a surface with its unit normal (the shape's own orientation).
#[derive(Debug, Clone, Copy)]
pub struct SurfaceSample {
    pub point: Vec3,
    pub normal: Vec3,
    /// Error bound of `point`, as in `Hit`.
    pub error: f32,
}

/// Where a ray meets a shape, before its hit record is made: a closest-hit search tests many
/// shapes but makes the record (point, normals, error bound) only for the one it keeps.
#[derive(Debug, Clone, Copy)]
pub struct Intersection {
    pub t: f32,
    /// Planar shapes' and triangles' coordinates along their two edges.
    pub st: Vec2,
    /// The triangle of a mesh, the face of a box, the part of a cone (0 the side, 1 and 2 the
    /// base and cap disks).
    pub triangle: u32,
    /// For a CSG solid, the operand whose surface this is (`Csg::operand`), and whether its
    /// normal is turned (`Csg::TURNED`); 0 for other shapes.
    pub part: u32,
}

impl Intersection {
    /// At distance `t`, for shapes that need nothing more to make their hit record.
    pub fn at(t: f32) -> Self {
        Intersection { t, st: Vec2::ZERO, triangle: 0, part: 0 }
    }
}

impl Shape {
    /// The closest intersection with `0 < t < t_max`; `primitive` is left 0 for the caller.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        Some(self.hit(ray, &self.intersection(ray, t_max)?))
    }

    /// Distance (and surface coordinates) of the closest intersection with `0 < t < t_max`.
    #[inline]
    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        match self {
            Shape::Plane { normal, offset } => {
                let (origin, dir) = ray_vectors(ray);
                ahead(plane_distance((*normal).into(), *offset, origin, dir), t_max)
                    .map(Intersection::at)
            }
            Shape::Sphere { center, radius } => {
                let (origin, dir) = ray_vectors(ray);
                ahead(sphere_distance((*center).into(), *radius, origin, dir), t_max)
                    .map(Intersection::at)
            }
            Shape::Planar(planar) => planar.intersection(ray, t_max),
            Shape::Quadric { kind, frame } => {
                kind.intersection(frame, ray, t_max).map(Intersection::at)
            }
            Shape::Box(cuboid) => cuboid.intersection(ray, t_max),
            Shape::Cone(cone) => cone.intersection(ray, t_max),
            Shape::Torus(torus) => torus.intersection(ray, t_max),
            Shape::Algebraic(surface) => surface.intersection(ray, t_max),
            Shape::Blob(blob) => blob.intersection(ray, t_max),
            Shape::Prism(prism) => prism.intersection(ray, t_max),
            Shape::Lathe(lathe) => lathe.intersection(ray, t_max),
            Shape::Sor(sor) => sor.intersection(ray, t_max),
            Shape::ArcSolid(solid) => solid.intersection(ray, t_max),
            Shape::Polygon(polygon) => polygon.intersection(ray, t_max),
            Shape::Superellipsoid(s) => s.intersection(ray, t_max),
            Shape::Julia(julia) => julia.intersection(ray, t_max),
            Shape::Csg(csg) => csg.intersection(ray, t_max),
            Shape::Isosurface(isosurface) => isosurface.intersection(ray, t_max),
            Shape::Parametric(surface) => surface.intersection(ray, t_max),
            Shape::Mesh { mesh, placement: None } => mesh.intersection(ray, t_max),
            Shape::Mesh { mesh, placement: Some(placement) } => {
                mesh.intersection(&placement.ray_to_object(ray), t_max)
            }
        }
    }

    /// The hit record of an intersection of `ray` found by `intersection`.
    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let t = at.t;
        let surface = |point, normal, error| Hit {
            t,
            point,
            normal,
            shading_normal: normal,
            error,
            primitive: 0,
        };
        match self {
            Shape::Plane { normal, offset } => {
                let (point, error) = plane_point((*normal).into(), *offset, ray.at(t).into());
                surface(point.into(), *normal, error)
            }
            Shape::Sphere { center, radius } => {
                let (point, normal) = sphere_point((*center).into(), *radius, ray.at(t).into());
                surface(point.into(), normal.into(), sphere_error(*center, *radius))
            }
            Shape::Planar(planar) => planar.hit(t, at.st),
            Shape::Quadric { kind, frame } => kind.hit(frame, ray, t),
            Shape::Mesh { mesh, placement: None } => mesh.hit(at),
            Shape::Mesh { mesh, placement: Some(placement) } => {
                placement.hit_to_world(mesh.hit(at))
            }
            Shape::Box(cuboid) => cuboid.hit(at),
            Shape::Cone(cone) => cone.hit(ray, at),
            Shape::Torus(torus) => torus.hit(ray, at),
            Shape::Algebraic(surface) => surface.hit(ray, at),
            Shape::Blob(blob) => blob.hit(ray, at),
            Shape::Prism(prism) => prism.hit(ray, at),
            Shape::Lathe(lathe) => lathe.hit(ray, at),
            Shape::Sor(sor) => sor.hit(ray, at),
            Shape::ArcSolid(solid) => solid.hit(ray, at),
            Shape::Polygon(polygon) => polygon.hit(ray, at),
            Shape::Superellipsoid(s) => s.hit(ray, at),
            Shape::Julia(julia) => julia.hit(ray, at),
            Shape::Csg(csg) => csg.hit(ray, at),
            Shape::Isosurface(isosurface) => isosurface.hit(ray, at),
            Shape::Parametric(surface) => surface.hit(ray, at),
        }
    }

    /// Whether the ray meets the shape before `t_max` (any hit, for shadow rays).
    #[inline]
    pub fn occludes(&self, ray: &Ray, t_max: f32) -> bool {
        match self {
            Shape::Mesh { mesh, placement: None } => mesh.occluded(ray, t_max),
            Shape::Mesh { mesh, placement: Some(placement) } => {
                mesh.occluded(&placement.ray_to_object(ray), t_max)
            }
            // The closest hit is as cheap as any hit.
            Shape::Plane { .. }
            | Shape::Sphere { .. }
            | Shape::Planar(_)
            | Shape::Quadric { .. }
            | Shape::Box(_)
            | Shape::Cone(_)
            | Shape::Torus(_)
            | Shape::Csg(_)
            | Shape::Isosurface(_)
            | Shape::Parametric(_)
            | Shape::Algebraic(_)
            | Shape::Blob(_)
            | Shape::Prism(_)
            | Shape::Lathe(_)
            | Shape::Sor(_)
            | Shape::ArcSolid(_)
            | Shape::Polygon(_)
            | Shape::Superellipsoid(_)
            | Shape::Julia(_) => self.intersection(ray, t_max).is_some(),
        }
    }

    /// `None` for the unbounded plane.
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Plane { .. } | Shape::Algebraic(_) => None,
            Shape::Sphere { center, radius } => Some(Aabb {
                min: center - Vec3::splat(*radius),
                max: center + Vec3::splat(*radius),
            }),
            Shape::Planar(planar) => Some(planar.bounds()),
            Shape::Quadric { frame, .. } => Some(frame.bounds()),
            Shape::Mesh { mesh, placement } => {
                let local = mesh.bounds();
                Some(match placement {
                    None => local,
                    Some(p) => Aabb::from_points(&QuadricFrame::canonical_corners().map(|c| {
                        let corner = local.centroid() + 0.5 * c * local.extent();
                        p.to_world.transform_point3(corner)
                    })),
                })
            }
            Shape::Box(cuboid) => Some(cuboid.bounds()),
            Shape::Cone(cone) => Some(cone.bounds()),
            Shape::Torus(torus) => Some(torus.bounds()),
            Shape::Blob(blob) => Some(blob.bounds()),
            Shape::Prism(prism) => Some(prism.bounds()),
            Shape::Lathe(lathe) => Some(lathe.bounds()),
            Shape::Sor(sor) => Some(sor.bounds()),
            Shape::ArcSolid(solid) => Some(solid.bounds()),
            Shape::Polygon(polygon) => Some(polygon.bounds()),
            Shape::Superellipsoid(s) => Some(s.bounds()),
            Shape::Julia(julia) => Some(julia.bounds()),
            Shape::Csg(csg) => csg.bounds(),
            Shape::Isosurface(isosurface) => Some(isosurface.bounds()),
            Shape::Parametric(surface) => Some(surface.bounds()),
        }
    }

    /// Surface area, when it is finite and known in closed form (meshes are not sampled as lights).
    pub fn area(&self) -> Option<f32> {
        match self {
            Shape::Plane { .. }
            | Shape::Mesh { .. }
            | Shape::Algebraic(_)
            | Shape::Blob(_)
            | Shape::Prism(_)
            | Shape::Lathe(_)
            | Shape::Sor(_)
            | Shape::ArcSolid(_)
            | Shape::Polygon(_)
            | Shape::Superellipsoid(_)
            | Shape::Julia(_) => None,
            Shape::Sphere { radius, .. } => Some(4.0 * std::f32::consts::PI * radius * radius),
            Shape::Planar(planar) => Some(planar.area()),
            Shape::Quadric { frame, .. } => frame.area,
            Shape::Box(cuboid) => Some(cuboid.area),
            Shape::Cone(cone) => cone.area(),
            Shape::Torus(torus) => torus.area(),
            // Its surfaces are parts of its operands': not sampled as a light.
            Shape::Csg(_) => None,
            // No closed form: not sampled as a light.
            Shape::Isosurface(_) | Shape::Parametric(_) => None,
        }
    }

    /// A point distributed uniformly by area (pdf 1 / area); `None` where `area` is `None`.
    /// Always inlined: an area light samples it once per light sample.
    #[inline(always)]
    pub fn sample_area(&self, u: Vec2) -> Option<SurfaceSample> {
        match self {
            Shape::Plane { .. }
            | Shape::Mesh { .. }
            | Shape::Csg(_)
            | Shape::Isosurface(_)
            | Shape::Parametric(_)
            | Shape::Algebraic(_)
            | Shape::Blob(_)
            | Shape::Prism(_)
            | Shape::Lathe(_)
            | Shape::Sor(_)
            | Shape::ArcSolid(_)
            | Shape::Polygon(_)
            | Shape::Superellipsoid(_)
            | Shape::Julia(_) => None,
            Shape::Box(cuboid) => Some(cuboid.sample(u)),
            Shape::Cone(cone) => cone.sample(u),
            Shape::Torus(torus) => torus.sample(u),
            Shape::Sphere { center, radius } => {
                let normal = uniform_sphere(u);
                let point = center + *radius * normal;
                Some(SurfaceSample { point, normal, error: sphere_error(*center, *radius) })
            }
            Shape::Planar(planar) => Some(planar.sample(u)),
            Shape::Quadric { kind, frame } => kind.sample(frame, u),
        }
    }

    /// Where the ray crosses the solid's surface in (0, t_max), and whether it starts inside.
    /// (Not a solid: no crossings, never inside.)
    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        match self {
            Shape::Plane { normal, offset } => plane_crossings(*normal, *offset, ray, t_max),
            Shape::Sphere { center, radius } => {
                Crossings::between(sphere_roots(*center, *radius, ray), t_max)
            }
            Shape::Quadric { kind, frame } => kind.crossings(frame, ray, t_max),
            Shape::Box(cuboid) => cuboid.crossings(ray, t_max),
            Shape::Cone(cone) => cone.crossings(ray, t_max),
            Shape::Torus(torus) => torus.crossings(ray, t_max),
            Shape::Algebraic(surface) => surface.crossings(ray, t_max),
            Shape::Blob(blob) => blob.crossings(ray, t_max),
            Shape::Prism(prism) => prism.crossings(ray, t_max),
            Shape::Lathe(lathe) => lathe.crossings(ray, t_max),
            Shape::Sor(sor) => sor.crossings(ray, t_max),
            Shape::ArcSolid(solid) => solid.crossings(ray, t_max),
            Shape::Superellipsoid(s) => s.crossings(ray, t_max),
            Shape::Julia(julia) => julia.crossings(ray, t_max),
            Shape::Mesh { mesh, placement } => match placement {
                None => mesh.crossings(ray, t_max),
                Some(placement) => mesh.crossings(&placement.ray_to_object(ray), t_max),
            },
            Shape::Csg(csg) => csg.crossings(ray, t_max),
            Shape::Isosurface(isosurface) => isosurface.crossings(ray, t_max),
            Shape::Planar(_) | Shape::Polygon(_) | Shape::Parametric(_) => Crossings::outside(),
        }
    }

    /// Whether `p` is inside the solid (false for shapes that are not solids).
    pub fn contains(&self, p: Vec3) -> bool {
        match self {
            Shape::Plane { normal, offset } => normal.dot(p) + offset < 0.0,
            Shape::Sphere { center, radius } => p.distance_squared(*center) < radius * radius,
            Shape::Quadric { kind, frame } => kind.contains(frame, p),
            Shape::Box(cuboid) => cuboid.contains(p),
            Shape::Cone(cone) => cone.contains(p),
            Shape::Torus(torus) => torus.contains(p),
            Shape::Algebraic(surface) => surface.contains(p),
            Shape::Blob(blob) => blob.contains(p),
            Shape::Prism(prism) => prism.contains(p),
            Shape::Lathe(lathe) => lathe.contains(p),
            Shape::Sor(sor) => sor.contains(p),
            Shape::ArcSolid(solid) => solid.contains(p),
            Shape::Superellipsoid(s) => s.contains(p),
            Shape::Julia(julia) => julia.contains(p),
            Shape::Mesh { mesh, placement } => match placement {
                None => mesh.contains(p),
                Some(placement) => mesh.contains(placement.to_object.transform_point3(p)),
            },
            Shape::Csg(csg) => csg.contains(p),
            Shape::Isosurface(isosurface) => isosurface.contains(p),
            Shape::Planar(_) | Shape::Polygon(_) | Shape::Parametric(_) => false,
        }
    }
}

/// The scale of a similarity (rotation or reflection, uniform scale, translation); `None` for
/// any other affine map.
pub fn similarity_scale(m: &Affine3A) -> Option<f32> {
    let gram = m.matrix3.transpose() * m.matrix3;
    let s2 = gram.x_axis.x;
    let off = gram - Mat3A::from_diagonal(Vec3::splat(s2));
    off.to_cols_array().iter().all(|e| e.abs() <= 1e-5 * s2).then(|| s2.sqrt())
}

/// Picks one of several parts of a surface in proportion to its area with `u.x`, and reuses
/// what is left of `u.x` for a point on it.
pub(super) fn choose_part(areas: impl Iterator<Item = f32>, total: f32, u: Vec2) -> (usize, Vec2) {
    let target = u.x * total;
    let mut below = 0.0;
    let mut last = (0, 0.0, 0.0);
    for (i, area) in areas.enumerate() {
        if area > 0.0 {
            last = (i, below, area);
            if target < below + area {
                break;
            }
        }
        below += area;
    }
    let (i, below, area) = last;
    (i, Vec2::new(((target - below) / area).clamp(0.0, 1.0 - f32::EPSILON / 2.0), u.y))
}

/// A ray's origin and direction as vectors of the kernels below, which are written once for
/// one ray (`f32`) and for rays in lanes (`FewShapes`).
#[inline]
pub(crate) fn ray_vectors(ray: &Ray) -> (Vector<f32>, Vector<f32>) {
    (Vec3::from(ray.origin).into(), Vec3::from(ray.dir).into())
}

/// A distance from a kernel below if it is in (0, t_max) (never where it is NaN).
#[inline]
pub(crate) fn ahead(t: f32, t_max: f32) -> Option<f32> {
    (t > 0.0 && t < t_max).then_some(t)
}

/// The distance along the ray to the plane `normal . p + offset = 0` (negative or NaN where
/// the ray does not meet it ahead).
#[inline]
pub(crate) fn plane_distance<F: Real>(
    normal: Vector<F>,
    offset: F,
    origin: Vector<F>,
    dir: Vector<F>,
) -> F {
    -(normal.dot(origin) + offset) / normal.dot(dir)
}

/// The point of the plane hit at `p`, and its error bound: projected back onto the plane, its
/// error is that of its coordinates alone.
#[inline]
pub(crate) fn plane_point<F: Real>(normal: Vector<F>, offset: F, p: Vector<F>) -> (Vector<F>, F) {
    let point = p - normal * (normal.dot(p) + offset);
    (point, F::splat(REL_ERROR) * (point.abs().max_element() + offset.abs()))
}

/// The half-space `normal . p + offset < 0` along a ray.
fn plane_crossings(normal: Vec3, offset: f32, ray: &Ray, t_max: f32) -> Crossings {
    let (origin, dir) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let (side, slope) = (normal.dot(origin) + offset, normal.dot(dir));
    let t = -side / slope;
    let mut crossings = Crossings { inside_at_start: side < 0.0, list: Default::default() };
    if t > 0.0 && t < t_max {
        crossings.inside_at_start = slope > 0.0;
        crossings.push(Intersection::at(t), slope < 0.0);
    }
    crossings
}

/// Error bound of a point on a sphere (its coordinates are at most |center| + radius).
pub fn sphere_error(center: Vec3, radius: f32) -> f32 {
    REL_ERROR * (center.abs().max_element() + radius)
}

/// The distance along the ray to the sphere: the nearer crossing ahead (negative or NaN where
/// the ray does not meet it ahead).
#[inline]
pub(crate) fn sphere_distance<F: Real>(
    center: Vector<F>,
    radius: F,
    origin: Vector<F>,
    dir: Vector<F>,
) -> F {
    let (real, t0, t1) = sphere_roots_in_lanes(center, radius, origin, dir);
    F::select(real, F::select(t0.gt(F::ZERO), t0, t1), F::NAN)
}

/// Both intersections of the sphere with the ray's line, in order.
#[inline]
fn sphere_roots(center: Vec3, radius: f32, ray: &Ray) -> Option<(f32, f32)> {
    let (origin, dir) = ray_vectors(ray);
    let (real, t0, t1) = sphere_roots_in_lanes(center.into(), radius, origin, dir);
    real.then_some((t0, t1))
}

/// Per lane, whether the ray's line meets the sphere, and where (in order).
#[inline]
fn sphere_roots_in_lanes<F: Real>(
    center: Vector<F>,
    radius: F,
    origin: Vector<F>,
    dir: Vector<F>,
) -> (F::Mask, F, F) {
    let oc = origin - center;
    let b = oc.dot(dir);
    // r^2 - |oc - b d|^2 instead of b^2 - (|oc|^2 - r^2): no cancellation for distant spheres
    // (Ray Tracing Gems, ch. 7).
    let perp = oc - dir * b;
    let radius_squared = radius * radius;
    let discriminant = radius_squared - perp.length_squared();
    quadratic_roots_in_lanes(F::ONE, b, oc.length_squared() - radius_squared, discriminant)
}

/// The point of the sphere hit at `p`, and its unit normal there.
#[inline]
pub(crate) fn sphere_point<F: Real>(
    center: Vector<F>,
    radius: F,
    p: Vector<F>,
) -> (Vector<F>, Vector<F>) {
    let from_center = p - center;
    // As glam's `normalize`: by the reciprocal of the length.
    let normal = from_center * (F::ONE / from_center.length_squared().sqrt());
    (center + normal * radius, normal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::PlanarKind;

    fn ray(origin: Vec3, dir: Vec3) -> Ray {
        Ray::new(origin, dir.normalize())
    }

    #[test]
    fn sphere_hit_from_outside_and_inside() {
        let sphere = Shape::Sphere { center: Vec3::new(0.0, 0.0, 5.0), radius: 1.0 };
        let outside = sphere.intersect(&ray(Vec3::ZERO, Vec3::Z), f32::INFINITY).unwrap();
        assert!((outside.t - 4.0).abs() < 1e-6);
        assert_eq!(outside.normal, -Vec3::Z);
        let inside =
            sphere.intersect(&ray(Vec3::new(0.0, 0.0, 5.0), Vec3::X), f32::INFINITY).unwrap();
        assert!((inside.t - 1.0).abs() < 1e-6);
        assert_eq!(inside.normal, Vec3::X, "outward, whichever side the ray came from");
        assert!(sphere.intersect(&ray(Vec3::ZERO, Vec3::Z), 3.9).is_none(), "t_max respected");
    }

    #[test]
    fn quadrics_under_affine_maps() {
        // The unit sphere stretched to x radius 2: hit from +x at distance 3 from x = 5.
        let ellipsoid = Shape::Quadric {
            kind: QuadricKind::Ellipsoid,
            frame: Box::new(QuadricFrame::new(
                Affine3A::from_scale(Vec3::new(2.0, 1.0, 1.0)),
                None,
            )),
        };
        let hit =
            ellipsoid.intersect(&ray(Vec3::new(5.0, 0.0, 0.0), -Vec3::X), f32::INFINITY).unwrap();
        assert!((hit.t - 3.0).abs() < 1e-5 && (hit.normal - Vec3::X).length() < 1e-6);
        assert!(ellipsoid.area().is_none(), "no closed-form area: not sampled");
        // A tube of radius 0.5 along z from 0 to 2, seen from the side and along its axis.
        let tube = Shape::Quadric {
            kind: QuadricKind::Tube,
            frame: Box::new(QuadricFrame::new(
                Affine3A::from_scale(Vec3::new(0.5, 0.5, 2.0)),
                None,
            )),
        };
        let side = tube.intersect(&ray(Vec3::new(-3.0, 0.0, 1.5), Vec3::X), f32::INFINITY).unwrap();
        assert!((side.t - 2.5).abs() < 1e-5 && (side.normal + Vec3::X).length() < 1e-6);
        assert!(tube.intersect(&ray(Vec3::new(-3.0, 0.0, 2.5), Vec3::X), f32::INFINITY).is_none());
        // Along the axis the ray meets the open tube from inside only at grazing: no hit.
        assert!(tube.intersect(&ray(Vec3::new(0.0, 0.0, -1.0), Vec3::Z), f32::INFINITY).is_none());
        let rotated = Affine3A::from_rotation_y(0.3) * Affine3A::from_scale(Vec3::splat(3.0));
        assert!((similarity_scale(&rotated).unwrap() - 3.0).abs() < 1e-6);
        assert_eq!(similarity_scale(&Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0))), None);
    }

    #[test]
    fn area_samples_lie_on_the_shape() {
        let shapes = [
            Shape::Sphere { center: Vec3::ONE, radius: 2.0 },
            Shape::Planar(Planar::new(PlanarKind::Disk, Vec3::ZERO, Vec3::X, Vec3::Y)),
        ];
        for shape in &shapes {
            for i in 0..100 {
                let u = Vec2::new((i % 10) as f32 / 10.0 + 0.05, (i / 10) as f32 / 10.0 + 0.05);
                let s = shape.sample_area(u).unwrap();
                // A ray from just off the surface along -normal hits at the sample itself.
                let hit =
                    shape.intersect(&Ray::new(s.point + s.normal * 1e-3, -s.normal), 1.0).unwrap();
                assert!((hit.point - s.point).length() < 1e-4, "{shape:?} {u}");
            }
        }
    }

    #[test]
    fn choosing_parts_by_area_reuses_u() {
        let areas = [1.0, 0.0, 3.0];
        assert_eq!(
            choose_part(areas.into_iter(), 4.0, Vec2::new(0.1, 0.5)),
            (0, Vec2::new(0.4, 0.5))
        );
        let (part, u) = choose_part(areas.into_iter(), 4.0, Vec2::new(0.625, 0.5));
        assert_eq!(part, 2);
        assert!((u.x - 0.5).abs() < 1e-6);
        assert_eq!(choose_part(areas.into_iter(), 4.0, Vec2::new(0.9999, 0.5)).0, 2);
    }
}
