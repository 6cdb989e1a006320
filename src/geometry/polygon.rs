//! POV-Ray's polygon: closed outlines of points in one plane, the inside by the even-odd rule
//! (an outline inside another is a hole). An affine transform keeps it planar, so it is stored
//! in world space: its plane, and the outlines in the plane's coordinates.

use glam::{DVec2, Vec2, Vec3};

use super::shape::{Intersection, REL_ERROR};
use super::spline::{SplineKind, inside_curves, spline_segments};
use super::{Aabb, Hit, Ray};

#[derive(Debug, Clone)]
pub struct Polygon {
    origin: Vec3,
    /// Unit axes of the plane's coordinates, and the normal (u x v).
    u: Vec3,
    v: Vec3,
    normal: Vec3,
    /// The outlines' edges in the plane's coordinates.
    edges: Vec<[DVec2; 4]>,
    bounds: Aabb,
}

/// Closes the last outline of `points` if it is open (a point repeating an outline's first
/// closes it, as in POV-Ray); whether it had to.
pub fn close_outlines(points: &mut Vec<Vec3>) -> bool {
    let same = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-10;
    let (mut start, mut i) = (0, 1);
    while i < points.len() {
        if same(points[i], points[start]) {
            start = i + 1;
            i += 2;
        } else {
            i += 1;
        }
    }
    let open = start < points.len();
    if open {
        points.push(points[start]);
    }
    open
}

/// The normal of the plane of closed outlines (the sum of the edges' cross products, twice the
/// area enclosed along the normal), or `None` when they enclose none.
pub fn outline_normal(points: &[Vec3]) -> Option<Vec3> {
    // From the first point: every edge's cross product is then along the plane's normal.
    let from_first = |p: Vec3| p - points[0];
    let sum: Vec3 = points.windows(2).map(|e| from_first(e[0]).cross(from_first(e[1]))).sum();
    sum.try_normalize()
}

impl Polygon {
    /// The polygon of closed outlines of world `points` (`close_outlines`) around `normal`
    /// (`outline_normal`).
    pub fn new(points: &[Vec3], normal: Vec3) -> Self {
        let origin = points[0];
        let (u, v) = normal.any_orthonormal_pair();
        let normal = u.cross(v);
        let flat: Vec<Vec2> =
            points.iter().map(|&p| Vec2::new((p - origin).dot(u), (p - origin).dot(v))).collect();
        let edges = spline_segments(SplineKind::Linear, &flat)
            .expect("the outlines are closed")
            .iter()
            .map(|s| s.map(|p| p.as_dvec2()))
            .collect();
        Polygon { origin, u, v, normal, edges, bounds: Aabb::from_points(points) }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let dir = Vec3::from(ray.dir);
        let to_origin = self.origin - Vec3::from(ray.origin);
        let t = to_origin.dot(self.normal) / dir.dot(self.normal);
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let p = t * dir - to_origin;
        let flat = DVec2::new(f64::from(p.dot(self.u)), f64::from(p.dot(self.v)));
        inside_curves(&self.edges, flat).then(|| Intersection::at(t))
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let point = ray.at(at.t);
        // The point put back in the plane.
        let point = point - (point - self.origin).dot(self.normal) * self.normal;
        let magnitude = self.bounds.min.abs().max(self.bounds.max.abs()).max_element();
        // Not a solid, and its points' order says nothing of a side: it faces the ray.
        let normal =
            if self.normal.dot(Vec3::from(ray.dir)) > 0.0 { -self.normal } else { self.normal };
        Hit {
            t: at.t,
            point,
            normal,
            shading_normal: normal,
            error: REL_ERROR * magnitude,
            primitive: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_with_a_square_hole_is_hit_around_the_hole() {
        let square =
            |r: f32| [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, y)| Vec3::new(x, y, 2.0));
        let mut points: Vec<Vec3> = square(1.0).into_iter().chain([square(1.0)[0]]).collect();
        points.extend(square(0.5));
        assert!(close_outlines(&mut points), "the hole was left open");
        assert_eq!(points.len(), 10);
        let normal = outline_normal(&points).unwrap();
        assert!((normal.abs() - Vec3::Z).length() < 1e-6);
        let polygon = Polygon::new(&points, normal);
        let towards = |x: f32, y: f32| Ray::new(Vec3::new(x, y, -1.0), Vec3::Z);
        let hit = polygon.intersection(&towards(0.75, 0.1), 10.0).expect("the rim");
        assert!((hit.t - 3.0).abs() < 1e-6);
        let hit = polygon.hit(&towards(0.75, 0.1), &hit);
        assert!((hit.point - Vec3::new(0.75, 0.1, 2.0)).length() < 1e-6);
        assert!((hit.normal + Vec3::Z).length() < 1e-6, "facing the ray: {hit:?}");
        assert!(polygon.intersection(&towards(0.0, 0.1), 10.0).is_none(), "the hole");
        assert!(polygon.intersection(&towards(1.5, 0.1), 10.0).is_none());
        assert!(polygon.intersection(&towards(0.75, 0.1), 2.0).is_none(), "beyond t_max");
        assert!(outline_normal(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::ZERO]).is_none());
    }
}
