//! POV-Ray's `sphere_sweep`: the union of the spheres whose centre and radius follow a spline.
//! Between two spheres whose centre and radius change linearly the swept solid is exactly their
//! convex hull: the two spheres and the cone frustum tangent to both. A linear spline is made of
//! such pieces; a cubic or B-spline segment is cut into `PIECES` of them, so its centre line is
//! replaced by chords (radii are exact at the chords' ends).

use glam::DVec3;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ObjectNode, ShapeNode};
use crate::lang::syntax::{Expr, SweepSpline};

/// Chords a cubic or B-spline segment is cut into.
pub const PIECES: usize = 32;

/// A sphere of the sweep: its centre and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    pub centre: DVec3,
    pub radius: f64,
}

impl Evaluator {
    pub(super) fn sphere_sweep(
        &mut self,
        spline: SweepSpline,
        count: &Expr,
        points: &[Expr],
        tolerance: Option<&Expr>,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let n = self.number(count, "the sphere_sweep's number of spheres")?;
        let least = match spline {
            SweepSpline::Linear => 2.0,
            SweepSpline::Cubic | SweepSpline::BSpline => 4.0,
        };
        if n.fract() != 0.0 || n < least {
            return Err(SceneError::at(
                &count.span,
                format!(
                    "this sphere_sweep needs a whole number of spheres, at least {least}, not {n}"
                ),
            ));
        }
        if points.len() != 2 * n as usize {
            return Err(SceneError::at(
                span,
                format!(
                    "the sphere_sweep says {n} spheres but gives {} numbers and vectors (a centre \
                     and a radius for each)",
                    points.len()
                ),
            ));
        }
        // The tolerance is POV-Ray's root finder's: every crossing here is found exactly.
        if let Some(tolerance) = tolerance {
            self.positive(tolerance, "the sphere_sweep's tolerance")?;
        }
        let mut balls = Vec::with_capacity(n as usize);
        for pair in points.chunks_exact(2) {
            let centre = self.vector(&pair[0])?;
            let radius = self.number(&pair[1], "a sphere_sweep's radius")?;
            if radius.is_nan() || radius < 0.0 {
                return Err(SceneError::at(
                    &pair[1].span,
                    format!("a sphere_sweep's radius is 0 or more, not {radius}"),
                ));
            }
            balls.push(Ball { centre, radius });
        }
        let path = sweep_path(spline, &balls);
        let mut children = Vec::new();
        let node = |shape| ObjectNode {
            shape,
            material: None,
            transforms: Vec::new(),
            depth: 1,
            span: span.clone(),
        };
        for ball in path.iter().filter(|b| b.radius > 0.0) {
            children.push(node(ShapeNode::Sphere {
                center: ball.centre.as_vec3(),
                radius: ball.radius as f32,
            }));
        }
        for pair in path.windows(2) {
            if let Some(cone) = tangent_cone(pair[0], pair[1]) {
                children.push(node(cone));
            }
        }
        if children.is_empty() {
            return Err(SceneError::at(span, "every sphere of this sphere_sweep has radius 0"));
        }
        self.objects_made += children.len() as u64;
        Ok(ShapeNode::Union(children))
    }
}

/// The spheres at the ends of the chords that stand for the spline: the points themselves for a
/// linear spline; for the cubic ones, `PIECES` chords per segment of four points.
pub fn sweep_path(spline: SweepSpline, balls: &[Ball]) -> Vec<Ball> {
    // The segment's blend of its four points at t (Catmull–Rom; the uniform B-spline).
    let weights = |t: f64| -> [f64; 4] {
        let (t2, t3) = (t * t, t * t * t);
        match spline {
            SweepSpline::Cubic => [
                0.5 * (-t + 2.0 * t2 - t3),
                0.5 * (2.0 - 5.0 * t2 + 3.0 * t3),
                0.5 * (t + 4.0 * t2 - 3.0 * t3),
                0.5 * (-t2 + t3),
            ],
            SweepSpline::BSpline | SweepSpline::Linear => [
                (1.0 - t).powi(3) / 6.0,
                (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
                (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
                t3 / 6.0,
            ],
        }
    };
    if spline == SweepSpline::Linear {
        return balls.to_vec();
    }
    let mut path = Vec::new();
    for four in balls.windows(4) {
        let first = if path.is_empty() { 0 } else { 1 };
        for k in first..=PIECES {
            let w = weights(k as f64 / PIECES as f64);
            let centre = (0..4).map(|i| w[i] * four[i].centre).sum();
            let radius = (0..4).map(|i| w[i] * four[i].radius).sum::<f64>().max(0.0);
            path.push(Ball { centre, radius });
        }
    }
    path
}

/// The cone frustum tangent to two spheres, which with them bounds their convex hull; `None`
/// where one sphere holds the other (the hull is the larger sphere). With sin a = (r1 − r2) / d
/// for centres d apart, it touches sphere i along the circle of radius r_i cos a about
/// c_i + r_i sin a û (û from the first centre to the second).
fn tangent_cone(a: Ball, b: Ball) -> Option<ShapeNode> {
    let axis = b.centre - a.centre;
    let d = axis.length();
    if d <= (a.radius - b.radius).abs() || d == 0.0 {
        return None;
    }
    let u = axis / d;
    let sin = (a.radius - b.radius) / d;
    let cos = (1.0 - sin * sin).sqrt();
    let end = |ball: Ball| (ball.centre + ball.radius * sin * u, ball.radius * cos);
    let ((base, base_radius), (cap, cap_radius)) = (end(a), end(b));
    (base_radius > 0.0 || cap_radius > 0.0).then(|| ShapeNode::Cone {
        base: base.as_vec3(),
        base_radius: base_radius as f32,
        cap: cap.as_vec3(),
        cap_radius: cap_radius as f32,
        open: false,
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn ball(x: f64, y: f64, radius: f64) -> Ball {
        Ball { centre: DVec3::new(x, y, 0.0), radius }
    }

    #[test]
    fn the_tangent_cone_touches_both_spheres() {
        let (a, b) = (ball(0.0, 0.0, 1.0), ball(3.0, 0.0, 0.4));
        let Some(ShapeNode::Cone { base, base_radius, cap, cap_radius, .. }) = tangent_cone(a, b)
        else {
            panic!("a cone")
        };
        // The cone's side through its two rims: each rim point is on its sphere, and the side's
        // line there is perpendicular to the sphere's radius (tangent).
        let rim = |centre: Vec3, r: f32| centre + Vec3::new(0.0, r, 0.0);
        let (p, q) = (rim(base, base_radius), rim(cap, cap_radius));
        for (point, sphere) in [(p, a), (q, b)] {
            let radius = point - sphere.centre.as_vec3();
            assert!((radius.length() - sphere.radius as f32).abs() < 1e-5, "{point} {sphere:?}");
            assert!(radius.normalize().dot((q - p).normalize()).abs() < 1e-5);
        }
        assert!(tangent_cone(a, ball(0.3, 0.0, 0.5)).is_none(), "a sphere inside the other");
    }

    #[test]
    fn a_catmull_rom_path_passes_through_its_inner_points_and_a_b_spline_near_them() {
        let points = [
            ball(0.0, 0.0, 0.1),
            ball(1.0, 1.0, 0.2),
            ball(2.0, 0.0, 0.3),
            ball(3.0, 1.0, 0.4),
            ball(4.0, 0.0, 0.5),
        ];
        let cubic = sweep_path(SweepSpline::Cubic, &points);
        assert_eq!(cubic.len(), 2 * PIECES + 1);
        for (k, inner) in [(0, points[1]), (PIECES, points[2]), (2 * PIECES, points[3])] {
            assert!((cubic[k].centre - inner.centre).length() < 1e-12);
            assert!((cubic[k].radius - inner.radius).abs() < 1e-12);
        }
        // The uniform B-spline starts at (P0 + 4 P1 + P2) / 6.
        let b = sweep_path(SweepSpline::BSpline, &points);
        let start = (points[0].centre + 4.0 * points[1].centre + points[2].centre) / 6.0;
        assert!((b[0].centre - start).length() < 1e-12, "{:?}", b[0]);
        assert_eq!(sweep_path(SweepSpline::Linear, &points), points.to_vec());
    }
}
