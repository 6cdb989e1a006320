//! Inputs the fuzzers (`fuzz/`) found to crash, exhaust memory or hang, replayed through the
//! same entry points: each must now end in an error (or a result), promptly.

use std::path::PathBuf;

fn inputs(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let folder = format!("tests/fuzz_regressions/{target}");
    let mut found: Vec<_> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let bytes = std::fs::read(&path).unwrap();
            (path, bytes)
        })
        .collect();
    found.sort();
    assert!(!found.is_empty());
    found
}

#[test]
fn scene_inputs() {
    for (path, bytes) in inputs("scene") {
        let text = String::from_utf8_lossy(&bytes);
        let result = raydiance::lang::parse_scene(&path, &text);
        assert!(result.is_err(), "{}", path.display());
    }
}

#[test]
fn exr_inputs() {
    for (path, bytes) in inputs("exr") {
        let error = raydiance::image::exr::read_bytes(&bytes).unwrap_err();
        let too_large = matches!(error, raydiance::image::exr::ExrError::TooLarge { .. });
        assert!(too_large, "{}: {error}", path.display());
    }
}

#[test]
fn mesh_inputs() {
    // The fuzz target's format: the first byte picks PLY (even) or OBJ (odd).
    for (path, bytes) in inputs("mesh") {
        let format = if bytes[0] % 2 == 0 {
            raydiance::mesh::MeshFormat::Ply
        } else {
            raydiance::mesh::MeshFormat::Obj
        };
        // It used to loop for ages over an element of no bytes; now it ends, with an error.
        let start = std::time::Instant::now();
        let result = raydiance::mesh::parse(&bytes[1..], format);
        assert!(result.is_err(), "{}", path.display());
        assert!(start.elapsed().as_secs() < 5, "{} is no longer slow", path.display());
    }
}
