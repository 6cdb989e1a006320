//! Textures in scenes: the course's Lab 4 formula with kd from the pattern, patterns that move with
//! their objects, image maps decoded to linear.

use crate::common;

use std::f32::consts::PI;

use common::{LAB_BOX, scene};
use glam::Vec3;
use raydiance::geometry::Ray;
use raydiance::integrator::{Direct, SampleIntegrator};
use raydiance::sampling::Sampler;

#[test]
fn a_textured_wall_follows_the_formula_with_kd_from_the_pattern() {
    let s = scene(&format!(
        "{LAB_BOX}
         light_source {{ <0, 0.5, 0>  power rgb 1 }}
         plane {{ <0, 0, -1>, 0.999  material {{ diffuse checker {{ rgb <0.9, 0.1, 0.1>, rgb <0.1, 0.1, 0.9>  scale 0.5 }} }} }}"
    ));
    let camera = Vec3::new(0.0, 0.0, -3.5);
    for (x, y) in [(0.2, 0.3), (-0.3, 0.1), (0.6, -0.4), (-0.7, -0.8), (0.1, -0.2)] {
        let point = Vec3::new(x, y, 0.999);
        // The pattern by hand: cells of 0.5, the first colour where the cell sum is even.
        let cell = (point / 0.5).floor();
        let even = (cell.x + cell.y + cell.z).rem_euclid(2.0) == 0.0;
        let kd = if even { Vec3::new(0.9, 0.1, 0.1) } else { Vec3::new(0.1, 0.1, 0.9) };
        let to_light = Vec3::new(0.0, 0.5, 0.0) - point;
        let expected = kd / PI / to_light.length_squared() * to_light.normalize().z.abs();
        let ray = Ray::new(camera, (point - camera).normalize());
        let seen = Direct { max_depth: 4 }.radiance(&s, ray, &mut Sampler::new(0, 0, 0));
        assert!((seen - expected).abs().max_element() < 1e-5, "at {point}: {seen} vs {expected}");
    }
}

#[test]
fn a_pattern_moves_with_its_object() {
    let material = "material { diffuse checker { rgb 1, rgb 0  scale 0.3 } }";
    let camera = "camera { location <0, 0, -5>  look_at <0, 0, 0> }";
    let at_origin = scene(&format!("{camera} sphere {{ <0, 0, 0>, 1  {material} }}"));
    let moved =
        scene(&format!("{camera} sphere {{ <0, 0, 0>, 1  {material}  translate <2, 0.5, 0> }}"));
    // The same sphere written in place: its pattern stays in world space.
    let written_there = scene(&format!("{camera} sphere {{ <2, 0.5, 0>, 1  {material} }}"));
    let kd = |s: &raydiance::scene::Scene, x: f32, y: f32| {
        let hit = s.intersect(&Ray::new(Vec3::new(x, y, -5.0), Vec3::Z)).unwrap();
        s.material(hit.primitive, hit.point).diffuse
    };
    let mut differs = 0;
    for (x, y) in [(0.1, 0.2), (-0.4, 0.3), (0.5, -0.5), (0.05, -0.15), (-0.6, -0.2), (0.3, 0.6)] {
        assert_eq!(kd(&at_origin, x, y), kd(&moved, x + 2.0, y + 0.5), "moves with the sphere");
        differs += usize::from(kd(&at_origin, x, y) != kd(&written_there, x + 2.0, y + 0.5));
    }
    assert!(differs > 0, "a pattern fixed in world space would fail the assertion above");
}

#[test]
fn image_maps_are_decoded_to_linear_and_projected_onto_x_y() {
    let s = scene(
        "camera { location <0, 0, -5>  look_at <0, 0, 0> }
         quad { <0, 0, 0>, <1, 0, 0>, <0, 1, 0>  material { diffuse image_map { \"scenes/parts/grid.png\" } } }",
    );
    let kd = |x: f32, y: f32| {
        let hit = s.intersect(&Ray::new(Vec3::new(x, y, -1.0), Vec3::Z)).unwrap();
        s.material(hit.primitive, hit.point).diffuse
    };
    // grid.png: red top left, green top right, blue bottom left, sRGB 188 grey bottom right.
    assert!((kd(0.1, 0.9) - Vec3::X).length() < 1e-5, "{}", kd(0.1, 0.9));
    assert!((kd(0.9, 0.9) - Vec3::Y).length() < 1e-5);
    assert!((kd(0.1, 0.1) - Vec3::Z).length() < 1e-5);
    // sRGB 188/255 = 0.737 decodes to linear ((0.737 + 0.055) / 1.055)^2.4 = 0.503.
    assert!((kd(0.9, 0.1) - Vec3::splat(0.5029)).abs().max_element() < 1e-3, "{}", kd(0.9, 0.1));
}
