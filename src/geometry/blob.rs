//! POV-Ray's blob: a field summed from components, each a sphere or a capsule (a cylinder with
//! hemispherical ends) of radius r and strength s contributing s (1 - (d / r)^2)^2 at distance
//! d < r from its centre or axis segment; the surface is where the field equals the threshold,
//! the solid where it exceeds it. Along a ray each component's contribution is a quartic on
//! the stretches where the ray is within it (a sphere's distance, or the distance to the axis
//! between the ends, is quadratic in the distance along the ray), so the field minus the
//! threshold is solved, stretch by stretch, by `polynomial`.

use arrayvec::ArrayVec;
use glam::{Affine3A, DAffine3, DVec3, Vec3};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};

/// A component's shape in its own space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ComponentShape {
    Sphere {
        center: Vec3,
    },
    /// The segment from `a` to `b` (distinct), with hemispherical ends.
    Capsule {
        a: Vec3,
        b: Vec3,
    },
}

/// One component: its shape, radius (> 0) and strength (non-zero), placed in the blob's space
/// by `to_blob` (its own transforms).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlobComponent {
    pub shape: ComponentShape,
    pub radius: f32,
    pub strength: f32,
    pub to_blob: Affine3A,
}

/// A component ready for rays: its shape in f64, and the map from the blob's space to its own.
#[derive(Debug, Clone)]
struct Component {
    shape: ComponentShape,
    radius_squared: f64,
    strength: f64,
    to_own: DAffine3,
}

/// A stretch of the ray where one component contributes the quartic `density` (in the
/// distance along the ray, lowest degree first).
#[derive(Debug, Clone, Copy)]
struct Piece {
    start: f64,
    end: f64,
    density: [f64; 5],
}

#[derive(Debug, Clone)]
pub struct Blob {
    /// Maps the blob's own space, where its components are placed, to the world.
    frame: QuadricFrame,
    components: Vec<Component>,
    threshold: f64,
    /// World bounds of the components of positive strength (nothing else can be inside).
    bounds: Aabb,
}

impl Blob {
    /// The blob of `components` (some of positive strength) and `threshold` (> 0) placed in
    /// the world by `to_world`.
    pub fn new(components: &[BlobComponent], threshold: f32, to_world: Affine3A) -> Self {
        let corners = |c: &BlobComponent| {
            let r = c.radius;
            let (lo, hi) = match c.shape {
                ComponentShape::Sphere { center } => (center - r, center + r),
                ComponentShape::Capsule { a, b } => (a.min(b) - r, a.max(b) + r),
            };
            let local = Aabb { min: lo, max: hi };
            QuadricFrame::canonical_corners().map(|k| {
                let corner = local.centroid() + 0.5 * k * local.extent();
                (to_world * c.to_blob).transform_point3(corner)
            })
        };
        let points: Vec<Vec3> =
            components.iter().filter(|c| c.strength > 0.0).flat_map(corners).collect();
        let bounds = Aabb::from_points(&points);
        let mut frame = QuadricFrame::new(to_world, None);
        frame.magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        let components = components
            .iter()
            .map(|c| Component {
                shape: c.shape,
                radius_squared: f64::from(c.radius).powi(2),
                strength: f64::from(c.strength),
                to_own: DAffine3::from_mat3_translation(
                    glam::Mat3::from(c.to_blob.matrix3).as_dmat3(),
                    Vec3::from(c.to_blob.translation).as_dvec3(),
                )
                .inverse(),
            })
            .collect();
        Blob { frame, components, threshold: f64::from(threshold), bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The field at a point of the blob's space, and its gradient there.
    fn field(&self, p: DVec3) -> (f64, DVec3) {
        let mut sum = (0.0, DVec3::ZERO);
        for c in &self.components {
            let q = c.to_own.transform_point3(p);
            let from = match c.shape {
                ComponentShape::Sphere { center } => q - center.as_dvec3(),
                ComponentShape::Capsule { a, b } => {
                    let (a, b) = (a.as_dvec3(), b.as_dvec3());
                    let axis = b - a;
                    let h = ((q - a).dot(axis) / axis.length_squared()).clamp(0.0, 1.0);
                    q - (a + h * axis)
                }
            };
            let fall = 1.0 - from.length_squared() / c.radius_squared;
            if fall > 0.0 {
                sum.0 += c.strength * fall * fall;
                // d/dq s (1 - |from|^2 / r^2)^2, back to the blob's space by the transpose.
                let own = -4.0 * c.strength * fall / c.radius_squared * from;
                sum.1 += c.to_own.matrix3.transpose() * own;
            }
        }
        sum
    }

    /// Where the ray crosses the surface at world distances in (0, t_max), in order, and
    /// whether it starts inside.
    fn roots(&self, ray: &Ray, t_max: f32) -> (bool, Vec<f32>) {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let inside = self.field(o).0 > self.threshold;
        let speed = d.length();
        let mut roots = Vec::new();
        if speed == 0.0 || !speed.is_finite() {
            return (inside, roots);
        }
        let d = d / speed;
        let pieces: Vec<Piece> = self.components.iter().flat_map(|c| pieces(c, o, d)).collect();
        let mut ends: Vec<f64> = pieces.iter().flat_map(|p| [p.start, p.end]).collect();
        ends.push(0.0);
        ends.retain(|&t| t >= 0.0 && t < f64::from(t_max) * speed);
        ends.push(f64::from(t_max) * speed);
        ends.sort_by(f64::total_cmp);
        ends.dedup();
        for stretch in ends.windows(2) {
            let (a, b) = (stretch[0], stretch[1]);
            let middle = 0.5 * (a + b);
            let mut c = [0.0; 5];
            c[0] = -self.threshold;
            let mut any = false;
            for p in pieces.iter().filter(|p| p.start <= middle && middle < p.end) {
                any = true;
                for (total, k) in c.iter_mut().zip(p.density) {
                    *total += k;
                }
            }
            if !any {
                continue;
            }
            let degree = c.iter().rposition(|&k| k != 0.0).unwrap_or(0);
            for s in polynomial_roots(&c[..=degree], a, b) {
                let t = (s / speed) as f32;
                // A root at the end of one stretch and the start of the next is one crossing.
                let repeated = roots.last().is_some_and(|&last: &f32| s == a && last == t);
                if t > 0.0 && t < t_max && !repeated {
                    roots.push(t);
                }
            }
        }
        (inside, roots)
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.roots(ray, t_max).1.first().map(|&t| Intersection::at(t))
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (inside_at_start, roots) = self.roots(ray, t_max);
        Crossings::alternating(inside_at_start, roots.into_iter().map(Intersection::at))
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        // The field falls outwards: the normal is against its gradient.
        self.frame.hit_along(ray, at, |own, _| -self.field(own).1)
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.field(p).0 > self.threshold
    }
}

/// The stretches of the line `o + s d` (blob space, |d| = 1) where a component contributes,
/// with its contribution there.
fn pieces(c: &Component, o: DVec3, d: DVec3) -> ArrayVec<Piece, 3> {
    let (o, d) = (c.to_own.transform_point3(o), c.to_own.transform_vector3(d));
    let mut found = ArrayVec::new();
    // s (1 - |from(t)|^2 / r^2)^2 for from(t) = from0 + t dir, on [start, end] within reach.
    let mut add = |from0: DVec3, dir: DVec3, start: f64, end: f64| {
        let r2 = c.radius_squared;
        let (a, b, k) = (dir.length_squared(), 2.0 * from0.dot(dir), from0.length_squared());
        // Where |from| < r: between the roots of a t^2 + b t + k - r^2 (all along a body the
        // ray runs parallel to, when within its radius).
        let (t0, t1) = if a == 0.0 {
            if k >= r2 {
                return;
            }
            (start, end)
        } else {
            let discriminant = b * b - 4.0 * a * (k - r2);
            if discriminant <= 0.0 {
                return;
            }
            let root = discriminant.sqrt();
            ((-b - root) / (2.0 * a), (-b + root) / (2.0 * a))
        };
        let (start, end) = (start.max(t0), end.min(t1));
        if start >= end {
            return;
        }
        // fall = 1 - (a t^2 + b t + k) / r^2, squared, times s.
        let q = [1.0 - k / r2, -b / r2, -a / r2];
        let s = c.strength;
        let density = [
            s * q[0] * q[0],
            s * 2.0 * q[0] * q[1],
            s * (q[1] * q[1] + 2.0 * q[0] * q[2]),
            s * 2.0 * q[1] * q[2],
            s * q[2] * q[2],
        ];
        found.push(Piece { start, end, density });
    };
    match c.shape {
        ComponentShape::Sphere { center } => {
            add(o - center.as_dvec3(), d, f64::NEG_INFINITY, f64::INFINITY);
        }
        ComponentShape::Capsule { a, b } => {
            let (a, b) = (a.as_dvec3(), b.as_dvec3());
            let length = (b - a).length();
            let axis = (b - a) / length;
            // The position along the axis, h(t) = h0 + t h1: the body where 0 <= h <= length,
            // the end spheres beyond.
            let (h0, h1) = ((o - a).dot(axis), d.dot(axis));
            let (at_a, at_b) = if h1 != 0.0 {
                (-h0 / h1, (length - h0) / h1)
            } else if (0.0..=length).contains(&h0) {
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                // Across the axis and beyond an end: that end's sphere all along.
                let end = if h0 < 0.0 { a } else { b };
                add(o - end, d, f64::NEG_INFINITY, f64::INFINITY);
                return found;
            };
            let (body_start, body_end) = (at_a.min(at_b), at_a.max(at_b));
            // Perpendicular to the axis in the body.
            let perpendicular = |v: DVec3| v - v.dot(axis) * axis;
            add(perpendicular(o - a), perpendicular(d), body_start, body_end);
            // The ends: before the body the ray is beyond the end it enters the body at.
            let (first, last) = if at_a <= at_b { (a, b) } else { (b, a) };
            add(o - first, d, f64::NEG_INFINITY, body_start);
            add(o - last, d, body_end, f64::INFINITY);
        }
    }
    found
}
