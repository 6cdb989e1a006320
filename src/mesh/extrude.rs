//! A closed solid from a flat outline: the region its contours fill (non-zero winding, as
//! TrueType fills a glyph) extruded along z from 0 to a thickness.
//!
//! The caps are cut into trapezoids between consecutive heights of the outline's vertices (in
//! each such slab the contours are straight segments that do not cross), and every point where
//! a cap edge meets another lies on both: each contour edge is split at every slab line it
//! crosses, and each cap row at every point on its line. So every edge of the mesh is shared
//! by exactly two triangles, which is what `TriangleMesh::is_closed` and the parity inside test
//! of CSG need.

use std::collections::HashMap;

use glam::{DVec2, Vec3};

use super::Mesh;

/// An edge of a contour that is not horizontal, from its lower end to its upper end.
#[derive(Debug, Clone, Copy)]
struct Rising {
    low: DVec2,
    high: DVec2,
    /// +1 where the contour goes up along it, -1 where it goes down.
    winding: i32,
}

impl Rising {
    /// Its x at height `y` in [low.y, high.y]: the end itself at either end, so that the same
    /// point comes out bit for bit wherever it is asked for.
    fn x_at(&self, y: f64) -> f64 {
        if y == self.low.y {
            self.low.x
        } else if y == self.high.y {
            self.high.x
        } else {
            let t = (y - self.low.y) / (self.high.y - self.low.y);
            self.low.x + t * (self.high.x - self.low.x)
        }
    }
}

/// The closed mesh of the region `contours` fill, from z = 0 to z = `thickness` (> 0), or
/// `None` when they fill nothing. Each contour is a closed polygon (its last point joins its
/// first); repeated points are dropped. Faces are turned outwards.
pub fn extrude(contours: &[Vec<DVec2>], thickness: f64) -> Option<Mesh> {
    let contours: Vec<Vec<DVec2>> = contours
        .iter()
        .map(|contour| {
            let mut points = contour.clone();
            points.dedup();
            while points.len() > 1 && points.first() == points.last() {
                points.pop();
            }
            points
        })
        // A contour of no area (its points on a line) would leave walls with nothing between.
        .filter(|points| points.len() >= 3 && signed_area(points) != 0.0)
        .collect();
    let edges =
        contours.iter().flat_map(|c| c.iter().zip(c.iter().cycle().skip(1)).map(|(&a, &b)| (a, b)));
    let (mut rising, mut flat) = (Vec::new(), Vec::new());
    for (a, b) in edges {
        match a.y.total_cmp(&b.y) {
            std::cmp::Ordering::Less => rising.push(Rising { low: a, high: b, winding: 1 }),
            std::cmp::Ordering::Greater => rising.push(Rising { low: b, high: a, winding: -1 }),
            std::cmp::Ordering::Equal => flat.push((a, b)),
        }
    }
    let mut heights: Vec<f64> = contours.iter().flatten().map(|p| p.y).collect();
    heights.sort_by(f64::total_cmp);
    heights.dedup();
    // The points on each slab line: where edges meet it, and the ends of flat edges on it.
    let mut lines: Vec<Vec<f64>> = vec![Vec::new(); heights.len()];
    let line_of = |y: f64| heights.binary_search_by(|h| h.total_cmp(&y)).ok();
    for edge in &rising {
        let (first, last) = (line_of(edge.low.y)?, line_of(edge.high.y)?);
        for (line, &y) in lines[first..=last].iter_mut().zip(&heights[first..=last]) {
            line.push(edge.x_at(y));
        }
    }
    for (a, b) in &flat {
        let line = &mut lines[line_of(a.y)?];
        line.extend([a.x, b.x]);
    }
    for line in &mut lines {
        line.sort_by(f64::total_cmp);
        line.dedup();
    }
    // Within [from, to] of a line, in order.
    let between = |line: usize, from: f64, to: f64| -> Vec<DVec2> {
        let xs = &lines[line];
        let start = xs.partition_point(|&x| x < from);
        let end = xs.partition_point(|&x| x <= to);
        xs[start..end].iter().map(|&x| DVec2::new(x, heights[line])).collect()
    };

    let mut solid = Solid::new(thickness);
    for slab in 0..heights.len().saturating_sub(1) {
        let (bottom, top) = (heights[slab], heights[slab + 1]);
        let middle = 0.5 * (bottom + top);
        let mut crossing: Vec<&Rising> =
            rising.iter().filter(|e| e.low.y <= bottom && e.high.y >= top).collect();
        crossing.sort_by(|a, b| a.x_at(middle).total_cmp(&b.x_at(middle)));
        let mut winding = 0;
        let mut left = None;
        for edge in crossing {
            let was_filled = winding != 0;
            winding += edge.winding;
            match (was_filled, winding != 0) {
                (false, true) => left = Some(edge),
                (true, false) => {
                    let left = left.take()?;
                    let lower = between(slab, left.x_at(bottom), edge.x_at(bottom));
                    let upper = between(slab + 1, left.x_at(top), edge.x_at(top));
                    solid.cap_strip(&lower, &upper);
                }
                (false, false) | (true, true) => {}
            }
        }
    }
    // Outwards is to the right of an edge where the contours run counter-clockwise around the
    // region (their signed areas sum to more than 0), to its left where they run clockwise.
    let counter_clockwise = contours.iter().map(|c| signed_area(c)).sum::<f64>() > 0.0;
    for edge in &rising {
        let (first, last) = (line_of(edge.low.y)?, line_of(edge.high.y)?);
        let points: Vec<DVec2> =
            heights[first..=last].iter().map(|&y| DVec2::new(edge.x_at(y), y)).collect();
        for pair in points.windows(2) {
            // Along the contour's own direction.
            let (a, b) = if edge.winding > 0 { (pair[0], pair[1]) } else { (pair[1], pair[0]) };
            solid.wall(a, b, counter_clockwise);
        }
    }
    for &(a, b) in &flat {
        let mut points = between(line_of(a.y)?, a.x.min(b.x), a.x.max(b.x));
        if a.x > b.x {
            points.reverse();
        }
        for pair in points.windows(2) {
            solid.wall(pair[0], pair[1], counter_clockwise);
        }
    }
    solid.mesh()
}

/// Twice the area a closed polygon encloses, positive where it runs counter-clockwise.
fn signed_area(points: &[DVec2]) -> f64 {
    points.iter().zip(points.iter().cycle().skip(1)).map(|(a, b)| a.perp_dot(*b)).sum()
}

/// The mesh being built: each distinct point once.
struct Solid {
    thickness: f64,
    positions: Vec<Vec3>,
    index: HashMap<[u32; 3], u32>,
    triangles: Vec<[u32; 3]>,
}

impl Solid {
    fn new(thickness: f64) -> Self {
        Solid { thickness, positions: Vec::new(), index: HashMap::new(), triangles: Vec::new() }
    }

    fn vertex(&mut self, p: DVec2, back: bool) -> u32 {
        let z = if back { self.thickness } else { 0.0 };
        let position = Vec3::new(p.x as f32, p.y as f32, z as f32);
        *self.index.entry(position.to_array().map(f32::to_bits)).or_insert_with(|| {
            self.positions.push(position);
            self.positions.len() as u32 - 1
        })
    }

    /// A triangle counter-clockwise in the x-y plane, on both caps: facing +z on the back
    /// one, -z (turned) on the front one.
    fn cap_triangle(&mut self, a: DVec2, b: DVec2, c: DVec2) {
        let back = [a, b, c].map(|p| self.vertex(p, true));
        let [a, b, c] = [a, b, c].map(|p| self.vertex(p, false));
        self.triangles.extend([back, [a, c, b]]);
    }

    /// The trapezoid between the points `lower` of one slab line and `upper` of the next, in
    /// increasing x, cut into triangles zipping along both.
    fn cap_strip(&mut self, lower: &[DVec2], upper: &[DVec2]) {
        // Empty only where contours cross themselves inside the slab: nothing to fill.
        if lower.is_empty() || upper.is_empty() {
            return;
        }
        let (mut i, mut j) = (0, 0);
        while i + 1 < lower.len() || j + 1 < upper.len() {
            let lower_next = i + 1 < lower.len();
            if lower_next && (j + 1 == upper.len() || lower[i + 1].x <= upper[j + 1].x) {
                self.cap_triangle(lower[i], lower[i + 1], upper[j]);
                i += 1;
            } else {
                self.cap_triangle(lower[i], upper[j + 1], upper[j]);
                j += 1;
            }
        }
    }

    /// The side wall along the contour from `a` to `b`: its normal points to the right of
    /// a -> b when the contours are counter-clockwise, to the left otherwise.
    fn wall(&mut self, a: DVec2, b: DVec2, counter_clockwise: bool) {
        let (a0, b0, a1, b1) = (
            self.vertex(a, false),
            self.vertex(b, false),
            self.vertex(a, true),
            self.vertex(b, true),
        );
        if counter_clockwise {
            self.triangles.extend([[a0, b0, b1], [a0, b1, a1]]);
        } else {
            self.triangles.extend([[a0, b1, b0], [a0, a1, b1]]);
        }
    }

    fn mesh(self) -> Option<Mesh> {
        (!self.triangles.is_empty()).then_some(Mesh {
            positions: self.positions,
            normals: None,
            triangles: self.triangles,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Ray, TriangleMesh};

    fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64, clockwise: bool) -> Vec<DVec2> {
        let mut corners =
            vec![DVec2::new(x0, y0), DVec2::new(x1, y0), DVec2::new(x1, y1), DVec2::new(x0, y1)];
        if clockwise {
            corners.reverse();
        }
        corners
    }

    /// Whether `p` is inside the contours' region by the non-zero winding rule, counted along
    /// a ray towards +x (independent of the slabs).
    fn winds_around(contours: &[Vec<DVec2>], p: DVec2) -> bool {
        let mut winding = 0;
        for c in contours {
            for (a, b) in c.iter().zip(c.iter().cycle().skip(1)) {
                if (a.y <= p.y) != (b.y <= p.y) {
                    let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                    if x > p.x {
                        winding += if b.y > a.y { 1 } else { -1 };
                    }
                }
            }
        }
        winding != 0
    }

    /// The signed volume the faces enclose (divergence theorem): the solid's volume when it is
    /// closed with its faces turned outwards.
    fn signed_volume(mesh: &Mesh) -> f64 {
        let corner = |i: u32| mesh.positions[i as usize].as_dvec3();
        mesh.triangles
            .iter()
            .map(|t| corner(t[0]).dot(corner(t[1]).cross(corner(t[2]))) / 6.0)
            .sum()
    }

    /// A frame with a square hole, a triangle beside it sharing no vertex heights with it, and
    /// a slanted quadrilateral: slabs that split edges and rows with points of other shapes.
    fn shapes(clockwise: bool) -> (Vec<Vec<DVec2>>, f64) {
        let triangle = vec![DVec2::new(1.2, 0.1), DVec2::new(1.9, 0.35), DVec2::new(1.3, 0.93)];
        let slanted = vec![
            DVec2::new(2.1, 0.0),
            DVec2::new(2.9, 0.2),
            DVec2::new(2.6, 1.1),
            DVec2::new(2.3, 0.7),
        ];
        let mut contours = vec![
            rectangle(0.0, 0.0, 1.0, 1.0, clockwise),
            rectangle(0.25, 0.3, 0.75, 0.8, !clockwise),
            if clockwise { triangle.iter().rev().copied().collect() } else { triangle },
            if clockwise { slanted.iter().rev().copied().collect() } else { slanted },
        ];
        let total = contours.iter().map(|c| signed_area(c) / 2.0).sum::<f64>().abs();
        let repeated = contours[0][1];
        contours[0].insert(2, repeated); // dropped
        (contours, total)
    }

    #[test]
    fn the_solid_is_closed_turned_outwards_and_holds_the_region() {
        for clockwise in [false, true] {
            let (contours, area) = shapes(clockwise);
            let thickness = 0.4;
            let mesh = extrude(&contours, thickness).expect("a region");
            assert!((signed_volume(&mesh) - area * thickness).abs() < 1e-5, "{clockwise}");
            let solid = TriangleMesh::new(mesh);
            assert!(solid.is_closed());
            // Inside tests (ray parity) agree with the winding of the outline, on a grid that
            // avoids the outline's own coordinates.
            for i in 0..61 {
                for j in 0..23 {
                    for z in [-0.1, 0.13, 0.29, 0.5] {
                        let p = DVec2::new(
                            -0.07 + 0.0513 * f64::from(i),
                            -0.05 + 0.0531 * f64::from(j),
                        );
                        let inside = (0.0..thickness).contains(&z) && winds_around(&contours, p);
                        let point = Vec3::new(p.x as f32, p.y as f32, z as f32);
                        assert_eq!(solid.contains(point), inside, "{point} {clockwise}");
                    }
                }
            }
        }
    }

    #[test]
    fn rays_cross_the_solid_in_and_out_in_turn() {
        let (contours, _) = shapes(true);
        let solid = TriangleMesh::new(extrude(&contours, 0.4).expect("a region"));
        for k in 0..200 {
            let angle = f32::from(k as u16) * 0.7;
            let origin = Vec3::new(1.5, 0.5, 0.2)
                + 4.0 * Vec3::new(angle.cos(), angle.sin(), 0.3 * (angle * 3.0).sin());
            let target = Vec3::new(0.1 + 0.014 * k as f32, 0.5 + 0.3 * (k as f32).sin(), 0.2);
            let ray = Ray::new(origin, (target - origin).normalize());
            let crossings = solid.crossings(&ray, f32::INFINITY);
            assert!(!crossings.inside_at_start);
            assert_eq!(crossings.list.len() % 2, 0, "ray {k} ends inside");
            for (n, crossing) in crossings.list.iter().enumerate() {
                assert_eq!(crossing.entering, n % 2 == 0);
            }
        }
    }

    #[test]
    fn nothing_is_made_of_nothing() {
        assert_eq!(extrude(&[], 1.0), None);
        let flat = vec![DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)];
        assert_eq!(extrude(&[flat, vec![DVec2::ZERO, DVec2::Y]], 1.0), None);
    }
}
