//! POV-Ray's superellipsoid `<e, n>`: the points where (|x|^(2/e) + |y|^(2/e))^(e/n) +
//! |z|^(2/n) = 1, within the cube [-1, 1]^3, under an affine map; solid where the sum is
//! below 1. Along a ray the sum is not a polynomial: the ray's stretch in the cube is cut where
//! it crosses the coordinate planes (within each piece every coordinate keeps its sign, and
//! the sum is smooth) and each piece into `PARTS` equal parts, each part is cut again at the
//! sum's least and greatest values (found by golden-section search), and each monotonic part
//! where the sum crosses 1 is bisected.

use glam::{Affine3A, DVec3, Vec3};

use super::crossings::Crossings;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};

/// The parts each smooth piece of the ray is cut into: within a part the sum has one least and
/// one greatest value (the pinched shapes, exponents above 2, can turn more than once within a
/// piece).
const PARTS: usize = 8;

#[derive(Debug, Clone)]
pub struct Superellipsoid {
    frame: QuadricFrame,
    /// 2 / e, e / n and 2 / n.
    east: f64,
    ratio: f64,
    north: f64,
}

impl Superellipsoid {
    /// `superellipsoid { <e, n> }` (both > 0) placed in the world by `to_world`.
    pub fn new(e: f32, n: f32, to_world: Affine3A) -> Self {
        let (e, n) = (f64::from(e), f64::from(n));
        Superellipsoid {
            frame: QuadricFrame::new(to_world, None),
            east: 2.0 / e,
            ratio: e / n,
            north: 2.0 / n,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.frame.bounds()
    }

    /// The sum, minus 1, at a point of the own space.
    fn value(&self, p: DVec3) -> f64 {
        let p = p.abs();
        (p.x.powf(self.east) + p.y.powf(self.east)).powf(self.ratio) + p.z.powf(self.north) - 1.0
    }

    fn gradient(&self, p: DVec3) -> DVec3 {
        let a = p.abs();
        // d/dx |x|^k = k |x|^(k - 1) sign(x), 0 at 0 (the surface is only singular on the axes,
        // where the other terms give the normal).
        let slope = |x: f64, v: f64, k: f64| {
            if v == 0.0 { 0.0 } else { k * v.powf(k - 1.0) * x.signum() }
        };
        let sum = a.x.powf(self.east) + a.y.powf(self.east);
        let outer = if sum == 0.0 { 0.0 } else { self.ratio * sum.powf(self.ratio - 1.0) };
        DVec3::new(
            outer * slope(p.x, a.x, self.east),
            outer * slope(p.y, a.y, self.east),
            slope(p.z, a.z, self.north),
        )
    }

    /// Every crossing of the surface along the ray at distances in (0, t_max), in order (own
    /// space and world distances agree: the direction is mapped, not normalised).
    fn roots(&self, ray: &Ray, t_max: f32) -> Vec<f32> {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let mut roots = Vec::new();
        // The stretch within the cube.
        let (mut near, mut far) = (0.0f64, f64::from(t_max));
        for axis in 0..3 {
            if d[axis] == 0.0 {
                if o[axis].abs() > 1.0 {
                    return roots;
                }
                continue;
            }
            let (a, b) = ((-1.0 - o[axis]) / d[axis], (1.0 - o[axis]) / d[axis]);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        if near >= far {
            return roots;
        }
        let mut cuts = vec![near, far];
        for axis in 0..3 {
            let t = -o[axis] / d[axis];
            if t > near && t < far {
                cuts.push(t);
            }
        }
        cuts.sort_by(f64::total_cmp);
        let cuts: Vec<f64> = cuts
            .windows(2)
            .flat_map(|piece| {
                let step = (piece[1] - piece[0]) / PARTS as f64;
                (0..PARTS).map(move |k| piece[0] + step * k as f64)
            })
            .chain([far])
            .collect();
        let f = |t: f64| self.value(o + t * d);
        for piece in cuts.windows(2) {
            let (a, b) = (piece[0], piece[1]);
            let mut ends = [a, golden(&f, a, b, 1.0), golden(&f, a, b, -1.0), b];
            ends.sort_by(f64::total_cmp);
            for part in ends.windows(2) {
                let (lo, hi) = (part[0], part[1]);
                let (f_lo, f_hi) = (f(lo), f(hi));
                if hi > lo && (f_lo < 0.0) != (f_hi < 0.0) {
                    let t = bisect(&f, lo, hi, f_lo);
                    if t > 0.0 && t < f64::from(t_max) {
                        roots.push(t as f32);
                    }
                }
            }
        }
        roots
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.roots(ray, t_max).first().map(|&t| Intersection::at(t))
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (o, _) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::ZERO);
        let inside_at_start = self.inside(o);
        Crossings::alternating(
            inside_at_start,
            self.roots(ray, t_max).into_iter().map(Intersection::at),
        )
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        self.frame.hit_along(ray, at, |own, _| self.gradient(own))
    }

    fn inside(&self, p: DVec3) -> bool {
        p.abs().max_element() <= 1.0 && self.value(p) < 0.0
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.inside(p)
    }
}

/// Where `sign * f` is least on [a, b], by golden-section search (exact for a function with
/// one minimum there; an end where `sign * f` is monotonic).
fn golden(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, sign: f64) -> f64 {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = b - ratio * (b - a);
    let mut x2 = a + ratio * (b - a);
    let (mut f1, mut f2) = (sign * f(x1), sign * f(x2));
    for _ in 0..60 {
        if f1 < f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - ratio * (b - a);
            f1 = sign * f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + ratio * (b - a);
            f2 = sign * f(x2);
        }
        if b - a <= 1e-12 * (1.0 + a.abs()) {
            break;
        }
    }
    0.5 * (a + b)
}

/// The point in [a, b] where `f` changes sign (`fa` at a).
fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, fa: f64) -> f64 {
    for _ in 0..80 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if (f(m) < 0.0) == (fa < 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}
