//! Writes the mesh of benchmark scene S6 (`scenes/mesh-heavy.scn`), too large to keep in the
//! repository: a geodesic icosphere of frequency 224 (20 · 224² = 1,003,520 triangles,
//! counter-clockwise seen from outside), displaced radially to
//! r(u) = 0.5 (1 + 0.05 sin 12uₓ sin 12u_y sin 12u_z + 0.03 sin 20(uₓ + u_y + u_z)
//!             + 0.02 cos(31uₓ − 17u_z)),
//! u the unit direction, centred at (0, −0.4, 0), as binary little-endian PLY.
//!
//! `cargo run --release --example bumpy_sphere [-- OUT.ply]` (default `scenes/data/bumpy.ply`).

use std::collections::HashMap;
use std::io::{BufWriter, Write};

const FREQUENCY: u32 = 224;
const CENTRE: [f64; 3] = [0.0, -0.4, 0.0];

/// The icosahedron's corners (unit length) and its faces, counter-clockwise from outside.
fn icosahedron() -> ([[f64; 3]; 12], [[usize; 3]; 20]) {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let corners = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .map(normalize);
    #[rustfmt::skip]
    let faces = [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    (corners, faces)
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / length)
}

/// The displaced radius in the unit direction `u`.
fn radius(u: [f64; 3]) -> f64 {
    let [x, y, z] = u;
    0.5 * (1.0
        + 0.05 * (12.0 * x).sin() * (12.0 * y).sin() * (12.0 * z).sin()
        + 0.03 * (20.0 * (x + y + z)).sin()
        + 0.02 * (31.0 * x - 17.0 * z).cos())
}

/// A point of the subdivided icosahedron, named by its integer weights on the corners (summing
/// to the frequency): zero weights dropped and the rest sorted by corner, so that a point on an
/// edge or corner shared by several faces has one name.
type Weights = [(usize, u32); 3];

const NO_CORNER: (usize, u32) = (usize::MAX, 0);

fn main() -> std::io::Result<()> {
    let output = std::env::args().nth(1).unwrap_or_else(|| "scenes/data/bumpy.ply".to_string());
    let (corners, faces) = icosahedron();
    let n = FREQUENCY;
    let mut index: HashMap<Weights, u32> = HashMap::new();
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut vertex = |mut weights: Weights| -> u32 {
        for w in &mut weights {
            if w.1 == 0 {
                *w = NO_CORNER;
            }
        }
        weights.sort();
        *index.entry(weights).or_insert_with(|| {
            let mut p = [0.0; 3];
            for (corner, weight) in weights.into_iter().filter(|&w| w != NO_CORNER) {
                for (p, c) in p.iter_mut().zip(corners[corner]) {
                    *p += c * f64::from(weight) / f64::from(n);
                }
            }
            let u = normalize(p);
            let r = radius(u);
            positions.push([0, 1, 2].map(|i| (CENTRE[i] + r * u[i]) as f32));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(20 * (n * n) as usize);
    for [a, b, c] in faces {
        // Point (i, j) is a + (b - a) i/n + (c - a) j/n.
        let mut at = |i: u32, j: u32| vertex([(a, n - i - j), (b, i), (c, j)]);
        for i in 0..n {
            for j in 0..n - i {
                triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < n {
                    triangles.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
    }
    let mut file = BufWriter::new(std::fs::File::create(&output)?);
    write!(
        file,
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        positions.len(),
        triangles.len()
    )?;
    for p in &positions {
        for c in p {
            file.write_all(&c.to_le_bytes())?;
        }
    }
    for t in &triangles {
        file.write_all(&[3])?;
        for i in t {
            file.write_all(&i.to_le_bytes())?;
        }
    }
    file.flush()?;
    println!("{output}: {} vertices, {} triangles", positions.len(), triangles.len());
    Ok(())
}
