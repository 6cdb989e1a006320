//! POV-Ray's fractal patterns (`mandel`, `julia`, `magnet 1|2 mandel|julia`) in the x-y plane:
//! the orbit of each point under the set's map, valued by the `exterior` colouring where it
//! escapes and the `interior` one where it stays for all `iterations` (`docs/povray.md`).

use glam::{DVec2, Vec2};

use crate::graph::{Fractal, FractalColouring, FractalSet};

/// Where an orbit is deemed escaped: |z|² past 4 (z^n + c); past 10⁴, or settled within 10⁻²
/// of 1 (the magnets, whose orbits also settle on 1).
const ESCAPE: f64 = 4.0;
const MAGNET_ESCAPE: f64 = 1e4;
const MAGNET_SETTLED: f64 = 1e-4;

/// The pattern's raw value at (x, y) (before the wave, which wraps it into [0, 1]).
pub fn fractal(f: &Fractal, p: Vec2) -> f32 {
    let p = p.as_dvec2();
    let (mut z, c, mut nearest) = match f.set {
        FractalSet::Mandel => (p, p, p.length_squared()),
        FractalSet::Julia(c) => (p, c.as_dvec2(), p.length_squared()),
        FractalSet::Magnet { julia: None, .. } => (DVec2::ZERO, p, MAGNET_ESCAPE),
        FractalSet::Magnet { julia: Some(c), .. } => (p, c.as_dvec2(), p.length_squared()),
    };
    for i in 0..f.iterations {
        z = match f.set {
            FractalSet::Mandel | FractalSet::Julia(_) => power(z, f.exponent) + c,
            FractalSet::Magnet { formula, .. } => magnet(z, c, formula),
        };
        let d2 = z.length_squared();
        nearest = nearest.min(d2);
        let escaped = match f.set {
            FractalSet::Mandel | FractalSet::Julia(_) => d2 > ESCAPE,
            FractalSet::Magnet { .. } => {
                d2 > MAGNET_ESCAPE || (z - DVec2::X).length_squared() < MAGNET_SETTLED
            }
        };
        if escaped {
            return colour(f.exterior, z, i as f64 / f.iterations as f64, None);
        }
    }
    colour(f.interior, z, 1.0, Some(nearest))
}

/// A colouring's value of the last z = a + bi; `share` the iterations' share (exterior type
/// 1), `nearest` the orbit's least |z|² (interior type 1).
fn colour(colouring: FractalColouring, z: DVec2, share: f64, nearest: Option<f64>) -> f32 {
    let factor = f64::from(colouring.factor);
    let value = match (colouring.kind, nearest) {
        (0, _) => factor,
        (1, None) => share,
        (1, Some(nearest)) => nearest.sqrt() * factor,
        (2, _) => z.x * factor,
        (3, _) => z.y * factor,
        (4, _) => z.x * z.x * factor,
        (5, _) => z.y * z.y * factor,
        (_, None) => z.length() * factor,
        (_, Some(_)) => z.length_squared() * factor,
    };
    value as f32
}

/// z^n for n in 2..=4.
fn power(z: DVec2, n: u32) -> DVec2 {
    let square = multiply(z, z);
    match n {
        2 => square,
        3 => multiply(square, z),
        _ => multiply(square, square),
    }
}

fn multiply(a: DVec2, b: DVec2) -> DVec2 {
    DVec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x)
}

fn divide(a: DVec2, b: DVec2) -> DVec2 {
    multiply(a, DVec2::new(b.x, -b.y)) / b.length_squared()
}

/// The magnet maps: formula 1 ((z² + c - 1) / (2z + c - 2))², formula 2
/// ((z³ + 3(c - 1)z + (c - 1)(c - 2)) / (3z² + 3(c - 2)z + (c - 1)(c - 2) + 1))².
fn magnet(z: DVec2, c: DVec2, formula: u32) -> DVec2 {
    let one = DVec2::X;
    let ratio = if formula == 1 {
        divide(multiply(z, z) + c - one, 2.0 * z + c - 2.0 * one)
    } else {
        let (c1, c2) = (c - one, c - 2.0 * one);
        let c1c2 = multiply(c1, c2);
        let top = power(z, 3) + 3.0 * multiply(c1, z) + c1c2;
        let bottom = 3.0 * multiply(z, z) + 3.0 * multiply(c2, z) + c1c2 + one;
        divide(top, bottom)
    };
    multiply(ratio, ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(set: FractalSet, interior: (u32, f32), exterior: (u32, f32)) -> Fractal {
        Fractal {
            set,
            exponent: 2,
            iterations: 50,
            interior: FractalColouring { kind: interior.0, factor: interior.1 },
            exterior: FractalColouring { kind: exterior.0, factor: exterior.1 },
        }
    }

    /// The colourings by their definitions: the origin stays in the Mandelbrot set, a far
    /// point escapes on the first step.
    #[test]
    fn the_colourings_value_the_orbit_as_defined() {
        let plain = set(FractalSet::Mandel, (0, 1.0), (1, 1.0));
        assert_eq!(fractal(&plain, Vec2::ZERO), 1.0);
        assert_eq!(fractal(&plain, Vec2::new(3.0, 3.0)), 0.0);
        // Interior type 1: the nearest approach; c = -1 cycles -1, 0, -1, ...: √0 × 200.
        let nearest = set(FractalSet::Mandel, (1, 200.0), (1, 1.0));
        assert_eq!(fractal(&nearest, Vec2::new(-1.0, 0.0)), 0.0);
        // c = -0.1: the orbit -0.1, -0.09, -0.0919, ... closes on (1 - √1.4) / 2 ≈ -0.0916
        // from both sides; its nearest approach is the second point, 0.09.
        assert!((fractal(&nearest, Vec2::new(-0.1, 0.0)) - 0.09 * 200.0).abs() < 1e-3);
        // Exterior type 0: the factor; type 2: the real part of the escaped z (c = 3: z = 3,
        // then 12, which escapes).
        let constant = set(FractalSet::Mandel, (0, 1.0), (0, 0.25));
        assert_eq!(fractal(&constant, Vec2::new(3.0, 0.0)), 0.25);
        let real = set(FractalSet::Mandel, (0, 1.0), (2, 0.5));
        assert_eq!(fractal(&real, Vec2::new(3.0, 0.0)), 6.0);
        // Julia at c = 0: |z| < 1 stays (z^(2^k) → 0), |z| > 2 escapes.
        let julia = set(FractalSet::Julia(Vec2::ZERO), (0, 1.0), (1, 1.0));
        assert_eq!(fractal(&julia, Vec2::new(0.5, 0.5)), 1.0);
        assert_eq!(fractal(&julia, Vec2::new(2.5, 0.0)), 0.0);
        // At c = 0.9i the squared map escapes (on its 8th step), the cubic one cycles between
        // about 0.17i and 0.89i (y -> 0.9 - y³).
        let cubic = Fractal { exponent: 3, ..plain };
        assert_eq!(fractal(&cubic, Vec2::new(0.0, 0.9)), 1.0);
        assert!(fractal(&plain, Vec2::new(0.0, 0.9)) < 1.0);
    }

    /// The magnet maps by their formulas, their fixed point 1, and the colourings of an
    /// orbit that settles and of one that stays.
    #[test]
    fn the_magnet_maps_follow_their_formulas() {
        let c = DVec2::new(0.3, 0.2);
        let z = DVec2::new(0.5, -0.1);
        let one = DVec2::X;
        let by_hand = {
            let r = divide(multiply(z, z) + c - one, 2.0 * z + c - 2.0 * one);
            multiply(r, r)
        };
        assert!((magnet(z, c, 1) - by_hand).length() < 1e-12);
        // z = 1 is a fixed point of both: formula 2's top and bottom are both c² there.
        assert!((magnet(one, c, 1) - one).length() < 1e-12);
        assert!((magnet(one, c, 2) - one).length() < 1e-12);
        // Mandelbrot-like from z = 0: at c = 300 the first step lands within 10⁻² of 1
        // ((299/298)²): settled, exterior type 1 gives 0; at c = 3 the orbit 0, 4, 4, ...
        // stays (|z - 1|² = 9, |z|² = 16): interior type 0 gives its factor.
        let m1 = set(FractalSet::Magnet { formula: 1, julia: None }, (0, 0.75), (1, 1.0));
        assert_eq!(fractal(&m1, Vec2::new(300.0, 0.0)), 0.0);
        assert_eq!(fractal(&m1, Vec2::new(3.0, 0.0)), 0.75);
    }
}
