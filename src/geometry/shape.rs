//! World-space shapes: intersection, bounds, area and uniform area sampling.

use std::sync::Arc;

use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};

use super::csg::Csg;
use super::quadratic::{quadratic_roots, quadratic_roots_with};
use super::solid::{Cone, Cuboid};
use super::torus::Torus;
use super::triangle_mesh::{Placement, TriangleMesh};
use super::{Aabb, Hit, Ray};
use crate::sampling::{concentric_disk, uniform_sphere, uniform_triangle};

/// Relative error allowance for computed hit points: a few hundred ulps of the coordinates'
/// magnitude, so that spawned rays clear the surface at any scene scale.
pub(crate) const REL_ERROR: f32 = 256.0 * f32::EPSILON;

/// Planar shapes are parameterised as `origin + s * edge1 + t * edge2`; the kind says which
/// (s, t) are inside. An affine transform keeps them planar, so they are stored in world space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanarKind {
    /// s, t >= 0, s + t <= 1
    Triangle,
    /// s, t in [0, 1]
    Quad,
    /// s^2 + t^2 <= 1, with `origin` the centre (an ellipse under non-uniform scale)
    Disk,
}

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
    Planar {
        kind: PlanarKind,
        origin: Vec3,
        edge1: Vec3,
        edge2: Vec3,
        normal: Vec3,
    },
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
    /// A CSG solid: one primitive whose surfaces belong to its operands.
    Csg(Box<Csg>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuadricKind {
    Ellipsoid,
    Tube,
}

/// The maps between a quadric's canonical space and the world.
#[derive(Debug, Clone)]
pub struct QuadricFrame {
    pub to_world: Affine3A,
    pub to_object: Affine3A,
    /// Inverse transpose of `to_world`'s linear part: maps normals.
    pub normal_to_world: Mat3A,
    /// The world-space area, when uniform sampling of the canonical parameters (z and angle
    /// for the tube, the sphere's directions) is uniform by area: when the map from the
    /// canonical shape is a similarity up to the tube's own radius and height.
    pub area: Option<f32>,
    /// Magnitude of the world coordinates, for the hit point's error bound.
    pub magnitude: f32,
}

impl QuadricFrame {
    pub fn new(to_world: Affine3A, area: Option<f32>) -> Self {
        let corners = Self::canonical_corners().map(|c| to_world.transform_point3(c).abs());
        QuadricFrame {
            to_world,
            to_object: to_world.inverse(),
            normal_to_world: to_world.matrix3.inverse().transpose(),
            area,
            magnitude: corners.iter().fold(0.0f32, |m, c| m.max(c.max_element())),
        }
    }

    /// The ray in canonical space, direction not normalised (so distances are the world's).
    pub(super) fn ray_to_object(&self, ray: &Ray) -> (Vec3A, Vec3A) {
        (self.to_object.transform_point3a(ray.origin), self.to_object.transform_vector3a(ray.dir))
    }

    /// Corners of a box holding both canonical quadrics.
    pub(super) fn canonical_corners() -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
    }
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
                plane_distance(*normal, *offset, ray, t_max).map(Intersection::at)
            }
            Shape::Sphere { center, radius } => {
                sphere_distance(*center, *radius, ray, t_max).map(Intersection::at)
            }
            Shape::Planar { kind, origin, edge1, edge2, .. } => {
                let (t, s, u) = planar_distance(*kind, *origin, *edge1, *edge2, ray, t_max)?;
                Some(Intersection { t, st: Vec2::new(s, u), triangle: 0, part: 0 })
            }
            Shape::Quadric { kind, frame } => {
                let (o, d) = frame.ray_to_object(ray);
                quadric_distance(*kind, o, d, t_max).map(Intersection::at)
            }
            Shape::Box(_) | Shape::Cone(_) => self.solid_intersection(ray, t_max),
            Shape::Torus(torus) => torus.intersection(ray, t_max),
            Shape::Csg(csg) => csg.intersection(ray, t_max),
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
                // Project the point back onto the plane: its error is then that of its
                // coordinates alone.
                let p = ray.at(t);
                let point = p - *normal * (normal.dot(p) + offset);
                surface(point, *normal, REL_ERROR * (point.abs().max_element() + offset.abs()))
            }
            Shape::Sphere { center, radius } => {
                let normal = (ray.at(t) - *center).normalize();
                surface(*center + *radius * normal, normal, sphere_error(*center, *radius))
            }
            Shape::Planar { origin, edge1, edge2, normal, .. } => surface(
                *origin + at.st.x * *edge1 + at.st.y * *edge2,
                *normal,
                planar_error(*origin, *edge1, *edge2),
            ),
            Shape::Quadric { kind, frame } => {
                let (o, d) = frame.ray_to_object(ray);
                let p = o + t * d;
                // Back onto the surface, then to the world.
                let (p, n) = match kind {
                    QuadricKind::Ellipsoid => {
                        let n = p.normalize();
                        (n, n)
                    }
                    QuadricKind::Tube => {
                        let radial = Vec3A::new(p.x, p.y, 0.0).normalize();
                        (radial + Vec3A::new(0.0, 0.0, p.z), radial)
                    }
                };
                surface(
                    frame.to_world.transform_point3a(p).into(),
                    (frame.normal_to_world * n).normalize().into(),
                    REL_ERROR * frame.magnitude,
                )
            }
            Shape::Mesh { mesh, placement: None } => mesh.hit(at),
            Shape::Mesh { mesh, placement: Some(placement) } => {
                placement.hit_to_world(mesh.hit(at))
            }
            Shape::Box(_) | Shape::Cone(_) => self.solid_hit(ray, at).expect("a solid's hit"),
            Shape::Torus(torus) => torus.hit(ray, at),
            Shape::Csg(csg) => csg.hit(ray, at),
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
            _ => self.intersection(ray, t_max).is_some(),
        }
    }

    /// `None` for the unbounded plane.
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Plane { .. } => None,
            Shape::Sphere { center, radius } => Some(Aabb {
                min: center - Vec3::splat(*radius),
                max: center + Vec3::splat(*radius),
            }),
            Shape::Planar { kind: PlanarKind::Triangle, origin, edge1, edge2, .. } => {
                Some(Aabb::from_points(&[*origin, origin + edge1, origin + edge2]))
            }
            Shape::Planar { kind: PlanarKind::Quad, origin, edge1, edge2, .. } => {
                Some(Aabb::from_points(&[
                    *origin,
                    origin + edge1,
                    origin + edge2,
                    origin + edge1 + edge2,
                ]))
            }
            Shape::Planar { kind: PlanarKind::Disk, origin, edge1, edge2, .. } => {
                // The ellipse origin + cos(a) e1 + sin(a) e2 reaches sqrt(e1_i^2 + e2_i^2) on axis i.
                let half = (edge1 * edge1 + edge2 * edge2).map(f32::sqrt);
                Some(Aabb { min: origin - half, max: origin + half })
            }
            Shape::Quadric { frame, .. } => Some(Aabb::from_points(
                &QuadricFrame::canonical_corners().map(|c| frame.to_world.transform_point3(c)),
            )),
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
            Shape::Box(_) | Shape::Cone(_) => self.solid_bounds(),
            Shape::Torus(torus) => Some(torus.bounds()),
            Shape::Csg(csg) => csg.bounds(),
        }
    }

    /// Surface area, when it is finite and known in closed form (meshes are not sampled as lights).
    pub fn area(&self) -> Option<f32> {
        match self {
            Shape::Plane { .. } | Shape::Mesh { .. } => None,
            Shape::Sphere { radius, .. } => Some(4.0 * std::f32::consts::PI * radius * radius),
            Shape::Planar { kind, edge1, edge2, .. } => {
                let parallelogram = edge1.cross(*edge2).length();
                Some(match kind {
                    PlanarKind::Triangle => 0.5 * parallelogram,
                    PlanarKind::Quad => parallelogram,
                    PlanarKind::Disk => std::f32::consts::PI * parallelogram,
                })
            }
            Shape::Quadric { frame, .. } => frame.area,
            Shape::Box(_) | Shape::Cone(_) => self.solid_area(),
            Shape::Torus(torus) => torus.area(),
            // Its surfaces are parts of its operands': not sampled as a light.
            Shape::Csg(_) => None,
        }
    }

    /// A point distributed uniformly by area (pdf 1 / area); `None` where `area` is `None`.
    pub fn sample_area(&self, u: Vec2) -> Option<SurfaceSample> {
        match self {
            Shape::Plane { .. } | Shape::Mesh { .. } | Shape::Csg(_) => None,
            Shape::Box(_) | Shape::Cone(_) => self.solid_sample(u),
            Shape::Torus(torus) => torus.sample(u),
            Shape::Sphere { center, radius } => {
                let normal = uniform_sphere(u);
                let point = center + *radius * normal;
                Some(SurfaceSample { point, normal, error: sphere_error(*center, *radius) })
            }
            Shape::Planar { kind, origin, edge1, edge2, normal } => {
                let (s, t) = planar_coordinates(*kind, u).into();
                Some(SurfaceSample {
                    point: origin + s * edge1 + t * edge2,
                    normal: *normal,
                    error: planar_error(*origin, *edge1, *edge2),
                })
            }
            Shape::Quadric { kind, frame } => {
                frame.area?;
                let (p, n) = match kind {
                    QuadricKind::Ellipsoid => {
                        let n = uniform_sphere(u);
                        (n, n)
                    }
                    QuadricKind::Tube => {
                        let phi = 2.0 * std::f32::consts::PI * u.y;
                        let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
                        (n + Vec3::new(0.0, 0.0, u.x), n)
                    }
                };
                Some(SurfaceSample {
                    point: frame.to_world.transform_point3(p),
                    normal: (frame.normal_to_world * Vec3A::from(n)).normalize().into(),
                    error: REL_ERROR * frame.magnitude,
                })
            }
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

/// Error bound of a point on a sphere (its coordinates are at most |center| + radius).
pub fn sphere_error(center: Vec3, radius: f32) -> f32 {
    REL_ERROR * (center.abs().max_element() + radius)
}

/// The coordinates along the edges of a point uniform in the area of a planar shape, from a
/// point `u` of the unit square.
pub fn planar_coordinates(kind: PlanarKind, u: Vec2) -> Vec2 {
    match kind {
        PlanarKind::Triangle => uniform_triangle(u),
        PlanarKind::Quad => u,
        PlanarKind::Disk => concentric_disk(u),
    }
}

/// Error bound of a point on a planar shape (its coordinates are at most
/// |origin| + |edge1| + |edge2|).
pub fn planar_error(origin: Vec3, edge1: Vec3, edge2: Vec3) -> f32 {
    REL_ERROR * (origin.abs() + edge1.abs() + edge2.abs()).max_element()
}

#[inline]
fn plane_distance(normal: Vec3, offset: f32, ray: &Ray, t_max: f32) -> Option<f32> {
    let (origin, dir) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let t = -(normal.dot(origin) + offset) / normal.dot(dir);
    (t > 0.0 && t < t_max).then_some(t)
}

#[inline]
fn sphere_distance(center: Vec3, radius: f32, ray: &Ray, t_max: f32) -> Option<f32> {
    let (t0, t1) = sphere_roots(center, radius, ray)?;
    let t = if t0 > 0.0 { t0 } else { t1 };
    (t > 0.0 && t < t_max).then_some(t)
}

/// Both intersections of the sphere with the ray's line, in order.
#[inline]
pub(super) fn sphere_roots(center: Vec3, radius: f32, ray: &Ray) -> Option<(f32, f32)> {
    let dir = Vec3::from(ray.dir);
    let oc = Vec3::from(ray.origin) - center;
    let b = oc.dot(dir);
    // r^2 - |oc - b d|^2 instead of b^2 - (|oc|^2 - r^2): no cancellation for distant spheres
    // (Ray Tracing Gems, ch. 7).
    let perp = oc - b * dir;
    let discriminant = radius * radius - perp.length_squared();
    quadratic_roots_with(1.0, b, oc.length_squared() - radius * radius, discriminant)
}

/// Möller–Trumbore's coordinates (s, t) along edge1 and edge2 of where the ray meets the
/// plane of a planar shape, inside it or not.
pub(super) fn planar_unbounded(origin: Vec3, edge1: Vec3, edge2: Vec3, ray: &Ray) -> (f32, f32) {
    let dir = Vec3::from(ray.dir);
    let pvec = dir.cross(edge2);
    let inv_det = 1.0 / edge1.dot(pvec);
    let tvec = Vec3::from(ray.origin) - origin;
    (tvec.dot(pvec) * inv_det, dir.dot(tvec.cross(edge1)) * inv_det)
}

/// Möller–Trumbore: distance and the coordinates (s, t) along edge1 and edge2.
#[inline]
pub(super) fn planar_distance(
    kind: PlanarKind,
    origin: Vec3,
    edge1: Vec3,
    edge2: Vec3,
    ray: &Ray,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    let dir = Vec3::from(ray.dir);
    let pvec = dir.cross(edge2);
    let det = edge1.dot(pvec);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = Vec3::from(ray.origin) - origin;
    let s = tvec.dot(pvec) * inv_det;
    let qvec = tvec.cross(edge1);
    let t = dir.dot(qvec) * inv_det;
    let inside = match kind {
        PlanarKind::Triangle => s >= 0.0 && t >= 0.0 && s + t <= 1.0,
        PlanarKind::Quad => (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t),
        PlanarKind::Disk => s * s + t * t <= 1.0,
    };
    if !inside {
        return None;
    }
    let distance = edge2.dot(qvec) * inv_det;
    (distance > 0.0 && distance < t_max).then_some((distance, s, t))
}

/// Distance along `o + t d` (canonical space, `d` not normalised, so t is the world distance).
pub(super) fn quadric_distance(kind: QuadricKind, o: Vec3A, d: Vec3A, t_max: f32) -> Option<f32> {
    let (a, half_b, c) = quadric_coefficients(kind, o, d);
    let (t0, t1) = quadratic_roots(a, half_b, c)?;
    let accept = |t: f32| {
        let in_range = t > 0.0 && t < t_max;
        in_range && (kind == QuadricKind::Ellipsoid || (0.0..=1.0).contains(&(o.z + t * d.z)))
    };
    [t0, t1].into_iter().find(|&t| accept(t))
}

/// The quadratic `a t^2 + 2 half_b t + c` (as `(a, half_b, c)`) that is 0 where `o + t d`
/// meets the canonical quadric (the tube's whole infinite cylinder).
pub(super) fn quadric_coefficients(kind: QuadricKind, o: Vec3A, d: Vec3A) -> (f32, f32, f32) {
    match kind {
        QuadricKind::Ellipsoid => (d.dot(d), o.dot(d), o.dot(o) - 1.0),
        QuadricKind::Tube => {
            (d.x * d.x + d.y * d.y, o.x * d.x + o.y * d.y, o.x * o.x + o.y * o.y - 1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn planar_kinds_accept_their_own_parameter_domains() {
        let (origin, edge1, edge2) = (Vec3::new(0.0, 0.0, 1.0), Vec3::X, Vec3::Y);
        let shape = |kind| Shape::Planar { kind, origin, edge1, edge2, normal: Vec3::Z };
        let down = |x, y| ray(Vec3::new(x, y, 0.0), Vec3::Z);
        let hits = |kind, x, y| shape(kind).intersect(&down(x, y), f32::INFINITY).is_some();
        assert!(hits(PlanarKind::Quad, 0.9, 0.9) && !hits(PlanarKind::Quad, 1.1, 0.5));
        assert!(hits(PlanarKind::Triangle, 0.4, 0.4) && !hits(PlanarKind::Triangle, 0.6, 0.6));
        assert!(hits(PlanarKind::Disk, -0.7, 0.7) && !hits(PlanarKind::Disk, 0.8, 0.8));
        let area = |kind| shape(kind).area().unwrap();
        assert_eq!(area(PlanarKind::Quad), 1.0);
        assert_eq!(area(PlanarKind::Triangle), 0.5);
        assert!((area(PlanarKind::Disk) - std::f32::consts::PI).abs() < 1e-6);
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
            Shape::Planar {
                kind: PlanarKind::Disk,
                origin: Vec3::ZERO,
                edge1: Vec3::X,
                edge2: Vec3::Y,
                normal: Vec3::Z,
            },
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
}
