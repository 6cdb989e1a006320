//! Every bad input — scenes, meshes (through scenes), PPM and EXR images, command-line values —
//! ends with a non-zero exit (not a panic), a message that locates the problem, and no output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn raydiance(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raydiance")).args(args).output().unwrap()
}

fn files(folder: &str, extension: &str) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == extension))
        .collect();
    found.sort();
    found
}

/// Runs `args` with the output `out` in a fresh folder; checks the failure; returns stderr.
fn assert_fails_cleanly(args: &[&str], output_name: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join(output_name);
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["-o", out.to_str().unwrap()]);
    let output = raydiance(&all);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    // 101 is Rust's exit status for a panic.
    assert_eq!(output.status.code(), Some(1), "{args:?}:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}:\n{stderr}");
    assert!(stderr.contains("error"), "{args:?}:\n{stderr}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "{args:?} left a file behind");
    stderr
}

#[test]
fn bad_scenes_and_meshes() {
    let scenes = files("tests/bad_scenes", "scn");
    for scene in &scenes {
        let path = scene.to_str().unwrap();
        let stderr = assert_fails_cleanly(&["render", path], "out.exr");
        // file:line:col of the scene or of a file it includes, then the line and a caret.
        assert!(
            stderr.starts_with("tests/bad_scenes/") && stderr.contains(": error: "),
            "{stderr}"
        );
        assert!(stderr.contains(" | ") && stderr.contains('^'), "{path} shows the line:\n{stderr}");
    }
    assert!(scenes.len() >= 40, "{} bad scenes", scenes.len());
}

#[test]
fn bad_ppm_images() {
    let images = files("tests/bad_ppm", "ppm");
    for image in &images {
        let path = image.to_str().unwrap();
        let stderr = assert_fails_cleanly(&["tonemap", path], "out.png");
        assert!(stderr.starts_with(&format!("error: {path}: ")), "names the file:\n{stderr}");
        let located = ["line ", "byte ", "more than raydiance reads", "the file is empty"];
        assert!(located.iter().any(|l| stderr.contains(l)), "{path} is located:\n{stderr}");
    }
    assert!(images.len() >= 13);
}

/// EXR files made here: not EXR at all, empty, cut short, and without colour channels.
fn bad_exr_files(dir: &Path) -> Vec<PathBuf> {
    use exr::prelude::*;
    let garbage = dir.join("garbage.exr");
    std::fs::write(&garbage, b"this is not an OpenEXR file at all").unwrap();
    let empty = dir.join("empty.exr");
    std::fs::write(&empty, b"").unwrap();
    let valid = dir.join("valid.exr");
    let image = raydiance::image::Image::new(16, 16);
    let info = raydiance::image::RenderInfo {
        samples_per_pixel: 1,
        integrator: "path".into(),
        seed: 0,
        seconds: 0.0,
        parameters: Vec::new(),
    };
    raydiance::image::exr::write(&valid, &image, &info).unwrap();
    let bytes = std::fs::read(&valid).unwrap();
    let truncated = dir.join("truncated.exr");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let luminance_only = dir.join("luminance_only.exr");
    let channel = AnyChannel::new("Y", FlatSamples::F32(vec![0.5; 16]));
    let layer = Layer::new(
        (4, 4),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(vec![channel].into()),
    );
    Image::from_layer(layer).write().to_file(&luminance_only).unwrap();
    vec![garbage, empty, truncated, luminance_only]
}

#[test]
fn bad_exr_images() {
    let dir = tempfile::tempdir().unwrap();
    for image in bad_exr_files(dir.path()) {
        let path = image.to_str().unwrap();
        let stderr = assert_fails_cleanly(&["tonemap", path], "out.ppm");
        assert!(stderr.starts_with(&format!("error: {path}: ")), "names the file:\n{stderr}");
    }
}

#[test]
fn bad_command_line_values() {
    let scene = "scenes/lab4-direct.scn";
    for (args, value) in [
        (vec!["render", scene, "--samples", "0"], "--samples 0"),
        (vec!["render", scene, "--height", "70000"], "--height 70000"),
        (vec!["render", scene, "--max-depth", "5000"], "--max-depth 5000"),
        (vec!["render", scene, "--ppm-res", "0"], "--ppm-res"),
        (vec!["render", "no_such_scene.scn"], "no_such_scene.scn"),
        (vec!["tonemap", "tests/bad_ppm/empty.ppm", "--v", "-1"], "--v -1"),
        (vec!["tonemap", "tests/bad_ppm/empty.ppm", "--white", "0"], "--white 0"),
    ] {
        let output_name =
            if args[0] == "render" && value == "--ppm-res" { "out.ppm" } else { "out.png" };
        let stderr = assert_fails_cleanly(&args, output_name);
        assert!(stderr.contains(value), "names {value}:\n{stderr}");
    }
}
