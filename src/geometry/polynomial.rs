//! The real roots of a polynomial in one variable on an interval, found robustly: each root is
//! isolated between consecutive roots of the derivative (found the same way, recursively),
//! where the polynomial is monotonic, and refined by bisection-safeguarded Newton steps in f64.
//! The torus' quartic and the algebraic surfaces' polynomials (POV-Ray's `sturm` asks for no
//! more) are solved here.

use arrayvec::ArrayVec;

/// The highest degree solved (POV-Ray's `poly` goes up to order 35).
pub const MAX_DEGREE: usize = 35;

/// The roots of one polynomial, in order.
pub type Roots = ArrayVec<f64, MAX_DEGREE>;

/// `c[0] + c[1] x + c[2] x^2 + ...` at `x`.
fn evaluate(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
}

/// The real roots of the polynomial `c` (lowest degree first, degree at most `MAX_DEGREE`, the
/// leading coefficient not 0) in [lo, hi], in order. Between consecutive roots of the
/// derivative the polynomial is monotonic, so each such interval holds at most one root. A
/// root of even multiplicity (a grazing ray) is kept, twice, when the polynomial reaches zero
/// at the derivative's root to within rounding.
pub fn polynomial_roots(c: &[f64], lo: f64, hi: f64) -> Roots {
    let mut roots = Roots::new();
    let degree = c.len().saturating_sub(1).min(MAX_DEGREE);
    let c = &c[..=degree];
    match degree {
        0 => return roots,
        1 => {
            if c[1] != 0.0 {
                let x = -c[0] / c[1];
                if (lo..=hi).contains(&x) {
                    roots.push(x);
                }
            }
            return roots;
        }
        _ => {}
    }
    let derivative: ArrayVec<f64, MAX_DEGREE> = (1..=degree).map(|i| c[i] * i as f64).collect();
    let mut ends = ArrayVec::<f64, { MAX_DEGREE + 1 }>::new();
    ends.push(lo);
    ends.extend(polynomial_roots(&derivative, lo, hi).into_iter().take(MAX_DEGREE - 1));
    ends.push(hi);
    // The size of the terms, for what counts as zero at a touching extremum.
    let scale = |x: f64| c.iter().rev().fold(0.0, |acc, &k| acc * x.abs() + k.abs());
    // An extremum that reaches zero within rounding is a touching root (a grazing ray): in and
    // out at once, so it counts twice and the monotonic pieces beside it hold no other root.
    let last = ends.len() - 1;
    let touching: ArrayVec<bool, { MAX_DEGREE + 1 }> = (0..ends.len())
        .map(|i| i > 0 && i < last && evaluate(c, ends[i]).abs() <= 1e-12 * scale(ends[i]))
        .collect();
    for i in 0..last {
        let (a, b) = (ends[i], ends[i + 1]);
        if !touching[i] && !touching[i + 1] {
            let (fa, fb) = (evaluate(c, a), evaluate(c, b));
            if fa == 0.0 {
                push_distinct(&mut roots, a);
            } else if fa.signum() != fb.signum() && fb != 0.0 {
                push_distinct(&mut roots, refine(c, &derivative, a, b, fa));
            }
        }
        if touching[i + 1] && roots.len() + 2 <= roots.capacity() {
            roots.push(b);
            roots.push(b);
        }
    }
    roots
}

fn push_distinct(roots: &mut Roots, x: f64) {
    if roots.last() != Some(&x) && !roots.is_full() {
        roots.push(x);
    }
}

/// The root in [a, b], where the polynomial changes sign (`fa` at a) and is monotonic.
fn refine(c: &[f64], derivative: &[f64], mut a: f64, mut b: f64, fa: f64) -> f64 {
    let mut x = 0.5 * (a + b);
    for _ in 0..200 {
        let fx = evaluate(c, x);
        if fx == 0.0 {
            return x;
        }
        if fx.signum() == fa.signum() {
            a = x;
        } else {
            b = x;
        }
        let slope = evaluate(derivative, x);
        let newton = x - fx / slope;
        let next = if newton > a && newton < b { newton } else { 0.5 * (a + b) };
        if (next - x).abs() <= 1e-15 * (1.0 + x.abs()) || b - a <= 1e-15 * (1.0 + x.abs()) {
            return next;
        }
        x = next;
    }
    x
}

/// A bound on the magnitude of every root (Cauchy's): 1 + max |c_i / c_n|.
pub fn root_bound(c: &[f64]) -> f64 {
    let (leading, rest) = c.split_last().expect("a polynomial has a coefficient");
    1.0 + rest.iter().fold(0.0f64, |m, k| m.max((k / leading).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomial_roots_of_known_factors() {
        // (x - 1)(x - 2)(x + 3)(x - 0.5) = x^4 - 0.5 x^3 - 7 x^2 + 9.5 x - 3
        let c = [-3.0, 9.5, -7.0, -0.5, 1.0];
        let roots = polynomial_roots(&c, -10.0, 10.0);
        let expected = [-3.0, 0.5, 1.0, 2.0];
        assert_eq!(roots.len(), 4, "{roots:?}");
        for (r, e) in roots.iter().zip(expected) {
            assert!((r - e).abs() < 1e-12, "{roots:?}");
        }
        // A double root (x - 1)^2 (x^2 + 1): touching, counted twice.
        let c = [1.0, -2.0, 2.0, -2.0, 1.0];
        let roots = polynomial_roots(&c, -10.0, 10.0);
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!(roots.iter().all(|r| (r - 1.0).abs() < 1e-6));
        assert!(polynomial_roots(&[1.0, 0.0, 1.0, 0.0, 1.0], -10.0, 10.0).is_empty());
    }

    #[test]
    fn roots_of_a_high_degree_product() {
        // prod (x - k/2) for k = -4..=4: degree 9, roots spaced 0.5 apart.
        let mut c = vec![1.0];
        for k in -4..=4 {
            let r = f64::from(k) / 2.0;
            let mut next = vec![0.0; c.len() + 1];
            for (i, &a) in c.iter().enumerate() {
                next[i + 1] += a;
                next[i] -= r * a;
            }
            c = next;
        }
        let roots = polynomial_roots(&c, -100.0, 100.0);
        assert_eq!(roots.len(), 9, "{roots:?}");
        for (i, r) in roots.iter().enumerate() {
            assert!((r - (i as f64 - 4.0) / 2.0).abs() < 1e-9, "{roots:?}");
        }
        assert!(root_bound(&c) >= 2.0, "every root within the bound");
        // The interval is respected.
        let within = polynomial_roots(&c, 0.25, 1.25);
        assert_eq!(within.len(), 2, "{within:?}");
        assert!((within[0] - 0.5).abs() < 1e-9 && (within[1] - 1.0).abs() < 1e-9, "{within:?}");
    }
}
