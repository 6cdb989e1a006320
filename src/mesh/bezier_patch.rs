//! POV-Ray's `bicubic_patch` as smooth triangles, as its type 1 patch is: the Bézier patch of 16
//! control points cut into 2^u_steps by 2^v_steps pieces, two triangles each, whose vertices lie
//! on the surface and carry its normals there (interpolated across each triangle).

use glam::{Vec2, Vec3};

use super::Mesh;

/// The most steps either way: 2^8 by 2^8 pieces, 131 072 triangles.
pub const MAX_PATCH_STEPS: u32 = 8;

/// The cubic Bernstein weights at t.
fn weights(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// The weights' derivatives at t.
fn slopes(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [-3.0 * s * s, 3.0 * s * (s - 2.0 * t), 3.0 * t * (2.0 * s - t), 3.0 * t * t]
}

/// The control points (row by row, u along a row) weighted by `along_u` and `along_v`.
fn blend(points: &[Vec3; 16], along_u: [f32; 4], along_v: [f32; 4]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for (row, wv) in along_v.iter().enumerate() {
        for (column, wu) in along_u.iter().enumerate() {
            sum += wu * wv * points[4 * row + column];
        }
    }
    sum
}

/// The point of the patch at (u, v).
pub fn patch_point(points: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    blend(points, weights(u), weights(v))
}

/// The unit normal of the patch at (u, v), along dP/du x dP/dv; zero only where the patch has
/// no tangent plane anywhere near. Where an edge of control points collapses to one point (the
/// teapot's lid) the tangents vanish: the normal there is its limit from inside the patch.
pub fn patch_normal(points: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    let size = points.iter().map(|p| (*p - points[0]).length()).fold(0.0, f32::max);
    let at = Vec2::new(u, v);
    for nudge in [0.0, 1e-4, 1e-3, 1e-2, 1e-1] {
        let (u, v) = at.lerp(Vec2::splat(0.5), nudge).into();
        let du = blend(points, slopes(u), weights(v));
        let dv = blend(points, weights(u), slopes(v));
        let normal = du.cross(dv);
        if normal.length() > 1e-6 * size * size {
            return normal.normalize();
        }
    }
    Vec3::ZERO
}

/// The patch as a mesh of `2^steps[0] * 2^steps[1] * 2` triangles (steps at most
/// `MAX_PATCH_STEPS`), less those of no area (where control points coincide).
pub fn tessellate(points: &[Vec3; 16], steps: [u32; 2]) -> Mesh {
    let [columns, rows] = steps.map(|s| 1usize << s.min(MAX_PATCH_STEPS));
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    for row in 0..=rows {
        let v = row as f32 / rows as f32;
        for column in 0..=columns {
            let u = column as f32 / columns as f32;
            positions.push(patch_point(points, u, v));
            normals.push(patch_normal(points, u, v));
        }
    }
    let mut triangles = Vec::with_capacity(2 * columns * rows);
    for row in 0..rows {
        for column in 0..columns {
            let a = (row * (columns + 1) + column) as u32;
            let (b, c) = (a + 1, a + columns as u32 + 1);
            for triangle in [[a, b, c + 1], [a, c + 1, c]] {
                let [p, q, r] = triangle.map(|i| positions[i as usize]);
                if (q - p).cross(r - p) != Vec3::ZERO {
                    triangles.push(triangle);
                }
            }
        }
    }
    Mesh { positions, normals: Some(normals), triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A patch bent both ways: the corners of the unit square lifted and pulled.
    fn saddle() -> [Vec3; 16] {
        std::array::from_fn(|k| {
            let (column, row) = ((k % 4) as f32, (k / 4) as f32);
            Vec3::new(column, row, (column - 1.5) * (row - 1.5) * 0.4 + 0.1 * column * column)
        })
    }

    #[test]
    fn the_patch_meets_its_corner_points_and_its_weights_sum_to_one() {
        let points = saddle();
        for (u, v, corner) in [(0.0, 0.0, 0), (1.0, 0.0, 3), (0.0, 1.0, 12), (1.0, 1.0, 15)] {
            assert!((patch_point(&points, u, v) - points[corner]).length() < 1e-6);
        }
        for t in [0.0, 0.3, 0.77, 1.0] {
            assert!((weights(t).iter().sum::<f32>() - 1.0).abs() < 1e-6, "{t}");
            assert!(slopes(t).iter().sum::<f32>().abs() < 1e-5, "{t}");
        }
    }

    #[test]
    fn normals_are_across_the_surface_s_tangents() {
        let points = saddle();
        let (u, v, h) = (0.37, 0.61, 1e-3);
        let normal = patch_normal(&points, u, v);
        let along_u = patch_point(&points, u + h, v) - patch_point(&points, u - h, v);
        let along_v = patch_point(&points, u, v + h) - patch_point(&points, u, v - h);
        assert!((normal.length() - 1.0).abs() < 1e-5);
        assert!(normal.dot(along_u.normalize()).abs() < 1e-3, "{normal} . {along_u}");
        assert!(normal.dot(along_v.normalize()).abs() < 1e-3, "{normal} . {along_v}");
    }

    #[test]
    fn a_collapsed_edge_keeps_normals_from_inside_and_drops_its_flat_triangles() {
        // The first row of control points all at one point, as at the top of the teapot's lid.
        let mut points = saddle();
        for point in &mut points[..4] {
            *point = Vec3::new(1.5, 0.0, 0.5);
        }
        let mesh = tessellate(&points, [2, 2]);
        let normals = mesh.normals.as_ref().unwrap();
        assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4), "{normals:?}");
        // The four pieces along the collapsed row lose one triangle each.
        assert_eq!(mesh.triangles.len(), 2 * 4 * 4 - 4);
    }

    #[test]
    fn the_mesh_has_two_triangles_per_piece_on_the_surface() {
        let points = saddle();
        let mesh = tessellate(&points, [3, 1]);
        assert_eq!(mesh.triangles.len(), 2 * 8 * 2);
        assert_eq!(mesh.positions.len(), 9 * 3);
        // A vertex in the middle of the grid is the patch's point there.
        let middle = mesh.positions[9 + 4];
        assert!((middle - patch_point(&points, 0.5, 0.5)).length() < 1e-6);
        // Each triangle's face normal agrees in side with its vertices' normals.
        let normals = mesh.normals.as_ref().unwrap();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let face = (b - a).cross(c - a);
            assert!(t.iter().all(|&i| normals[i as usize].dot(face) > 0.0), "{t:?}");
        }
    }
}
