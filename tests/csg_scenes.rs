//! CSG written in `.scn` text, end to end: a carved cube rendered by the command line against
//! its analytic silhouette, and the deepest nesting the language allows rendered on a small
//! stack.

use crate::common;

use std::path::Path;
use std::process::Command;

/// `box {-1, 1}` less `sphere {0, 1.3}`, emitting only, seen from a corner so that the cut faces
/// are in view.
const CARVED_CUBE: &str = r#"
settings { resolution 40, 30  samples 64 }
camera { location <3, 2.5, -4>  look_at <0, 0, 0>  angle 50 }
#declare Cube = box { -1, 1 }
difference {
  object { Cube }
  sphere { 0, 1.3 }
  material { emission rgb 1 }
}
"#;

#[test]
fn a_sphere_subtracted_from_a_cube_in_scn_text_renders_its_analytic_silhouette() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("carved.scn");
    std::fs::write(&scene_path, CARVED_CUBE).unwrap();
    let scene = raydiance::load(&scene_path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let (width, height) = (40, 30);
    for integrator in ["direct", "path"] {
        let out = dir.path().join(format!("{integrator}.exr"));
        let output = Command::new(env!("CARGO_BIN_EXE_raydiance"))
            .args(["render", scene_path.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .args(["--integrator", integrator])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{stderr}");
        assert!(stderr.contains("not sampled as lights"), "the warning is shown: {stderr}");
        let image = raydiance::image::exr::read(&out).unwrap();
        assert_eq!((image.width, image.height), (width, height));
        let (mut edge, mut error, mut lit) = (0, 0.0, 0);
        for y in 0..height {
            for x in 0..width {
                // Coverage of the pixel, and of the pixel with a margin of half a pixel around it
                // (where that is all or nothing, so is the pixel).
                let (pixel, size) = ((x, y), (width, height));
                let coverage = |margin: f32| {
                    common::pixel_coverage(
                        &scene.camera,
                        pixel,
                        size,
                        margin,
                        common::hits_carved_cube,
                    )
                };
                let (covered, around) = (coverage(0.0), coverage(0.5));
                let value = image.pixels[y * width + x];
                assert!(value.x == value.y && value.y == value.z, "grey: {value}");
                if around == 0.0 || around == 1.0 {
                    assert_eq!(value.x, covered, "pixel ({x}, {y}) with {integrator}");
                    lit += usize::from(covered == 1.0);
                } else {
                    edge += 1;
                    error += (value.x - covered).abs();
                    assert!(
                        (value.x - covered).abs() < 0.3,
                        "pixel ({x}, {y}) with {integrator}: {value} vs {covered}"
                    );
                }
            }
        }
        assert!(lit > 50, "{lit} pixels wholly on the solid");
        assert!(edge > 20 && error / (edge as f32) < 0.08, "{edge} edge pixels, error {error}");
    }
}

/// CSG nested as deep as the language allows (64 levels, made by a recursive macro), traced on
/// render threads with an eighth of the usual 2 MiB stack: each level keeps its crossings on the
/// stack, so this is the bound's reason.
#[test]
fn the_deepest_csg_nesting_allowed_renders_on_a_small_stack() {
    let text = |levels: u32| {
        format!(
            "settings {{ resolution 16, 16  samples 2 }}
             camera {{ location <0, 0, -5>  look_at <0, 0, 0> }}
             #macro Nest(N)
               #if (N > 0)
                 difference {{ Nest(N - 1)  sphere {{ <0, 0, -1>, 0.1 + N * 0.003 }} }}
               #else
                 sphere {{ 0, 1 }}
               #end
             #end
             object {{ Nest({levels})  material {{ emission rgb 1 }} }}"
        )
    };
    let too_deep = raydiance::lang::parse_scene(Path::new("tests/inline.scn"), &text(65));
    let error = too_deep.expect_err("65 levels are refused").to_string();
    assert!(error.contains("nested more than 64 levels deep"), "{error}");
    let scene = common::scene(&text(64));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).stack_size(256 * 1024).build();
    let image = pool.unwrap().install(|| common::render_image(&scene));
    let centre = image.pixels[8 * 16 + 8];
    let corner = image.pixels[0];
    // The centre sees the cut face of the last subtracted sphere; the corner misses the solid.
    assert!(centre.x > 0.0 && corner.x == 0.0, "{centre} {corner}");
}
