//! Warps from the unit square (pbrt-v4, section A.5).

use std::f32::consts::{FRAC_PI_4, PI};

use glam::{Vec2, Vec3};

use crate::lanes::{Real, Vector};

/// Shirley–Chiu concentric map onto the unit disk (area-preserving up to a constant).
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let (x, y) = concentric_disk_of(u.x, u.y);
    Vec2::new(x, y)
}

/// `concentric_disk` written once over `Real`: for one point or a point per lane.
#[inline(always)]
pub fn concentric_disk_of<F: Real>(ux: F, uy: F) -> (F, F) {
    let (ox, oy) = (F::splat(2.0) * ux - F::ONE, F::splat(2.0) * uy - F::ONE);
    // The angle from the axis of the larger coordinate is within pi/4 of it, where a short
    // polynomial gives sin and cos at a fraction of the cost of general ones; at pi/2 - phi
    // (y the larger) cos and sin trade places.
    let x_larger = ox.abs().gt(oy.abs());
    let (larger, smaller) = (F::select(x_larger, ox, oy), F::select(x_larger, oy, ox));
    let (sin, cos) = sin_cos_within_quarter(F::splat(FRAC_PI_4) * (smaller / larger));
    let (x, y) = (larger * F::select(x_larger, cos, sin), larger * F::select(x_larger, sin, cos));
    let centre = ox.eq(F::ZERO) & oy.eq(F::ZERO);
    (F::select(centre, F::ZERO, x), F::select(centre, F::ZERO, y))
}

/// sin and cos of `x` in [-pi/4, pi/4], to within a few ulps: the minimax polynomials of
/// Cephes' `sinf` and `cosf` (Moshier 1989).
#[inline(always)]
fn sin_cos_within_quarter<F: Real>(x: F) -> (F, F) {
    let c = F::splat;
    let z = x * x;
    let sin = x + x * z * (c(-1.666_665_5e-1) + z * (c(8.332_161e-3) + z * c(-1.951_529_6e-4)));
    let cos = F::ONE - c(0.5) * z
        + z * z * (c(4.166_664_6e-2) + z * (c(-1.388_731_6e-3) + z * c(2.443_315_7e-5)));
    (sin, cos)
}

/// Uniform on the unit sphere; pdf 1 / (4 pi).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Cosine-weighted on the hemisphere around +z (Malley's method); pdf cos(theta) / pi.
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    cosine_hemisphere_of(u.x, u.y).into()
}

/// `cosine_hemisphere` written once over `Real`: for one point or a point per lane.
#[inline(always)]
pub fn cosine_hemisphere_of<F: Real>(ux: F, uy: F) -> Vector<F> {
    let (x, y) = concentric_disk_of(ux, uy);
    let z_squared = F::ONE - (x * x + y * y);
    Vector { x, y, z: F::select(z_squared.gt(F::ZERO), z_squared, F::ZERO).sqrt() }
}

/// Barycentric coordinates (b1, b2) uniform over a triangle: the point is
/// `a + b1 (b - a) + b2 (c - a)` (the square-root warp).
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let (s, t) = uniform_triangle_of(u.x, u.y);
    Vec2::new(s, t)
}

/// `uniform_triangle` written once over `Real`: for one point or a point per lane.
#[inline(always)]
pub fn uniform_triangle_of<F: Real>(ux: F, uy: F) -> (F, F) {
    let su = ux.sqrt();
    (F::ONE - su, uy * su)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::{Floats, LANES, Lane, Wide};

    /// Midpoint-rule grid over the unit square.
    fn grid(n: usize) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |i| Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32)
    }

    #[test]
    fn concentric_disk_stays_inside_and_keeps_area() {
        // Equal areas of the square map to equal areas of the disk: the fraction of points in
        // the inner disk of radius 1/sqrt(2) is one half.
        let points: Vec<Vec2> = grid(200).map(concentric_disk).collect();
        assert!(points.iter().all(|p| p.length() <= 1.0 + 1e-6));
        let inner = points.iter().filter(|p| p.length_squared() < 0.5).count();
        assert!((inner as f32 / points.len() as f32 - 0.5).abs() < 0.005);
    }

    /// The lanes' instance of the cosine-weighted warp (the concentric map's branches taken by
    /// selects) gives each lane what one point gives, bit for bit: at the centre, on the
    /// diagonals where neither coordinate is the larger, on the edges, and between.
    #[test]
    fn cosine_hemisphere_in_lanes_is_each_point_s() {
        let mut u: Vec<Vec2> = grid(37).collect();
        u.extend([0.0, 0.25, 0.5, 0.75, 1.0 - f32::EPSILON / 2.0].iter().flat_map(|&x| {
            [Vec2::new(x, x), Vec2::new(x, 1.0 - x), Vec2::new(x, 0.0), Vec2::new(0.5, x)]
        }));
        for chunk in u.chunks(LANES) {
            let at = |lane: usize| chunk[lane.min(chunk.len() - 1)];
            let lanes = cosine_hemisphere_of(
                Floats::from_fn(|lane| at(lane).x),
                Floats::from_fn(|lane| at(lane).y),
            );
            for lane in 0..chunk.len() {
                let one = cosine_hemisphere(at(lane));
                assert_eq!(
                    lanes.lane(lane).to_array().map(f32::to_bits),
                    one.to_array().map(f32::to_bits),
                    "{}",
                    at(lane)
                );
            }
        }
    }

    #[test]
    fn sin_cos_within_a_quarter_agree_with_the_library() {
        for i in 0..=10_000 {
            let x = FRAC_PI_4 * (i as f32 / 5000.0 - 1.0);
            let (sin, cos) = sin_cos_within_quarter(x);
            assert!((sin - x.sin()).abs() < 2e-7 && (cos - x.cos()).abs() < 2e-7, "at {x}");
        }
    }

    #[test]
    fn uniform_sphere_directions_are_unit_and_balanced() {
        let dirs: Vec<Vec3> = grid(100).map(uniform_sphere).collect();
        assert!(dirs.iter().all(|d| (d.length() - 1.0).abs() < 1e-5));
        let mean = dirs.iter().sum::<Vec3>() / dirs.len() as f32;
        assert!(mean.length() < 1e-3, "mean {mean}");
    }

    #[test]
    fn cosine_hemisphere_has_mean_cosine_two_thirds() {
        // E[cos] under pdf cos/pi is (1/pi) * integral of cos^2 over the hemisphere = 2/3.
        let dirs: Vec<Vec3> = grid(200).map(cosine_hemisphere).collect();
        assert!(dirs.iter().all(|d| d.z >= 0.0 && (d.length() - 1.0).abs() < 1e-5));
        let mean_cos = dirs.iter().map(|d| d.z).sum::<f32>() / dirs.len() as f32;
        assert!((mean_cos - 2.0 / 3.0).abs() < 1e-3, "{mean_cos}");
    }

    #[test]
    fn uniform_triangle_has_centroid_one_third() {
        let bs: Vec<Vec2> = grid(200).map(uniform_triangle).collect();
        assert!(bs.iter().all(|b| b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6));
        let mean = bs.iter().sum::<Vec2>() / bs.len() as f32;
        assert!((mean - Vec2::splat(1.0 / 3.0)).length() < 1e-3, "{mean}");
    }
}
