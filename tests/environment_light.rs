//! The environment light (`docs/language.md`'s `background`, `docs/povray.md`'s `sky_sphere`):
//! white furnaces converge to 1 with every integrator, a textured sky's light sampling agrees
//! with BSDF sampling, and POV-Ray's `background` is seen without lighting.

use crate::common;

use std::path::Path;

use glam::Vec3;
use raydiance::image::Image;
use raydiance::lang::parse_scene;
use raydiance::scene::{Scene, build};

/// A `.pov` scene from text.
fn pov_scene(text: &str) -> Scene {
    let graph = parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
    build(&graph).unwrap_or_else(|e| panic!("{e}"))
}

/// An open box of albedo-1 walls (no lid) seen from above, with a ball on its floor: inside,
/// most light arrives after bounces, so a sky that sends no photons leaves it dark.
const OPEN_BOX: &str = "
    camera { location <0, 2.6, -1.2>  look_at <0, 0.2, 0>  angle 60 }
    quad { <-1, 0, -1>, <2, 0, 0>, <0, 0, 2>  material { diffuse rgb 1 } }
    quad { <-1, 0, -1>, <2, 0, 0>, <0, 1, 0>  material { diffuse rgb 1 } }
    quad { <-1, 0, 1>, <2, 0, 0>, <0, 1, 0>  material { diffuse rgb 1 } }
    quad { <-1, 0, -1>, <0, 0, 2>, <0, 1, 0>  material { diffuse rgb 1 } }
    quad { <1, 0, -1>, <0, 0, 2>, <0, 1, 0>  material { diffuse rgb 1 } }
    sphere { <0.3, 0.3, 0.2>, 0.3  material { diffuse rgb 1 } }";

/// In a white furnace (a sky of radiance 1, albedo-1 diffuse surfaces) radiance is 1
/// everywhere: the image's mean is 1 within `tolerance`, and so is the mean of the pixels that
/// see the inside of the box (the middle ninth of the image).
fn assert_furnace(image: &Image, tolerance: f32, what: &str) {
    let mean = common::mean(image);
    assert!((mean - Vec3::ONE).abs().max_element() < tolerance, "{what}: mean {mean}");
    let (w, h) = (image.width, image.height);
    let mut inside = Vec3::ZERO;
    for y in h / 3..2 * h / 3 {
        for x in w / 3..2 * w / 3 {
            inside += image.get(x, y);
        }
    }
    inside /= ((w / 3) * (h / 3)) as f32;
    assert!((inside - Vec3::ONE).abs().max_element() < tolerance, "{what}: inside {inside}");
}

/// `path`'s image is 1 within 4 standard errors of the image mean.
#[test]
fn path_converges_to_one_in_a_white_furnace() {
    let s = common::scene(&format!(
        "settings {{ resolution 24, 24  samples 64  max_depth 200  background rgb 1 }} {OPEN_BOX}"
    ));
    let film = common::render_film(&s);
    let variance: Vec3 = film.variance_of_mean().iter().sum();
    let pixels = (film.width * film.height) as f32;
    let standard_error = (variance / (pixels * pixels)).map(f32::sqrt).max_element();
    let mean = common::mean(&film.image());
    assert!(
        (mean - Vec3::ONE).abs().max_element() < 4.0 * standard_error,
        "mean {mean}, standard error {standard_error}"
    );
    assert_furnace(&film.image(), 0.02, "path");
}

/// The photon integrators see the sky's photons: in the furnace they converge to 1 too (the
/// floor of the box gets most of its light after bounces; without photons from the sky its
/// pixels would be near 0.5).
#[test]
fn photon_and_sppm_converge_to_one_in_a_white_furnace() {
    let sppm = common::scene(&format!(
        "settings {{ resolution 24, 24  samples 24  integrator sppm  photons 100000  \
         photon_radius 0.1  max_depth 200  background rgb 1 }} {OPEN_BOX}"
    ));
    assert_furnace(&common::render_image(&sppm), 0.03, "sppm");
    let photon = common::scene(&format!(
        "settings {{ resolution 24, 24  samples 8  integrator photon  photons 400000  \
         photon_k 50  max_depth 200  background rgb 1 }} {OPEN_BOX}"
    ));
    assert_furnace(&common::render_image(&photon), 0.05, "photon");
}

/// A `sky_sphere` of constant 1 over POV-Ray's albedo-1 surfaces is the same furnace.
#[test]
fn a_sky_sphere_of_one_is_a_white_furnace() {
    let s = pov_scene(
        "#default { finish { diffuse 1 ambient 0 } pigment { rgb 1 } }
         camera { location <0, 2.6, -1.2>  look_at <0, 0.2, 0>  angle 60 }
         sky_sphere { pigment { rgb 1 } }
         box { <-1, -0.2, -1>, <1, 0, 1> }
         sphere { <0.3, 0.3, 0.2>, 0.3 }
         sphere { <-0.4, 0.25, -0.3>, 0.25 }",
    );
    let mut s = s;
    s.settings.width = 24;
    s.settings.height = 24;
    s.settings.samples = 64;
    assert_furnace(&common::render_image(&s), 0.03, "sky_sphere");
}

/// `direct` over a convex albedo-1 ball lit by a constant sky: every direction from it sees the
/// sky, so its pixels are 1 (within 4 standard errors).
#[test]
fn direct_sees_one_on_a_convex_ball_under_a_sky_of_one() {
    let s = common::scene(
        "settings { resolution 9, 9  samples 256  integrator direct  max_depth 1  background rgb 1 }
        camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 10 }
        sphere { <0, 0, 0>, 0.6  material { diffuse rgb 1 } }",
    );
    let film = common::render_film(&s);
    let (image, variance) = (film.image(), film.variance_of_mean());
    for (i, (p, v)) in image.pixels.iter().zip(&variance).enumerate() {
        let error = v.map(f32::sqrt).max_element().max(1e-4);
        assert!((*p - Vec3::ONE).abs().max_element() < 4.0 * error, "pixel {i}: {p} ± {error}");
    }
}

/// A sky bright overhead and dim at the horizon (POV-Ray's own example, brighter), over a
/// ball on a disc.
const GRADIENT_SKY: &str = "
    camera { location <0, 1.5, -4>  look_at <0, 0.4, 0>  angle 45 }
    sky_sphere {
        pigment { gradient y  color_map { [0.5 rgb <0.3, 0.4, 0.6>] [0.9 rgb <1, 1, 1>] [1.0 rgb 6] }
                  scale 2  translate -1 }
        emission rgb <1, 0.9, 0.8>
    }
    disc { <0, 0, 0>, y, 2  pigment { rgb 0.7 } finish { diffuse 1 } }
    sphere { <0, 0.5, 0>, 0.5  pigment { rgb <0.8, 0.5, 0.3> } finish { diffuse 1 } }";

/// The textured sky's own samples (next-event estimation alone) and BSDF sampling alone
/// estimate the same image, and MIS agrees with both.
#[test]
fn sky_sampling_agrees_with_bsdf_sampling() {
    let mut s = pov_scene(GRADIENT_SKY);
    (s.settings.width, s.settings.height, s.settings.samples, s.settings.max_depth) =
        (32, 24, 128, 3);
    common::assert_light_and_bsdf_sampling_agree_with_mis(&s, "sky");
}

/// POV-Ray's `background` is seen but does not light: under it alone, with no light, a
/// diffuse ball is black and the rest of the image is the background's colour.
#[test]
fn a_pov_background_is_seen_and_does_not_light() {
    let mut s = pov_scene(
        "camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 30 }
         background { rgb <0.2, 0.4, 0.8> }
         sphere { <0, 0, 0>, 0.8  pigment { rgb 1 } finish { diffuse 1 } }",
    );
    (s.settings.width, s.settings.height, s.settings.samples) = (16, 12, 4);
    for integrator in ["path", "direct", "sppm", "photon"] {
        s.settings.integrator = raydiance::graph::IntegratorKind::named(integrator).unwrap();
        let image = common::render_image(&s);
        let (ball, corner) = (image.get(8, 6), image.get(0, 0));
        assert_eq!(ball, Vec3::ZERO, "{integrator}: the ball is lit by the background");
        assert!((corner - Vec3::new(0.2, 0.4, 0.8)).abs().max_element() < 1e-6, "{corner}");
    }
}

/// A mirror shows the background (the camera sees through delta bounces), and a sky_sphere
/// covers it.
#[test]
fn a_mirror_shows_the_background_and_a_sky_sphere_covers_it() {
    let text = "camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 30 }
         background { rgb <0.2, 0.4, 0.8> }
         sphere { <0, 0, 0>, 0.8  pigment { rgb 1 } finish { diffuse 0 ambient 0 reflection 1 } }";
    let mut s = pov_scene(text);
    (s.settings.width, s.settings.height, s.settings.samples) = (16, 12, 2);
    let centre = common::render_image(&s).get(8, 6);
    assert!((centre - Vec3::new(0.2, 0.4, 0.8)).abs().max_element() < 1e-6, "{centre}");
    let mut s = pov_scene(&format!("{text} sky_sphere {{ pigment {{ rgb <1, 0.5, 0.25> }} }}"));
    (s.settings.width, s.settings.height, s.settings.samples) = (16, 12, 2);
    let corner = common::render_image(&s).get(0, 0);
    assert!((corner - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-6, "{corner}");
}

/// The sky's photons carry its power π R² ∫ L dω: exactly for a constant sky (every photon the
/// same), on average for a textured one; and they enter the scene's bounding sphere, which the
/// ball on the disc lies in: photons aimed at the ball hit it.
#[test]
fn sky_photons_carry_the_power_the_sky_sends_in() {
    use raydiance::light::Light;
    use raydiance::sampling::Sampler;
    let constant = common::scene(
        "settings { background rgb <1, 2, 3> }
        camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 30 }
        sphere { <0, 0, 0>, 1  material { diffuse rgb 0.5 } }",
    );
    let textured = pov_scene(GRADIENT_SKY);
    for (scene, tolerance) in [(&constant, 1e-4), (&textured, 0.02)] {
        let Some(Light::Environment(sky)) = scene.lights.last() else { panic!("no sky") };
        let n = 100_000;
        let mut power = glam::DVec3::ZERO;
        let mut hits = 0;
        for i in 0..n {
            let mut s = Sampler::new(3, 4, i);
            let light = scene.lights.last().unwrap();
            let photon = light.sample_emission(n as u32, s.next_2d(), s.next_2d()).unwrap();
            power += photon.power.as_dvec3();
            hits += usize::from(scene.intersect(&photon.ray).is_some());
        }
        let expected = sky.power_rgb().as_dvec3();
        let error = ((power - expected) / expected).abs().max_element();
        assert!(error < tolerance, "photons carry {power}, the sky sends {expected}");
        assert!(hits > 0, "no photon reaches the scene");
    }
}
