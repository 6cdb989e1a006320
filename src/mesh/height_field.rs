//! POV-Ray's `height_field` as triangles: a grid of heights over the unit square of the x-z
//! plane (x = column / (columns − 1), z = 1 at the image's top row and 0 at its bottom), each
//! square of four neighbouring heights cut into the two triangles POV-Ray tests, the sheet's
//! normals pointing up (+y). `smooth` gives each vertex POV-Ray's normal (the mean of its four
//! triangles' unit normals, taken in the grid's own units: one per pixel across, 65535 up), which
//! the mesh interpolates across each triangle. Below `water_level` nothing is drawn: triangles
//! that cross it are cut along it, as POV-Ray's rays never look below it.

use glam::Vec3;

use super::Mesh;
use super::heights::Heights;

/// The sheet of `heights` above `water_level`, with `smooth` normals or flat ones; `None` when
/// nothing is left above the water.
pub fn tessellate(heights: &Heights, water_level: f32, smooth: bool) -> Option<Mesh> {
    let (columns, rows) = (heights.columns, heights.rows);
    // Grid point (j, i): column j, i rows up from the image's bottom row.
    let height = |j: usize, i: usize| heights.values[(rows - 1 - i) * columns + j];
    let scale = Vec3::new((columns - 1) as f32, 1.0, (rows - 1) as f32).recip();
    let mut positions = Vec::with_capacity(columns * rows);
    for i in 0..rows {
        for j in 0..columns {
            positions.push(Vec3::new(j as f32, height(j, i), i as f32) * scale);
        }
    }
    let mut normals = smooth.then(|| vertex_normals(&height, columns, rows));
    let mut triangles = Vec::with_capacity(2 * (columns - 1) * (rows - 1));
    let index = |j: usize, i: usize| (i * columns + j) as u32;
    for i in 0..rows - 1 {
        for j in 0..columns - 1 {
            let cell = [
                [index(j, i), index(j + 1, i), index(j, i + 1)],
                [index(j + 1, i + 1), index(j, i + 1), index(j + 1, i)],
            ];
            for triangle in cell {
                above_water(triangle, water_level, &mut positions, &mut normals, &mut triangles);
            }
        }
    }
    (!triangles.is_empty()).then_some(Mesh { positions, normals, triangles })
}

/// The solid of `heights` (POV-Ray's height field is one, for CSG): the points of its unit
/// square below the sheet, closed by the sheet (the same two triangles per grid square as
/// `tessellate`'s, without the water's cut), the four walls and a floor at y = −1, each facing
/// out. POV-Ray's solid reaches down without end; the floor one full height below the lowest
/// the sheet can be keeps the mesh within the sheet's size, and so its hit points' error bounds
/// those of the sheet. Every edge is shared by two triangles: the mesh is closed.
pub fn solid(heights: &Heights) -> Mesh {
    const FLOOR: f32 = -1.0;
    let (columns, rows) = (heights.columns, heights.rows);
    let height = |j: usize, i: usize| heights.values[(rows - 1 - i) * columns + j];
    let scale = Vec3::new((columns - 1) as f32, 1.0, (rows - 1) as f32).recip();
    // The sheet's points, then the floor's below them.
    let mut positions = Vec::with_capacity(2 * columns * rows);
    for floor in [false, true] {
        for i in 0..rows {
            for j in 0..columns {
                let y = if floor { FLOOR } else { height(j, i) };
                positions.push(Vec3::new(j as f32, y, i as f32) * scale);
            }
        }
    }
    let top = |j: usize, i: usize| (i * columns + j) as u32;
    let bottom = |j: usize, i: usize| ((rows + i) * columns + j) as u32;
    let mut triangles = Vec::with_capacity(4 * (columns - 1) * (rows - 1) + 4 * (columns + rows));
    for i in 0..rows - 1 {
        for j in 0..columns - 1 {
            // Counter-clockwise seen from above for the sheet, from below for the floor.
            triangles.push([top(j, i), top(j, i + 1), top(j + 1, i)]);
            triangles.push([top(j + 1, i + 1), top(j + 1, i), top(j, i + 1)]);
            triangles.push([bottom(j, i), bottom(j + 1, i), bottom(j, i + 1)]);
            triangles.push([bottom(j + 1, i + 1), bottom(j, i + 1), bottom(j + 1, i)]);
        }
    }
    // The boundary in order round the square (+x along z = 0 first), each edge (a, b) walled
    // by the quad a, b, b's floor, a's floor, facing out.
    let mut boundary = Vec::with_capacity(2 * (columns + rows));
    boundary.extend((0..columns - 1).map(|j| ((j, 0), (j + 1, 0))));
    boundary.extend((0..rows - 1).map(|i| ((columns - 1, i), (columns - 1, i + 1))));
    boundary.extend((1..columns).rev().map(|j| ((j, rows - 1), (j - 1, rows - 1))));
    boundary.extend((1..rows).rev().map(|i| ((0, i), (0, i - 1))));
    for ((ja, ia), (jb, ib)) in boundary {
        let (a, b) = (top(ja, ia), top(jb, ib));
        let (a_floor, b_floor) = (bottom(ja, ia), bottom(jb, ib));
        triangles.push([a, b, a_floor]);
        triangles.push([b, b_floor, a_floor]);
    }
    Mesh { positions, normals: None, triangles }
}

/// Adds the part of `triangle` at or above `water_level` (cut along it where it crosses),
/// turned to face up; new corners are appended to `positions` (and `normals`, interpolated).
fn above_water(
    triangle: [u32; 3],
    water_level: f32,
    positions: &mut Vec<Vec3>,
    normals: &mut Option<Vec<Vec3>>,
    triangles: &mut Vec<[u32; 3]>,
) {
    let corners = triangle.map(|v| positions[v as usize]);
    let mut kept: arrayvec::ArrayVec<u32, 4> = arrayvec::ArrayVec::new();
    if corners.iter().all(|p| p.y >= water_level) {
        kept.extend(triangle);
    } else {
        // Sutherland–Hodgman against the half-space y >= water_level: at most four corners.
        for k in 0..3 {
            let (a, b) = (triangle[k], triangle[(k + 1) % 3]);
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            if pa.y >= water_level {
                kept.push(a);
            }
            if (pa.y >= water_level) != (pb.y >= water_level) {
                let t = (water_level - pa.y) / (pb.y - pa.y);
                let mut cut = pa.lerp(pb, t);
                cut.y = water_level;
                positions.push(cut);
                if let Some(normals) = normals {
                    let n = normals[a as usize].lerp(normals[b as usize], t).normalize_or_zero();
                    normals.push(n);
                }
                kept.push(positions.len() as u32 - 1);
            }
        }
    }
    for k in 1..kept.len().saturating_sub(1) {
        let [a, b, c] = [kept[0], kept[k], kept[k + 1]];
        let [pa, pb, pc] = [a, b, c].map(|v| positions[v as usize]);
        let up = (pb - pa).cross(pc - pa).y;
        if up > 0.0 {
            triangles.push([a, b, c]);
        } else if up < 0.0 {
            triangles.push([a, c, b]);
        }
    }
}

/// Each grid point's smooth normal as POV-Ray makes it: the unit normals of the four triangles
/// it makes with its neighbours (along +x and +z, +z and −x, −x and −z, −z and +x), each turned
/// up, summed in the grid's units and normalized, then carried to the unit square (by the
/// inverse transpose of the scale from the grid's units to it).
fn vertex_normals(height: &dyn Fn(usize, usize) -> f32, columns: usize, rows: usize) -> Vec<Vec3> {
    let point = |j: isize, i: isize| {
        let inside = (0..columns as isize).contains(&j) && (0..rows as isize).contains(&i);
        inside.then(|| Vec3::new(j as f32, 65535.0 * height(j as usize, i as usize), i as f32))
    };
    let to_unit = Vec3::new((columns - 1) as f32, 65535.0, (rows - 1) as f32);
    let mut normals = Vec::with_capacity(columns * rows);
    for i in 0..rows as isize {
        for j in 0..columns as isize {
            let centre = point(j, i).expect("a grid point");
            let mut sum = Vec3::ZERO;
            for [(a, b), (c, d)] in
                [[(1, 0), (0, 1)], [(0, 1), (-1, 0)], [(-1, 0), (0, -1)], [(0, -1), (1, 0)]]
            {
                if let (Some(p), Some(q)) = (point(j + a, i + b), point(j + c, i + d)) {
                    let n = (q - centre).cross(p - centre).normalize();
                    sum += if n.y < 0.0 { -n } else { n };
                }
            }
            normals.push((sum.normalize() * to_unit).normalize());
        }
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heights from a function of (x, z) on the unit square, `n` by `n` samples.
    fn grid(n: usize, f: impl Fn(f32, f32) -> f32) -> Heights {
        let mut values = Vec::new();
        for row in 0..n {
            let z = 1.0 - row as f32 / (n - 1) as f32;
            for column in 0..n {
                values.push(f(column as f32 / (n - 1) as f32, z));
            }
        }
        Heights { columns: n, rows: n, values }
    }

    #[test]
    fn the_image_s_top_row_is_at_z_1_and_every_triangle_faces_up() {
        let heights = grid(3, |x, z| 0.25 * x + 0.5 * z);
        let mesh = tessellate(&heights, 0.0, false).unwrap();
        assert_eq!(mesh.triangles.len(), 2 * 2 * 2);
        // The first value is the image's top-left pixel: x = 0, z = 1, height 0.5.
        assert_eq!(heights.values[0], 0.5);
        assert!(mesh.positions.contains(&Vec3::new(0.0, 0.5, 1.0)));
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = (b - a).cross(c - a).normalize();
            // The plane y = x/4 + z/2 has the normal (-1/4, 1, -1/2).
            assert!((n - Vec3::new(-0.25, 1.0, -0.5).normalize()).length() < 1e-5, "{n}");
        }
    }

    #[test]
    fn smooth_normals_of_a_sphere_cap_point_away_from_its_centre() {
        // The cap of the sphere of radius 2 about (0.5, -1.5, 0.5): heights up to 0.5.
        let heights = grid(33, |x, z| (4.0 - (x - 0.5).powi(2) - (z - 0.5).powi(2)).sqrt() - 1.5);
        let mesh = tessellate(&heights, 0.0, true).unwrap();
        let normals = mesh.normals.unwrap();
        for (p, n) in mesh.positions.iter().zip(&normals) {
            let radial = (*p - Vec3::new(0.5, -1.5, 0.5)).normalize();
            assert!(n.dot(radial) > 0.999, "{p}: {n} against {radial}");
        }
    }

    #[test]
    fn the_solid_is_closed_faces_out_and_holds_the_points_below_the_sheet() {
        use crate::geometry::TriangleMesh;
        let f = |x: f32, z: f32| 0.3 + 0.2 * (6.0 * x).sin() * z;
        let mesh = solid(&grid(9, f));
        // Outward: the divergence theorem gives the enclosed volume from the faces.
        let volume: f32 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        let solid = TriangleMesh::new(mesh);
        assert!(solid.is_closed());
        // The mean height of the sheet (0.3007), and the unit below it down to the floor.
        assert!((volume - 1.3).abs() < 0.01, "volume {volume}");
        for (x, z) in [(0.1, 0.2), (0.5, 0.9), (0.93, 0.4), (0.25, 0.75)] {
            let h = f(x, z);
            assert!(solid.contains(Vec3::new(x, 0.7 * h, z)), "below the sheet at {x}, {z}");
            assert!(solid.contains(Vec3::new(x, -0.95, z)), "above the floor at {x}, {z}");
            assert!(!solid.contains(Vec3::new(x, h + 0.05, z)), "above the sheet at {x}, {z}");
            assert!(!solid.contains(Vec3::new(x, -1.05, z)), "below the floor at {x}, {z}");
        }
        assert!(!solid.contains(Vec3::new(1.05, 0.1, 0.5)), "beside the square");
        assert!(!solid.contains(Vec3::new(0.5, -0.5, -0.05)), "in front of the square");
    }

    #[test]
    fn below_the_water_level_triangles_are_cut_away() {
        // A ramp from 0 at x = 0 to 1 at x = 1: above 0.3 only x >= 0.3 is left.
        let heights = grid(5, |x, _| x);
        let mesh = tessellate(&heights, 0.3, false).unwrap();
        let used: Vec<Vec3> =
            mesh.triangles.iter().flatten().map(|&i| mesh.positions[i as usize]).collect();
        assert!(used.iter().all(|p| p.y >= 0.3 - 1e-6), "nothing below the water");
        assert!(used.iter().any(|p| (p.x - 0.3).abs() < 1e-6), "cut along it");
        // The area left is 0.7 of the plane's (whose area is sqrt(2)).
        let area: f32 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        assert!((area - 0.7 * 2f32.sqrt()).abs() < 1e-5, "{area}");
        assert!(tessellate(&heights, 1.5, false).is_none(), "all under water");
    }
}
