//! AOVs (`render --aov`): what they hold at the first surface that is not a perfect mirror or
//! glass, and that split renders merge into a single render's.

use crate::common;

use std::path::Path;
use std::process::Command;

use glam::Vec3;
use raydiance::aov::{self, AovImage, AovList};
use raydiance::region::Region;
use raydiance::scene::Scene;

fn every_aov() -> AovList {
    "albedo,normal,depth,position".parse().unwrap()
}

fn render_aovs(scene: &Scene) -> AovImage {
    let s = &scene.settings;
    aov::render(scene, &Region::whole(s.width, s.height, s.samples), s.samples, &every_aov())
}

/// The value of a three-channel AOV (`albedo`, `normal`, `position`) at a pixel.
fn vector(image: &AovImage, name: &str, pixel: usize) -> Vec3 {
    let suffixes = if name == "albedo" { ["R", "G", "B"] } else { ["X", "Y", "Z"] };
    let channel = |suffix| image.plane(&format!("{name}.{suffix}")).unwrap()[pixel];
    Vec3::new(channel(suffixes[0]), channel(suffixes[1]), channel(suffixes[2]))
}

fn depth(image: &AovImage, pixel: usize) -> f32 {
    image.plane("depth.T").unwrap()[pixel]
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).abs().max_element() <= tolerance
}

#[test]
fn the_albedo_of_a_diffuse_plane_is_its_diffuse_colour() {
    let scene = common::scene(
        "settings { resolution 9, 7  samples 8 }
        camera { location <0, 0, -3>  look_at <0, 0, 0>  angle 40 }
        plane { <0, 0, -1>, 0  material { diffuse rgb <0.2, 0.5, 0.7> } }",
    );
    let aovs = render_aovs(&scene);
    for pixel in 0..9 * 7 {
        let albedo = vector(&aovs, "albedo", pixel);
        assert!(close(albedo, Vec3::new(0.2, 0.5, 0.7), 1e-6), "pixel {pixel}: {albedo}");
        let normal = vector(&aovs, "normal", pixel);
        assert!(close(normal, Vec3::new(0.0, 0.0, -1.0), 1e-6), "pixel {pixel}: {normal}");
        assert!(vector(&aovs, "position", pixel).z.abs() < 1e-5);
    }
}

/// An emitter's albedo is its emission added to what it reflects, each channel at most 1 (the
/// denoiser's guide then marks a light as the bright surface it is, not as a black one).
#[test]
fn the_albedo_of_an_emitter_is_its_emission_clamped_to_one() {
    let scene = common::scene(
        "settings { resolution 5, 4  samples 4 }
        camera { location <0, 0, -3>  look_at <0, 0, 0>  angle 40 }
        plane { <0, 0, -1>, 0  material { diffuse rgb 0.2  emission rgb <10, 0.5, 0> } }",
    );
    let aovs = render_aovs(&scene);
    for pixel in 0..5 * 4 {
        let albedo = vector(&aovs, "albedo", pixel);
        assert!(close(albedo, Vec3::new(1.0, 0.7, 0.2), 1e-6), "pixel {pixel}: {albedo}");
    }
}

/// At one sample a pixel, each pixel's normal is the sphere's at the point it records: there
/// (p - c) / r, with |p - c| = r and depth the distance from the pinhole.
#[test]
fn the_normals_of_a_sphere_are_the_analytic_ones() {
    let (centre, radius) = (Vec3::new(0.2, -0.1, 0.5), 0.8);
    let eye = Vec3::new(0.0, 0.0, -3.0);
    let scene = common::scene(&format!(
        "settings {{ resolution 24, 20  samples 1 }}
        camera {{ location <0, 0, -3>  look_at <0, 0, 0>  angle 50 }}
        sphere {{ <{}, {}, {}>, {radius}  material {{ diffuse rgb 0.5 }} }}",
        centre.x, centre.y, centre.z
    ));
    let aovs = render_aovs(&scene);
    let mut on_sphere = 0;
    for pixel in 0..24 * 20 {
        let (point, normal) = (vector(&aovs, "position", pixel), vector(&aovs, "normal", pixel));
        if depth(&aovs, pixel) == 0.0 {
            assert_eq!((point, normal), (Vec3::ZERO, Vec3::ZERO), "a miss records nothing");
            continue;
        }
        on_sphere += 1;
        assert!(((point - centre).length() - radius).abs() < 1e-4, "pixel {pixel}: {point}");
        let analytic = (point - centre) / radius;
        assert!(close(normal, analytic, 1e-4), "pixel {pixel}: {normal} != {analytic}");
        assert!((depth(&aovs, pixel) - point.distance(eye)).abs() < 1e-4);
    }
    assert!(on_sphere > 100, "the sphere covers much of the image ({on_sphere} pixels)");
}

/// A mirror facing the camera shows a red wall behind the camera: the AOVs are the wall's, and
/// the depth is the way there and back.
#[test]
fn aovs_seen_in_a_mirror_are_the_reflected_objects() {
    let scene = common::scene(
        "settings { resolution 8, 6  samples 4 }
        camera { location <0, 0, -3>  look_at <0, 0, 0>  angle 20 }
        plane { <0, 0, -1>, 0  material { specular rgb 1 } }
        plane { <0, 0, 1>, 10  material { diffuse rgb <0.9, 0.1, 0.1> } }",
    );
    let aovs = render_aovs(&scene);
    for pixel in 0..8 * 6 {
        let albedo = vector(&aovs, "albedo", pixel);
        assert!(close(albedo, Vec3::new(0.9, 0.1, 0.1), 1e-6), "pixel {pixel}: {albedo}");
        let normal = vector(&aovs, "normal", pixel);
        assert!(close(normal, Vec3::new(0.0, 0.0, 1.0), 1e-6), "pixel {pixel}: {normal}");
        assert!((vector(&aovs, "position", pixel).z + 10.0).abs() < 1e-4);
        // 3 to the mirror, 10 back to the wall, a little more off the axis (20 degrees wide).
        let depth = depth(&aovs, pixel);
        assert!((13.0..13.0 * 1.02).contains(&depth), "pixel {pixel}: depth {depth}");
    }
}

fn raydiance(args: &[&str]) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_raydiance")).args(args).output().unwrap();
    assert!(output.status.success(), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    output
}

/// Two shares and a tile, rendered with `--aov` and merged, hold the AOVs a single render
/// writes (within float rounding: the merge adds means times counts).
#[test]
fn merged_aovs_are_a_single_renders() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let scene = "scenes/cornell-specular.scn";
    let common = [
        "--width",
        "12",
        "--height",
        "10",
        "--samples",
        "6",
        "--aov",
        "albedo,normal,depth,position",
    ];
    let render = |extra: &[&str], out: &str| {
        let mut args = vec!["render", scene, "-o", out];
        args.extend(common);
        args.extend(extra);
        raydiance(&args);
    };
    let single = path("single.exr");
    render(&[], &single);
    let parts = [path("a.exr"), path("b.exr"), path("c.exr")];
    render(&["--part", "0/2", "--crop", "0,12,0,4"], &parts[0]);
    render(&["--part", "1/2", "--crop", "0,12,0,4"], &parts[1]);
    render(&["--crop", "0,12,4,10"], &parts[2]);
    let merged = path("merged.exr");
    raydiance(&["merge", &parts[0], &parts[1], &parts[2], "-o", &merged]);
    let read = |p: &str| raydiance::image::exr::read_aovs(Path::new(p)).unwrap();
    let (single, merged) = (read(&single), read(&merged));
    assert_eq!(merged.list, every_aov());
    assert_eq!((merged.width, merged.height), (12, 10));
    for ((name, a), (_, b)) in single.channels().zip(merged.channels()) {
        for (pixel, (a, b)) in a.iter().zip(b).enumerate() {
            assert!((a - b).abs() <= 1e-5 * a.abs().max(1.0), "{name} at {pixel}: {a} != {b}");
        }
    }
    assert!(single.plane("albedo.R").unwrap().iter().any(|v| *v > 0.0));
}

#[test]
fn parts_with_other_aovs_do_not_merge() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (a, b) = (path("a.exr"), path("b.exr"));
    let small = ["--width", "4", "--height", "4", "--samples", "2"];
    let mut args = vec!["render", "scenes/cornell-area.scn", "--part", "0/2", "-o", &a];
    args.extend(small);
    raydiance(&[&args[..], &["--aov", "albedo"][..]].concat());
    let mut args = vec!["render", "scenes/cornell-area.scn", "--part", "1/2", "-o", &b];
    args.extend(small);
    raydiance(&args);
    let out = path("out.exr");
    let output = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["merge", &a, &b, "-o", &out])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("other AOVs (--aov albedo and no AOVs)"), "{stderr}");
    assert!(!Path::new(&out).exists());
}

#[test]
fn aovs_into_a_png_are_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let output = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", "scenes/cornell-area.scn", "--aov", "normal", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("name it .exr"));
    assert!(!out.exists());
}
