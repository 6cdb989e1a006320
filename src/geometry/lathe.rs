//! POV-Ray's lathe: a curve of (r, y) points turned about the y axis, solid where a point's
//! (distance from the axis, height) is inside the curve by the even-odd rule. Each segment of
//! the curve is a cubic in its parameter u in [0, 1] (`spline`); a ray at distance² from the
//! axis a t² + 2 m t + c meets the surface a segment turns where that equals r(u)² at the
//! height y(u) = o.y + t d.y: a polynomial of degree 6 in u, solved by `polynomial`. A ray in a
//! plane of constant height meets it where y(u) = o.y, each u at the two points of the circle
//! of radius r(u).

use glam::{Affine3A, DVec2, DVec3, Vec2, Vec3};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::spline::{Segment, inside_curves, segment_bounds};
use super::{Aabb, Hit, Ray};

/// The ray's own-space direction has a vertical part below this fraction of its length: the
/// ray stays at one height across the lathe (to within f32's rounding), and the sextic's pairs
/// of roots would be too close to tell apart.
const LEVEL: f64 = 1e-7;

/// Whether the ray goes into the solid at an intersection, in `Intersection::triangle` above
/// the segment's index.
const ENTERING: u32 = 1 << 31;

#[derive(Debug, Clone)]
pub struct Lathe {
    frame: QuadricFrame,
    /// The curve's segments, points (r, y).
    segments: Vec<[DVec2; 4]>,
    /// Each segment's least and greatest r and y.
    extents: Vec<(DVec2, DVec2)>,
    /// All segments' least and greatest r and y.
    min: DVec2,
    max: DVec2,
    bounds: Aabb,
}

impl Lathe {
    /// The lathe of `segments` (points (r, y), r >= 0) placed in the world by `to_world`.
    pub fn new(segments: &[Segment], to_world: Affine3A) -> Self {
        let segments: Vec<[DVec2; 4]> = segments.iter().map(|s| s.map(|v| v.as_dvec2())).collect();
        let extents: Vec<(DVec2, DVec2)> = segments.iter().map(segment_bounds).collect();
        let min = extents.iter().fold(DVec2::INFINITY, |m, e| m.min(e.0));
        let max = extents.iter().fold(DVec2::NEG_INFINITY, |m, e| m.max(e.1));
        let radius = max.x.max(-min.x) as f32;
        let corners = QuadricFrame::canonical_corners().map(|c| {
            let y = if c.y < 0.0 { min.y } else { max.y } as f32;
            to_world.transform_point3(Vec3::new(c.x * radius, y, c.z * radius))
        });
        let bounds = Aabb::from_points(&corners);
        let mut frame = QuadricFrame::new(to_world, None);
        frame.magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        Lathe { frame, segments, extents, min, max, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn inside(&self, p: DVec3) -> bool {
        let section = DVec2::new(p.x.hypot(p.z), p.y);
        if section.y < self.min.y || section.y > self.max.y || section.x > self.max.x {
            return false;
        }
        inside_curves(&self.segments, section)
    }

    /// Every crossing of the surface in (0, t_max), in order, with the segment and its
    /// parameter; whether the ray starts inside.
    fn crossings_along(&self, ray: &Ray, t_max: f32) -> (bool, Vec<Intersection>) {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let inside_at_start = self.inside(o);
        // The ray's squared distance from the axis: a t^2 + 2 m t + c.
        let (a, m, c) = (d.x * d.x + d.z * d.z, o.x * d.x + o.z * d.z, o.x * o.x + o.z * o.z);
        // Its least distance from the axis, to pass over segments that do not reach it.
        let nearest = if a > 0.0 { (c - m * m / a).max(0.0).sqrt() } else { c.sqrt() };
        let level = d.y.abs() <= LEVEL * d.length();
        let t_end = f64::from(t_max);
        let mut found: Vec<(f64, u32, f64)> = Vec::new();
        for (index, (s, (lo, hi))) in self.segments.iter().zip(&self.extents).enumerate() {
            if hi.x < nearest || level && (o.y < lo.y || o.y > hi.y) {
                continue;
            }
            let y = [s[0].y - o.y, s[1].y, s[2].y, s[3].y];
            let r = [s[0].x, s[1].x, s[2].x, s[3].x];
            let mut keep = |t: f64, u: f64| {
                if t > 0.0 && t < t_end {
                    found.push((t, index as u32, u));
                }
            };
            if level {
                for u in roots_in_segment(&y) {
                    let radius = cubic(&r, u);
                    // a t^2 + 2 m t + c - r^2 = 0.
                    let discriminant = m * m - a * (c - radius * radius);
                    if a > 0.0 && discriminant >= 0.0 {
                        let root = discriminant.sqrt();
                        let q = -m - root.copysign(m);
                        let (t0, t1) = (q / a, (c - radius * radius) / q);
                        keep(t0.min(t1), u);
                        keep(t0.max(t1), u);
                    }
                }
                continue;
            }
            // With t = y / d.y: a y^2 + 2 m d.y y + (c - r^2) d.y^2 = 0.
            let mut p = [0.0; 7];
            for i in 0..4 {
                for j in 0..4 {
                    p[i + j] += a * y[i] * y[j] - d.y * d.y * r[i] * r[j];
                }
                p[i] += 2.0 * m * d.y * y[i];
            }
            p[0] += c * d.y * d.y;
            for u in roots_in_segment(&p) {
                keep(cubic(&y, u) / d.y, u);
            }
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut inside = inside_at_start;
        let list = found
            .into_iter()
            .map(|(t, segment, u)| {
                inside = !inside;
                let flag = if inside { ENTERING } else { 0 };
                Intersection {
                    t: t as f32,
                    st: Vec2::new(u as f32, 0.0),
                    triangle: segment | flag,
                    part: 0,
                }
            })
            .collect();
        (inside_at_start, list)
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.crossings_along(ray, t_max).1.into_iter().next()
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (inside_at_start, list) = self.crossings_along(ray, t_max);
        let mut crossings = Crossings { inside_at_start, list: Default::default() };
        for at in list {
            crossings.push(at, at.triangle & ENTERING != 0);
        }
        crossings
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let s = &self.segments[(at.triangle & !ENTERING) as usize];
        let u = f64::from(at.st.x);
        let slope = s[1] + u * (2.0 * s[2] + 3.0 * u * s[3]);
        // Outward: against the ray where it goes in, along it where it comes out (the even-odd
        // rule gives a segment no side of its own).
        let entering = at.triangle & ENTERING != 0;
        self.frame.hit_along(ray, at, |own, d| {
            let radius = own.x.hypot(own.z);
            let across = if radius > 0.0 { slope.y / radius } else { 0.0 };
            let normal = DVec3::new(across * own.x, -slope.x, across * own.z);
            if (normal.dot(d) < 0.0) == entering { normal } else { -normal }
        })
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.inside(p)
    }
}

/// The roots in [0, 1) of a polynomial (lowest degree first; each segment's end belongs to the
/// segment it starts).
fn roots_in_segment(c: &[f64]) -> impl Iterator<Item = f64> {
    let degree = c.iter().rposition(|&k| k != 0.0).unwrap_or(0);
    polynomial_roots(&c[..=degree], 0.0, 1.0).into_iter().filter(|&u| u < 1.0)
}

/// `c[0] + c[1] u + c[2] u^2 + c[3] u^3`.
fn cubic(c: &[f64; 4], u: f64) -> f64 {
    c[0] + u * (c[1] + u * (c[2] + u * c[3]))
}
