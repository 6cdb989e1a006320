//! Curves of POV-Ray's splines through 2D points, as the prism, the lathe and the polygon take
//! them: each segment a cubic in its parameter u in [0, 1], made from a window of the points as
//! POV-Ray 3.7 makes it, and the even-odd rule for whether a point is inside closed curves.

use glam::{DVec2, Vec2};

use super::polynomial::polynomial_roots;

/// POV-Ray's kinds of spline through a prism's (or lathe's) points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplineKind {
    Linear,
    Quadratic,
    Cubic,
    Bezier,
}

/// One segment of a curve: the point `d + c u + b u^2 + a u^3` for u in [0, 1], as
/// `[d, c, b, a]`.
pub type Segment = [Vec2; 4];

impl SplineKind {
    /// The points one segment is made from (consecutive windows of this many).
    fn window(self) -> usize {
        match self {
            SplineKind::Linear => 2,
            SplineKind::Quadratic => 3,
            SplineKind::Cubic | SplineKind::Bezier => 4,
        }
    }

    /// The segment of a window of `window()` points: a line, the quadratic or Catmull-Rom
    /// piece between the second and third point, or the Bézier curve from the fourth point
    /// (u = 0) to the first.
    fn segment(self, p: &[Vec2]) -> Segment {
        match self {
            SplineKind::Linear => [p[0], p[1] - p[0], Vec2::ZERO, Vec2::ZERO],
            SplineKind::Quadratic => {
                [p[1], 0.5 * (p[2] - p[0]), 0.5 * p[0] - p[1] + 0.5 * p[2], Vec2::ZERO]
            }
            SplineKind::Cubic => [
                p[1],
                0.5 * (p[2] - p[0]),
                p[0] - 2.5 * p[1] + 2.0 * p[2] - 0.5 * p[3],
                -0.5 * p[0] + 1.5 * p[1] - 1.5 * p[2] + 0.5 * p[3],
            ],
            SplineKind::Bezier => [
                p[3],
                3.0 * p[2] - 3.0 * p[3],
                3.0 * p[1] - 6.0 * p[2] + 3.0 * p[3],
                p[0] - 3.0 * p[1] + 3.0 * p[2] - p[3],
            ],
        }
    }
}

/// Points that make no curve of their spline, with how many there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SplineError {
    #[error("{0} points are too few for this spline")]
    TooFew(usize),
    #[error("{points} points are too few for this spline (it needs {needed})")]
    TooFewFor { points: usize, needed: usize },
    #[error("{0} points do not close the last curve (or its control points are missing)")]
    Open(usize),
}

/// A segment's point at u.
pub(super) fn point(s: &[DVec2; 4], u: f64) -> DVec2 {
    s[0] + u * (s[1] + u * (s[2] + u * s[3]))
}

/// The segments of POV-Ray's prism (and of a spline of closed curves generally) of `kind`
/// through `points`: each as POV-Ray 3.7 computes them, a sub-curve closing where a point
/// repeats the sub-curve's first (for quadratic and cubic splines the first point after the
/// leading control point); `Err` with what is wrong when the points do not close.
pub fn spline_segments(kind: SplineKind, points: &[Vec2]) -> Result<Vec<Segment>, SplineError> {
    let n = points.len();
    let (needed, first_index) = match kind {
        SplineKind::Linear => (1, 0),
        SplineKind::Quadratic => (2, 1),
        SplineKind::Cubic => (3, 1),
        SplineKind::Bezier => (3, 0),
    };
    let mut segments = Vec::new();
    let Some(&start) = points.get(first_index) else {
        return Err(SplineError::TooFew(n));
    };
    let mut first = start;
    let same = |a: Vec2, b: Vec2| (a - b).abs().max_element() < 1e-10;
    let mut i = 0;
    while i + 1 < n {
        if i + needed >= n {
            return Err(SplineError::Open(n));
        }
        let window = &points[i..i + kind.window()];
        segments.push(kind.segment(window));
        match kind {
            SplineKind::Linear => {
                if same(window[1], first) {
                    i += 1;
                    if i + 1 < n {
                        first = points[i + 1];
                    }
                }
            }
            SplineKind::Quadratic | SplineKind::Cubic => {
                if same(window[2], first) {
                    i += if kind == SplineKind::Quadratic { 2 } else { 3 };
                    if i + 2 < n {
                        first = points[i + 2];
                    }
                }
            }
            SplineKind::Bezier => i += 3,
        }
        i += 1;
    }
    Ok(segments)
}

/// The segments of POV-Ray's lathe of `kind` through `points`: one curve, not closed, through
/// every window of points in turn (Bézier: every group of four); `Err` with what is wrong when
/// the points are too few.
pub fn open_spline_segments(
    kind: SplineKind,
    points: &[Vec2],
) -> Result<Vec<Segment>, SplineError> {
    let n = points.len();
    let window = kind.window();
    if n < window {
        return Err(SplineError::TooFewFor { points: n, needed: window });
    }
    Ok(match kind {
        SplineKind::Bezier => points.chunks_exact(4).map(|p| kind.segment(p)).collect(),
        SplineKind::Linear | SplineKind::Quadratic | SplineKind::Cubic => {
            points.windows(window).map(|p| kind.segment(p)).collect()
        }
    })
}

/// Whether `p` is inside the curves of `segments` by the even-odd rule: the crossings of the
/// line from `p` along +x, each segment's end belonging to the segment it starts.
pub(super) fn inside_curves(segments: &[[DVec2; 4]], p: DVec2) -> bool {
    let mut inside = false;
    for s in segments {
        let y = [s[0].y - p.y, s[1].y, s[2].y, s[3].y];
        let degree = y.iter().rposition(|&k| k != 0.0).unwrap_or(0);
        for u in polynomial_roots(&y[..=degree], 0.0, 1.0) {
            if u < 1.0 && point(s, u).x > p.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The least and greatest points of a segment (its ends, and its turning points in x and y).
pub(super) fn segment_bounds(s: &[DVec2; 4]) -> (DVec2, DVec2) {
    let (mut min, mut max) = (point(s, 0.0).min(point(s, 1.0)), point(s, 0.0).max(point(s, 1.0)));
    for axis in [0, 1] {
        let slope = [s[1][axis], 2.0 * s[2][axis], 3.0 * s[3][axis]];
        let degree = slope.iter().rposition(|&k| k != 0.0).unwrap_or(0);
        for u in polynomial_roots(&slope[..=degree], 0.0, 1.0) {
            min = min.min(point(s, u));
            max = max.max(point(s, u));
        }
    }
    (min, max)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The corners of a square of half-side `size` about the origin, in turn.
    pub(in crate::geometry) fn square(size: f32) -> Vec<Vec2> {
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, z)| Vec2::new(x, z) * size)
            .to_vec()
    }

    #[test]
    fn splines_join_points_as_pov_ray_does() {
        // Two closed squares: four sides each, none joining them.
        let mut points = square(1.0);
        points.push(points[0]);
        let inner = square(0.5);
        points.extend(inner.iter().chain([&inner[0]]));
        let segments = spline_segments(SplineKind::Linear, &points).unwrap();
        assert_eq!(segments.len(), 8);
        assert_eq!(segments[4][0], inner[0], "the hole starts at its own first point");
        // A quadratic spline passes through the points after the control point.
        let mut quadratic = vec![Vec2::new(-1.0, 1.0)];
        quadratic.extend(square(1.0));
        quadratic.push(Vec2::new(-1.0, -1.0));
        let segments = spline_segments(SplineKind::Quadratic, &quadratic).unwrap();
        assert_eq!(segments.len(), 4);
        let end = |s: &Segment| s[0] + s[1] + s[2] + s[3];
        assert_eq!(end(&segments[0]), Vec2::new(1.0, -1.0));
        // A Bézier segment runs from its fourth point (u = 0) to its first (u = 1).
        let bezier = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        let segments = spline_segments(SplineKind::Bezier, &bezier).unwrap();
        assert_eq!((segments[0][0], end(&segments[0])), (Vec2::Y, Vec2::ZERO));
        assert!(spline_segments(SplineKind::Cubic, &square(1.0)[..2]).is_err());
    }

    #[test]
    fn a_lathe_spline_takes_every_window_of_points() {
        let points: Vec<Vec2> = (0..6).map(|i| Vec2::new(1.0 + i as f32, i as f32)).collect();
        let end = |s: &Segment| s[0] + s[1] + s[2] + s[3];
        for (kind, count) in [
            (SplineKind::Linear, 5),
            (SplineKind::Quadratic, 4),
            (SplineKind::Cubic, 3),
            (SplineKind::Bezier, 1),
        ] {
            let segments = open_spline_segments(kind, &points).unwrap();
            assert_eq!(segments.len(), count, "{kind:?}");
            if kind != SplineKind::Bezier {
                // Consecutive segments join.
                for pair in segments.windows(2) {
                    assert!((end(&pair[0]) - pair[1][0]).length() < 1e-5, "{kind:?}");
                }
            }
        }
        assert!(open_spline_segments(SplineKind::Cubic, &points[..3]).is_err());
    }

    #[test]
    fn inside_curves_by_the_even_odd_rule() {
        let square = |r: f32| {
            let p = [(-r, -r), (r, -r), (r, r), (-r, r), (-r, -r)].map(|(x, y)| Vec2::new(x, y));
            spline_segments(SplineKind::Linear, &p).unwrap()
        };
        let segments: Vec<[DVec2; 4]> =
            square(1.0).iter().chain(&square(0.5)).map(|s| s.map(|v| v.as_dvec2())).collect();
        assert!(inside_curves(&segments, DVec2::new(0.75, 0.1)));
        assert!(!inside_curves(&segments, DVec2::new(0.0, 0.1)), "the hole");
        assert!(!inside_curves(&segments, DVec2::new(1.5, 0.1)));
        let (min, max) = segment_bounds(&segments[0]);
        assert_eq!((min, max), (DVec2::new(-1.0, -1.0), DVec2::new(1.0, -1.0)));
    }
}
