//! The real roots of a quadratic, without cancellation: of the two roots, the textbook formula
//! takes one as the difference of nearly equal numbers when b^2 >> 4ac; here it comes from
//! the other by Vieta's c / q instead (Numerical Recipes, section 5.6). Written once, for the
//! f32 of most shapes and the f64 of the cone.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic the solver needs: f32 and f64.
pub trait Real:
    Copy
    + PartialOrd
    + Neg<Output = Self>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    const ZERO: Self;
    fn sqrt(self) -> Self;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    #[inline]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// The roots of `a t^2 + 2 half_b t + c = 0`, smaller first. `None` when they are not real,
/// and when `a = 0`: the equation is then at most linear, which for a quadric means a line
/// along its degenerate direction (a tube's axis), a miss.
#[inline]
pub fn quadratic_roots<T: Real>(a: T, half_b: T, c: T) -> Option<(T, T)> {
    quadratic_roots_with(a, half_b, c, half_b * half_b - a * c)
}

/// `quadratic_roots` with the discriminant `half_b^2 - a c` computed by the caller, who may
/// know a form of it that cancels less (a sphere's, Ray Tracing Gems, chapter 7).
#[inline]
pub fn quadratic_roots_with<T: Real>(a: T, half_b: T, c: T, discriminant: T) -> Option<(T, T)> {
    if a == T::ZERO || discriminant < T::ZERO {
        return None;
    }
    let root = discriminant.sqrt();
    // The sum of two terms of one sign: the root of larger magnitude, a q.
    let q = if half_b > T::ZERO { -half_b - root } else { -half_b + root };
    if q == T::ZERO {
        // half_b = 0 and a c = 0: the double root 0, not 0 / 0.
        return Some((T::ZERO, T::ZERO));
    }
    let (x, y) = (q / a, c / q);
    Some(if x < y { (x, y) } else { (y, x) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place.
    fn ulps(x: f32, exact: f64) -> f64 {
        let exact32 = exact as f32;
        ((f64::from(x) - exact) / f64::from(exact32.next_up() - exact32)).abs()
    }

    #[test]
    fn roots_of_known_polynomials_in_order() {
        // (t - 2)(t + 3) = t^2 + t - 6, and 2 (t - 0.5)(t - 4) = 2 t^2 - 9 t + 4.
        assert_eq!(quadratic_roots(1.0f32, 0.5, -6.0), Some((-3.0, 2.0)));
        assert_eq!(quadratic_roots(2.0f64, -4.5, 4.0), Some((0.5, 4.0)));
        // A negative leading coefficient: still smaller first.
        assert_eq!(quadratic_roots(-1.0f32, -0.5, 6.0), Some((-3.0, 2.0)));
        // Double roots, the one at 0 included.
        assert_eq!(quadratic_roots(1.0f64, -1.0, 1.0), Some((1.0, 1.0)));
        assert_eq!(quadratic_roots(1.0f32, 0.0, 0.0), Some((0.0, 0.0)));
        // t^2 = 4 (half_b = 0, q from the positive branch).
        assert_eq!(quadratic_roots(1.0f32, 0.0, -4.0), Some((-2.0, 2.0)));
    }

    #[test]
    fn no_real_roots_and_no_quadratic() {
        assert_eq!(quadratic_roots(1.0f32, 0.0, 1.0), None);
        assert_eq!(quadratic_roots(1.0f64, 1.0, 1.000001), None);
        // 2 t - 4 = 0 has a root, but a = 0 is documented as a miss.
        assert_eq!(quadratic_roots(0.0f32, 1.0, -4.0), None);
        assert_eq!(quadratic_roots(0.0f64, 0.0, 0.0), None);
    }

    #[test]
    fn small_root_keeps_its_precision_when_b_squared_dwarfs_4ac() {
        // t^2 + 2e4 t + 1: roots near -5e-5 and -2e4.
        let (a, half_b, c) = (1.0f32, 1.0e4f32, 1.0f32);
        let exact_small = -1.0 / (1.0e4 + (1.0e8f64 - 1.0).sqrt());
        let exact_large = -1.0e4 - (1.0e8f64 - 1.0).sqrt();
        let (large, small) = quadratic_roots(a, half_b, c).unwrap();
        assert!(ulps(small, exact_small) <= 2.0, "{small} vs {exact_small}");
        assert!(ulps(large, exact_large) <= 2.0, "{large} vs {exact_large}");
        // The textbook formula loses every digit of the small root here.
        let naive = (-half_b + (half_b * half_b - a * c).sqrt()) / a;
        assert!(ulps(naive, exact_small) > 1.0e6, "{naive}");
        // The same in f64, where it takes b^2 / 4ac = 1e24.
        let (_, small) = quadratic_roots(1.0f64, 1.0e12, 1.0).unwrap();
        assert!((small - -5.0e-13).abs() <= 2.0 * f64::EPSILON * 5.0e-13, "{small}");
    }

    #[test]
    fn the_callers_discriminant_is_used() {
        // t^2 - 4 t + 3 has the discriminant 1 and the roots 1 and 3; told 4, q is 4 instead.
        assert_eq!(quadratic_roots(1.0f32, -2.0, 3.0), Some((1.0, 3.0)));
        assert_eq!(quadratic_roots_with(1.0f32, -2.0, 3.0, 4.0), Some((0.75, 4.0)));
        assert_eq!(quadratic_roots_with(1.0f32, -2.0, 3.0, -1.0), None);
    }
}
