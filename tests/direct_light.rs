//! The course's Lab 4 result: direct light from point lights, checked against the formula
//! L = p / r^2 * kd / pi * |n . wi| computed here, independently of the renderer.

use crate::common;

use std::f32::consts::PI;

use common::{LAB_BOX, OneAtATime, max_abs_difference, render_image, scene};
use glam::Vec3;
use raydiance::geometry::Ray;
use raydiance::integrator::{Direct, SampleIntegrator};
use raydiance::progress::Silent;
use raydiance::render::render_with;
use raydiance::sampling::Sampler;

fn radiance_along(scene: &raydiance::scene::Scene, origin: Vec3, target: Vec3) -> Vec3 {
    let ray = Ray::new(origin, (target - origin).normalize());
    Direct { max_depth: 32 }.radiance(scene, ray, &mut Sampler::new(0, 0, 0))
}

#[test]
fn floor_below_the_light_matches_the_formula() {
    // The example: kd 0.9, p 1, a floor 1.5 below the light: 0.9 / (2.25 pi) = 0.127324.
    let s = scene(&format!(
        "{LAB_BOX} light_source {{ <0, 0.5, 0> power rgb 1 }}
         plane {{ <0, 1, 0>, 0.999  material {{ diffuse rgb 0.9 }} }}"
    ));
    assert!((0.9 / (2.25 * PI) - 0.127324).abs() < 1e-6);
    // This floor lies just above the box's (at y = -0.999) so that it is the one seen.
    let expected = 0.9 / (1.499f32.powi(2) * PI);
    let seen = radiance_along(&s, Vec3::new(0.0, 0.0, -3.5), Vec3::new(0.0, -0.999, 0.0));
    assert!((seen - Vec3::splat(expected)).abs().max_element() < 1e-5 * expected, "{seen}");
}

#[test]
fn lit_points_of_the_seed_scene_match_the_formula() {
    let s = common::scene_file("scenes/lab4-direct.scn");
    let light = Vec3::new(0.0, 0.5, 0.0);
    let camera = Vec3::new(0.0, 0.0, -3.5);
    // Points on the back wall (n = -z), the floor (n = +y) and the red wall (n = +x), each seen
    // from the camera and lit, with their kd.
    let cases = [
        (Vec3::new(0.3, 0.2, 1.0), Vec3::NEG_Z, Vec3::splat(0.8)),
        (Vec3::new(0.1, -1.0, -0.6), Vec3::Y, Vec3::splat(0.8)),
        (Vec3::new(-1.0, 0.4, 0.2), Vec3::X, Vec3::new(0.8, 0.1, 0.1)),
    ];
    for (point, normal, kd) in cases {
        let to_light = light - point;
        let wi = to_light.normalize();
        let expected = 1.0 / to_light.length_squared() * kd / PI * normal.dot(wi).abs();
        let seen = radiance_along(&s, camera, point);
        assert!((seen - expected).abs().max_element() < 1e-5, "at {point}: {seen} vs {expected}");
    }
}

#[test]
fn shadowed_points_are_exactly_black() {
    let s = common::scene_file("scenes/lab4-direct.scn");
    // The centre of the left sphere's shadow on the floor: light (0, 0.5, 0) through the
    // centre (-0.5, -0.7, 0.25) reaches y = -1 at t = 1.25: (-0.625, -1, 0.3125).
    let shadow = Vec3::new(-0.625, -1.0, 0.3125);
    let seen = radiance_along(&s, shadow + Vec3::new(0.0, 0.05, 0.0), shadow);
    assert_eq!(seen, Vec3::ZERO);
}

#[test]
fn two_lights_render_as_the_sum_of_each_alone() {
    let with = |lights: &str| {
        render_image(&scene(&format!(
            "{LAB_BOX} {lights}
             settings {{ resolution 32, 32  samples 4  integrator direct }}
             sphere {{ <-0.5, -0.7, 0.25>, 0.3  material {{ diffuse rgb <0.2, 0.4, 0.8> }} }}
             sphere {{ <0.5, -0.7, -0.25>, 0.3  material {{ diffuse rgb <0.8, 0.7, 0.2> }} }}"
        )))
    };
    let a = "light_source { <0, 0.5, 0> power rgb 1 }";
    let b = "light_source { <0.6, 0.8, -0.5> power rgb <0.5, 1, 2> }";
    let (alone_a, alone_b, both) = (with(a), with(b), with(&format!("{a} {b}")));
    let mut sum = alone_a.clone();
    for (s, p) in sum.pixels.iter_mut().zip(&alone_b.pixels) {
        *s += *p;
    }
    let largest = both.pixels.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    assert!(largest > 0.05, "the lights light the scene");
    assert!(max_abs_difference(&both, &sum) < 1e-5 * largest);
}

/// Lights of every kind (point lights, planar area lights, a sphere light sampled one vertex
/// at a time, a sky) over every kind of lobe (Lambertian, textured, plastic's diffuse with a
/// mirror coat, rough metal, a mirror, glass), so that lanes of a bounce mix what is done in
/// lanes with what is done one vertex at a time. The box is open above and to the right: the
/// sky is seen and lights.
const EVERY_LIGHT_AND_LOBE: &str =
    "settings { resolution 24, 20  samples 4  integrator direct  max_depth 6  background rgb 0.2 }
    camera { origin <0, 0, -3.5>  left <-1, 0, 0>  up <0, 1, 0>  forward <0, 0, 3> }
    plane { <1, 0, 0>, 1   material { diffuse rgb <0.8, 0.1, 0.1> } }
    plane { <0, 0, -1>, 1  material { diffuse rgb 0.8 } }
    light_source { <0, 0.5, 0>  power rgb 1 }
    light_source { <0.6, 0.8, -0.5>  power rgb <0.2, 0.3, 0.1> }
    quad { <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5>  material { emission rgb 4 } }
    disk { <0.7, 0.2, 0.9>, <-1, 0, -1>, 0.2  material { emission rgb <1, 2, 3> } }
    sphere { <-0.7, 0.7, 0.6>, 0.1  material { emission rgb 6 } }
    sphere { <-0.5, -0.7, 0.25>, 0.3  material { specular rgb 0.9 } }
    sphere { <0.5, -0.7, -0.25>, 0.3  material { transmission rgb 1  ior 1.5  fresnel } }
    sphere { <0, -0.2, 0.4>, 0.25  material { diffuse rgb 0.5  specular rgb 0.3 } }
    sphere { <0.55, 0.2, 0.5>, 0.2  material { specular rgb <0.9, 0.6, 0.3>  roughness 0.3 } }
    plane { <0, 1, 0>, 1  material { diffuse checker { rgb 0.8, rgb 0.2  scale 0.25 } } }";

/// `direct` traces four paths at a time (`radiance_of_all`); each must get exactly what it gets
/// alone (`radiance`, through `whitted`), in the scene of every light and lobe at every depth and
/// in every shipped scene.
#[test]
fn four_paths_at_a_time_match_the_scalar_direct_integrator() {
    let check = |scene: &raydiance::scene::Scene, name: &str| {
        let direct = Direct { max_depth: scene.settings.max_depth };
        let four = render_with(scene, &direct, &Silent).0.image();
        let one = render_with(scene, &OneAtATime(&direct), &Silent).0.image();
        let differing = four.pixels.iter().zip(&one.pixels).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{name}: {differing} pixels differ");
        assert!(four.pixels.iter().any(|p| p.max_element() > 0.0), "{name} is black");
    };
    let mut every = scene(EVERY_LIGHT_AND_LOBE);
    for depth in [0, 1, 2, 6] {
        every.settings.max_depth = depth;
        check(&every, &format!("every light and lobe, max_depth {depth}"));
    }
    for (name, scene) in common::small_shipped_scenes() {
        check(&scene, &name);
    }
}
