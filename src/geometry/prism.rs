//! POV-Ray's prism: closed curves in the x-z plane swept along y between two heights, either
//! straight up (`linear_sweep`) or from the origin outwards (`conic_sweep`, the curves scaled
//! by the height), solid where a point's section is inside the curves by the even-odd rule.
//! Each curve is made of segments, each a cubic in its parameter u in [0, 1] (a line, or a
//! piece of POV-Ray's quadratic, cubic or Bézier spline); a ray meets the side a segment sweeps
//! where a cubic in u is zero, solved by `polynomial`, and the end caps where the section of
//! its crossing point is inside.

use glam::{Affine3A, DVec2, DVec3, Vec2, Vec3};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};

/// How the section is swept along y.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    Linear,
    Conic,
}

/// One segment of a curve: the point `d + c u + b u^2 + a u^3` (x, z) for u in [0, 1], as
/// `[d, c, b, a]`.
pub type Segment = [Vec2; 4];

/// Which surface an intersection is on, in `Intersection::triangle`: a segment's side by its
/// index, or a cap; the top bit says whether the ray goes into the solid there.
const BOTTOM: u32 = u32::MAX >> 1;
const TOP: u32 = BOTTOM - 1;
const ENTERING: u32 = 1 << 31;

#[derive(Debug, Clone)]
pub struct Prism {
    frame: QuadricFrame,
    segments: Vec<[DVec2; 4]>,
    sweep: Sweep,
    /// The heights, lower first.
    heights: [f64; 2],
    /// Without caps: the side alone, not a solid.
    open: bool,
    bounds: Aabb,
}

impl Prism {
    /// The prism of `segments` swept between `heights` (distinct; for a conic sweep not below
    /// 0), placed in the world by `to_world`.
    pub fn new(
        segments: &[Segment],
        sweep: Sweep,
        heights: [f32; 2],
        open: bool,
        to_world: Affine3A,
    ) -> Self {
        let segments: Vec<[DVec2; 4]> = segments.iter().map(|s| s.map(|v| v.as_dvec2())).collect();
        let (lo, hi) = (heights[0].min(heights[1]), heights[0].max(heights[1]));
        // The section's bounds: each segment's ends and its extremes in x and z.
        let mut min = DVec2::splat(f64::INFINITY);
        let mut max = -min;
        for s in &segments {
            let mut extend = |u: f64| {
                let p = point(s, u);
                min = min.min(p);
                max = max.max(p);
            };
            extend(0.0);
            extend(1.0);
            for axis in [0, 1] {
                let slope = [s[1][axis], 2.0 * s[2][axis], 3.0 * s[3][axis]];
                let degree = slope.iter().rposition(|&k| k != 0.0).unwrap_or(0);
                for u in polynomial_roots(&slope[..=degree], 0.0, 1.0) {
                    extend(u);
                }
            }
        }
        let scales = match sweep {
            Sweep::Linear => [1.0, 1.0],
            Sweep::Conic => [f64::from(lo), f64::from(hi)],
        };
        let mut corners = Vec::with_capacity(8);
        for (y, scale) in [(lo, scales[0]), (hi, scales[1])] {
            for x in [min.x, max.x] {
                for z in [min.y, max.y] {
                    let p = Vec3::new((x * scale) as f32, y, (z * scale) as f32);
                    corners.push(to_world.transform_point3(p));
                }
            }
        }
        let bounds = Aabb::from_points(&corners);
        let mut frame = QuadricFrame::new(to_world, None);
        frame.magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        Prism { frame, segments, sweep, heights: [f64::from(lo), f64::from(hi)], open, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether the section's point (x, z) is inside the curves: the crossings of the ray from
    /// it along +x, counted by the even-odd rule.
    fn inside_section(&self, p: DVec2) -> bool {
        let mut inside = false;
        for s in &self.segments {
            let z = [s[0].y - p.y, s[1].y, s[2].y, s[3].y];
            let degree = z.iter().rposition(|&k| k != 0.0).unwrap_or(0);
            for u in polynomial_roots(&z[..=degree], 0.0, 1.0) {
                // Each end belongs to one segment only: the start.
                if u < 1.0 && point(s, u).x > p.x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// The section of a point of the prism's own space, if its height is within the prism's.
    fn section(&self, p: DVec3) -> Option<DVec2> {
        let [lo, hi] = self.heights;
        if !(lo..=hi).contains(&p.y) {
            return None;
        }
        match self.sweep {
            Sweep::Linear => Some(DVec2::new(p.x, p.z)),
            Sweep::Conic => (p.y > 0.0).then(|| DVec2::new(p.x, p.z) / p.y),
        }
    }

    fn inside(&self, p: DVec3) -> bool {
        !self.open && self.section(p).is_some_and(|s| self.inside_section(s))
    }

    /// Every crossing of the ray's surfaces in (0, t_max), in order: its distance and surface
    /// (`triangle`) and segment parameter (`st.x`), whether the ray starts inside.
    fn crossings_along(&self, ray: &Ray, t_max: f32) -> (bool, Vec<Intersection>) {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let inside_at_start = self.inside(o);
        let mut found: Vec<(f64, u32, f64)> = Vec::new();
        let t_end = f64::from(t_max);
        let keep = |t: f64| t > 0.0 && t < t_end;
        if !self.open {
            for (h, cap) in [(self.heights[0], BOTTOM), (self.heights[1], TOP)] {
                let t = (h - o.y) / d.y;
                if keep(t) {
                    let p = o + t * d;
                    let section = match self.sweep {
                        Sweep::Linear => Some(DVec2::new(p.x, p.z)),
                        Sweep::Conic => (h > 0.0).then(|| DVec2::new(p.x, p.z) / h),
                    };
                    if section.is_some_and(|s| self.inside_section(s)) {
                        found.push((t, cap, 0.0));
                    }
                }
            }
        }
        for (index, s) in self.segments.iter().enumerate() {
            // The side is met where the ray meets the line the segment's point sweeps along:
            // straight up, or through the origin (`conic`); zero of a cubic in u.
            let (k, base) = match self.sweep {
                // (x(u) - o.x) d.z - (z(u) - o.z) d.x = 0.
                Sweep::Linear => (DVec2::new(d.z, -d.x), o.z * d.x - o.x * d.z),
                // (o x d) . (x(u), 1, z(u)) = 0.
                Sweep::Conic => {
                    let n = o.cross(d);
                    (DVec2::new(n.x, n.z), n.y)
                }
            };
            let c: [f64; 4] =
                std::array::from_fn(|i| k.dot(s[i]) + if i == 0 { base } else { 0.0 });
            let degree = c.iter().rposition(|&v| v != 0.0).unwrap_or(0);
            if degree == 0 {
                continue;
            }
            // Each end belongs to one segment only: the start.
            for u in polynomial_roots(&c[..=degree], 0.0, 1.0).into_iter().filter(|&u| u < 1.0) {
                let q = point(s, u);
                let t = match self.sweep {
                    Sweep::Linear => {
                        if d.x.abs() > d.z.abs() {
                            (q.x - o.x) / d.x
                        } else {
                            (q.y - o.z) / d.z
                        }
                    }
                    // o + t d = y (q.x, 1, q.y): t from the larger of the two denominators.
                    Sweep::Conic => {
                        let (nx, nz) = (d.x - q.x * d.y, d.z - q.y * d.y);
                        if nx.abs() > nz.abs() {
                            (q.x * o.y - o.x) / nx
                        } else {
                            (q.y * o.y - o.z) / nz
                        }
                    }
                };
                let y = o.y + t * d.y;
                if keep(t) && (self.heights[0]..=self.heights[1]).contains(&y) {
                    found.push((t, index as u32, u));
                }
            }
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut inside = inside_at_start;
        let list = found
            .into_iter()
            .map(|(t, surface, u)| {
                inside = !inside;
                let flag = if inside { ENTERING } else { 0 };
                Intersection {
                    t: t as f32,
                    st: Vec2::new(u as f32, 0.0),
                    triangle: surface | flag,
                    part: 0,
                }
            })
            .collect();
        (inside_at_start, list)
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.crossings_along(ray, t_max).1.into_iter().find(|i| i.t > 0.0 && i.t < t_max)
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        if self.open {
            return Crossings::outside();
        }
        let (inside_at_start, list) = self.crossings_along(ray, t_max);
        let mut crossings = Crossings { inside_at_start, list: Default::default() };
        for at in list.into_iter().filter(|i| i.t > 0.0 && i.t < t_max) {
            crossings.push(at, at.triangle & ENTERING != 0);
        }
        crossings
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let surface = at.triangle & !ENTERING;
        let normal = match surface {
            BOTTOM => -DVec3::Y,
            TOP => DVec3::Y,
            index => {
                let s = &self.segments[index as usize];
                let u = f64::from(at.st.x);
                let slope = s[1] + u * (2.0 * s[2] + 3.0 * u * s[3]);
                match self.sweep {
                    Sweep::Linear => DVec3::new(slope.y, 0.0, -slope.x),
                    Sweep::Conic => {
                        let q = point(s, u);
                        DVec3::new(-slope.y, slope.y * q.x - slope.x * q.y, slope.x)
                    }
                }
            }
        };
        // Outward: against the ray where it goes in, along it where it comes out (the even-odd
        // rule gives a segment no side of its own). An open prism faces the ray.
        let entering = self.open || at.triangle & ENTERING != 0;
        self.frame.hit_along(ray, at, |_, d| {
            if (normal.dot(d) < 0.0) == entering { normal } else { -normal }
        })
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.inside(p)
    }
}

/// A segment's point at u.
fn point(s: &[DVec2; 4], u: f64) -> DVec2 {
    s[0] + u * (s[1] + u * (s[2] + u * s[3]))
}

/// The segments of POV-Ray's prism (and of a spline of points generally) of `kind` through
/// `points`: each as POV-Ray 3.7 computes them, a sub-curve closing where a point repeats the
/// sub-curve's first (for quadratic and cubic splines the first point after the leading
/// control point); `Err` with what is wrong when the points do not close.
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
        let p = |k: usize| points[i + k];
        let segment = match kind {
            SplineKind::Linear => [p(0), p(1) - p(0), Vec2::ZERO, Vec2::ZERO],
            SplineKind::Quadratic => {
                [p(1), 0.5 * (p(2) - p(0)), 0.5 * p(0) - p(1) + 0.5 * p(2), Vec2::ZERO]
            }
            SplineKind::Cubic => [
                p(1),
                0.5 * (p(2) - p(0)),
                p(0) - 2.5 * p(1) + 2.0 * p(2) - 0.5 * p(3),
                -0.5 * p(0) + 1.5 * p(1) - 1.5 * p(2) + 0.5 * p(3),
            ],
            SplineKind::Bezier => [
                p(3),
                3.0 * p(2) - 3.0 * p(3),
                3.0 * p(1) - 6.0 * p(2) + 3.0 * p(3),
                p(0) - 3.0 * p(1) + 3.0 * p(2) - p(3),
            ],
        };
        segments.push(segment);
        match kind {
            SplineKind::Linear => {
                if same(p(1), first) {
                    i += 1;
                    if i + 1 < n {
                        first = points[i + 1];
                    }
                }
            }
            SplineKind::Quadratic | SplineKind::Cubic => {
                if same(p(2), first) {
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

/// Points that make no closed spline, with how many there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum SplineError {
    #[error("{0} points are too few for this spline")]
    TooFew(usize),
    #[error("{0} points do not close the last curve (or its control points are missing)")]
    Open(usize),
}

/// POV-Ray's kinds of spline through a prism's (or lathe's) points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplineKind {
    Linear,
    Quadratic,
    Cubic,
    Bezier,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(size: f32) -> Vec<Vec2> {
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
    fn a_square_prism_with_a_hole_is_hit_on_its_walls_and_caps() {
        let mut points = square(1.0);
        points.push(points[0]);
        let inner = square(0.5);
        points.extend(inner.iter().chain([&inner[0]]));
        let segments = spline_segments(SplineKind::Linear, &points).unwrap();
        let prism = Prism::new(&segments, Sweep::Linear, [0.0, 1.0], false, Affine3A::IDENTITY);
        // Along x at mid height: the outer wall, the hole's two walls, the outer wall.
        let ray = Ray::new(Vec3::new(-3.0, 0.5, 0.1), Vec3::X);
        let crossings = prism.crossings(&ray, f32::INFINITY);
        let ts: Vec<f32> = crossings.list.iter().map(|c| c.at.t).collect();
        assert_eq!(ts.len(), 4, "{ts:?}");
        for (t, expected) in ts.iter().zip([2.0, 2.5, 3.5, 4.0]) {
            assert!((t - expected).abs() < 1e-5, "{ts:?}");
        }
        let first = prism.hit(&ray, &crossings.list[0].at);
        assert!((first.normal + Vec3::X).length() < 1e-6, "outward: {first:?}");
        let second = prism.hit(&ray, &crossings.list[1].at);
        assert!((second.normal - Vec3::X).length() < 1e-6, "out into the hole: {second:?}");
        // Down through the hole: nothing; down onto the rim: the top cap.
        assert!(prism.intersection(&Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y), 10.0).is_none());
        let rim = Ray::new(Vec3::new(0.75, 3.0, 0.0), -Vec3::Y);
        let top = prism.hit(&rim, &prism.intersection(&rim, 10.0).expect("the cap"));
        assert!((top.t - 2.0).abs() < 1e-6 && (top.normal - Vec3::Y).length() < 1e-6);
        assert!(prism.contains(Vec3::new(0.75, 0.5, 0.0)));
        assert!(!prism.contains(Vec3::new(0.0, 0.5, 0.0)));
    }
}
