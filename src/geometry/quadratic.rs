//! The real roots of a quadratic, without cancellation: of the two roots, the textbook formula
//! takes one as the difference of nearly equal numbers when b^2 >> 4ac; here it comes from
//! the other by Vieta's c / q instead (Numerical Recipes, section 5.6). Written once, for the
//! f32 of most shapes, the f64 of the cone and the lanes of spheres tested together.

use crate::lanes::Real;

/// The roots of `a t^2 + 2 half_b t + c = 0`, smaller first. `None` when they are not real,
/// and when `a = 0`: the equation is then at most linear, which for a quadric means a line
/// along its degenerate direction (a tube's axis), a miss.
#[inline]
pub fn quadratic_roots<T: Real<Mask = bool>>(a: T, half_b: T, c: T) -> Option<(T, T)> {
    quadratic_roots_with(a, half_b, c, half_b * half_b - a * c)
}

/// `quadratic_roots` with the discriminant `half_b^2 - a c` computed by the caller, who may
/// know a form of it that cancels less (a sphere's, Ray Tracing Gems, chapter 7).
#[inline]
pub fn quadratic_roots_with<T: Real<Mask = bool>>(
    a: T,
    half_b: T,
    c: T,
    discriminant: T,
) -> Option<(T, T)> {
    let (real, smaller, larger) = quadratic_roots_in_lanes(a, half_b, c, discriminant);
    real.then_some((smaller, larger))
}

/// `quadratic_roots_with` in lanes: per lane, whether the roots are real, and the roots
/// (smaller first) where they are.
#[inline]
pub fn quadratic_roots_in_lanes<T: Real>(
    a: T,
    half_b: T,
    c: T,
    discriminant: T,
) -> (T::Mask, T, T) {
    let real = a.ne(T::ZERO) & discriminant.ge(T::ZERO);
    let root = discriminant.sqrt();
    // The sum of two terms of one sign: the root of larger magnitude, a q.
    let q = T::select(half_b.gt(T::ZERO), -half_b - root, -half_b + root);
    // q = 0 where half_b = 0 and a c = 0: the double root 0, not 0 / 0.
    let double_zero = q.eq(T::ZERO);
    let (x, y) = (T::select(double_zero, T::ZERO, q / a), T::select(double_zero, T::ZERO, c / q));
    let in_order = x.lt(y);
    (real, T::select(in_order, x, y), T::select(in_order, y, x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

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

    #[test]
    fn lanes_solve_each_their_own_quadratic() {
        // Two real roots, none, a = 0, the double root 0 (q = 0): one case per lane.
        let (a, half_b, c) =
            ([1.0f32, 1.0, 0.0, 1.0], [0.5, 0.0, 1.0, 0.0], [-6.0, 1.0, -4.0, 0.0]);
        let lanes = quadratic_roots_in_lanes(
            Vec4::from_array(a),
            Vec4::from_array(half_b),
            Vec4::from_array(c),
            Vec4::from_array(std::array::from_fn(|i| half_b[i] * half_b[i] - a[i] * c[i])),
        );
        let (real, smaller, larger) = lanes;
        for lane in 0..4 {
            let alone = quadratic_roots(a[lane], half_b[lane], c[lane]);
            assert_eq!(real.test(lane), alone.is_some(), "lane {lane}");
            if let Some(roots) = alone {
                assert_eq!((smaller[lane], larger[lane]), roots, "lane {lane}");
            }
        }
        assert_eq!(quadratic_roots(1.0f32, 0.5, -6.0), Some((-3.0, 2.0)));
    }
}
