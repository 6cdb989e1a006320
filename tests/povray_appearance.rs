//! POV-Ray's appearance in `.pov` scenes (`docs/povray.md`): pigment, finish, texture, interior,
//! normal and `#default`, each read as the material stated there.

use std::path::Path;

use glam::Vec3;
use raydiance::graph::{MaterialDesc, Pattern, SceneGraph};
use raydiance::lang::parse_scene;

fn pov(text: &str) -> SceneGraph {
    parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"))
}

/// The material of the scene's first object.
fn material(text: &str) -> MaterialDesc {
    (*pov(text).objects[0].material.clone().expect("a material")).clone()
}

fn solid(m: &MaterialDesc) -> Vec3 {
    match m.diffuse.pattern {
        Pattern::Solid(c) => c,
        ref other => panic!("not a solid colour: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-6
}

#[test]
fn the_albedo_is_the_pigment_times_diffuse_with_povray_s_default_finish() {
    let m = material("sphere { 0, 1 pigment { color rgb <1, 0.5, 0> } }");
    assert!(close(solid(&m), 0.6 * Vec3::new(1.0, 0.5, 0.0)), "diffuse 0.6 by default");
    assert_eq!((m.specular, m.transmission, m.emission), (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO));
    let m = material("sphere { 0, 1 pigment { rgb 0.5 } finish { diffuse 0.8 } }");
    assert!(close(solid(&m), Vec3::splat(0.4)));
}

#[test]
fn an_object_without_texture_has_the_default_texture_black_until_default_changes_it() {
    assert!(close(solid(&material("sphere { 0, 1 }")), Vec3::ZERO));
    let m = material(
        "#default { texture { pigment { rgb <0, 1, 0> } finish { diffuse 0.5 } } }\n\
         sphere { 0, 1 }",
    );
    assert!(close(solid(&m), Vec3::new(0.0, 0.5, 0.0)));
    // A finish alone keeps the default pigment, and the other way round.
    let m = material(
        "#default { pigment { rgb 1 } }  #default { finish { diffuse 0.3 } }\n\
         sphere { 0, 1 finish { reflection 0.2 } }",
    );
    assert!(close(solid(&m), Vec3::splat(0.3)) && close(m.specular, Vec3::splat(0.2)));
}

#[test]
fn energy_is_conserved_by_scaling_never_refused() {
    let m = material("sphere { 0, 1 pigment { rgb 1 } finish { diffuse 0.9 reflection 0.5 } }");
    assert!(close(solid(&m), Vec3::splat(0.9 / 1.4)), "{}", solid(&m));
    assert!(close(m.specular, Vec3::splat(0.5 / 1.4)));
    assert!(close(solid(&m) + m.specular, Vec3::ONE));
}

#[test]
fn filter_and_transmit_pass_light_through_the_interior_s_ior() {
    let m =
        material("sphere { 0, 1 pigment { color rgbf <1, 0.5, 0.5, 0.6> } interior { ior 1.5 } }");
    // filter is tinted by the colour; the opaque 40 % is diffuse.
    assert!(close(m.transmission, 0.6 * Vec3::new(1.0, 0.5, 0.5)), "{}", m.transmission);
    assert!(close(solid(&m), 0.4 * 0.6 * Vec3::new(1.0, 0.5, 0.5)));
    assert_eq!(m.ior, 1.5);
    let m = material("sphere { 0, 1 pigment { rgbt <0, 0, 1, 0.25> } }");
    assert!(close(m.transmission, Vec3::splat(0.25)), "transmit is not tinted");
    let m = material("sphere { 0, 1 pigment { rgbft <1, 0, 0, 0.5, 0.5> } }");
    assert!(close(m.transmission, Vec3::new(1.0, 0.5, 0.5)));
    assert!(close(solid(&m), Vec3::ZERO));
}

#[test]
fn only_an_object_that_does_not_diffuse_glows_with_its_ambient() {
    let c = Vec3::new(0.2, 0.4, 0.6);
    let flat = material(
        "sphere { 0, 1 pigment { rgb <0.2, 0.4, 0.6> } finish { emission 1 ambient 0 diffuse 0 } }",
    );
    assert!(close(flat.emission, c) && close(solid(&flat), Vec3::ZERO));
    let ambient =
        material("sphere { 0, 1 pigment { rgb <0.2, 0.4, 0.6> } finish { ambient 1 diffuse 0 } }");
    assert!(close(ambient.emission, c));
    // With diffuse, ambient is what path tracing computes: not light.
    let lit = material("sphere { 0, 1 pigment { rgb <0.2, 0.4, 0.6> } finish { ambient 1 } }");
    assert_eq!(lit.emission, Vec3::ZERO);
}

#[test]
fn metallic_reflection_is_tinted_and_a_reflection_range_keeps_its_largest() {
    let m = material(
        "sphere { 0, 1 pigment { rgb <1, 0.5, 0> } finish { diffuse 0 reflection 0.8 metallic } }",
    );
    assert!(close(m.specular, 0.8 * Vec3::new(1.0, 0.5, 0.0)));
    let m = material(
        "sphere { 0, 1 pigment { rgb 1 } finish { diffuse 0 reflection { 0.1, 0.6 fresnel on } } }",
    );
    assert!(close(m.specular, Vec3::splat(0.6)) && m.fresnel);
}

#[test]
fn declared_pigments_finishes_and_textures_are_used_by_name() {
    let m = material(
        "#declare P = pigment { color rgb <0, 0, 1> }\n\
         #declare F = finish { diffuse 1 }\n\
         #declare T = texture { pigment { P } finish { F } }\n\
         sphere { 0, 1 texture { T } }",
    );
    assert!(close(solid(&m), Vec3::new(0.0, 0.0, 1.0)));
    let m = material("#declare I = interior { ior 1.33 }  sphere { 0, 1 interior { I } }");
    assert_eq!(m.ior, 1.33);
}

#[test]
fn a_checker_pigment_is_scaled_by_diffuse_and_keeps_its_transforms() {
    let m = material("plane { y, 0 pigment { checker color rgb 1, color rgb 0 scale 2 } }");
    let Pattern::Mix { a, t, .. } = &m.diffuse.pattern else { panic!("{:?}", m.diffuse) };
    assert!(matches!(a.pattern, Pattern::Checker(..)));
    assert_eq!(a.transforms.len(), 1, "scale 2");
    assert!(matches!(t.pattern, Pattern::Solid(c) if close(c, Vec3::splat(0.4))));
}

#[test]
fn normal_is_read_with_a_warning_and_srgb_is_decoded() {
    let graph = pov(
        "sphere { 0, 1 pigment { srgb <1, 0.5, 0> } finish { diffuse 1 } normal { bumps 0.5 scale 0.1 } }",
    );
    assert!(
        graph.warnings.iter().any(|w| w.contains("`normal`") && w.contains(":1:")),
        "{:?}",
        graph.warnings
    );
    let m = graph.objects[0].material.as_ref().unwrap();
    let Pattern::Solid(c) = m.diffuse.pattern else { panic!() };
    assert!((c.y - 0.214_041).abs() < 1e-5, "sRGB 0.5 is linear 0.214: {c}");
}

#[test]
fn povray_s_appearance_is_refused_in_scn() {
    let error = parse_scene(
        Path::new("tests/inline.scn"),
        "camera { location <0, 0, -3> look_at 0 } sphere { 0, 1 finish { diffuse 1 } }",
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains(":1:56") && error.contains("`finish`: POV-Ray's"), "{error}");
}
