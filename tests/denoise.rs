//! `raydiance denoise`: with the cargo feature `denoise` (Intel Open Image Denoise, fetched by
//! scripts/fetch-oidn), guided by the albedo and normal AOVs, it brings a 16-spp render of
//! cornell-area at least 3 times nearer a converged one; without it, it says how to build it.
//! With it, `raydiance preview` shows each pass denoised beside the pass as rendered.
//!
//! The converged render is committed, made by (docs/cli.md#denoise):
//! `raydiance render scenes/cornell-area.scn --width 128 --height 128 --samples 4096 --seed 1
//! -o tests/denoise/cornell-area-128-4096spp.exr`

#[cfg(feature = "denoise")]
mod common;

#[cfg(feature = "denoise")]
use std::path::Path;

#[cfg(feature = "denoise")]
use glam::Vec3;
#[cfg(feature = "denoise")]
use raydiance::image::Image;
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

/// What an RMSE counts.
#[cfg(feature = "denoise")]
#[derive(Debug, Clone, Copy)]
enum Measure {
    /// Linear radiance, every pixel.
    Linear,
    /// Linear radiance, the pixels under 1 in every channel of the reference: all but the
    /// directly seen light (radiance 10) and its edges.
    UnderOne,
    /// Radiance as a display shows it at exposure 0: clamped to [0, 1] (the clamp of the default
    /// tone mapping, before its gamma), every pixel. The light is white either way.
    Displayed,
}

/// Root mean square error of `image`'s RGB against `reference`'s, as `measure` counts it.
#[cfg(feature = "denoise")]
fn rmse(image: &Image, reference: &Image, measure: Measure) -> f64 {
    assert_eq!((image.width, image.height), (reference.width, reference.height));
    let shown = |value: f32| match measure {
        Measure::Linear | Measure::UnderOne => value,
        Measure::Displayed => value.clamp(0.0, 1.0),
    };
    let counted = |reference: &Vec3| match measure {
        Measure::Linear | Measure::Displayed => true,
        Measure::UnderOne => reference.max_element() < 1.0,
    };
    let (mut squares, mut values) = (0.0, 0);
    for (a, b) in image.pixels.iter().zip(&reference.pixels).filter(|(_, b)| counted(b)) {
        squares += (0..3).map(|c| f64::from(shown(a[c]) - shown(b[c])).powi(2)).sum::<f64>();
        values += 3;
    }
    (squares / f64::from(values)).sqrt()
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

    let read = |p: &str| raydiance::image::exr::read(Path::new(p)).unwrap();
    let reference = raydiance::image::exr::read(reference).unwrap();
    let (noisy, alone, guided) = (read(&noisy), read(&alone), read(&guided));
    for measure in [Measure::Linear, Measure::UnderOne, Measure::Displayed] {
        println!(
            "RMSE ({measure:?}) against 4096 spp: raw {:.5}, beauty only {:.5}, albedo and \
             normal {:.5}",
            rmse(&noisy, &reference, measure),
            rmse(&alone, &reference, measure),
            rmse(&guided, &reference, measure)
        );
    }
    // The issue's factor of 3, on what a display shows, and on the linear radiance of every
    // pixel but the light's (docs/cli.md#denoise: the noiseless light, returned by the filter
    // within about 1.5 %, outweighs the rest in linear RMSE over every pixel).
    for measure in [Measure::Displayed, Measure::UnderOne] {
        let raw = rmse(&noisy, &reference, measure);
        let with_guides = rmse(&guided, &reference, measure);
        assert!(
            raw >= 3.0 * with_guides,
            "{measure:?}: raw {raw}, with albedo and normal {with_guides}"
        );
    }
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

#[cfg(feature = "denoise")]
#[test]
fn the_preview_shows_each_pass_denoised_beside_the_pass_as_rendered() {
    use common::preview::{Preview, lab_scene};
    let dir = tempfile::tempdir().unwrap();
    let scene = lab_scene(
        dir.path(),
        "settings { resolution 64, 64  samples 4  integrator path  max_depth 4 }\n\
         object { CeilingLight }\n\
         sphere { LeftSphere, 0.3  material { Blue } }\n",
    );
    let preview = Preview::start(&scene, &["--listen", "127.0.0.1:0"]);
    let last = |s: &serde_json::Value| s["picture"]["spp"] == 4 && s["picture"]["denoised"] == true;
    let state = preview.events().until(last).pop().unwrap().json();
    assert_eq!(state["denoising"], true);
    // The page offers the denoised view, the raw pass chosen at first.
    let page = String::from_utf8(preview.get("/").1).unwrap();
    let raw = r#"<input type="radio" name="view" value="raw" checked>"#;
    assert!(page.contains(raw) && page.contains(r#"value="denoised">"#), "{page}");
    let (status, png) = preview.get("/denoised.png");
    assert_eq!((status, &png[1..4]), (200, &b"PNG"[..]));
    assert!(png != preview.get("/image.png").1, "the denoised view is another image");
    // Save as EXR is still the unbiased pass; the denoised one is a file of its own that says
    // what guided it: the AOVs of the preview's own render.
    let (status, rendered) = preview.get("/image.exr");
    assert_eq!(status, 200);
    let (status, denoised) = preview.get("/denoised.exr");
    assert_eq!(status, 200);
    let header = |exr: &[u8]| String::from_utf8_lossy(exr).into_owned();
    assert!(!header(&rendered).contains("raydiance:denoised"));
    assert!(header(&denoised).contains("from the beauty, albedo and normal"));
    let read = |exr: &[u8]| raydiance::image::exr::read_bytes(exr).unwrap();
    let (rendered, denoised) = (read(&rendered), read(&denoised));
    assert_eq!((denoised.width, denoised.height), (rendered.width, rendered.height));
    assert!(denoised.pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0));
    assert_ne!(denoised.pixels, rendered.pixels);
    // Nearer the converged image than the pass, the scene at 128 spp (whose own error, a
    // sixth of the pass's, barely counts): by about 2 (the CLI's factor of 3 above is at 16
    // spp and twice the size, where the filter has more to work with).
    let mut scene = raydiance::load(&scene, &Default::default()).unwrap();
    scene.settings.samples = 128;
    let converged = raydiance::render::render(&scene, &raydiance::progress::Silent).0.image();
    let raw = rmse(&rendered, &converged, Measure::Displayed);
    let with_guides = rmse(&denoised, &converged, Measure::Displayed);
    println!("RMSE (displayed) of the preview's 4 spp: raw {raw}, denoised {with_guides}");
    assert!(with_guides < raw / 1.5, "raw {raw}, denoised {with_guides}");
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
