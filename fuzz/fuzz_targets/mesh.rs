//! Mesh files: the first byte picks PLY or OBJ, the rest is the file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raydiance::mesh::{MeshFormat, parse};

fuzz_target!(|data: &[u8]| {
    if let Some((&selector, bytes)) = data.split_first() {
        let format = if selector % 2 == 0 { MeshFormat::Ply } else { MeshFormat::Obj };
        if let Ok(mesh) = parse(bytes, format) {
            let _ = raydiance::geometry::TriangleMesh::new(mesh);
        }
    }
});
