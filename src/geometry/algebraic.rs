//! An algebraic surface: the points where a polynomial P(x, y, z) is 0, under an affine map,
//! as POV-Ray's `quadric`, `cubic`, `quartic` and `poly` define it. The solid is where P < 0
//! (POV-Ray's inside); it is unbounded unless P says otherwise, so it has no bounds, area or
//! samples. Along a ray P is a polynomial in the distance, solved in the surface's own space,
//! in f64, from the line's point nearest the own space's origin (where the coefficients are of
//! the surface's own size however far away the ray starts) by `polynomial`.

use arrayvec::ArrayVec;
use glam::{Affine3A, DVec3, Vec3};

use super::crossings::Crossings;
use super::polynomial::{MAX_DEGREE, Roots, polynomial_roots, root_bound};
use super::quadric::QuadricFrame;
use super::shape::{Intersection, REL_ERROR};
use super::{Hit, Ray};

/// One term of a polynomial in x, y, z: `coefficient x^i y^j z^k` for powers [i, j, k].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    pub coefficient: f64,
    pub powers: [u32; 3],
}

impl Term {
    pub fn degree(&self) -> usize {
        self.powers.iter().sum::<u32>() as usize
    }
}

/// A polynomial in one variable, lowest degree first.
type Coefficients = ArrayVec<f64, { MAX_DEGREE + 1 }>;

#[derive(Debug, Clone)]
pub struct Algebraic {
    /// Maps the surface's own space, where P is written, to the world.
    frame: QuadricFrame,
    /// The terms of P with a coefficient other than 0.
    terms: Vec<Term>,
    /// The degree of P, at most `MAX_DEGREE`.
    degree: usize,
}

impl Algebraic {
    /// The surface P = 0 of the polynomial `terms` (total degree at most `MAX_DEGREE`),
    /// placed in the world by `to_world`.
    pub fn new(terms: &[Term], to_world: Affine3A) -> Self {
        let terms: Vec<Term> = terms.iter().filter(|t| t.coefficient != 0.0).copied().collect();
        let degree = terms.iter().map(Term::degree).max().unwrap_or(0);
        assert!(degree <= MAX_DEGREE, "the language checks the degree");
        Algebraic { frame: QuadricFrame::new(to_world, None), terms, degree }
    }

    /// P at a point of its own space.
    fn value(&self, p: DVec3) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                let [i, j, k] = t.powers.map(|n| n as i32);
                t.coefficient * p.x.powi(i) * p.y.powi(j) * p.z.powi(k)
            })
            .sum()
    }

    /// The gradient of P at a point of its own space: the outward normal (P grows outwards).
    fn gradient(&self, p: DVec3) -> DVec3 {
        let power = |x: f64, n: u32| if n == 0 { 1.0 } else { x.powi(n as i32) };
        // d/dx x^n = n x^(n - 1), 0 for n = 0.
        let slope = |x: f64, n: u32| if n == 0 { 0.0 } else { f64::from(n) * power(x, n - 1) };
        self.terms.iter().fold(DVec3::ZERO, |g, t| {
            let [i, j, k] = t.powers;
            let (px, py, pz) = (power(p.x, i), power(p.y, j), power(p.z, k));
            let (sx, sy, sz) = (slope(p.x, i), slope(p.y, j), slope(p.z, k));
            g + t.coefficient * DVec3::new(sx * py * pz, px * sy * pz, px * py * sz)
        })
    }

    /// The crossings of P = 0 with the ray at world distances in (0, t_max), in order, and
    /// whether the ray starts inside (P < 0 at its origin).
    fn roots(&self, ray: &Ray, t_max: f32) -> (bool, Roots) {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let inside = self.value(o) < 0.0;
        let speed = d.length();
        let mut roots = Roots::new();
        if speed == 0.0 || !speed.is_finite() {
            return (inside, roots);
        }
        let d = d / speed;
        let shift = -o.dot(d);
        let near = o + shift * d;
        let mut c = self.along(near, d);
        // Leading coefficients lost to rounding (a line along an asymptotic direction) would
        // make roots at absurd distances: they are dropped relative to the largest.
        let largest = c.iter().fold(0.0f64, |m, k| m.max(k.abs()));
        while c.len() > 1 && c.last().is_some_and(|k| k.abs() <= 1e-14 * largest) {
            c.pop();
        }
        if c.len() < 2 {
            return (inside, roots);
        }
        let lo = -shift;
        let hi = (f64::from(t_max) * speed - shift).min(root_bound(&c));
        if hi > lo {
            let found = polynomial_roots(&c, lo, hi);
            let world = |s: f64| ((shift + s) / speed) as f32;
            roots.extend(
                found
                    .into_iter()
                    .filter(|&s| world(s) > 0.0 && world(s) < t_max)
                    .map(|s| f64::from(world(s))),
            );
        }
        (inside, roots)
    }

    /// P(near + s d) as a polynomial in s, lowest degree first.
    fn along(&self, near: DVec3, d: DVec3) -> Coefficients {
        let n = self.degree;
        let width = n + 1;
        // (near_axis + s d_axis)^i at [(axis * width + i) * width + k], its s^k coefficient.
        let at = |axis: usize, i: usize, k: usize| (axis * width + i) * width + k;
        let mut powers = vec![0.0; 3 * width * width];
        for axis in 0..3 {
            let (a, b) = (near[axis], d[axis]);
            powers[at(axis, 0, 0)] = 1.0;
            for i in 1..=n {
                for k in 0..=i {
                    let from_a = if k < i { a * powers[at(axis, i - 1, k)] } else { 0.0 };
                    let from_b = if k > 0 { b * powers[at(axis, i - 1, k - 1)] } else { 0.0 };
                    powers[at(axis, i, k)] = from_a + from_b;
                }
            }
        }
        let mut c: Coefficients = std::iter::repeat_n(0.0, width).collect();
        for term in &self.terms {
            let [i, j, k] = term.powers.map(|p| p as usize);
            for a in 0..=i {
                let x = term.coefficient * powers[at(0, i, a)];
                for b in 0..=j {
                    let xy = x * powers[at(1, j, b)];
                    for e in 0..=k {
                        c[a + b + e] += xy * powers[at(2, k, e)];
                    }
                }
            }
        }
        c
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.roots(ray, t_max).1.first().map(|&t| Intersection::at(t as f32))
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (inside_at_start, roots) = self.roots(ray, t_max);
        Crossings::alternating(
            inside_at_start,
            roots.into_iter().map(|t| Intersection::at(t as f32)),
        )
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let hit = self.frame.hit_along(ray, at, |own, _| self.gradient(own));
        // Far from the frame's origin the polynomial's terms lose more.
        Hit { error: hit.error.max(REL_ERROR * hit.point.abs().max_element()), ..hit }
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.value(p) < 0.0
    }
}

/// POV-Ray's terms of a `poly` of `order` (and of `cubic`, order 3, and `quartic`, order 4),
/// in the order its coefficients are written: the powers of x from the highest down, within
/// each those of y from the highest down, within each those of z.
pub fn pov_ray_terms(order: usize, coefficients: &[f64]) -> Vec<Term> {
    let n = order as u32;
    let mut powers = Vec::new();
    for i in (0..=n).rev() {
        for j in (0..=n - i).rev() {
            for k in (0..=n - i - j).rev() {
                powers.push([i, j, k]);
            }
        }
    }
    powers
        .into_iter()
        .zip(coefficients)
        .map(|(powers, &coefficient)| Term { coefficient, powers })
        .collect()
}

/// How many coefficients POV-Ray's `poly` of `order` takes: (order + 1)(order + 2)(order + 3)/6.
pub fn pov_ray_term_count(order: usize) -> usize {
    (order + 1) * (order + 2) * (order + 3) / 6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pov_ray_order_of_terms() {
        assert_eq!(pov_ray_term_count(4), 35);
        assert_eq!(pov_ray_term_count(3), 20);
        let terms = pov_ray_terms(4, &[1.0; 35]);
        // The manual's table: A1 x^4, A2 x^3 y, A4 x^3, A5 x^2 y^2, A10 x^2, A21 y^4, A35 1.
        assert_eq!(terms[0].powers, [4, 0, 0]);
        assert_eq!(terms[1].powers, [3, 1, 0]);
        assert_eq!(terms[3].powers, [3, 0, 0]);
        assert_eq!(terms[4].powers, [2, 2, 0]);
        assert_eq!(terms[9].powers, [2, 0, 0]);
        assert_eq!(terms[20].powers, [0, 4, 0]);
        assert_eq!(terms[34].powers, [0, 0, 0]);
    }
}
