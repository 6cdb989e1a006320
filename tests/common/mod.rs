//! Helpers shared by the integration tests: scenes from text, small renders.
#![allow(dead_code)] // each test binary uses its own subset

use std::path::Path;

use glam::Vec3;
use raydiance::film::Film;
use raydiance::image::Image;
use raydiance::render::{Silent, render};
use raydiance::scene::{Scene, build};

/// The lab box of the seed's scene without lights or spheres, for tests to add to.
pub const LAB_BOX: &str = r#"
camera { origin <0, 0, -3.5>  left <-1, 0, 0>  up <0, 1, 0>  forward <0, 0, 3> }
plane { <1, 0, 0>, 1   material { diffuse rgb <0.8, 0.1, 0.1> } }
plane { <-1, 0, 0>, 1  material { diffuse rgb <0.1, 0.8, 0.1> } }
plane { <0, 1, 0>, 1   material { diffuse rgb 0.8 } }
plane { <0, -1, 0>, 1  material { diffuse rgb 0.8 } }
plane { <0, 0, -1>, 1  material { diffuse rgb 0.8 } }
"#;

/// Builds a scene from `.scn` text (as if read from `tests/inline.scn`).
pub fn scene(text: &str) -> Scene {
    let graph = raydiance::lang::parse_scene(Path::new("tests/inline.scn"), text)
        .unwrap_or_else(|e| panic!("test scene does not parse:\n{e}"));
    build(&graph).unwrap_or_else(|e| panic!("test scene does not build:\n{e}"))
}

pub fn scene_file(path: &str) -> Scene {
    let graph = raydiance::lang::load_scene(Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    build(&graph).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders with the scene's own settings.
pub fn render_image(scene: &Scene) -> Image {
    render(scene, &Silent).0.image()
}

pub fn render_film(scene: &Scene) -> Film {
    render(scene, &Silent).0
}

pub fn max_abs_difference(a: &Image, b: &Image) -> f32 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p - *q).abs().max_element()).fold(0.0, f32::max)
}

pub fn mean(image: &Image) -> Vec3 {
    image.pixels.iter().sum::<Vec3>() / image.pixels.len() as f32
}

/// Whether an outside program a test runs (e.g. OpenEXR's `exrheader`) is on the PATH. Without it the test is skipped, with one line on the terminal saying so; under CI
/// (`CI=true`, where `.ci/run` installs it) its absence fails the test.
pub fn outside_tool(name: &str, package: &str, test: &str) -> bool {
    let found = std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|folder| folder.join(name).is_file())
    });
    if found {
        return true;
    }
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "{test}: `{name}` (Debian package `{package}`) must be installed under CI"
    );
    // Written to stderr directly: the test harness captures `eprintln!` of passing tests.
    use std::io::Write;
    let line = format!("skipped {test}: `{name}` is not installed (Debian package `{package}`)\n");
    let _ = std::io::stderr().write_all(line.as_bytes());
    false
}
