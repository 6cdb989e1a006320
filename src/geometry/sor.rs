//! POV-Ray's surface of revolution (`sor`): the squared radius a cubic in the height, piece by
//! piece between consecutive points (r, y) (the first and last points only set the slopes at
//! the ends), turned about the y axis and closed by discs at the lowest and highest point
//! unless `open`. A ray's squared distance from the axis is quadratic in its distance t and its
//! height linear, so each piece is met where a cubic in t is zero.

use glam::{Affine3A, DVec3, Vec2, Vec3};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};

/// One piece: r^2 = g(s), g a cubic in s = (y - base) / height, s in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SorPiece {
    base: f64,
    height: f64,
    /// g's coefficients, lowest degree first.
    g: [f64; 4],
}

impl SorPiece {
    /// g's value and its first, second (halved) and third (a sixth) derivatives at s: its
    /// Taylor coefficients there.
    fn taylor(&self, s: f64) -> [f64; 4] {
        let g = &self.g;
        [
            g[0] + s * (g[1] + s * (g[2] + s * g[3])),
            g[1] + s * (2.0 * g[2] + 3.0 * s * g[3]),
            g[2] + 3.0 * s * g[3],
            g[3],
        ]
    }
}

/// Points that make no `sor`, with the points at fault (counted from 1).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum SorError {
    #[error("{0} points are too few (a sor needs 4)")]
    TooFew(usize),
    #[error("point {point} has a negative radius {radius}")]
    NegativeRadius { point: usize, radius: f64 },
    #[error("the heights must increase from point 2 on: point {0} does not")]
    Falling(usize),
    #[error("points {0} and {1} are at the same height")]
    SameHeight(usize, usize),
}

/// The pieces of POV-Ray's `sor` through `points` (at least 4): between points 1 and 2, 2 and
/// 3, ..., the cubic in y that takes each point's r^2 and, at each end, the slope of r^2 that
/// the points either side give (2 r (r_next - r_previous) / (y_next - y_previous)), as POV-Ray
/// 3.7 fits it. `Err` with what is wrong: too few points, a negative r, heights not
/// increasing.
pub fn sor_pieces(points: &[Vec2]) -> Result<Vec<SorPiece>, SorError> {
    let n = points.len();
    if n < 4 {
        return Err(SorError::TooFew(n));
    }
    let p: Vec<(f64, f64)> = points.iter().map(|v| (f64::from(v.x), f64::from(v.y))).collect();
    if let Some(i) = p.iter().position(|q| q.0 < 0.0) {
        return Err(SorError::NegativeRadius { point: i + 1, radius: p[i].0 });
    }
    if let Some(i) = (2..n - 1).find(|&i| p[i].1 <= p[i - 1].1) {
        return Err(SorError::Falling(i + 1));
    }
    let mut pieces = Vec::with_capacity(n - 3);
    for i in 0..n - 3 {
        let [(r0, y0), (r1, y1), (r2, y2), (r3, y3)] = [p[i], p[i + 1], p[i + 2], p[i + 3]];
        if (y2 - y0).abs() < 1e-10 || (y3 - y1).abs() < 1e-10 {
            return Err(SorError::SameHeight(i + 1, i + 3));
        }
        let height = y2 - y1;
        // Values and slopes (per unit of s) at s = 0 and 1: Hermite's cubic.
        let (v0, v1) = (r1 * r1, r2 * r2);
        let s0 = height * 2.0 * r1 * (r2 - r0) / (y2 - y0);
        let s1 = height * 2.0 * r2 * (r3 - r1) / (y3 - y1);
        let g = [v0, s0, 3.0 * (v1 - v0) - 2.0 * s0 - s1, 2.0 * (v0 - v1) + s0 + s1];
        pieces.push(SorPiece { base: y1, height, g });
    }
    Ok(pieces)
}

/// Which surface an intersection is on, in `Intersection::triangle`: a piece by its index, or
/// a cap.
const BOTTOM: u32 = u32::MAX;
const TOP: u32 = u32::MAX - 1;

#[derive(Debug, Clone)]
pub struct Sor {
    frame: QuadricFrame,
    pieces: Vec<SorPiece>,
    /// The lowest and highest heights, and the caps' squared radii there.
    heights: [f64; 2],
    caps: [f64; 2],
    /// The greatest radius.
    radius: f64,
    open: bool,
    bounds: Aabb,
}

impl Sor {
    /// The surface of `pieces` (from `sor_pieces`), placed in the world by `to_world`.
    pub fn new(pieces: &[SorPiece], open: bool, to_world: Affine3A) -> Self {
        let first = pieces.first().expect("a sor has a piece");
        let last = pieces.last().expect("a sor has a piece");
        // The greatest r^2: at the ends of each piece, or where its slope is 0.
        let mut greatest = 0.0f64;
        for piece in pieces {
            let g = &piece.g;
            let slope = [g[1], 2.0 * g[2], 3.0 * g[3]];
            let degree = slope.iter().rposition(|&k| k != 0.0).unwrap_or(0);
            let turns = polynomial_roots(&slope[..=degree], 0.0, 1.0);
            for s in [0.0, 1.0].into_iter().chain(turns) {
                greatest = greatest.max(piece.taylor(s)[0]);
            }
        }
        let radius = greatest.sqrt();
        let heights = [first.base, last.base + last.height];
        let caps = [first.taylor(0.0)[0], last.taylor(1.0)[0]];
        let corners = QuadricFrame::canonical_corners().map(|c| {
            let y = if c.y < 0.0 { heights[0] } else { heights[1] };
            let own = DVec3::new(f64::from(c.x) * radius, y, f64::from(c.z) * radius);
            to_world.transform_point3(own.as_vec3())
        });
        let bounds = Aabb::from_points(&corners);
        let mut frame = QuadricFrame::new(to_world, None);
        frame.magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        Sor { frame, pieces: pieces.to_vec(), heights, caps, radius, open, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The piece at height y, with y's s in it.
    fn piece_at(&self, y: f64) -> Option<(&SorPiece, f64)> {
        if y < self.heights[0] || y > self.heights[1] {
            return None;
        }
        let index = self.pieces.partition_point(|p| p.base + p.height < y);
        let piece = &self.pieces[index.min(self.pieces.len() - 1)];
        Some((piece, (y - piece.base) / piece.height))
    }

    fn inside(&self, p: DVec3) -> bool {
        !self.open
            && self
                .piece_at(p.y)
                .is_some_and(|(piece, s)| p.x * p.x + p.z * p.z < piece.taylor(s)[0])
    }

    /// Every crossing of the surface in (0, t_max), in order, with its surface.
    fn crossings_along(&self, ray: &Ray, t_max: f32) -> Vec<Intersection> {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        // The ray's squared distance from the axis: a t^2 + 2 m t + c.
        let (a, m, c) = (d.x * d.x + d.z * d.z, o.x * d.x + o.z * d.z, o.x * o.x + o.z * o.z);
        // Where the ray is within the bounding cylinder.
        let (mut near, mut far) = (0.0f64, f64::from(t_max));
        let outside = c - self.radius * self.radius;
        if a > 0.0 {
            let discriminant = m * m - a * outside;
            if discriminant < 0.0 {
                return Vec::new();
            }
            let root = discriminant.sqrt();
            near = near.max((-m - root) / a);
            far = far.min((-m + root) / a);
        } else if outside > 0.0 {
            return Vec::new();
        }
        let mut found: Vec<(f64, u32)> = Vec::new();
        if !self.open && d.y != 0.0 {
            for (h, r2, cap) in
                [(self.heights[0], self.caps[0], BOTTOM), (self.heights[1], self.caps[1], TOP)]
            {
                let t = (h - o.y) / d.y;
                if t > 0.0 && t < f64::from(t_max) && a * t * t + 2.0 * m * t + c <= r2 {
                    found.push((t, cap));
                }
            }
        }
        let last = self.pieces.len() - 1;
        for (index, piece) in self.pieces.iter().enumerate() {
            // The stretch of the ray within the piece's heights.
            let (mut lo, mut hi) = (near, far);
            let top = piece.base + piece.height;
            if d.y != 0.0 {
                let (t0, t1) = ((piece.base - o.y) / d.y, (top - o.y) / d.y);
                (lo, hi) = (lo.max(t0.min(t1)), hi.min(t0.max(t1)));
            } else if o.y < piece.base || o.y > top {
                continue;
            }
            if lo >= hi {
                continue;
            }
            // r^2 at the ray's height, g(s0 + ds t), minus its squared distance from the axis.
            let ds = d.y / piece.height;
            let k = piece.taylor((o.y - piece.base) / piece.height);
            let cubic = [k[0] - c, k[1] * ds - 2.0 * m, k[2] * ds * ds - a, k[3] * ds * ds * ds];
            let degree = cubic.iter().rposition(|&v| v != 0.0).unwrap_or(0);
            for t in polynomial_roots(&cubic[..=degree], lo, hi) {
                let y = o.y + t * d.y;
                // A joint between pieces belongs to the upper one.
                if t > 0.0 && (y < top || index == last) {
                    found.push((t, index as u32));
                }
            }
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        found
            .into_iter()
            .map(|(t, surface)| Intersection {
                t: t as f32,
                st: Vec2::ZERO,
                triangle: surface,
                part: 0,
            })
            .collect()
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.crossings_along(ray, t_max).into_iter().next()
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        if self.open {
            return Crossings::outside();
        }
        let (o, _) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::ZERO);
        Crossings::alternating(self.inside(o), self.crossings_along(ray, t_max))
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        self.frame.hit_along(ray, at, |own, _| match at.triangle {
            BOTTOM => -DVec3::Y,
            TOP => DVec3::Y,
            index => {
                let piece = &self.pieces[index as usize];
                let slope = piece.taylor((own.y - piece.base) / piece.height)[1] / piece.height;
                DVec3::new(own.x, -0.5 * slope, own.z)
            }
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

    #[test]
    fn the_pieces_pass_through_the_points_with_pov_rays_slopes() {
        let points = [(1.0, -1.0), (1.0, 0.0), (2.0, 1.0), (0.5, 3.0), (0.5, 4.0)]
            .map(|(r, y)| Vec2::new(r, y));
        let pieces = sor_pieces(&points).unwrap();
        assert_eq!(pieces.len(), 2);
        let r2 = |piece: &SorPiece, y: f64| piece.taylor((y - piece.base) / piece.height)[0];
        assert!((r2(&pieces[0], 0.0) - 1.0).abs() < 1e-12);
        assert!((r2(&pieces[0], 1.0) - 4.0).abs() < 1e-12);
        assert!((r2(&pieces[1], 1.0) - 4.0).abs() < 1e-12);
        assert!((r2(&pieces[1], 3.0) - 0.25).abs() < 1e-12);
        // The slope of r^2 at y = 1 is 2 r (r_next - r_previous) / (y_next - y_previous).
        let slope = |piece: &SorPiece, y: f64| {
            piece.taylor((y - piece.base) / piece.height)[1] / piece.height
        };
        let expected = 2.0 * 2.0 * (0.5 - 1.0) / (3.0 - 0.0);
        assert!((slope(&pieces[0], 1.0) - expected).abs() < 1e-12);
        assert!((slope(&pieces[1], 1.0) - expected).abs() < 1e-12);
        assert!(sor_pieces(&points[..3]).is_err());
        let mut falling = points;
        falling[2].y = -0.5;
        assert_eq!(sor_pieces(&falling).unwrap_err(), SorError::Falling(3));
    }
}
