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
use super::spline::{Segment, inside_curves, point, segment_bounds};
use super::{Aabb, Hit, Ray};

/// How the section is swept along y.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    Linear,
    Conic,
}

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
        // The section's bounds.
        let (mut min, mut max) = (DVec2::splat(f64::INFINITY), DVec2::splat(-f64::INFINITY));
        for s in &segments {
            let (lo, hi) = segment_bounds(s);
            (min, max) = (min.min(lo), max.max(hi));
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
        !self.open && self.section(p).is_some_and(|s| inside_curves(&self.segments, s))
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
                    if section.is_some_and(|s| inside_curves(&self.segments, s)) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::spline::tests::square;
    use crate::geometry::{SplineKind, spline_segments};

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
