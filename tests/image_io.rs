//! Image files: EXR and HDR PPM round trips, OpenEXR's own reader, malformed PPMs.

use crate::common;

use std::path::Path;

use glam::Vec3;
use raydiance::image::{Image, RenderInfo, exr, ppm};

/// A non-square image with values across many magnitudes, and zeros.
fn test_image() -> Image {
    let (width, height) = (7, 5);
    let pixels = (0..width * height)
        .map(|i| {
            let f = i as f32;
            Vec3::new(
                f * 1e-4,
                (f * 0.37).sin().abs() * 1e3,
                if i % 3 == 0 { 0.0 } else { 1.0 / (f + 1.0) },
            )
        })
        .collect();
    Image { width, height, pixels }
}

fn info() -> RenderInfo {
    RenderInfo {
        samples_per_pixel: 64,
        integrator: "path".into(),
        seed: 7,
        seconds: 1.25,
        parameters: vec![("max_depth", "32".into())],
    }
}

#[test]
fn exr_round_trip_is_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("round.exr");
    let image = test_image();
    exr::write(&path, &image, &info()).unwrap();
    let read = exr::read(&path).unwrap();
    assert_eq!((read.width, read.height), (image.width, image.height));
    let bits = |img: &Image| {
        img.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>()
    };
    assert_eq!(bits(&read), bits(&image));
    assert_eq!(exr::read_samples_per_pixel(&path).unwrap(), Some(64));
}

#[test]
fn openexr_tools_read_our_files_and_their_metadata() {
    let test = "openexr_tools_read_our_files_and_their_metadata";
    if !common::outside_tool("exrheader", "openexr", test) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("meta.exr");
    exr::write(&path, &test_image(), &info()).unwrap();
    let output = std::process::Command::new("exrheader").arg(&path).output().unwrap();
    assert!(output.status.success());
    let text = String::from_utf8_lossy(&output.stdout);
    for expected in [
        "raydiance:samples_per_pixel (type int): 64",
        "raydiance:integrator (type string): \"path\"",
        "raydiance:seed (type string): \"7\"",
        "raydiance:render_seconds (type double): 1.25",
        "raydiance:max_depth (type string): \"32\"",
        "R, 32-bit floating-point",
        "lineOrder (type lineOrder): increasing y",
        "dataWindow (type box2i): (0 0) - (6 4)",
    ] {
        assert!(text.contains(expected), "exrheader shows `{expected}`:\n{text}");
    }
}

#[test]
fn hdr_ppm_round_trip_within_half_a_step() {
    let dir = tempfile::tempdir().unwrap();
    let image = test_image();
    let max = image.max_component();
    for res in [255, 10_000_000] {
        let path = dir.path().join(format!("round{res}.ppm"));
        ppm::write_hdr(&path, &image, res).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with(&format!("P3\n#MAX={max}\n# round{res}.ppm\n7 5\n{res}\n")),
            "{text}"
        );
        let read = ppm::parse(text.as_bytes()).unwrap();
        let step = max / res as f32;
        // Half a quantisation step, plus the f32 rounding of the decoded value itself.
        for (a, b) in read.pixels.iter().zip(&image.pixels) {
            let bound = 0.5 * step + b.abs() * f32::EPSILON;
            assert!((*a - *b).abs().cmple(bound).all(), "{a} vs {b} (res {res})");
        }
    }
}

#[test]
fn malformed_ppms_say_where() {
    insta::glob!("bad_ppm/*.ppm", |path| {
        let bytes = std::fs::read(path).unwrap();
        let message = ppm::parse(&bytes).expect_err("a malformed file must be an error");
        insta::assert_snapshot!(message.to_string());
    });
}

#[test]
fn all_black_image_writes_and_reads_back_as_black() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("black.ppm");
    ppm::write_hdr(&path, &Image::new(3, 2), ppm::HDR_RES).unwrap();
    let read = ppm::parse(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!(read, Image::new(3, 2));
    assert!(Path::new(&path).exists());
}
