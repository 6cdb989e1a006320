//! Planar shapes: a triangle, a quad or a disk (an ellipse under non-uniform scale), stand-alone
//! or as a face of a box or a cone's end. An affine transform keeps them planar, so they are
//! stored in world space.

use glam::{Vec2, Vec3};

use super::shape::{Intersection, REL_ERROR, SurfaceSample};
use super::shape::{ahead, ray_vectors};
use super::{Aabb, Hit, Ray};
use crate::lanes::{Real, Vector};
use crate::sampling::{concentric_disk, concentric_disk_of, uniform_triangle_of};

/// Which coordinates (s, t) along the edges of `origin + s * edge1 + t * edge2` are inside.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanarKind {
    /// s, t >= 0, s + t <= 1
    Triangle,
    /// s, t in [0, 1]
    Quad,
    /// hole^2 <= s^2 + t^2 <= 1, with `origin` the centre (an ellipse under non-uniform scale)
    Disk,
}

/// `origin + s * edge1 + t * edge2` for the (s, t) its kind takes, facing `normal`, the unit
/// `edge1 x edge2` (a solid's face: out of the solid).
#[derive(Debug, Clone, Copy)]
pub struct Planar {
    pub kind: PlanarKind,
    pub origin: Vec3,
    pub edge1: Vec3,
    pub edge2: Vec3,
    pub normal: Vec3,
    /// A disk's hole: its radius over the disk's, in [0, 1) (POV-Ray's `disc` with a hole
    /// radius); 0 for the other kinds.
    pub hole: f32,
}

impl Planar {
    pub fn new(kind: PlanarKind, origin: Vec3, edge1: Vec3, edge2: Vec3) -> Self {
        Planar { kind, origin, edge1, edge2, normal: edge1.cross(edge2).normalize(), hole: 0.0 }
    }

    /// This disk with a hole of `hole` times its radius.
    pub fn with_hole(self, hole: f32) -> Self {
        Planar { hole, ..self }
    }

    /// The distance in (0, t_max) and the coordinates along the edges.
    #[inline]
    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let (origin, dir) = ray_vectors(ray);
        let at = |v: Vec3| v.into();
        let (distance, [s, t]) = planar_distance(
            self.kind,
            self.hole,
            at(self.origin),
            at(self.edge1),
            at(self.edge2),
            origin,
            dir,
        );
        let t_hit = ahead(distance, t_max)?;
        Some(Intersection { t: t_hit, st: Vec2::new(s, t), triangle: 0, part: 0 })
    }

    /// The intersection of a ray known to cross this plane at `t` (found another way, by a
    /// solid that has this as its face `part`), with its coordinates along the edges.
    pub fn intersection_at(&self, ray: &Ray, t: f32, part: u32) -> Intersection {
        let dir = Vec3::from(ray.dir);
        let pvec = dir.cross(self.edge2);
        let inv_det = 1.0 / self.edge1.dot(pvec);
        let tvec = Vec3::from(ray.origin) - self.origin;
        let st = Vec2::new(tvec.dot(pvec) * inv_det, dir.dot(tvec.cross(self.edge1)) * inv_det);
        Intersection { t, st, triangle: part, part: 0 }
    }

    /// The hit record at distance `t` and coordinates `st`.
    pub fn hit(&self, t: f32, st: Vec2) -> Hit {
        Hit {
            t,
            point: planar_point(
                self.origin.into(),
                self.edge1.into(),
                self.edge2.into(),
                st.x,
                st.y,
            )
            .into(),
            normal: self.normal,
            shading_normal: self.normal,
            error: self.error(),
            primitive: 0,
        }
    }

    pub fn bounds(&self) -> Aabb {
        let (origin, edge1, edge2) = (self.origin, self.edge1, self.edge2);
        match self.kind {
            PlanarKind::Triangle => Aabb::from_points(&[origin, origin + edge1, origin + edge2]),
            PlanarKind::Quad => {
                Aabb::from_points(&[origin, origin + edge1, origin + edge2, origin + edge1 + edge2])
            }
            PlanarKind::Disk => {
                // The ellipse origin + cos(a) e1 + sin(a) e2 reaches sqrt(e1_i^2 + e2_i^2) on
                // axis i.
                let half = (edge1 * edge1 + edge2 * edge2).map(f32::sqrt);
                Aabb { min: origin - half, max: origin + half }
            }
        }
    }

    pub fn area(&self) -> f32 {
        let parallelogram = self.edge1.cross(self.edge2).length();
        match self.kind {
            PlanarKind::Triangle => 0.5 * parallelogram,
            PlanarKind::Quad => parallelogram,
            PlanarKind::Disk => std::f32::consts::PI * parallelogram * (1.0 - self.hole.powi(2)),
        }
    }

    /// A point distributed uniformly by area, from a point `u` of the unit square.
    #[inline(always)]
    pub fn sample(&self, u: Vec2) -> SurfaceSample {
        let (s, t) = planar_coordinates(self.kind, self.hole, u).into();
        SurfaceSample {
            point: self.point_at(s, t).into(),
            normal: self.normal,
            error: self.error(),
        }
    }

    /// The point at coordinates (s, t) along the edges, written once over `Real`: one, or one
    /// per lane.
    #[inline(always)]
    pub fn point_at<F: Real>(&self, s: F, t: F) -> Vector<F> {
        Vector::splat(self.origin) + Vector::splat(self.edge1) * s + Vector::splat(self.edge2) * t
    }

    /// Error bound of its points.
    #[inline]
    pub fn error(&self) -> f32 {
        planar_error(self.origin, self.edge1, self.edge2)
    }
}

/// The coordinates along the edges of a point uniform in the area of a planar shape (a disk's
/// with its `hole`), from a point `u` of the unit square.
#[inline]
pub fn planar_coordinates(kind: PlanarKind, hole: f32, u: Vec2) -> Vec2 {
    if let Some((s, t)) = planar_coordinates_of(kind, hole, u.x, u.y) {
        return Vec2::new(s, t);
    }
    // A disk's ring: the squared radius of a point of the disk is uniform in [0, 1]: mapped to
    // [hole^2, 1] linearly, the point stays uniform by area, now in the ring.
    let p = concentric_disk(u);
    let squared = p.length_squared();
    let ring = (hole * hole + squared * (1.0 - hole * hole)).sqrt();
    if squared > 0.0 { p * (ring / squared.sqrt()) } else { Vec2::new(ring, 0.0) }
}

/// `planar_coordinates` written once over `Real` (one point, or a point per lane), but for a
/// disk with a hole: `None`.
#[inline(always)]
pub fn planar_coordinates_of<F: Real>(kind: PlanarKind, hole: f32, ux: F, uy: F) -> Option<(F, F)> {
    match kind {
        PlanarKind::Triangle => Some(uniform_triangle_of(ux, uy)),
        PlanarKind::Quad => Some((ux, uy)),
        PlanarKind::Disk if hole > 0.0 => None,
        PlanarKind::Disk => Some(concentric_disk_of(ux, uy)),
    }
}

/// Möller–Trumbore: the distance along the ray to the planar shape of that kind (NaN where the
/// ray's line misses it), and the coordinates along the edges where the line meets its plane.
#[inline]
pub(crate) fn planar_distance<F: Real>(
    kind: PlanarKind,
    hole: F,
    origin: Vector<F>,
    edge1: Vector<F>,
    edge2: Vector<F>,
    ray_origin: Vector<F>,
    dir: Vector<F>,
) -> (F, [F; 2]) {
    let pvec = dir.cross(edge2);
    let det = edge1.dot(pvec);
    let inv_det = F::ONE / det;
    let tvec = ray_origin - origin;
    let s = tvec.dot(pvec) * inv_det;
    let qvec = tvec.cross(edge1);
    let t = dir.dot(qvec) * inv_det;
    let (zero, one) = (F::ZERO, F::ONE);
    let inside = match kind {
        PlanarKind::Triangle => s.ge(zero) & t.ge(zero) & (s + t).le(one),
        PlanarKind::Quad => s.ge(zero) & s.le(one) & t.ge(zero) & t.le(one),
        PlanarKind::Disk => (s * s + t * t).le(one) & (s * s + t * t).ge(hole * hole),
    };
    let distance = edge2.dot(qvec) * inv_det;
    (F::select(inside & det.ne(zero), distance, F::NAN), [s, t])
}

/// The point at coordinates (s, t) along the edges.
#[inline]
pub(crate) fn planar_point<F: Real>(
    origin: Vector<F>,
    edge1: Vector<F>,
    edge2: Vector<F>,
    s: F,
    t: F,
) -> Vector<F> {
    origin + edge1 * s + edge2 * t
}

/// Error bound of a point on a planar shape (its coordinates are at most
/// |origin| + |edge1| + |edge2|).
#[inline]
pub fn planar_error(origin: Vec3, edge1: Vec3, edge2: Vec3) -> f32 {
    REL_ERROR * (origin.abs() + edge1.abs() + edge2.abs()).max_element()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_accept_their_own_parameter_domains() {
        let planar = |kind| Planar::new(kind, Vec3::new(0.0, 0.0, 1.0), Vec3::X, Vec3::Y);
        let down = |x, y| Ray::new(Vec3::new(x, y, 0.0), Vec3::Z);
        let hits = |kind, x, y| planar(kind).intersection(&down(x, y), f32::INFINITY).is_some();
        assert!(hits(PlanarKind::Quad, 0.9, 0.9) && !hits(PlanarKind::Quad, 1.1, 0.5));
        assert!(hits(PlanarKind::Triangle, 0.4, 0.4) && !hits(PlanarKind::Triangle, 0.6, 0.6));
        assert!(hits(PlanarKind::Disk, -0.7, 0.7) && !hits(PlanarKind::Disk, 0.8, 0.8));
        assert_eq!(planar(PlanarKind::Quad).area(), 1.0);
        assert_eq!(planar(PlanarKind::Triangle).area(), 0.5);
        assert!((planar(PlanarKind::Disk).area() - std::f32::consts::PI).abs() < 1e-6);
        assert_eq!(planar(PlanarKind::Quad).normal, Vec3::Z, "edge1 x edge2");
        let ring = planar(PlanarKind::Disk).with_hole(0.5);
        let ring_hits = |x, y| ring.intersection(&down(x, y), f32::INFINITY).is_some();
        assert!(ring_hits(0.6, 0.0) && ring_hits(0.0, -0.9) && !ring_hits(0.3, 0.3));
        assert!((ring.area() - 0.75 * std::f32::consts::PI).abs() < 1e-6);
        // Samples of the ring are in it, and uniform: as many within radius sqrt(5/8) (half
        // its area) as outside it.
        let radii: Vec<f32> = (0..1024)
            .map(|i| {
                ring.sample(Vec2::new((i % 32) as f32 / 32.0 + 0.01, (i / 32) as f32 / 32.0 + 0.01))
            })
            .map(|s| (s.point - ring.origin).length())
            .collect();
        assert!(radii.iter().all(|&r| (0.5 - 1e-6..=1.0 + 1e-6).contains(&r)));
        let inner = radii.iter().filter(|&&r| r < (0.625f32).sqrt()).count();
        assert!((inner as i32 - 512).abs() < 40, "{inner}");
    }

    #[test]
    fn a_crossing_found_elsewhere_gets_the_coordinates_of_a_hit() {
        let quad = Planar::new(PlanarKind::Quad, Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 4.0);
        let ray = Ray::new(Vec3::new(1.0, 1.0, 3.0), -Vec3::Z);
        let hit = quad.intersection(&ray, f32::INFINITY).unwrap();
        let at = quad.intersection_at(&ray, hit.t, 5);
        assert_eq!((at.st, at.triangle), (hit.st, 5));
        assert_eq!(at.st, Vec2::new(0.5, 0.25));
    }
}
