//! The shipped scenes against their snapshots (`scenes/__snapshots__/`), through the same
//! statistical comparison as `raydiance snapshot`: a change that keeps the picture (a new
//! sampler, another CPU) passes; one that changes it fails, leaving `NAME.new.exr` and a heat map
//! `NAME.diff.png` beside the snapshot. Each snapshot was reviewed as a picture
//! (`raydiance tonemap scenes/__snapshots__/NAME.exr -o NAME.png`) before it was accepted with
//! `raydiance snapshot scenes --accept`. S6 (`mesh-heavy`) is left to that command: its mesh is
//! generated, not shipped.

use std::path::Path;

fn check(scene: &str) -> String {
    let path = format!("scenes/{scene}.scn");
    raydiance::snapshot::check(Path::new(&path), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .summary()
}

#[test]
fn lab4_direct() {
    insta::assert_snapshot!(check("lab4-direct"));
}

#[test]
fn lab4_gi_point() {
    insta::assert_snapshot!(check("lab4-gi-point"));
}

#[test]
fn cornell_area() {
    insta::assert_snapshot!(check("cornell-area"));
}

#[test]
fn cornell_specular() {
    insta::assert_snapshot!(check("cornell-specular"));
}

#[test]
fn gallery_textures() {
    insta::assert_snapshot!(check("gallery-textures"));
}

#[test]
fn gallery_bunnies() {
    insta::assert_snapshot!(check("gallery-bunnies"));
}

#[test]
fn gallery_rough() {
    insta::assert_snapshot!(check("rough"));
}

#[test]
fn cornell_rough() {
    insta::assert_snapshot!(check("cornell-rough"));
}

#[test]
fn gallery_csg() {
    insta::assert_snapshot!(check("gallery-csg"));
}

#[test]
fn mesh_bunny() {
    insta::assert_snapshot!(check("mesh-bunny"));
}
