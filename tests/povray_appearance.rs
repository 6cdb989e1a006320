//! POV-Ray's appearance in `.pov` scenes (`docs/povray.md`): pigment, finish, texture, interior,
//! normal and `#default`, each read as the material stated there.

use std::path::Path;
use std::sync::Arc;

use crate::common;

use glam::{Affine3A, Vec3};
use raydiance::graph::{Covers, MaterialDesc, Pattern, SceneGraph, ShapeNode, compose};
use raydiance::integrator::Strategy;
use raydiance::lang::parse_scene;
use raydiance::material::{LobeFlags, Material, TransportMode};
use raydiance::scene::build;

fn pov(text: &str) -> SceneGraph {
    parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"))
}

/// The error that refuses `text`.
fn pov_error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.pov"), text).map(|_| ()).unwrap_err().to_string()
}

/// The material of the scene's first object.
fn material(text: &str) -> MaterialDesc {
    (*pov(text).objects[0].material.clone().expect("a material")).clone()
}

fn solid(m: &MaterialDesc) -> Vec3 {
    solid_node(&m.diffuse.pattern)
}

fn solid_node(pattern: &Pattern) -> Vec3 {
    match pattern {
        Pattern::Solid(c) => *c,
        other => panic!("not a solid colour: {other:?}"),
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
    // Faded by the light the pigment lets through, 1 − f − t (povray: `rgbft <1, 0.5, 0.2,
    // 0.3, 0.4>` glows 0.3 of its colour).
    let faded = material(
        "sphere { 0, 1 pigment { rgbft <0.2, 0.4, 0.6, 0.3, 0.4> } finish { ambient 1 diffuse 0 } }",
    );
    assert!(close(faded.emission, 0.3 * c), "{}", faded.emission);
    // With diffuse, ambient is what path tracing computes: not light.
    let lit = material("sphere { 0, 1 pigment { rgb <0.2, 0.4, 0.6> } finish { ambient 1 } }");
    assert_eq!(lit.emission, Vec3::ZERO);
}

#[test]
fn a_glow_by_ambient_is_multiplied_by_ambient_light_and_emission_is_not() {
    // POV-Ray 3.7's manual (3.4.1.2): Ambient = Finish_Ambient × Global_Ambient.
    let m = material(
        "global_settings { assumed_gamma 1 ambient_light <1, 0.5, 0.25> }\n\
         sphere { 0, 1 pigment { rgb <0.2, 0.4, 0.6> } \
         finish { ambient 0.8 emission 0.1 diffuse 0 } }",
    );
    let glow = (0.8 * Vec3::new(1.0, 0.5, 0.25) + Vec3::splat(0.1)) * Vec3::new(0.2, 0.4, 0.6);
    assert!(close(m.emission, glow), "{} against {glow}", m.emission);
    // Only the block's other settings are warned about.
    assert_eq!(pov("global_settings { ambient_light 0.5 }").warnings, Vec::<String>::new());
    let late = "sphere { 0, 1 pigment { rgb 1 } finish { ambient 1 diffuse 0 } }\n\
                global_settings { ambient_light 0.5 }";
    let error = pov_error(late);
    assert!(error.starts_with("tests/inline.pov:2:33:"), "{error}");
    assert!(error.contains("glows by its `ambient` (tests/inline.pov:1:1)"), "{error}");
    // After a surface whose ambient is not light, or with the light unchanged, it is read.
    pov("sphere { 0, 1 finish { ambient 1 } }\nglobal_settings { ambient_light 0.5 }");
    pov("sphere { 0, 1 finish { ambient 1 diffuse 0 } }\nglobal_settings { ambient_light 1 }");
}

#[test]
fn assumed_gamma_makes_surface_and_light_colours_c_to_the_gamma_in_linear_light() {
    // POV-Ray 3.7 takes colours as encoded with `assumed_gamma` G: a colour c is c^G of linear
    // light, whether declared before `global_settings` (colors.inc is) or after it.
    let g: f32 = 2.2;
    let decoded = |c: Vec3| c.powf(g);
    let scene = |items: &str| {
        pov(&format!(
            "#declare C = rgb <0.2, 0.8, 0.1>;\n\
             global_settings {{ assumed_gamma {g} }}\n\
             light_source {{ <0, 5, 0> color rgb <0.5, 1, 0.25> }}\n\
             sphere {{ 0, 1 {items} finish {{ ambient 1 diffuse 0 }} }}"
        ))
    };
    let flat = scene("pigment { C }");
    let c = Vec3::new(0.2, 0.8, 0.1);
    let glow = flat.objects[0].material.as_ref().expect("a material").emission;
    assert!(close(glow, decoded(c)), "{glow} against {}", decoded(c));
    // The light's power is its colour times π d² (Lights): its colour's proportions decoded.
    let power = flat.lights[0].power;
    let shades = power / power.y;
    assert!(close(shades, decoded(Vec3::new(0.5, 1.0, 0.25))), "{power}");
    // A pattern's map: each entry's colour, decoded.
    let mapped = scene("pigment { gradient x color_map { [0 rgb 0.5] [1 C] } }");
    let m = mapped.objects[0].material.as_ref().expect("a material");
    let Pattern::Field { map, .. } = &m.diffuse.pattern else { panic!("{:?}", m.diffuse) };
    let entries: Vec<Vec3> = map.iter().map(|(_, node)| solid_node(&node.pattern)).collect();
    assert_eq!(entries.len(), 2, "{entries:?}");
    assert!(close(entries[0], decoded(Vec3::splat(0.5))), "{entries:?}");
    assert!(close(entries[1], decoded(c)), "{entries:?}");
    // A gamma of 1, or none, leaves colours as written.
    let linear =
        material("global_settings { assumed_gamma 1 }\nsphere { 0, 1 pigment { rgb 0.5 } }");
    assert!(close(solid(&linear), Vec3::splat(0.6 * 0.5)));
}

#[test]
fn assumed_gamma_after_a_surface_or_light_it_would_change_is_refused_by_place() {
    let error =
        pov_error("sphere { 0, 1 pigment { rgb 1 } }\nglobal_settings { assumed_gamma 2.2 }");
    assert!(error.starts_with("tests/inline.pov:2:33:"), "{error}");
    assert!(error.contains("takes a colour (tests/inline.pov:1:1)"), "{error}");
    let error = pov_error("light_source { 0, rgb 1 }\nglobal_settings { assumed_gamma 1.5 }");
    assert!(error.contains("takes a colour (tests/inline.pov:1:1)"), "{error}");
    let error = pov_error("global_settings { assumed_gamma 0 }");
    assert!(error.contains("must be positive"), "{error}");
    // The same gamma again changes nothing, and is read.
    pov("global_settings { assumed_gamma 2.2 }\nsphere { 0, 1 pigment { rgb 1 } }\n\
         global_settings { assumed_gamma 2.2 }");
    assert_eq!(pov("global_settings { assumed_gamma 2.2 }").warnings, Vec::<String>::new());
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
fn a_macro_in_a_pigment_writes_its_items_or_starts_a_colour_s_expression() {
    // isocacti.pov: `pigment { Rand_Array_Item(RockColors, RS) * RRand(0.1, 1, RS) }`.
    let m = material(
        "#macro Red() rgb <1, 0, 0> #end\n\
         sphere { 0, 1 pigment { Red() * 0.5 } finish { diffuse 1 } }",
    );
    assert!(close(solid(&m), Vec3::new(0.5, 0.0, 0.0)));
    // A macro that writes the pigment's items stays one.
    let m = material(
        "#macro Blue() color rgb <0, 0, 1> #end\n\
         sphere { 0, 1 pigment { Blue() } finish { diffuse 1 } }",
    );
    assert!(close(solid(&m), Vec3::new(0.0, 0.0, 1.0)));
}

#[test]
fn layers_that_differ_in_finish_are_warned_about_where_an_object_wears_them() {
    let declared = "#declare T = texture { pigment { rgb 1 } finish { diffuse 0.9 } }\n\
                    texture { pigment { rgbt <1, 0, 0, 0.5> } finish { phong 1 } }\n";
    let differ = |graph: &SceneGraph| {
        let said: Vec<&String> =
            graph.warnings.iter().filter(|w| w.contains("differ in their finish")).collect();
        said.iter().map(|w| w.contains("inline.pov:2:")).collect::<Vec<_>>()
    };
    // Declared and never worn (as the library's textures are): nothing said.
    assert_eq!(differ(&pov(declared)), Vec::<bool>::new());
    // Worn, twice: said once, at the layer that differs.
    let worn =
        format!("{declared}sphere {{ 0, 1 texture {{ T }} }}\nbox {{ 0, 1 texture {{ T }} }}");
    assert_eq!(differ(&pov(&worn)), [true]);
    // Layered on the object itself.
    let own = "sphere { 0, 1 texture { pigment { rgb 1 } }\n\
               texture { pigment { rgbt <1, 0, 0, 0.5> } finish { phong 1 } } }";
    assert_eq!(differ(&pov(own)), [true]);
    // Three layers, the lower two differing and the top one like the middle: still said.
    let three = format!(
        "{}\ntexture {{ pigment {{ rgbt <0, 0, 1, 0.5> }} finish {{ phong 1 }} }}\n\
         sphere {{ 0, 1 texture {{ T }} }}",
        declared.trim_end()
    );
    assert_eq!(differ(&pov(&three)), [true]);
}

#[test]
fn a_checker_pigment_is_scaled_by_diffuse_and_keeps_its_transforms() {
    let m = material("plane { y, 0 pigment { checker color rgb 1, color rgb 0 scale 2 } }");
    // The pigment's colour, which each hit shares out by the finish's `diffuse` 0.6.
    let a = &m.diffuse;
    let Pattern::Field { shape, map } = &a.pattern else { panic!("{a:?}") };
    assert_eq!(shape.field, raydiance::graph::Field::Checker);
    assert_eq!(map.len(), 2, "its two colours");
    assert_eq!(a.transforms.len(), 1, "scale 2");
    assert_eq!(m.pigment.as_ref().map(|p| p.finish.diffuse), Some(0.6));
}

#[test]
fn normal_is_bump_mapping_and_srgb_is_decoded() {
    let bumped = pov("sphere { 0, 1 pigment { rgb 1 } normal { bumps 0.5 scale 0.1 } }");
    let m = bumped.objects[0].material.as_ref().unwrap();
    assert!(m.normal.is_some(), "bumps: bump mapping");
    assert!(bumped.warnings.iter().all(|w| !w.contains("`normal`")), "{:?}", bumped.warnings);
    // An image's bumps (`bump_map`) are read too: a missing file is refused where it is named.
    let missing = pov_error("sphere { 0, 1 normal { bump_map { png \"b.png\" } } }");
    assert!(missing.contains(":1:39:") && missing.contains("b.png"), "{missing}");
    let graph = pov("sphere { 0, 1 pigment { srgb <1, 0.5, 0> } finish { diffuse 1 } }");
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

/// The lobes a `.pov` object's material makes (`docs/povray.md`, finish).
fn lobes(text: &str) -> LobeFlags {
    Material::from(&material(text)).bsdf(Vec3::Z, TransportMode::Radiance).flags()
}

#[test]
fn highlights_become_a_glossy_coat_over_the_diffuse_base() {
    let m = material("sphere { 0, 1 pigment { rgb <1, 0.5, 0> } finish { phong 0.7 } }");
    assert!(close(solid(&m), 0.6 * Vec3::new(1.0, 0.5, 0.0)), "the base keeps its albedo");
    assert!((m.coat - 0.7).abs() < 1e-6, "{}", m.coat);
    // Default phong_size 40: Blinn n = 160, alpha = sqrt(2 / 162).
    assert!((m.coat_roughness - (2.0f32 / 162.0).sqrt()).abs() < 1e-6, "{}", m.coat_roughness);
    assert_eq!((m.specular, m.roughness), (Vec3::ZERO, 0.0), "no mirror, no metal");
    let glossy_diffuse = LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::REFLECTION;
    assert_eq!(lobes("sphere { 0, 1 pigment { rgb 1 } finish { phong 1 } }"), glossy_diffuse);
    // specular's roughness is 1 / n: roughness 0.02 is n = 50, alpha = sqrt(2 / 52).
    let m = material("sphere { 0, 1 pigment { rgb 1 } finish { specular 0.5 roughness 0.02 } }");
    assert!((m.coat - 0.5).abs() < 1e-6);
    assert!((m.coat_roughness - (2.0f32 / 52.0).sqrt()).abs() < 1e-6);
    // A wider phong is a rougher coat; both highlights add up, their widths averaged.
    let narrow = material("sphere { 0, 1 finish { phong 1 phong_size 200 } }");
    let wide = material("sphere { 0, 1 finish { phong 1 phong_size 5 } }");
    assert!(narrow.coat_roughness < 0.06 && wide.coat_roughness > 0.3);
    let both = material(
        "sphere { 0, 1 finish { phong 0.3 phong_size 200  specular 0.3 roughness 0.05 } }",
    );
    let mean = 0.5 * ((2.0f32 / 802.0).sqrt() + (2.0f32 / 22.0).sqrt());
    assert!((both.coat - 0.6).abs() < 1e-6 && (both.coat_roughness - mean).abs() < 1e-6);
    // No highlight, no coat: the plain Lambertian lobe.
    let plain = material("sphere { 0, 1 pigment { rgb 1 } }");
    assert_eq!(plain.coat, 0.0);
    assert_eq!(
        lobes("sphere { 0, 1 pigment { rgb 1 } }"),
        LobeFlags::DIFFUSE | LobeFlags::REFLECTION
    );
}

#[test]
fn a_highlight_with_reflection_is_a_coat_over_a_mirror_scaled_to_conserve_energy() {
    let m =
        material("sphere { 0, 1 pigment { rgb 1 } finish { diffuse 0.9 phong 1 reflection 0.5 } }");
    // The base 0.9 and the mirror 0.5 are scaled by 1 / 1.4; the coat over them keeps its 1.
    assert!(close(solid(&m), Vec3::splat(0.9 / 1.4)), "{}", solid(&m));
    assert_eq!((m.coat, m.coat_covers), (1.0, Covers::Everything));
    assert!(close(m.specular, Vec3::splat(0.5 / 1.4)));
    assert_eq!(m.roughness, 0.0, "the reflection stays a mirror");
    let flags = lobes("sphere { 0, 1 pigment { rgb 1 } finish { phong 1 reflection 0.3 } }");
    assert!(flags.contains(LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::DELTA), "{flags:?}");
}

/// A clear sphere under a full highlight (`rgbf 1`, `phong 1`; issue 33) in front of a glowing
/// wall: seen head-on, the wall through it is dimmed only by what the coat reflects at its two
/// crossings, (1 - F)^2 with F = 0.04 (POV-Ray, which adds its highlight, leaves the wall as it
/// is); the light each reflection sends back inside, F^2 of it, adds a little. Before, the
/// highlight took half the transmission at each crossing: a quarter of the wall.
#[test]
fn a_clear_sphere_under_a_highlight_lets_through_all_the_coat_does_not_reflect() {
    for pigment in ["rgbf 1", "rgbt 1"] {
        let mut graph = pov(&format!(
            "camera {{ location <0, 0, -10> look_at 0 angle 2 }}\n\
             plane {{ z, 3 pigment {{ rgb 0.5 }} finish {{ ambient 1 diffuse 0 }} }}\n\
             sphere {{ 0, 1 pigment {{ {pigment} }} finish {{ phong 1 }} }}"
        ));
        graph.settings.width = 4;
        graph.settings.height = 4;
        graph.settings.samples = 64;
        let seen = common::mean(&common::render_image(&build(&graph).unwrap())).x;
        let expected = 0.5 * 0.96f32.powi(2) * (1.0 + 0.04f32.powi(2));
        assert!((seen - expected).abs() < 0.015, "{pigment}: {seen} vs {expected}");
    }
}

/// Light crosses a clear sphere under a highlight to the floor below as the camera's rays
/// cross it: a shadow ray straight down through its middle keeps (1 - F)^2 of the light, F =
/// 0.04 at normal incidence (`Scene::transmittance`; half of it at each crossing before).
#[test]
fn a_shadow_through_a_clear_sphere_under_a_highlight_keeps_what_the_coat_lets_through() {
    let floor = |sphere: &str| {
        let mut graph = pov(&format!(
            "camera {{ location <0, 1, -6> look_at 0 angle 2 }}\n\
             light_source {{ <0, 10, 0> color rgb 1 }}\n\
             plane {{ y, 0 pigment {{ rgb 1 }} }}\n{sphere}"
        ));
        (graph.settings.width, graph.settings.height, graph.settings.samples) = (2, 2, 4);
        graph.settings.integrator = raydiance::graph::IntegratorKind::Direct;
        common::mean(&common::render_image(&build(&graph).unwrap())).x
    };
    let open = floor("");
    let shaded = floor("sphere { <0, 2, 0>, 1 pigment { rgbf 1 } finish { phong 1 } }");
    let ratio = shaded / open;
    assert!(open > 0.0 && (ratio - 0.96f32.powi(2)).abs() < 0.01, "{shaded} / {open} = {ratio}");
}

/// glass.inc's glass wears POV-Ray's highlight as a coat over it: the coat takes nothing of the
/// glass's transmission or reflection (it passes 1 - h F of the light where it lies).
#[test]
fn the_library_s_glass_keeps_its_highlight_as_a_coat_over_the_glass() {
    let bare = material(
        "sphere { 0, 1 pigment { rgbf <1, 1, 1, 0.7> } \
         finish { ambient 0 diffuse 0 reflection 0.1 } }",
    );
    for glass in ["texture { T_Glass1 }", "texture { Glass }"] {
        let m = material(&format!(
            "#include \"glass.inc\"\n#include \"textures.inc\"\nsphere {{ 0, 1 {glass} }}"
        ));
        assert_eq!((m.coat, m.coat_covers), (1.0, Covers::Everything), "{glass}");
        assert!(close(m.transmission, bare.transmission), "{glass}: {}", m.transmission);
        assert!(close(m.specular, bare.specular), "{glass}: {}", m.specular);
    }
}

#[test]
fn a_metallic_highlight_is_the_blur_of_a_metal_s_tinted_reflection() {
    let gold = Vec3::new(1.0, 0.8, 0.3);
    let m = material(
        "sphere { 0, 1 pigment { rgb <1, 0.8, 0.3> } \
         finish { diffuse 0.1 reflection 0.7 metallic specular 0.8 roughness 0.01 } }",
    );
    assert!(close(m.specular, 0.7 * gold), "{}", m.specular);
    assert!((m.roughness - (2.0f32 / 102.0).sqrt()).abs() < 1e-6, "{}", m.roughness);
    assert_eq!(m.coat, 0.0, "a metal has no dielectric coat");
    let flags = lobes(
        "sphere { 0, 1 pigment { rgb 1 } finish { diffuse 0.1 reflection 0.7 metallic phong 1 } }",
    );
    assert_eq!(flags, LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::REFLECTION);
    // Without reflection, the metallic highlight's amount is the metal's reflectance.
    let m = material(
        "sphere { 0, 1 pigment { rgb <1, 0.8, 0.3> } finish { diffuse 0.5 phong 0.5 metallic } }",
    );
    assert!(close(m.specular, 0.5 * gold) && m.roughness > 0.0, "{} {}", m.specular, m.roughness);
}

#[test]
fn finish_words_without_a_physical_meaning_are_warned_about_by_name() {
    let graph =
        pov("sphere { 0, 1 finish { brilliance 2 crand 0.1 irid { 0.3 thickness 0.2 } } }\n\
         sphere { 0, 1 finish { reflection { 0, 1 falloff 2 } conserve_energy } }");
    for (word, at) in
        [("brilliance", ":1:24"), ("crand", ":1:37"), ("irid", ":1:47"), ("falloff", ":2:42")]
    {
        assert!(
            graph.warnings.iter().any(|w| w.contains(&format!("`{word}`")) && w.contains(at)),
            "{word}: {:?}",
            graph.warnings
        );
    }
    assert!(!graph.warnings.iter().any(|w| w.contains("conserve_energy")), "always conserved");
    assert!(!graph.warnings.iter().any(|w| w.contains("phong")));
}

/// A grey sphere lit from the camera: with `phong` its middle (where the mirror direction meets
/// the camera) shows the coat's highlight, several times brighter than without; away from it
/// the coat lets through what it does not reflect, the base a little darker.
#[test]
fn a_phong_highlight_renders() {
    let render = |finish: &str| {
        let text = format!(
            "camera {{ location <0, 0, -4> look_at 0 angle 30 }}\n\
             light_source {{ <0, 0, -4> color rgb 1 }}\n\
             sphere {{ 0, 1 pigment {{ rgb 0.5 }} finish {{ {finish} }} }}"
        );
        let mut graph = pov(&text);
        graph.settings.width = 33;
        graph.settings.height = 33;
        graph.settings.samples = 16;
        common::render_image(&build(&graph).unwrap_or_else(|e| panic!("{e}")))
    };
    let (plain, shiny) = (render("diffuse 0.6"), render("diffuse 0.6 phong 1"));
    let middle = (shiny.get(16, 16).x, plain.get(16, 16).x);
    assert!(middle.1 > 0.0 && middle.0 > 2.5 * middle.1, "middle {middle:?}");
    let aside = (shiny.get(16, 8).x, plain.get(16, 8).x);
    assert!(aside.1 > 0.0, "the sphere is lit off-centre: {aside:?}");
    assert!(aside.0 < aside.1 && aside.0 > 0.85 * aside.1, "aside {aside:?}");
}

/// The pigment a scene's sky_sphere shows at `p`.
fn sky_at(text: &str, p: Vec3) -> Vec3 {
    let sky = pov(text).sky.expect("a sky");
    let texture = raydiance::texture::Texture::new(&sky.pigment, &mut |_| unreachable!("no image"));
    texture.unwrap().eval(p)
}

#[test]
fn a_pigment_map_blends_its_pigments_as_a_color_map_blends_colours() {
    let text = "#declare Stripes = pigment { checker rgb <1, 0, 0>, rgb <0, 0, 1> }
         sky_sphere { pigment { gradient x pigment_map {
           [0.2 rgb 0] [0.6 rgb 1] [0.8 Stripes scale 0.5] } } }";
    // Below the first position the first pigment, between two a blend, above the last the last
    // (with its own transform: checker cells of 0.5).
    assert!(close(sky_at(text, Vec3::new(0.1, 0.0, 0.0)), Vec3::ZERO));
    assert!(close(sky_at(text, Vec3::new(0.3, 0.0, 0.0)), Vec3::splat(0.25)));
    assert!(close(sky_at(text, Vec3::new(0.7, 0.1, 0.1)), Vec3::new(0.5, 0.5, 1.0)));
    assert!(close(sky_at(text, Vec3::new(0.9, 0.1, 0.1)), Vec3::new(0.0, 0.0, 1.0)));
    assert!(close(sky_at(text, Vec3::new(0.9, 0.6, 0.1)), Vec3::new(1.0, 0.0, 0.0)));

    let one = "sky_sphere { pigment { bozo pigment_map { [0.5 rgb <0, 1, 0>] } } }";
    assert!(close(sky_at(one, Vec3::new(0.3, 0.2, 0.1)), Vec3::new(0.0, 1.0, 0.0)));

    let order =
        pov_error("sphere { 0, 1 pigment { marble pigment_map { [0.5 rgb 0] [0.2 rgb 1] } } }");
    assert!(order.contains(":1:59:") && order.contains("0.2 must be"), "{order}");
    // A pigment's transmit in a pigment_map is kept: the material lets light through where
    // the pattern picks it.
    let clear = material("sphere { 0, 1 pigment { wood pigment_map { [0 rgbt 1] [1 rgb 1] } } }");
    assert!(clear.pigment.is_some(), "patterned transparency is made at each point");
}

/// The camera looks through a plane with a checker of a see-through colour and white at an
/// emitter of radiance 1 behind it, with nothing lit in front: each see-through cell shows the
/// emitter through filter × colour + transmit (interior ior 1: straight through), each white
/// cell black, exactly (`ambient 0 diffuse 0`: nothing glows, and the only paths are delta ones, so there is no
/// noise).
fn seen_through_checker(see_through: &str) -> raydiance::image::Image {
    let text = format!(
        "camera {{ orthographic location <0, 0, -5> look_at 0 right x*4 up y*4 }}
         background {{ rgb 0 }}
         plane {{ -z, -1 pigment {{ rgb 1 }} finish {{ emission 1 ambient 0 diffuse 0 }} }}
         plane {{ -z, 0 pigment {{ checker {see_through} rgb 1 }} finish {{ ambient 0 diffuse 0 }} }}"
    );
    let mut graph = pov(&text);
    (graph.settings.width, graph.settings.height, graph.settings.samples) = (8, 8, 2);
    common::render_image(&build(&graph).unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn a_checker_of_see_through_cells_passes_the_light_behind_it_cell_by_cell() {
    for (colour, through) in [
        ("rgbf <1, 0.5, 0.25, 1>", Vec3::new(1.0, 0.5, 0.25)),
        ("rgbt <1, 0.5, 0.25, 1>", Vec3::ONE),
        ("rgbft <1, 0, 0, 0.5, 0.25>", Vec3::new(0.75, 0.25, 0.25)),
    ] {
        let image = seen_through_checker(colour);
        // Pixels are half a cell: the cells alternate every two pixels, see-through or white.
        let first = close(image.get(0, 0), through);
        for y in 0..8 {
            for x in 0..8 {
                let cell = ((x / 2 + y / 2) % 2 == 0) == first;
                let expected = if cell { through } else { Vec3::ZERO };
                let got = image.get(x, y);
                assert!(close(got, expected), "{colour}: pixel ({x}, {y}) {got}, not {expected}");
            }
        }
    }
}

#[test]
fn a_function_pattern_is_its_function_s_value_wrapped_into_zero_to_one() {
    // POV-Ray's manual: `pigment { function { ... } }` uses the function of (x, y, z) as the
    // pattern's value; its ramp wave keeps [0, 1] and wraps what is outside (fmod, then + 1).
    let sky = |function: &str, modifiers: &str| {
        format!(
            "#declare Half = function(a) {{ a / 2 }}\n\
             sky_sphere {{ pigment {{ function {{ {function} }} {modifiers}\n\
             color_map {{ [0 rgb 0] [1 rgb <1, 0, 0>] }} }} }}"
        )
    };
    let red = |v: f32| Vec3::new(v, 0.0, 0.0);
    let square = sky("x * x", "");
    assert!(close(sky_at(&square, Vec3::new(0.5, 0.3, 0.0)), red(0.25)));
    assert!(close(sky_at(&square, Vec3::new(1.0, 0.3, 0.0)), red(1.0)));
    assert!(close(sky_at(&square, Vec3::new(1.5, 0.3, 0.0)), red(0.25)));
    let wrapped = sky("y - 1", "");
    assert!(close(sky_at(&wrapped, Vec3::new(0.0, 0.25, 0.0)), red(0.25)));
    // Declared functions are called, and the pigment's transforms move the pattern.
    let called = sky("Half(y)", "scale 2");
    assert!(close(sky_at(&called, Vec3::new(0.0, 1.2, 0.0)), red(0.3)));
    // A function with no value at the point (a pole) colours as 0, not as NaN.
    let pole = sky("1 / x - 1 / x", "");
    assert!(close(sky_at(&pole, Vec3::ZERO), red(0.0)));
    // In a normal, the number after the function is its bump size.
    pov("sphere { 0, 1 pigment { rgb 1 } normal { function { sin(x * 10) } 0.5 } }");
}

#[test]
fn a_colour_function_gives_its_pigment_s_colour_and_in_a_function_a_component() {
    // POV-Ray's manual: `function { pigment { } }` is a colour function of (x, y, z); `.gray` is
    // 0.297 red + 0.589 green + 0.114 blue.
    let declare = "#declare C = function { pigment { gradient x\n\
                   color_map { [0 rgb <0, 0.5, 1>] [1 rgb <1, 0.5, 0>] } } }\n";
    let colour_at = |x: f32| Vec3::new(x, 0.5, 1.0 - x);
    // Called from the scene, the colour there, with filter and transmit 0.
    let called = format!(
        "{declare}#declare V = C(0.25, 3, 4);\n\
         #if (abs(V.red - 0.25) + abs(V.green - 0.5) + abs(V.blue - 0.75) + V.filter \
         + V.transmit > 1e-6) #error \"C(0.25, 3, 4)\" #end\n\
         #declare Y = rgb <1, 1, 0>;\n\
         #if (abs(Y.gray - 0.886) > 1e-9) #error \"gray\" #end"
    );
    pov(&called);
    // In a function pattern, each component at the pattern's point.
    for (component, of) in [
        ("red", (|c: Vec3| c.x) as fn(Vec3) -> f32),
        ("z", |c: Vec3| c.z),
        ("gray", |c: Vec3| c.dot(Vec3::new(0.297, 0.589, 0.114))),
    ] {
        let sky = format!(
            "{declare}sky_sphere {{ pigment {{ function {{ C(x, y, z).{component} }}\n\
             color_map {{ [0 rgb 0] [1 rgb <0, 1, 0>] }} }} }}"
        );
        for x in [0.2f32, 0.7] {
            let seen = sky_at(&sky, Vec3::new(x, 0.1, 0.0));
            assert!(close(seen, Vec3::new(0.0, of(colour_at(x)), 0.0)), "{component} at {x}");
        }
    }
    // A colour function is no number: a function takes its components.
    let error = pov_error(&format!("{declare}#declare F = function {{ C(x, y, z) + 1 }}"));
    assert!(error.contains(":3:") && error.contains("`C` is a colour function"), "{error}");
}

#[test]
fn pigment_pattern_is_its_pigment_s_gray_and_quick_color_is_not_rendered() {
    // POV-Ray's manual: pigment_pattern converts its pigment to gray, the value through the map.
    let sky = "sky_sphere { pigment { pigment_pattern { gradient x scale 2\n\
               color_map { [0 rgb 0] [1 rgb <1, 0.5, 0>] } }\n\
               color_map { [0 rgb 0] [1 rgb <0, 0, 1>] } } }";
    for x in [0.4f32, 1.2] {
        let inner = Vec3::new(1.0, 0.5, 0.0) * (x / 2.0);
        let gray = inner.dot(Vec3::new(0.297, 0.589, 0.114));
        assert!(close(sky_at(sky, Vec3::new(x, 0.3, 0.0)), Vec3::new(0.0, 0.0, gray)), "{x}");
    }
    // quick_color is the colour of POV-Ray's quick previews, which a full render ignores.
    let m = material("sphere { 0, 1 pigment { rgb <0, 1, 0> quick_color red 0.7 green 0.2 } }");
    assert!(close(solid(&m), Vec3::new(0.0, 0.6, 0.0)), "{:?}", solid(&m));
}

#[test]
fn an_average_s_entries_may_be_function_patterns_without_a_weight() {
    // As in the woods *_37.pov scenes: `[function { } color_map { }]`, no position before the
    // pattern; average's missing weights are 1, so the colour is the two entries' mean.
    let text = "sky_sphere { pigment { average pigment_map {
           [function { 0.5 } color_map { [0 rgb 0] [1 rgb <1, 0, 0>] }]
           [function { 0.25 } color_map { [0 rgb 0] [1 rgb <0, 1, 0>] }] } } }";
    let seen = sky_at(text, Vec3::new(0.3, 0.2, 0.1));
    assert!(close(seen, Vec3::new(0.25, 0.125, 0.0)), "{seen}");
}

#[test]
fn functions_inc_s_f_hexagon_gives_the_hexagon_s_three_values() {
    // POV-Ray's functions.inc: `f_hexagon` is the colour function of `hexagon` over the colours
    // 0, 0.5 and 1; its `.gray` at points across the x-z plane takes each of them.
    let text = "#include \"functions.inc\"
        #declare Seen = array[3] { 0, 0, 0 }
        #for (I, 0, 199)
          #declare V = f_hexagon(mod(I, 20) * 0.31, 0, div(I, 20) * 0.29).gray;
          #for (K, 0, 2)
            #if (abs(V - K / 2) < 1e-6) #declare Seen[K] = Seen[K] + 1; #end
          #end
          #if (abs(V) > 1e-6 & abs(V - 0.5) > 1e-6 & abs(V - 1) > 1e-6) #error \"other\" #end
        #end
        #if (Seen[0] = 0 | Seen[1] = 0 | Seen[2] = 0) #error \"not all three\" #end";
    pov(text);
}

/// A floor lit by an emitter through a sheet of see-through cells (a tinted filter and clear):
/// light samples alone (shadow rays crossing the sheet with its transmission there) and
/// BSDF-sampled paths alone (crossing it as a delta transmission) estimate the same image, and
/// MIS agrees with both, so light through the sheet is counted once.
#[test]
fn light_through_a_see_through_sheet_is_found_alike_by_light_and_bsdf_samples() {
    let mut graph = pov("camera { location <0, 3, -3> look_at 0 angle 60 }
         disc { <0, 3, 0>, -y, 2 pigment { rgb 1 } finish { emission 1 ambient 0 diffuse 0 } }
         disc { <0, 1.5, 0>, y, 1.5 pigment { checker rgbf <1, 0.3, 0.3, 0.8> rgbt 1 scale 0.5 } }
         plane { y, 0 pigment { rgb 0.8 } finish { diffuse 1 } }");
    (graph.settings.width, graph.settings.height) = (24, 18);
    (graph.settings.samples, graph.settings.max_depth) = (64, 3);
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    common::assert_light_and_bsdf_sampling_agree_with_mis(&scene, "see-through sheet");
}

/// POV-Ray's glow is seen from both sides (docs/povray.md). Inside a closed sphere whose wall
/// glows with E and diffuses with albedo a, the radiance everywhere is E / (1 - a) (here
/// 0.5 / (1 - 0.5) = 1): the wall lights its own inside, and light samples alone, BSDF samples
/// alone and MIS each find it. With the glow on the outer side only, the inside would be black.
#[test]
fn a_glow_is_seen_from_both_sides_and_lights_the_inside_of_its_sphere() {
    let mut graph = pov("camera { location <0.3, -0.2, 0.1> look_at <1, 0, 2> angle 100 }
         sphere { 0, 2 pigment { rgb 1 } finish { emission 0.5 diffuse 0.5 } }");
    (graph.settings.width, graph.settings.height) = (16, 16);
    (graph.settings.samples, graph.settings.max_depth) = (64, 64);
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    for strategy in [Strategy::Mis, Strategy::LightSampling, Strategy::BsdfSampling] {
        let film = common::path_with(&scene, strategy);
        common::assert_uniform_radiance(&film, Vec3::ONE, &format!("{strategy:?}"));
    }
}

/// A glowing disc that faces away from a floor lights it with its back: light samples alone
/// and BSDF samples alone agree with MIS (the back's radiance, pdf and power are the front's).
#[test]
fn the_back_of_a_glow_is_found_alike_by_light_and_bsdf_samples() {
    let mut graph = pov("camera { location <0, 3, -3> look_at 0 angle 60 }
         disc { <0, 3, 0>, y, 2 pigment { rgb 1 } finish { emission 1 diffuse 0 } }
         plane { y, 0 pigment { rgb 0.8 } finish { diffuse 1 } }");
    (graph.settings.width, graph.settings.height) = (24, 18);
    (graph.settings.samples, graph.settings.max_depth) = (64, 3);
    let scene = build(&graph).unwrap_or_else(|e| panic!("{e}"));
    let image = common::path_with(&scene, Strategy::Mis).image();
    assert!(common::mean(&image).x > 0.05, "the floor is lit: {}", common::mean(&image));
    common::assert_light_and_bsdf_sampling_agree_with_mis(&scene, "the glow's back");
}

/// A glow whose pigment is red on one half of a square and blue on the other lights a floor
/// as the two halves, each glowing in one colour, do; and light samples alone (each reading
/// the pattern where it lands on the square), BSDF samples alone (each reading it where the
/// ray hits) and MIS agree: the area light's radiance is the pattern's at each point, its
/// density the square's, uniform by area. (Glowing with its brightest colour everywhere, the
/// square would light the floor magenta.)
#[test]
fn a_patterned_glow_lights_as_its_colours_do_found_alike_by_light_and_bsdf_samples() {
    let render = |glow: &str| {
        let mut graph = pov(&format!(
            "camera {{ location <0, 3, -3> look_at 0 angle 60 }}
             #default {{ finish {{ emission 1 diffuse 0 }} }}
             {glow}
             plane {{ y, 0 pigment {{ rgb 0.8 }} finish {{ diffuse 1 emission 0 }} }}"
        ));
        (graph.settings.width, graph.settings.height) = (24, 18);
        (graph.settings.samples, graph.settings.max_depth) = (128, 1);
        build(&graph).unwrap_or_else(|e| panic!("{e}"))
    };
    let patterned = render(
        "box { <-2, 3, -2>, <2, 3, 2> pigment { gradient x scale 4
           color_map { [0 rgb <2, 0, 0>] [0.5 rgb <2, 0, 0>] [0.5 rgb <0, 0, 2>] [1 rgb <0, 0, 2>] } } }",
    );
    let halves = render(
        "box { <0, 3, -2>, <2, 3, 2> pigment { rgb <2, 0, 0> } }
         box { <-2, 3, -2>, <0, 3, 2> pigment { rgb <0, 0, 2> } }",
    );
    common::assert_light_and_bsdf_sampling_agree_with_mis(&patterned, "a patterned glow");
    common::assert_films_agree(
        &common::path_with(&patterned, Strategy::Mis),
        &common::path_with(&halves, Strategy::Mis),
        "a patterned glow vs its halves",
    );
}

/// `image_map { [type] "file" options }` in a pigment: the file is found beside the scene, its
/// options are the look of the pigment's parts, and a `once` image lets light through outside
/// its square; options raydiance does not read are refused where they stand.
#[test]
fn an_image_map_pigment_reads_its_options_and_refuses_what_it_cannot_honour() {
    use raydiance::graph::{ImageChannel, ImageLook, ImageProjection};
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 128, 0]))
        .save(dir.path().join("tile.png"))
        .unwrap();
    let scene = dir.path().join("scene.pov");
    let read = |pigment: &str| {
        let text = format!("sphere {{ 0, 1 pigment {{ {pigment} }} }}");
        parse_scene(&scene, &text).map(|g| (*g.objects[0].material.clone().unwrap()).clone())
    };
    let m =
        read(r#"image_map { png "tile" map_type 1 once interpolate 2 gamma 2.2 filter all 0.25 }"#)
            .unwrap_or_else(|e| panic!("{e}"));
    let look = |node: &raydiance::graph::TextureNode| match &node.pattern {
        Pattern::Image { path, look } => {
            assert_eq!(path, &dir.path().join("tile.png"), "found with its extension");
            *look
        }
        other => panic!("not an image: {other:?}"),
    };
    let colour = look(&m.diffuse);
    let expected = ImageLook {
        projection: ImageProjection::Spherical,
        once: true,
        bilinear: true,
        gamma: Some(2.2),
        channel: ImageChannel::Colour,
    };
    assert_eq!(colour, expected);
    let see_through = m.pigment.expect("a once image lets light through outside it");
    assert_eq!(look(&see_through.filter).channel, ImageChannel::Filter(0.25));
    assert_eq!(look(&see_through.through).channel, ImageChannel::Through(0.25));
    // Repeating, opaque, without alpha: a plain colour texture.
    let plain = read(r#"image_map { "tile.png" }"#).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(look(&plain.diffuse), ImageLook::colour());
    let through = plain.pigment.expect("a patterned pigment").through;
    assert_eq!(through.pattern, Pattern::Solid(Vec3::ZERO), "no light through anywhere");
    // Each error names the file, line and column of the word (or value) it refuses.
    for (option, at, says) in [
        ("map_type 7", "7", "`map_type 7`"),
        ("filter 3, 0.5", "filter", "`filter`: raydiance reads"),
        ("use_index", "use_index", "`use_index`"),
        ("", "\"nothing.png\"", "cannot read `nothing.png`"),
    ] {
        let file = if option.is_empty() { "nothing.png" } else { "tile.png" };
        let pigment = format!(r#"image_map {{ png "{file}" {option} }}"#);
        let column = format!("sphere {{ 0, 1 pigment {{ {pigment} }} }}").find(at).unwrap() + 1;
        let error = read(&pigment).unwrap_err().to_string();
        let expected = format!("scene.pov:1:{column}: error: {says}");
        assert!(error.contains(&expected), "{option}: {error}, not {expected}");
    }
}

/// An image that is neither beside the scene nor on the include path is looked for in POV-Ray's
/// installed library, as height fields and fonts are: its `test.png`, which sample scenes use.
#[test]
fn an_image_map_finds_povray_s_test_png_in_its_library() {
    let library = Path::new("/usr/share/povray-3.7/include");
    if !library.join("test.png").is_file() {
        assert!(std::env::var_os("CI").is_none(), "CI needs POV-Ray's library (povray-includes)");
        println!("skipped: POV-Ray's library (Debian's povray-includes) is not installed");
        return;
    }
    let m = material(r#"sphere { 0, 1 pigment { image_map { png "test.png" } } }"#);
    match &m.diffuse.pattern {
        Pattern::Image { path, .. } => assert_eq!(path, &library.join("test.png")),
        other => panic!("not an image: {other:?}"),
    }
}

/// The materials a node's shapes wear, in order: each its own, or its nearest wearer's above it.
fn worn(node: &raydiance::graph::ObjectNode, above: Option<&MaterialDesc>) -> Vec<MaterialDesc> {
    use raydiance::graph::Below;
    let wearer = node.material.as_deref().or(above);
    match node.shape.below() {
        Below::Children(nodes) | Below::Operands(nodes) => {
            nodes.iter().flat_map(|n| worn(n, wearer)).collect()
        }
        Below::Shared(target) => worn(target, wearer),
        Below::Nothing => vec![wearer.expect("a material").clone()],
    }
}

const WORN: &str = "#declare T = box { -1, 1 texture { pigment { rgb 1 } } }\n";

#[test]
fn a_wrapper_s_pigment_normal_and_finish_modify_the_wrapped_object_s_own_texture() {
    let first = |text: &str| worn(&pov(&format!("{WORN}{text}")).objects[0], None).remove(0);
    // POV-Ray 3.7 renders each box below in the wrapper's colour (measured: /tmp/wrap33).
    let m = first("object { T pigment { rgb <1, 0, 0> } }");
    assert!(close(solid(&m), Vec3::new(0.6, 0.0, 0.0)), "{:?}", solid(&m));
    let m = first("object { T finish { diffuse 0.3 } }");
    assert!(close(solid(&m), Vec3::splat(0.3)), "the white pigment kept");
    let m = first("object { T normal { bumps 1 scale 0.1 } }");
    assert!(m.normal.is_some() && close(solid(&m), Vec3::splat(0.6)));
    // Down a chain of wrappers; the declared object itself is left as it was.
    let scene = pov(&format!(
        "{WORN}#declare A = object {{ T }}\nobject {{ A pigment {{ rgb <0, 0, 1> }} }}\n\
         object {{ T }}"
    ));
    let m = worn(&scene.objects[0], None).remove(0);
    assert!(close(solid(&m), Vec3::new(0.0, 0.0, 0.6)));
    assert!(close(solid(&worn(&scene.objects[1], None)[0]), Vec3::splat(0.6)));
}

#[test]
fn a_wrapper_s_texture_is_layered_over_the_wrapped_one_and_reaches_a_group_s_bare_parts() {
    // POV-Ray layers it: half-transparent red over the white box shows pink, not the background.
    let scene =
        pov(&format!("{WORN}object {{ T texture {{ pigment {{ rgbt <1, 0, 0, 0.5> }} }} }}"));
    let m = worn(&scene.objects[0], None).remove(0);
    assert!(close(solid(&m), 0.6 * Vec3::new(1.0, 0.5, 0.5)), "{:?}", solid(&m));
    assert_eq!(m.transmission, Vec3::ZERO);
    // A group without a texture of its own: the wrapper's reaches only its untextured parts.
    let scene =
        pov("#declare U = union { sphere { -x, 1 pigment { rgb <0, 1, 0> } } sphere { x, 1 } }\n\
         object { U pigment { rgb <1, 0, 0> } }");
    let parts: Vec<Vec3> = worn(&scene.objects[0], None).iter().map(solid).collect();
    assert!(close(parts[0], Vec3::new(0.0, 0.6, 0.0)) && close(parts[1], Vec3::new(0.6, 0.0, 0.0)));
}

/// Where the pattern and the bumps of the scene's first object lie in the scene: their own
/// transforms, then the object's.
fn laid(text: &str) -> (Affine3A, Option<Affine3A>) {
    let graph = pov(text);
    let object = &graph.objects[0];
    let m = object.material.as_ref().expect("a material");
    let to_world = compose(&object.transforms);
    let normal = m.normal.as_ref().map(|n| to_world * compose(&n.transforms));
    (to_world * compose(&m.diffuse.transforms), normal)
}

fn same(a: Affine3A, b: Affine3A) -> bool {
    a.abs_diff_eq(b, 1e-5)
}

#[test]
fn an_object_s_transforms_move_its_texture_only_when_written_after_it() {
    let turned =
        Affine3A::from_rotation_y(30f32.to_radians()) * Affine3A::from_scale(Vec3::splat(5.0));
    let after = Affine3A::from_translation(Vec3::X);
    for given in [
        "pigment { checker } normal { bumps }",
        "texture { pigment { checker } normal { bumps } }",
        "material { texture { pigment { checker } normal { bumps } } }",
    ] {
        let (pigment, normal) =
            laid(&format!("box {{ -1, 1 scale 5 rotate 30*y {given} translate x }}"));
        assert!(same(pigment, after), "{given}: {pigment:?}");
        assert!(same(normal.expect("bumps"), after), "{given}: {normal:?}");
        let (pigment, normal) =
            laid(&format!("box {{ -1, 1 {given} scale 5 rotate 30*y translate x }}"));
        assert!(same(pigment, after * turned), "{given} first: {pigment:?}");
        assert!(same(normal.expect("bumps"), after * turned), "{given} first: {normal:?}");
    }
    // POV-Ray's default texture lies in the scene's space.
    let (pigment, _) = laid("#default { pigment { checker } } box { -1, 1 scale 5 }");
    assert!(same(pigment, Affine3A::IDENTITY), "{pigment:?}");
}

#[test]
fn a_pigment_modified_after_a_transform_keeps_what_moved_it_as_povray_s_does() {
    let six = Affine3A::from_scale(Vec3::splat(6.0));
    let (pigment, _) = laid("box { -1, 1 pigment { checker } scale 2 pigment { scale 3 } }");
    assert!(same(pigment, six), "{pigment:?}");
    // A new pattern keeps the pigment's transforms and those that moved it.
    let (pigment, _) =
        laid("box { -1, 1 pigment { checker scale 3 } scale 2 pigment { granite } }");
    assert!(same(pigment, six), "{pigment:?}");
    // A declared pigment is itself, laid where it is given.
    let (pigment, _) = laid(
        "#declare P = pigment { checker }\n\
         box { -1, 1 pigment { granite } scale 2 pigment { P } }",
    );
    assert!(same(pigment, Affine3A::IDENTITY), "{pigment:?}");
    // A wrapper's modifies the texture of the object it wraps, as that object stands.
    let graph = pov("#declare T = box { -1, 1 scale 2 pigment { checker } }\n\
                     object { T scale 3 pigment { scale 0.5 } }");
    let wrapper = &graph.objects[0];
    let ShapeNode::Instance(target) = &wrapper.shape else { panic!("{:?}", wrapper.shape) };
    let m = target.material.as_ref().expect("the wrapped box's, modified");
    let world = compose(&wrapper.transforms) * compose(&target.transforms);
    let pigment = world * compose(&m.diffuse.transforms);
    assert!(same(pigment, Affine3A::from_scale(Vec3::splat(1.5))), "{pigment:?}");
}

#[test]
fn a_group_s_texture_lies_in_the_group_s_space_whatever_its_parts_transforms() {
    let graph = pov("union { box { -1, 1 scale 2 } sphere { 0, 1 } scale 3 pigment { checker } }");
    let union = &graph.objects[0];
    let ShapeNode::Union(parts) = &union.shape else { panic!("{:?}", union.shape) };
    let m = parts[0].material.as_ref().expect("the group's, moved back by the box's scale");
    let world = compose(&union.transforms) * compose(&parts[0].transforms);
    let pigment = world * compose(&m.diffuse.transforms);
    assert!(same(pigment, Affine3A::IDENTITY), "{pigment:?}");
    assert!(parts[1].material.is_none(), "the unmoved sphere wears the group's own");
    // A declared object placed twice in the same place under one texture is laid once.
    let graph = pov("#declare U = union { box { -1, 1 translate x } }\n\
                     union { object { U } object { U } pigment { checker } }");
    let ShapeNode::Union(parts) = &graph.objects[0].shape else { panic!() };
    let (ShapeNode::Instance(a), ShapeNode::Instance(b)) = (&parts[0].shape, &parts[1].shape)
    else {
        panic!("{parts:?}")
    };
    assert!(Arc::ptr_eq(a, b), "one copy");
    // `.scn` lays a material in the space of each shape that wears it, as it always has.
    let scn = parse_scene(
        Path::new("tests/inline.scn"),
        "camera { location <0, 0, -5> look_at <0, 0, 0> }\n\
         union { box { <-1, -1, -1>, <1, 1, 1> scale 2 } scale 3\n\
         material { diffuse checker { rgb 1, rgb 0 } } }",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let ShapeNode::Union(parts) = &scn.objects[0].shape else { panic!() };
    assert!(parts[0].material.is_none(), "the box wears the union's, in its own space");
}
