//! The integration tests, compiled and linked as one binary (Cargo.toml: `autotests = false`):
//! one link of the library and the dependencies instead of one per file, and one pool of test
//! threads, so a file's slow test runs beside the other files' tests instead of after them. Each
//! file of `tests/` is a module here; `every_file_of_tests_is_a_module_here` fails for one that is
//! not. `cargo test --test all parse::` runs one file's tests. `tests/denoise.rs` is a binary of
//! its own: CI builds it with the `denoise` feature alone.

mod common;

mod aovs;
mod area_spotlight;
mod bad_inputs;
mod camera;
mod chi_square;
mod cli;
mod csg_scenes;
mod determinism;
mod direct_light;
mod docs;
mod environment_light;
mod fuzz_regressions;
mod hostile_inputs;
mod image_io;
mod language_equivalence;
mod layers;
mod media;
mod meshes;
mod mutated_scenes;
mod parse;
mod path_tracing;
mod patterns;
mod photon_emission;
mod photon_mapping;
mod plastic_bsdf;
mod povray_appearance;
mod povray_builtins;
mod povray_dialect;
mod povray_directives;
mod povray_language;
mod povray_lights;
mod povray_oracle;
mod povray_transforms;
mod preview;
mod preview_browser;
mod ray_lanes;
mod render_job;
mod render_snapshots;
mod robustness;
mod rough_bsdf;
mod slurm;
mod snapshot;
mod solids;
mod split_cli;
mod split_merge;
mod textures;

use std::path::Path;

/// A test file cargo no longer finds on its own (autotests are off) would never run: every
/// `tests/*.rs` but this one and `denoise.rs` is declared above, and no folder of `tests/` is a
/// test binary of its own (`main.rs`).
#[test]
fn every_file_of_tests_is_a_module_here() {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let declared = include_str!("all.rs");
    for entry in std::fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap();
        if path.is_dir() {
            assert!(!path.join("main.rs").exists(), "tests/{name}/main.rs is not built");
        } else if let Some(module) = name.strip_suffix(".rs") {
            let standalone = ["all", "denoise"].contains(&module);
            assert!(
                standalone || declared.lines().any(|line| line == format!("mod {module};")),
                "tests/{name} is not declared in tests/all.rs (`mod {module};`): it would not run"
            );
        }
    }
}
