//! Participating media (`docs/language.md`, Media): Beer–Lambert absorption in a dielectric, the
//! transmittance of scattering slabs by free-flight sampling, emission against its closed form,
//! a fog's estimators against each other, and the integrators that refuse media.

use crate::common;

use std::path::Path;

use common::scene;
use glam::Vec3;
use raydiance::film::Film;
use raydiance::integrator::{Path as PathIntegrator, Strategy};
use raydiance::progress::Silent;
use raydiance::render::render_with;
use raydiance::scene::Scene;

fn path(scene: &Scene, strategy: Strategy) -> Film {
    render_with(scene, &PathIntegrator { max_depth: scene.settings.max_depth, strategy }, &Silent).0
}

/// A camera on the z axis looking along +z through a 1° cone (paths within 2e-4 of the axis's
/// length), a white emitter of radiance 1 filling the view at z = 4, and `between`.
fn through(settings: &str, between: &str) -> Scene {
    scene(&format!(
        "settings {{ resolution 8, 8  {settings} }}
         camera {{ location <0, 0, -5>  look_at <0, 0, 0>  angle 1 }}
         quad {{ <-1, -1, 4>, <0, 2, 0>, <2, 0, 0>  material {{ emission rgb 1 }} }}
         {between}"
    ))
}

/// Every pixel of `film` within `tolerance` (relative) of `expected`.
fn assert_every_pixel(film: &Film, expected: Vec3, tolerance: f32, what: &str) {
    for p in &film.image().pixels {
        assert!(
            (*p - expected).abs().cmple(tolerance * expected + Vec3::splat(1e-6)).all(),
            "{what}: pixel {p}, expected {expected}"
        );
    }
}

/// The mean of a film whose pixels all estimate `expected`, within 5 standard errors of at
/// most 2 % of it.
fn assert_mean(film: &Film, expected: Vec3, what: &str) {
    assert_mean_within(film, expected, 0.02, what);
}

fn assert_mean_within(film: &Film, expected: Vec3, noise: f32, what: &str) {
    let n = film.sum.len() as f32;
    let mean = film.image().pixels.iter().sum::<Vec3>() / n;
    let standard_error = (film.variance_of_mean().iter().sum::<Vec3>() / (n * n)).map(f32::sqrt);
    assert!(
        (mean - expected).abs().cmple(5.0 * standard_error + 1e-6).all(),
        "{what}: mean {mean}, expected {expected}, standard error {standard_error}"
    );
    let noisy = standard_error.max_element() >= noise * expected.max_element();
    assert!(!noisy, "{what}: too noisy ({standard_error})");
}

/// Beer–Lambert: light crossing a slab 1 thick of a dielectric whose interior absorbs sigma_a
/// keeps exp(-sigma_a), with the surface letting light straight through (`ior 1`) and
/// refracting it (`ior 1.5`: at normal incidence the 1/eta² in and eta² out cancel).
#[test]
fn absorbing_dielectric_slab_transmits_by_beer_lambert() {
    let sigma = Vec3::new(0.2, 1.0, 3.0);
    for ior in [1.0, 1.5] {
        let s = through(
            "samples 4",
            &format!(
                "box {{ <-1, -1, -0.5>, <1, 1, 0.5>
                   material {{ transmission rgb 1  ior {ior}
                              medium {{ absorption rgb <0.2, 1, 3> }} }} }}"
            ),
        );
        let film = path(&s, Strategy::Mis);
        assert_every_pixel(&film, (-sigma).exp(), 2e-3, &format!("ior {ior}"));
    }
}

/// Free-flight sampling through a slab that absorbs and scatters, scattered light left out
/// (`max_depth 0`: a path ends where it scatters): what arrives unscattered is exp(-sigma_t d).
#[test]
fn scattering_slab_transmits_exp_of_minus_extinction() {
    let s = through(
        "samples 256  max_depth 0",
        "box { <-1, -1, -0.75>, <1, 1, 0.75>
           material { transmission rgb 1
                      medium { absorption rgb 0.3  scattering rgb <0.2, 0.7, 1.2> } } }",
    );
    let sigma_t = Vec3::new(0.5, 1.0, 1.5);
    assert_mean(&path(&s, Strategy::Mis), (-sigma_t * 1.5).exp(), "slab");
}

/// A sphere of radius 1 filled with a medium that absorbs sigma_a and emits e per unit length,
/// seen through its centre in front of a black emitter: e (1 - exp(-2 sigma_a)) / sigma_a.
#[test]
fn emissive_medium_matches_its_closed_form() {
    let s = scene(
        "settings { resolution 8, 8  samples 4 }
         camera { location <0, 0, -5>  look_at <0, 0, 0>  angle 1 }
         sphere { <0, 0, 0>, 1
           material { transmission rgb 1
                      medium { absorption rgb <0.5, 1, 2>  emission rgb <1, 2, 3> } } }",
    );
    let (sigma, e) = (Vec3::new(0.5, 1.0, 2.0), Vec3::new(1.0, 2.0, 3.0));
    let expected = e * (Vec3::ONE - (-2.0 * sigma).exp()) / sigma;
    assert_every_pixel(&path(&s, Strategy::Mis), expected, 3e-3, "glowing sphere");
}

/// An atmosphere that absorbs 1 / D and emits c / D is POV-Ray's fog: an emitter of radiance 1
/// at distance d is seen as exp(-d / D) + c (1 - exp(-d / D)).
#[test]
fn absorbing_emitting_atmosphere_is_povray_fog() {
    let s = through("samples 4", "atmosphere { absorption rgb 0.25  emission rgb <0.1, 0.05, 0> }");
    let t = (-0.25f32 * 9.0).exp();
    let expected = Vec3::splat(t) + Vec3::new(0.4, 0.2, 0.0) * (1.0 - t);
    assert_every_pixel(&path(&s, Strategy::Mis), expected, 2e-3, "fog");
}

/// Single and multiple scattering in a fog lit by an area light over a floor: next-event
/// estimation through the phase function, phase-function sampling alone, and their MIS agree.
#[test]
fn fog_estimators_agree() {
    let s = scene(
        "settings { resolution 12, 12  samples 256  max_depth 6 }
         camera { location <0, 1, -4>  look_at <0, 0.5, 0>  angle 60 }
         atmosphere { absorption rgb 0.05  scattering rgb <0.2, 0.3, 0.4>  anisotropy 0.3 }
         quad { <-3, 0, -5>, <0, 0, 8>, <6, 0, 0>  material { diffuse rgb 0.6 } }
         quad { <-1, 3, -1>, <2, 0, 0>, <0, 0, 2>  material { emission rgb 4 } }",
    );
    let mis = path(&s, Strategy::Mis);
    for (strategy, what) in
        [(Strategy::LightSampling, "light sampling"), (Strategy::BsdfSampling, "phase sampling")]
    {
        let other = path(&s, strategy);
        let (a, b) = (mis.image(), other.image());
        let (va, vb) = (mis.variance_of_mean(), other.variance_of_mean());
        let mut outliers = 0;
        for i in 0..a.pixels.len() {
            let z = (a.pixels[i] - b.pixels[i]).abs()
                / (va[i] + vb[i]).map(f32::sqrt).max(Vec3::splat(1e-6));
            outliers += z.to_array().iter().filter(|&&z| z > 4.0).count();
        }
        assert!(outliers * 100 < 3 * a.pixels.len(), "{what}: {outliers} channels differ");
        let (ma, mb) = (common::mean(&a), common::mean(&b));
        let n = a.pixels.len() as f32;
        let se = ((va.iter().sum::<Vec3>() + vb.iter().sum::<Vec3>()) / (n * n)).map(f32::sqrt);
        assert!((ma - mb).abs().cmple(5.0 * se).all(), "{what}: means {ma} vs {mb} (se {se})");
        assert!(ma.min_element() > 0.01, "the fog scatters light: {ma}");
    }
}

/// The integrators that do not render media refuse a scene with one, naming themselves and
/// pointing at the medium.
#[test]
fn other_integrators_refuse_media() {
    for integrator in ["direct", "photon", "final_gather", "sppm"] {
        let text = format!(
            "settings {{ integrator {integrator} }}
             camera {{ location <0, 0, -5>  look_at <0, 0, 0>  angle 40 }}
             atmosphere {{ absorption rgb 0.1 }}"
        );
        let graph = raydiance::lang::parse_scene(Path::new("tests/inline.scn"), &text).unwrap();
        let error = raydiance::scene::build(&graph).expect_err("media refused").to_string();
        assert!(error.contains(&format!("`{integrator}`")), "{error}");
        assert!(error.contains("participating media") && error.contains(":3:"), "{error}");
    }
}

/// POV-Ray's fog, interior fade and media read as media (`docs/povray.md`).
#[test]
fn povray_fog_fade_and_media_are_media() {
    let graph = raydiance::lang::parse_scene(
        Path::new("tests/inline.pov"),
        "camera { location <0, 0, -5> look_at <0, 0, 0> }
         fog { distance 4 color rgb <0.4, 0.8, 1> }
         sphere { 0, 1 pigment { rgbf 1 } hollow
           interior { ior 1.5 fade_distance 2 fade_color rgb <1, 0.5, 0>
                      media { emission 0.5 scattering { 5, rgb 0.2 eccentricity 0.6 } } } }",
    )
    .unwrap();
    let fog = graph.atmosphere.as_ref().expect("the fog");
    assert_eq!(fog.absorption, Vec3::splat(0.25));
    assert_eq!(fog.emission, Vec3::new(0.1, 0.2, 0.25));
    let material = graph.objects[0].material.as_ref().unwrap();
    let interior = material.interior.as_ref().expect("the interior's medium");
    assert_eq!(material.ior, 1.5);
    assert_eq!(interior.absorption, Vec3::new(0.0, 0.25, 0.5));
    assert_eq!((interior.scattering, interior.emission), (Vec3::splat(0.2), Vec3::splat(0.5)));
    assert!((interior.anisotropy - 0.6).abs() < 1e-6);
}

/// A declared media stands for its items in a `media { }`, which may add to it; media in the
/// same interior add up, their g weighted by how much each scatters.
#[test]
fn povray_declared_media_add_up() {
    let graph = raydiance::lang::parse_scene(
        Path::new("tests/inline.pov"),
        "camera { location <0, 0, -5> look_at <0, 0, 0> }
         #declare Smoke = media { absorption 0.1 scattering { 5, 0.3 eccentricity 0.5 } }
         sphere { 0, 1 pigment { rgbt 1 } hollow
           interior { media { Smoke emission <1, 0, 0> }
                      media { scattering { 1, 0.1 } } } }",
    )
    .unwrap();
    let material = graph.objects[0].material.as_ref().unwrap();
    let medium = material.interior.as_ref().expect("the media");
    assert_eq!(medium.absorption, Vec3::splat(0.1));
    assert!((medium.scattering - Vec3::splat(0.4)).abs().max_element() < 1e-6);
    assert_eq!(medium.emission, Vec3::new(1.0, 0.0, 0.0));
    assert!((medium.anisotropy - 0.375).abs() < 1e-6, "{}", medium.anisotropy);
}

/// A white furnace for media: a sphere of a medium that scatters without absorbing, under a
/// uniform sky of radiance 1, looks exactly like the sky (every path, however often it
/// scatters, leaves with radiance 1), with each estimator; with absorption it is darker.
#[test]
fn scattering_medium_in_a_furnace_is_invisible() {
    let furnace = |absorption: f32| {
        scene(&format!(
            "settings {{ resolution 8, 8  samples 256  max_depth 256  background rgb 1 }}
             camera {{ location <0, 0, -4>  look_at <0, 0, 0>  angle 20 }}
             sphere {{ <0, 0, 0>, 1
               material {{ transmission rgb 1
                          medium {{ absorption rgb {absorption}
                                   scattering rgb <0.5, 1, 2>  anisotropy 0.6 }} }} }}"
        ))
    };
    let s = furnace(0.0);
    for strategy in [Strategy::Mis, Strategy::LightSampling, Strategy::BsdfSampling] {
        // Light sampling alone is the noisiest: every scattering sees the sky through the sphere.
        assert_mean_within(&path(&s, strategy), Vec3::ONE, 0.05, &format!("{strategy:?}"));
    }
    let dark = common::mean(&path(&furnace(0.5), Strategy::Mis).image());
    assert!(dark.max_element() < 0.9, "absorption darkens the sphere: {dark}");
}

/// Ground fog seen level at height 2 above its offset, where its density is 1/(1 + 2)²: an
/// emitter 9 away is seen through a density-weighted length of 1.
#[test]
fn ground_fog_thins_with_height() {
    let s = scene(
        "settings { resolution 8, 8  samples 4 }
         camera { location <0, 2, -5>  look_at <0, 2, 0>  angle 0.1 }
         quad { <-1, 1, 4>, <0, 2, 0>, <2, 0, 0>  material { emission rgb 1 } }
         atmosphere { absorption rgb 0.5  emission rgb 0.25  ground y, 0, 1 }",
    );
    let t = (-0.5f32).exp();
    assert_every_pixel(&path(&s, Strategy::Mis), Vec3::splat(t + 0.5 * (1.0 - t)), 3e-3, "ground");
    let graph = raydiance::lang::parse_scene(
        Path::new("tests/inline.pov"),
        "camera { location <0, 0, -5> look_at <0, 0, 0> }
         fog { fog_type 2 distance 4 color rgb 1 fog_offset 0.5 fog_alt 2 }",
    )
    .unwrap();
    let ground = graph.atmosphere.and_then(|fog| fog.ground).expect("ground fog");
    assert_eq!((ground.up, ground.offset, ground.falloff), (Vec3::Y, 0.5, 2.0));
}
