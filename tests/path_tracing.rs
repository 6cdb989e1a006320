//! The path integrator against closed forms of the rendering equation, and its estimators
//! (light sampling, BSDF sampling, MIS) against each other, with statistical bounds.

use crate::common;

use common::{LAB_BOX, OneAtATime, assert_films_agree, assert_uniform_radiance, path_with, scene};
use glam::{Vec2, Vec3};
use raydiance::integrator::{CameraSample, Direct, Path, SampleIntegrator, Strategy};
use raydiance::progress::Silent;
use raydiance::render::render_with;
use raydiance::sampling::Sampler;
use raydiance::scene::Scene;

/// A closed box [-1, 1]^3 of six quads facing inwards with the given material, and a camera
/// inside it looking along +z.
fn inward_box(material: &str) -> String {
    let faces = [
        "<-1, -1, -1>, <2, 0, 0>, <0, 2, 0>", // z = -1: x cross y = +z, inwards
        "<-1, -1, 1>, <0, 2, 0>, <2, 0, 0>",  // z = +1: y cross x = -z
        "<-1, -1, -1>, <0, 0, 2>, <2, 0, 0>", // y = -1: z cross x = +y
        "<-1, 1, -1>, <2, 0, 0>, <0, 0, 2>",  // y = +1: x cross z = -y
        "<-1, -1, -1>, <0, 2, 0>, <0, 0, 2>", // x = -1: y cross z = +x
        "<1, -1, -1>, <0, 0, 2>, <0, 2, 0>",  // x = +1: z cross y = -x
    ];
    let quads: String = faces.iter().map(|f| format!("quad {{ {f} }}\n")).collect();
    format!(
        "camera {{ location <0.1, 0.2, -0.3>  look_at <0.5, 0.3, 1>  angle 90 }}
         union {{ {quads} material {{ {material} }} }}"
    )
}

/// A point light of power 4 pi at the centre of a closed sphere of radius 2 and albedo 0.5, and
/// `more` beside them: wall radiance a p / (pi R^2 (1 - a)) = 1.
fn closed_sphere(samples: u32, more: &str) -> Scene {
    scene(&format!(
        "settings {{ resolution 16, 16  samples {samples}  integrator path  max_depth 64 }}
         camera {{ location <0.3, -0.2, 0.1>  look_at <1, 0, 2>  angle 100 }}
         light_source {{ <0, 0, 0>  power rgb 4 * pi }}
         sphere {{ <0, 0, 0>, 2  material {{ diffuse rgb 0.5 }} }}
         {more}"
    ))
}

#[test]
fn closed_sphere_with_a_point_light_at_its_centre() {
    let s = closed_sphere(64, "");
    assert_uniform_radiance(&path_with(&s, Strategy::Mis), Vec3::ONE, "path");
}

/// The same sphere inside a huge glowing shell that faces away from it (POV-Ray's sky spheres of
/// radius 3000 seen from a scene inside a closed room). By power alone the shell would take all
/// but 4e-6 of the light choices and the point light's light would arrive as rare fireflies;
/// half of the choices are uniform among the lights, so the closed form holds at the same noise.
#[test]
fn a_point_light_beside_a_huge_emitter_is_still_sampled() {
    let s = closed_sphere(128, "sphere { <0, 0, 0>, 1000  material { emission rgb 1 } }");
    assert!(s.light_probability(0) >= 0.25, "the point light: {}", s.light_probability(0));
    assert_uniform_radiance(&path_with(&s, Strategy::Mis), Vec3::ONE, "path");
}

#[test]
fn furnace_with_emitting_walls() {
    // Walls of albedo a emitting Le: L = Le / (1 - a) = 0.25 / (1 - 0.75) = 1, by every estimator.
    let s = scene(&format!(
        "settings {{ resolution 16, 16  samples 64  integrator path  max_depth 100 }}
         {}",
        inward_box("diffuse rgb 0.75  emission rgb 0.25")
    ));
    for strategy in [Strategy::Mis, Strategy::LightSampling, Strategy::BsdfSampling] {
        assert_uniform_radiance(
            &path_with(&s, strategy),
            Vec3::splat(1.0),
            &format!("{strategy:?}"),
        );
    }
}

#[test]
fn white_furnace_with_bounded_depth_counts_each_bounce_once() {
    // Albedo 1, emission Le, max_depth d: emission is gathered at d + 1 vertices: (d + 1) Le.
    for depth in [0u32, 1, 3] {
        let s = scene(&format!(
            "settings {{ resolution 8, 8  samples 32  integrator path  max_depth {depth} }}
             {}",
            inward_box("diffuse rgb 1  emission rgb 0.5")
        ));
        let expected = Vec3::splat(0.5 * (depth + 1) as f32);
        assert_uniform_radiance(
            &path_with(&s, Strategy::Mis),
            expected,
            &format!("max_depth {depth}"),
        );
    }
}

#[test]
fn glass_sphere_in_a_uniformly_emitting_box_keeps_its_radiance() {
    // A lossless dielectric neither adds nor removes radiance: every pixel sees Le = 1.
    let s = scene(&format!(
        "settings {{ resolution 16, 16  samples 16  integrator path  max_depth 64 }}
         {}
         sphere {{ <0.4, 0.25, 0.5>, 0.45  material {{ transmission rgb 1  ior 1.5  fresnel }} }}",
        inward_box("emission rgb 1")
    ));
    let image = path_with(&s, Strategy::Mis).image();
    for p in &image.pixels {
        assert!((*p - Vec3::ONE).abs().max_element() < 1e-3, "{p}");
    }
}

/// A small S3 with a large ceiling light (so that BSDF sampling alone finds it often enough for
/// per-pixel statistics) and an emissive diffuse sphere (a light that also reflects).
fn small_cornell(samples: u32) -> Scene {
    scene(&format!(
        "{LAB_BOX}
         settings {{ resolution 24, 24  samples {samples}  integrator path  max_depth 8 }}
         quad {{ <-0.8, 0.99, -0.8>, <1.6, 0, 0>, <0, 0, 1.6>  material {{ emission rgb 2 }} }}
         sphere {{ <-0.5, -0.7, 0.25>, 0.3  material {{ emission rgb <0, 0, 2> diffuse rgb 0.5 }} }}
         sphere {{ <0.5, -0.7, -0.25>, 0.3  material {{ diffuse rgb <0.8, 0.7, 0.2> }} }}"
    ))
}

#[test]
fn light_sampling_bsdf_sampling_and_mis_agree() {
    let s = small_cornell(256);
    let mis = path_with(&s, Strategy::Mis);
    assert_films_agree(&mis, &path_with(&s, Strategy::LightSampling), "light sampling vs MIS");
    assert_films_agree(&mis, &path_with(&s, Strategy::BsdfSampling), "BSDF sampling vs MIS");
}

/// `small_cornell` with rough spheres (`docs/language.md`): metal, frosted glass, and plastic (a
/// diffuse base under a rough specular coat), seen directly and in each other.
fn rough_cornell(samples: u32) -> Scene {
    scene(&format!(
        "{LAB_BOX}
         settings {{ resolution 24, 24  samples {samples}  integrator path  max_depth 8 }}
         quad {{ <-0.8, 0.99, -0.8>, <1.6, 0, 0>, <0, 0, 1.6>  material {{ emission rgb 2 }} }}
         sphere {{ <-0.5, -0.7, 0.25>, 0.3  material {{ specular rgb 0.9  roughness 0.3 }} }}
         sphere {{ <0.5, -0.7, -0.25>, 0.3  material {{ transmission rgb 1  ior 1.5  fresnel  roughness 0.3 }} }}
         sphere {{ <0, -0.2, 0.4>, 0.3  material {{ diffuse rgb <0.5, 0.1, 0.1>  specular rgb 0.3  roughness 0.2 }} }}"
    ))
}

#[test]
fn light_sampling_bsdf_sampling_and_mis_agree_on_rough_surfaces() {
    let s = rough_cornell(256);
    let mis = path_with(&s, Strategy::Mis);
    assert_films_agree(
        &mis,
        &path_with(&s, Strategy::LightSampling),
        "rough: light sampling vs MIS",
    );
    assert_films_agree(&mis, &path_with(&s, Strategy::BsdfSampling), "rough: BSDF sampling vs MIS");
}

#[test]
fn direct_and_path_with_max_depth_one_agree_on_rough_surfaces() {
    // `direct` samples lights at rough vertices and follows no ray from them; `path` at depth 1
    // weighs light samples against BSDF samples: the same direct light.
    let mut s = rough_cornell(256);
    s.settings.max_depth = 1;
    let direct = render_with(&s, &Direct { max_depth: 1 }, &Silent).0;
    assert_films_agree(&direct, &path_with(&s, Strategy::Mis), "rough: direct vs path at depth 1");
}

#[test]
fn direct_and_path_with_max_depth_one_agree() {
    let mut s = small_cornell(128);
    s.settings.max_depth = 1;
    let direct = render_with(&s, &Direct { max_depth: 1 }, &Silent).0;
    assert_films_agree(&direct, &path_with(&s, Strategy::Mis), "direct vs path at depth 1");
    // With point lights only, both are exact and take the same rays.
    let mut seed = common::scene_file("scenes/lab4-direct.scn");
    seed.settings.width = 16;
    seed.settings.height = 16;
    seed.settings.max_depth = 1;
    let direct = render_with(&seed, &Direct { max_depth: 1 }, &Silent).0.image();
    let path = path_with(&seed, Strategy::Mis).image();
    assert!(common::max_abs_difference(&direct, &path) < 1e-6);
}

#[test]
fn max_depth_zero_shows_only_emitters() {
    let mut s = small_cornell(8);
    s.settings.max_depth = 0;
    let image = path_with(&s, Strategy::Mis).image();
    // Each sample sees 2 (the light), <0, 0, 2> (the emissive sphere) or nothing.
    for p in &image.pixels {
        let light_share = p.x / 2.0 * 8.0;
        assert!((light_share - light_share.round()).abs() < 1e-4 && p.y == p.x, "{p}");
        let sphere_share = (p.z - p.x) / 2.0 * 8.0;
        assert!((sphere_share - sphere_share.round()).abs() < 1e-4, "{p}");
    }
    assert!(image.pixels.iter().any(|p| p.x > 0.0) && image.pixels.iter().any(|p| p.z > p.x));
}

#[test]
fn error_falls_like_one_over_root_spp() {
    let reference = {
        let mut s = small_cornell(2048);
        s.settings.seed = 99;
        path_with(&s, Strategy::Mis).image()
    };
    let rmse = |spp| {
        let image = path_with(&small_cornell(spp), Strategy::Mis).image();
        let squared: f32 = image
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, b)| (*a - *b).length_squared())
            .sum();
        (squared / (3 * image.pixels.len()) as f32).sqrt()
    };
    let errors: Vec<f32> = [16, 64, 256].map(rmse).to_vec();
    // Slope of log RMSE against log spp: -0.5 for plain Monte Carlo; stratification may do better.
    let slope = (errors[2] / errors[0]).ln() / 16f32.ln();
    assert!(slope < -0.4 && slope > -1.0, "RMSE {errors:?}, slope {slope}");
}

/// Lights of every kind a bounce's lanes sample together (point lights, a quad and a triangle
/// light, the triangle seen from both sides) or one lane at a time (a disk, a sphere), over a
/// diffuse floor, a glossy wall and a mirror: each lane's light sample must be the one its path
/// gets alone.
const EVERY_LIGHT: &str = "settings { max_depth 6 }
    camera { location <0, 0.5, -3>  look_at <0, 0, 0>  angle 60 }
    plane { <0, 1, 0>, -1  material { diffuse rgb 0.6 } }
    plane { <0, 0, -1>, 2  material { specular rgb 0.5  roughness 0.2 } }
    sphere { <-0.6, -0.6, 0.3>, 0.4  material { specular rgb 0.9 } }
    light_source { <0, 0.8, 0>  power rgb 1 }
    light_source { <0.7, 0.2, -0.6>  power rgb <0.2, 0.3, 0.1> }
    quad { <-0.3, 1.2, -0.3>, <0.6, 0, 0>, <0, 0, 0.6>  material { emission rgb 3 } }
    triangle { <0.8, -1, 0.5>, <1.2, -1, 0.9>, <1, 0, 0.7>  material { emission rgb 2 } }
    disk { <-1, 0.5, 1>, <1, 0, -1>, 0.2  material { emission rgb <1, 2, 3> } }
    sphere { <0.5, 0.6, 1>, 0.1  material { emission rgb 6 } }
    quad { <-1.5, -1, 1.5>, <0, 0, -0.6>, <0, 0.6, 0>  material { diffuse rgb 0.5  emission rgb 1 } }";

#[test]
fn paths_traced_together_get_the_radiance_each_gets_alone() {
    paths_together_match_paths_alone(&common::scene_file("scenes/cornell-specular.scn"), 32);
    paths_together_match_paths_alone(&scene(EVERY_LIGHT), 6);
}

fn paths_together_match_paths_alone(scene: &Scene, max_depth: u32) {
    // Lanes share nothing but their tests against the scene: a path's radiance must not depend
    // on which paths it was traced beside (glass and mirrors end paths at different bounces).
    // Every seventh slot has no sample (as where the film is dark): it is left as it was.
    let integrator = Path { max_depth, strategy: Strategy::Mis };
    let camera_sample = |i: usize| {
        let mut sampler = Sampler::new(9, i as u64 % 4000, i as u64 / 4000);
        let (x, y) = (sampler.next_1d(), sampler.next_1d());
        CameraSample { slot: i, ray: scene.camera.ray(x, y, Vec2::ZERO), sampler }
    };
    let count = 1001; // not a multiple of the lane count
    let untouched = Vec3::splat(-1.0);
    let mut together = vec![untouched; count];
    let samples: Vec<_> = (0..count).filter(|i| i % 7 != 3).map(camera_sample).collect();
    integrator.radiance_of_all(scene, &samples, &mut together);
    for (i, radiance) in together.iter().enumerate() {
        if i % 7 == 3 {
            assert_eq!(*radiance, untouched, "slot {i} has no sample");
            continue;
        }
        let CameraSample { ray, mut sampler, .. } = camera_sample(i);
        assert_eq!(*radiance, integrator.radiance(scene, ray, &mut sampler), "sample {i}");
    }
    assert!(together.iter().filter(|r| r.max_element() > 0.0).count() > count / 2);
}

/// Depth of field over a floor lit by a disk light: camera rays that graze the floor hit it
/// 10^7 units away, where the light's pdf squared overflowed in the MIS weight and made NaN
/// samples (with seeds 0 and 4 at 256 x 160, 64 spp). No sample may be dropped for any seed.
#[test]
fn depth_of_field_over_an_area_lit_floor_gives_no_nan() {
    let text = "settings { resolution 128, 80  samples 16  integrator path  max_depth 8 }
        camera { location <0, 0.8, -4>  look_at <0, 0.5, 0>  angle 45  aperture 0.12  focal_distance 4.03 }
        plane { <0, 1, 0>, 0  material { diffuse rgb 0.5 } }
        disk { <0, 4, 0>, <0, -1, 0>, 1.2  material { emission rgb 8 } }";
    let mut scene = common::scene(text);
    for seed in 0..32 {
        scene.settings.seed = seed;
        let film = common::render_film(&scene);
        assert_eq!(film.dropped, 0, "seed {seed}: samples were NaN or infinite");
    }
}

/// The background is an environment light for `direct` as for `path`: a scene lit by it alone
/// renders alike with both at depth 1, and a convex diffuse object under it reflects kd L
/// (every direction from its surface sees the sky), within 4 standard errors.
#[test]
fn the_background_lights_direct_as_it_lights_path() {
    let lit_by_sky =
        "settings { resolution 24, 24  samples 64  max_depth 1  background rgb <0.5, 1, 2> }
        camera { location <0, 1.5, -4>  look_at <0, 0.3, 0>  angle 50 }
        plane { <0, 1, 0>, 0  material { diffuse rgb 0.6 } }
        sphere { <0, 0.6, 0>, 0.6  material { diffuse rgb <0.8, 0.4, 0.2> } }";
    let s = scene(lit_by_sky);
    let direct = render_with(&s, &Direct { max_depth: 1 }, &Silent).0;
    assert_films_agree(
        &direct,
        &path_with(&s, Strategy::Mis),
        "direct vs path at depth 1, sky only",
    );

    let sphere_alone = "settings { resolution 9, 9  samples 64  background rgb <0.5, 1, 2> }
        camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 10 }
        sphere { <0, 0, 0>, 0.6  material { diffuse rgb <0.8, 0.4, 0.2> } }";
    let film = render_with(&scene(sphere_alone), &Direct { max_depth: 1 }, &Silent).0;
    let expected = Vec3::new(0.8, 0.4, 0.2) * Vec3::new(0.5, 1.0, 2.0);
    let centre = film.image().get(4, 4);
    let error = film.variance_of_mean()[4 * 9 + 4].map(f32::sqrt);
    assert!(
        ((centre - expected).abs() - 4.0 * error).max_element() < 1e-5,
        "{centre} ± {error} vs kd L = {expected}"
    );
}

/// The four-path integrator gives every shipped scene exactly the image of the scalar one, with
/// each estimator. (`mesh-heavy` takes part when its generated mesh is there.)
#[test]
fn four_paths_at_a_time_match_the_scalar_path_integrator_on_every_shipped_scene() {
    for (name, scene) in common::small_shipped_scenes() {
        for strategy in [Strategy::Mis, Strategy::LightSampling, Strategy::BsdfSampling] {
            let path = Path { max_depth: scene.settings.max_depth, strategy };
            let four = render_with(&scene, &path, &Silent).0.image();
            let one = render_with(&scene, &OneAtATime(&path), &Silent).0.image();
            let differing = four.pixels.iter().zip(&one.pixels).filter(|(a, b)| a != b).count();
            assert_eq!(differing, 0, "{name} with {strategy:?}");
            assert!(four.pixels.iter().any(|p| p.max_element() > 0.0), "{name}");
        }
    }
}
