//! `raydiance denoise`: with the cargo feature `denoise` (Intel Open Image Denoise, fetched by
//! scripts/fetch-oidn), guided by the albedo and normal AOVs, it brings a 16-spp render of
//! cornell-area at least 3 times nearer a converged one; without it, it says how to build it.
//!
//! The converged render is committed, made by (docs/cli.md#denoise):
//! `raydiance render scenes/cornell-area.scn --width 128 --height 128 --samples 4096 --seed 1
//! -o tests/denoise/cornell-area-128-4096spp.exr`

#[cfg(feature = "denoise")]
use std::path::Path;
use std::process::{Command, Output};

fn raydiance(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raydiance")).args(args).output().unwrap()
}

#[cfg(feature = "denoise")]
fn succeeds(args: &[&str]) -> String {
    let output = raydiance(args);
    assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Root mean square error over every pixel's linear RGB.
#[cfg(feature = "denoise")]
fn rmse(image: &Path, reference: &Path) -> f64 {
    let read = |p: &Path| raydiance::image::exr::read(p).unwrap();
    let (image, reference) = (read(image), read(reference));
    assert_eq!((image.width, image.height), (reference.width, reference.height));
    let squares: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| f64::from((*a - *b).length_squared()))
        .sum();
    (squares / (3 * image.pixels.len()) as f64).sqrt()
}

#[cfg(feature = "denoise")]
#[test]
fn albedo_and_normal_guided_denoising_divides_the_error_by_three() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let reference = Path::new("tests/denoise/cornell-area-128-4096spp.exr");
    let render = |out: &str, aovs: &[&str]| {
        let mut args = vec!["render", "scenes/cornell-area.scn", "--width", "128"];
        args.extend(["--height", "128", "--samples", "16", "-o", out]);
        args.extend(aovs);
        succeeds(&args);
    };
    let (noisy, guided) = (path("noisy.exr"), path("guided.exr"));
    render(&noisy, &["--aov", "albedo,normal"]);
    let before = std::fs::read(&noisy).unwrap();
    let summary = succeeds(&["denoise", &noisy, "-o", &guided]);
    assert!(summary.contains("from the beauty, albedo and normal"), "{summary}");
    assert_eq!(std::fs::read(&noisy).unwrap(), before, "the render stays as it was");
    let (plain, alone) = (path("plain.exr"), path("alone.exr"));
    render(&plain, &[]);
    let summary = succeeds(&["denoise", &plain, "-o", &alone]);
    assert!(summary.contains("from the beauty alone"), "{summary}");

    let raw = rmse(Path::new(&noisy), reference);
    let beauty_only = rmse(Path::new(&alone), reference);
    let with_guides = rmse(Path::new(&guided), reference);
    println!(
        "RMSE against 4096 spp: raw {raw:.5}, beauty only {beauty_only:.5}, albedo and normal {with_guides:.5}"
    );
    assert!(raw >= 3.0 * with_guides, "raw {raw}, denoised with albedo and normal {with_guides}");
}

#[cfg(feature = "denoise")]
#[test]
fn a_part_is_refused_and_so_is_writing_over_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let part = path("part.exr");
    let small = ["--width", "8", "--height", "8", "--samples", "2", "--part", "0/2"];
    succeeds(&[&["render", "scenes/cornell-area.scn", "-o", &part][..], &small[..]].concat());
    let out = path("out.exr");
    let output = raydiance(&["denoise", &part, "-o", &out]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("merge the parts first"));
    assert!(!Path::new(&out).exists());
    let output = raydiance(&["denoise", &part, "-o", &part]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("is the input"));
}

#[cfg(not(feature = "denoise"))]
#[test]
fn without_the_feature_denoise_says_how_to_build_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    let reference = "tests/denoise/cornell-area-128-4096spp.exr";
    let output = raydiance(&["denoise", reference, "-o", out.to_str().unwrap()]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--features denoise") && stderr.contains("scripts/fetch-oidn"));
    assert!(!out.exists());
}
