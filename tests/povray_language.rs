//! POV-Ray's language in `.pov` scenes (`docs/povray.md`): `#switch`, colours by components and
//! their arithmetic, every form of `color_map`, `inverse` and `clipped_by` — each read, and each
//! misuse refused where it is written.

use std::path::Path;

use glam::Vec3;
use raydiance::graph::{CsgOp, Pattern, SceneGraph, ShapeNode, TextureNode};
use raydiance::lang::parse_scene;
use raydiance::texture::{Octaves, Texture};

fn pov(text: &str) -> SceneGraph {
    parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"))
}

fn pov_error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.pov"), text).map(|_| ()).unwrap_err().to_string()
}

fn scn_error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.scn"), text).map(|_| ()).unwrap_err().to_string()
}

/// The radius of the scene's first object, a sphere: where a test puts the number it computes.
fn radius(graph: &SceneGraph) -> f32 {
    match graph.objects[0].shape {
        ShapeNode::Sphere { radius, .. } => radius,
        ref other => panic!("not a sphere: {other:?}"),
    }
}

fn sphere_of(value: &str, declarations: &str) -> f32 {
    radius(&pov(&format!("{declarations}\nsphere {{ 0, {value} }}")))
}

const SWITCH: &str = "
#switch (V)
  #case (1)
    #declare R = 1;
  #break
  #range (2, 3)
    #declare R = 2;
  #case (4)
    #declare R = R + 10;
  #break
  #case (5)
    #declare R = 5;
    #break
    #declare R = 50;
  #else
    #declare R = 100;
#end";

#[test]
fn switch_runs_the_first_clause_that_holds_and_falls_through_until_break() {
    let r = |v: f64| sphere_of("R", &format!("#declare V = {v};\n#declare R = 0;\n{SWITCH}"));
    assert_eq!(r(1.0), 1.0);
    // A `#range` holds at its ends; without `#break` the next clause runs too.
    assert_eq!(r(2.0), 12.0);
    assert_eq!(r(3.0), 12.0);
    assert_eq!(r(4.0), 10.0);
    // What follows a `#break` up to the next clause is skipped.
    assert_eq!(r(5.0), 5.0);
    assert_eq!(r(7.0), 100.0);
    assert_eq!(r(3.5), 100.0);
}

#[test]
fn switch_misuse_is_refused_where_it_stands() {
    let outside = pov_error("#case (1)\nsphere { 0, 1 }");
    assert!(outside.starts_with("tests/inline.pov:1:1:"), "{outside}");
    assert!(outside.contains("`#case` stands only among a `#switch`'s clauses"), "{outside}");
    let nested = pov_error("#switch (1)\n#case (1)\n#if (1)\n#break\n#end\n#end");
    assert!(nested.starts_with("tests/inline.pov:4:1:"), "{nested}");
    let before = pov_error("#switch (1)\nsphere { 0, 1 }\n#case (1)\n#end");
    assert!(before.starts_with("tests/inline.pov:2:1:"), "{before}");
    assert!(before.contains("before its first `#case`"), "{before}");
    let after_else = pov_error("#switch (1)\n#else\n#case (1)\n#end");
    assert!(after_else.contains("after the `#else`"), "{after_else}");
    let open = pov_error("#switch (1)\n#case (1)\n");
    assert!(open.contains("`#switch` without its `#end`"), "{open}");
    let scn = scn_error("#switch (1)\n#end");
    assert!(scn.contains("`#switch`") && scn.contains("#elseif"), "{scn}");
}

#[test]
fn colours_have_components_keywords_and_arithmetic() {
    let c = "#declare C = color red 0.5 green 0.25 filter 0.5;";
    assert_eq!(sphere_of("C.red + C.green", c), 0.75);
    assert_eq!(sphere_of("C.filter + C.transmit + 1", c), 1.5);
    // A colour times a number scales every component; a vector adds as a colour without filter.
    assert_eq!(
        sphere_of("D.red + D.filter", &format!("{c}\n#declare D = C * 0.5 + <0.1, 0, 0>;")),
        0.6
    );
    // A component changes a declared colour; an rgb colour has no filter or transmit.
    assert_eq!(
        sphere_of("E.blue + E.transmit + 1", "#declare E = color rgb <1, 1, 0.5> transmit 0.25;"),
        1.75
    );
    assert_eq!(sphere_of("F.filter + F.transmit + F.x", "#declare F = rgb <0.5, 0, 0>;"), 0.5);
    assert_eq!(sphere_of("G.t + G.transmit", "#declare G = rgbf <0, 0, 0, 0.5>;"), 0.5);
    let component = scn_error("#declare V = <1, 2, 3>;\n#declare W = V.red;");
    assert!(component.starts_with("tests/inline.scn:2:15:"), "{component}");
    let word = scn_error("#declare C = rgb 1 filter 0.5;");
    assert!(word.contains("`filter`"), "{word}");
    let missing = pov_error("#declare V = <1, 2>;\nsphere { 0, V.z }");
    assert!(missing.starts_with("tests/inline.pov:2:14:"), "{missing}");
    assert!(missing.contains("a 2-vector has no component 3"), "{missing}");
}

/// The colour map of the first object's gradient pigment.
fn gradient_map(graph: &SceneGraph) -> Vec<(f32, Vec3)> {
    fn find(node: &TextureNode) -> Option<Vec<(f32, Vec3)>> {
        match &node.pattern {
            Pattern::Field { map, .. } => Some(
                map.iter()
                    .map(|(t, entry)| match entry.pattern {
                        Pattern::Solid(c) => (*t, c),
                        _ => panic!("a color_map's entries are colours"),
                    })
                    .collect(),
            ),
            Pattern::Mix { a, .. } => find(a),
            _ => None,
        }
    }
    let material = graph.objects[0].material.clone().expect("a material");
    find(&material.diffuse).expect("a gradient")
}

#[test]
fn color_maps_take_every_form_povray_writes() {
    let graph =
        pov("#declare M = color_map { [0, 0.5 color rgb 0 color rgb 1] [0.5 rgb <1, 0, 0>] \
                     [1.0 color red 1 blue 0.5] }\n\
                     sphere { 0, 1 pigment { gradient y color_map { M } } }");
    let expected = [
        (0.0, Vec3::ZERO),
        (0.5, Vec3::ONE),
        (0.5, Vec3::new(1.0, 0.0, 0.0)),
        (1.0, Vec3::new(1.0, 0.0, 0.5)),
    ];
    assert_eq!(gradient_map(&graph), expected);
    // An entry's filter and transmit are kept, interpolated as the colour is.
    let graph = pov(
        "sphere { 0, 1 pigment { gradient y color_map { [0 rgbt <1, 1, 1, 0.5>] [1 rgb 0] } } }",
    );
    assert_eq!(gradient_map(&graph)[0], (0.0, Vec3::ONE));
    assert!(graph.warnings.is_empty(), "{:?}", graph.warnings);
    let material = graph.objects[0].material.clone().expect("a material");
    let through = &material.pigment.as_ref().expect("a see-through pigment").through;
    let through = Texture::new(through, &mut |_| unreachable!("no image")).unwrap();
    assert_eq!(through.eval(Vec3::ZERO), Vec3::splat(0.5));
    assert_eq!(through.eval(Vec3::new(0.0, 0.5, 0.0)), Vec3::splat(0.25));
}

#[test]
fn color_map_misuse_is_refused_where_it_stands() {
    let one = pov_error("sphere { 0, 1 pigment { gradient y color_map { [0, 1 color rgb 1] } } }");
    assert!(
        one.starts_with("tests/inline.pov:1:52:") && one.contains("needs two colours"),
        "{one}"
    );
    let two = pov_error("sphere { 0, 1 pigment { gradient y color_map { [0 rgb 1 rgb 0] } } }");
    assert!(two.starts_with("tests/inline.pov:1:57:") && two.contains("range's end"), "{two}");
    let name = pov_error("#declare N = 3;\nsphere { 0, 1 pigment { gradient y color_map { N } } }");
    assert!(name.starts_with("tests/inline.pov:2:48:") && name.contains("not a number"), "{name}");
    let scn = scn_error("#declare M = color_map { [0 rgb 1] }");
    assert!(scn.contains("`color_map`"), "{scn}");
    let down =
        pov_error("sphere { 0, 1 pigment { gradient y color_map { [0.5 rgb 1] [0.2 rgb 0] } } }");
    assert!(
        down.starts_with("tests/inline.pov:1:61:") && down.contains("not below the one before")
    );
}

#[test]
fn color_map_positions_outside_0_1_shape_the_map_inside_it_as_in_povray() {
    // POV-Ray's colour at 0.25 of `[-1 rgb 0] [0.5 rgb 0.5] [1.01 rgb 1]` is 0.417, at 0.75 0.745.
    let graph = pov("sphere { 0, 1 pigment { gradient x \
                     color_map { [-1 rgb 0] [0.5 rgb 0.5] [1.01 rgb 1] } } finish { diffuse 1 } }");
    let diffuse = &graph.objects[0].material.as_ref().unwrap().diffuse;
    let texture = Texture::new(diffuse, &mut |_| unreachable!("no image")).unwrap();
    let at = |x: f32| texture.eval(Vec3::new(x, 0.0, 0.0)).x;
    assert!((at(0.25) - 0.4167).abs() < 1e-3 && (at(0.75) - 0.7451).abs() < 1e-3);
    let scn = "camera { location <0, 0, -3> look_at 0 }\n\
               sphere { 0, 1 material { diffuse gradient { color_map { [-1 rgb 0] [1 rgb 1] } } } }";
    let error = parse_scene(Path::new("tests/inline.scn"), scn).map(|_| ()).unwrap_err();
    assert!(error.to_string().contains("must be in [0, 1]"), "{error}");
}

#[test]
fn inverse_and_clipped_by_wrap_the_object_transforms_after_clipped_by_move_both() {
    let graph = pov("sphere { 0, 1 inverse pigment { rgb 1 } }\n\
                     sphere { 0, 1 translate x clipped_by { plane { y, 0 } } scale 2 }");
    match &graph.objects[0].shape {
        ShapeNode::Csg { op: CsgOp::Inverse, operands } => {
            assert!(matches!(operands[0].shape, ShapeNode::Sphere { .. }));
            assert!(graph.objects[0].material.is_some(), "the look is on the whole");
        }
        other => panic!("not inverted: {other:?}"),
    }
    let clipped = &graph.objects[1];
    match &clipped.shape {
        ShapeNode::Csg { op: CsgOp::Clip, operands } => {
            assert_eq!(operands.len(), 2);
            assert_eq!(operands[0].transforms.len(), 1, "translate moves the sphere alone");
            assert!(matches!(operands[1].shape, ShapeNode::Plane { .. }));
        }
        other => panic!("not clipped: {other:?}"),
    }
    assert_eq!(clipped.transforms.len(), 1, "scale moves the sphere and its clip");
    let scn = scn_error("camera { location <0, 0, -1> look_at 0 }\nsphere { 0, 1 inverse }");
    assert!(scn.starts_with("tests/inline.scn:2:15:") && scn.contains("`inverse`"), "{scn}");
    let empty = pov_error("sphere { 0, 1 clipped_by { } }");
    assert!(empty.starts_with("tests/inline.pov:1:15:") && empty.contains("no objects"), "{empty}");
}

#[test]
fn a_pov_material_holds_a_texture_and_an_interior_and_may_be_declared() {
    let graph = pov("#declare M = material { texture { pigment { rgbf <1, 1, 1, 1> } } \
                     interior { ior 1.5 } }\n\
                     sphere { 0, 1 material { M } }\n\
                     sphere { 0, 1 material { texture { pigment { rgb <1, 0, 0> } } } }");
    let glass = graph.objects[0].material.clone().expect("a material");
    assert_eq!((glass.ior, glass.transmission), (1.5, Vec3::ONE));
    let red = graph.objects[1].material.clone().expect("a material");
    assert_eq!(red.diffuse.pattern, Pattern::Solid(Vec3::new(0.6, 0.0, 0.0)));
    let wrong = pov_error("#declare N = 1;\nsphere { 0, 1 material { N } }");
    assert!(
        wrong.starts_with("tests/inline.pov:2:26:") && wrong.contains("not a material"),
        "{wrong}"
    );
}

#[test]
fn layered_textures_show_the_lower_layer_through_the_upper_with_a_warning() {
    let graph = pov("sphere { 0, 1 texture { pigment { rgb <1, 0, 0> } } \
                     texture { pigment { rgbt <0, 0, 1, 0.25> } } }\n\
                     sphere { 0, 1 texture { pigment { rgb <1, 0, 0> } } \
                     texture { pigment { rgb <0, 0, 1> } } }\n\
                     #declare T = texture { pigment { rgb <0, 1, 0> } } texture { pigment { rgbf <1, 1, 1, 1> } }\n\
                     sphere { 0, 1 texture { T } }\n\
                     sphere { 0, 1 texture { pigment { rgb 1 } finish { phong 1 } } texture { pigment { rgbt 0.5 } } }");
    let albedo = |n: usize| {
        let diffuse = graph.objects[n].material.clone().expect("a material").diffuse.clone();
        let texture = Texture::new(&diffuse, &mut |_| unreachable!("no image")).unwrap();
        texture.eval(Vec3::ZERO)
    };
    // A quarter of the red under the blue shows through: 0.6 × (0.25 red + 0.75 blue).
    assert!((albedo(0) - Vec3::new(0.15, 0.0, 0.45)).abs().max_element() < 1e-6, "{}", albedo(0));
    // An opaque top layer covers the one under it, as in POV-Ray.
    assert_eq!(albedo(1), Vec3::new(0.0, 0.0, 0.6));
    // A clear top layer shows all of the declared green under it.
    assert_eq!(albedo(2), Vec3::new(0.0, 0.6, 0.0));
    // Where the layers' finishes differ, the top one's applies to both, with a warning.
    let layered: Vec<_> =
        graph.warnings.iter().filter(|w| w.contains("layered `texture`")).collect();
    assert_eq!(layered.len(), 1, "{:?}", graph.warnings);
    assert!(layered[0].starts_with("tests/inline.pov:5:64:"), "{layered:?}");
}

#[test]
fn commas_between_a_shape_s_arguments_are_optional_in_pov_only() {
    let graph = pov("box { <-1, -1, -1> <1, 1, 1> }\nsphere { <0, 0, 0> 1 }\n\
                     cylinder { <0, 0, 0> <0, 1, 0> 0.5 }");
    assert!(matches!(graph.objects[0].shape, ShapeNode::Box { .. }));
    assert_eq!(radius(&SceneGraph { objects: graph.objects[1..].to_vec(), ..graph.clone() }), 1.0);
    let scn = scn_error("camera { location <0, 0, -1> look_at 0 }\nbox { <-1, -1, -1> <1, 1, 1> }");
    assert!(
        scn.starts_with("tests/inline.scn:2:20:") && scn.contains("is a `,` missing?"),
        "{scn}"
    );
}

/// Renders `scene` with `--include-path` folders and `RAYDIANCE_INCLUDE_PATH`; its stderr if it
/// failed.
fn render_with(scene: &Path, paths: &[&Path], variable: &Path) -> Option<String> {
    let out = scene.with_extension("exr");
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"));
    command.args(["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    command.args(["--width", "4", "--height", "4", "--samples", "1"]);
    for path in paths {
        command.arg("--include-path").arg(path);
    }
    let output = command.env("RAYDIANCE_INCLUDE_PATH", variable).output().unwrap();
    (!output.status.success()).then(|| String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn includes_are_found_beside_the_file_then_on_the_include_path_then_the_variable() {
    let dir = tempfile::tempdir().unwrap();
    let folder = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::create_dir_all(&path).unwrap();
        std::fs::write(path.join("x.inc"), text).unwrap();
        path
    };
    let scenes = dir.path().join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let scene = scenes.join("main.pov");
    std::fs::write(&scene, "#include \"x.inc\"\nsphere { 0, 1 pigment { rgb 1 } }\n").unwrap();
    let first = folder("first", "#declare A = 1;");
    let second = folder("second", "#error \"from the second --include-path\"");
    let variable = folder("variable", "#error \"from RAYDIANCE_INCLUDE_PATH\"");
    let failed = render_with(&scene, &[], &variable).expect("the variable's file is read");
    assert!(failed.contains("from RAYDIANCE_INCLUDE_PATH"), "{failed}");
    assert_eq!(render_with(&scene, &[&first, &second], &variable), None, "--include-path first");
    let failed = render_with(&scene, &[&second, &first], &variable).expect("in the order given");
    assert!(failed.contains("from the second --include-path"), "{failed}");
    std::fs::write(scenes.join("x.inc"), "#error \"beside the scene\"").unwrap();
    let failed = render_with(&scene, &[&first], &variable).expect("the scene's folder first");
    assert!(failed.contains("beside the scene"), "{failed}");
}

#[test]
fn vectors_and_array_elements_need_no_commas_in_pov_only() {
    // As POV-Ray reads them: `<1 -2 3>` is `<1 - 2, 3>`, and a last comma may end a vector.
    let declarations = "#declare A = <1 2 3>;\n#declare B = <1 -2 3>;\n#declare C = <4, 5, 6,>;\n\
                        #declare D = array[3] { 7 8, 9 }";
    assert_eq!(sphere_of("A.z + C.y + D[1]", declarations), 3.0 + 5.0 + 8.0);
    assert_eq!(sphere_of("B.x + 10 * B.y", declarations), -1.0 + 30.0);
    let vector = scn_error("#declare A = <1 2 3>;");
    assert!(vector.starts_with("tests/inline.scn:1:17:") && vector.contains("`,` is missing"));
    let last = scn_error("#declare A = <1, 2, 3,>;");
    assert!(last.starts_with("tests/inline.scn:1:22:") && last.contains("not a `,`"), "{last}");
    let array = scn_error("#declare D = array[2] { 7 8 }");
    assert!(array.starts_with("tests/inline.scn:1:27:") && array.contains("array element"));
}

#[test]
fn a_declared_value_may_be_an_ifdef_or_ifndef() {
    let value = "#declare R = #ifdef (S) 2 #else 3 #end\n#declare Q = #ifndef (S) 4 #end";
    assert_eq!(sphere_of("R + Q", value), 7.0);
    let r = "#declare R = #ifdef (S) 2 #else 3 #end";
    assert_eq!(sphere_of("R", &format!("#declare S = 1;\n{r}")), 2.0);
    let missing = pov_error("#declare S = 1;\n#declare Q = #ifndef (S) 4 #end\nsphere { 0, Q }");
    assert!(missing.starts_with("tests/inline.pov:2:14:") && missing.contains("add an `#else`"));
}

#[test]
fn default_may_be_written_without_its_hash() {
    let text = "default { finish { diffuse 0.5 } }\nsphere { 0, 1 pigment { rgb 1 } }";
    let hashed = pov(&text.replacen("default", "#default", 1));
    let plain = pov(text);
    let albedo = |g: &SceneGraph| g.objects[0].material.as_ref().unwrap().diffuse.max_value();
    assert_eq!(albedo(&plain), albedo(&hashed));
    assert!(albedo(&plain).x < 0.6, "the default finish applies: {:?}", albedo(&plain));
    assert!(scn_error(text).starts_with("tests/inline.scn:1:1:"));
}

#[test]
fn a_material_may_be_an_array_s_element() {
    let text = "#declare M = array[2] { material { texture { pigment { rgb <1, 0, 0> } } },\n\
                material { texture { pigment { rgb <0, 0, 1> } } } }\n\
                #declare I = 1;\nsphere { 0, 1 material { M[I] } }";
    let graph = pov(text);
    let colour = graph.objects[0].material.as_ref().unwrap().diffuse.max_value();
    assert!(colour.z > 0.0 && colour.x == 0.0, "{colour:?}");
    let wrong = pov_error("#declare M = array[1] { 3 }\nsphere { 0, 1 material { M[0] } }");
    assert!(
        wrong.starts_with("tests/inline.pov:2:26:") && wrong.contains("a number, not a material")
    );
    let scn = "#declare M = array[1] { material { diffuse rgb 0.5 } }\n\
               camera { location <0, 0, -3> look_at 0 }\nsphere { 0, 1 material { M[0] } }";
    let graph = parse_scene(Path::new("tests/inline.scn"), scn).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(graph.objects[0].material.as_ref().unwrap().diffuse.max_value(), Vec3::splat(0.5));
}

#[test]
fn a_macro_may_hold_a_background_a_sky_and_global_settings() {
    let inline = pov("background { rgb <0.1, 0.2, 0.3> }\nsphere { 0, 1 }");
    let called =
        pov("#macro Setup(C) background { C } global_settings { max_trace_level 5 } #end\n\
                      Setup(rgb <0.1, 0.2, 0.3>)\nsphere { 0, 1 }");
    assert_eq!(called.backdrop, inline.backdrop);
    assert_ne!(called.backdrop, Vec3::ZERO);
    let sky = pov("#macro Sky() sky_sphere { pigment { rgb 1 } } #end\nSky()\nsphere { 0, 1 }");
    assert!(sky.sky.is_some());
}

#[test]
fn a_lone_hash_and_a_form_feed_read_as_nothing_in_pov() {
    // image_size.pov's `look_at <0,2,0>#`: a warning, the camera unchanged.
    let graph = pov("camera { location <0, 0, -5> look_at <0, 2, 0>#\n }\nsphere { 0, 1 }");
    let hashes: Vec<_> =
        graph.warnings.iter().filter(|w| w.contains("begins no directive")).collect();
    assert_eq!(hashes.len(), 1, "{:?}", graph.warnings);
    assert!(hashes[0].contains("inline.pov:1:47"), "{hashes:?}");
    assert_eq!(radius(&pov("\u{c}sphere { 0,\u{c}2 }\u{c}")), 2.0);
    assert!(scn_error("# }").contains('#'));
}

#[test]
fn a_semicolon_may_follow_the_value_a_macro_gives_and_photons_stand_in_macros() {
    // tracevines.pov's `Q;` and optics.pov's `photons { }` in a macro.
    let declarations = "#macro M(A) #if (A) 2; #else 3; #end #end\n#declare R = M(0);";
    assert_eq!(sphere_of("R", declarations), 3.0);
    let graph = pov("#macro P() photons { target } #end\nsphere { 0, 1 P() }");
    assert!(graph.warnings.iter().any(|w| w.contains("photons")), "{:?}", graph.warnings);
}

#[test]
fn a_component_that_vanishes_in_f32_beside_others_is_zero_but_a_vanishing_vector_is_refused() {
    // float5.pov: pow(x, 3) for x = -3.9e-14 beside x itself.
    let graph = pov("sphere { <1, -6e-41, 2>, 1 }");
    let ShapeNode::Sphere { center, .. } = graph.objects[0].shape else { panic!() };
    assert_eq!(center, Vec3::new(1.0, 0.0, 2.0));
    assert!(pov_error("sphere { <1e-41, 0, 0>, 1 }").contains("1e-41 is too small"));
}

#[test]
fn an_object_flattened_by_its_transforms_is_left_out_with_a_warning_in_pov_only() {
    // swirlbox.pov's last box, scaled by (1 - Counter) * 5 ≈ 5e-16.
    let graph = pov("box { 0, 1 scale <5e-16, 1, 5e-16> }");
    assert!(matches!(&graph.objects[0].shape, ShapeNode::Union(c) if c.is_empty()));
    assert!(graph.warnings.iter().any(|w| w.contains("flatten it")), "{:?}", graph.warnings);
    let kept = pov("box { 0, 1 scale <1e-5, 1, 1e-5> }");
    assert!(matches!(kept.objects[0].shape, ShapeNode::Box { .. }));
}

#[test]
fn focal_blur_s_confidence_and_variance_are_read_with_the_blur_warning() {
    let graph = pov(
        "camera { location <0, 0, -5> look_at 0 confidence 0.9 variance 1/128 }\nsphere { 0, 1 }",
    );
    assert!(graph.warnings.iter().any(|w| w.contains("focal blur")), "{:?}", graph.warnings);
    assert!(scn_error("camera { confidence 0.9 }").contains("confidence"));
}

/// The sample mean of `count` draws of `draw` (a rand.inc macro call on stream S).
fn mean_of(draw: &str, count: u32) -> f32 {
    let declarations = format!(
        "#include \"stdinc.inc\"\n#declare S = seed(7);\n#declare Sum = 0;\n\
         #for (I, 1, {count}) #declare Sum = Sum + {draw}; #end"
    );
    sphere_of(&format!("Sum / {count}"), &declarations)
}

#[test]
fn rand_inc_draws_have_their_distributions_means() {
    // 4000 draws: each mean within 4 standard errors of the distribution's.
    let n = 4000;
    let within = |draw: &str, mean: f32, sd: f32| {
        let got = mean_of(draw, n);
        let bound = 4.0 * sd / (n as f32).sqrt();
        assert!((got - mean).abs() < bound, "{draw}: mean {got}, expected {mean} ± {bound}");
    };
    within("RRand(2, 4, S)", 3.0, 2.0 / 12f32.sqrt());
    within("Rand_Normal(1, 2, S)", 1.0, 2.0);
    within("Rand_Exp(2, S)", 0.5, 0.5);
    within("Rand_Triangle(0, 3, 1, S)", 4.0 / 3.0, (7.0f32 / 18.0).sqrt());
    within("Rand_Binomial(10, 0.3, S)", 3.0, 2.1f32.sqrt());
    // POV-Ray's Rand_Poisson counts one more than a Poisson draw.
    within("Rand_Poisson(2, S)", 3.0, 2f32.sqrt());
    within("vlength(VRand_On_Sphere(S))", 1.0, 1e-3);
    // Uniform in the unit ball: E|p| = 3/4, sd sqrt(3/5 - 9/16).
    within("vlength(VRand_In_Sphere(S))", 0.75, (3.0f32 / 5.0 - 9.0 / 16.0).sqrt());
}

#[test]
fn vturbulence_is_the_displacement_of_a_turbulence_warp() {
    // vturbulence.pov: vturbulence(lambda, omega, octaves, p).
    let graph = pov("sphere { vturbulence(3, 0.4, 2, <0.3, 1.7, 2.1>), 1 }");
    let ShapeNode::Sphere { center, .. } = graph.objects[0].shape else { panic!() };
    let octaves = Octaves { octaves: 2, omega: 0.4, lambda: 3.0 };
    assert_eq!(center, octaves.vector(Vec3::new(0.3, 1.7, 2.1)));
    assert_ne!(center, Octaves { octaves: 1, ..octaves }.vector(Vec3::new(0.3, 1.7, 2.1)));
    assert!(pov_error("sphere { vturbulence(2, 0.5, <1, 2, 3>), 1 }").contains("vturbulence"));
}

#[test]
fn directives_may_run_through_a_shape_s_points_and_a_mesh_s_triangles() {
    // Three points made by `#while`, the count after them: a triangle's worth of polygon.
    let graph = pov(r#"
        #declare K = 0;
        polygon { 4,
          #while (K < 3)
            #declare P = <cos(K * 2 * pi / 3), sin(K * 2 * pi / 3)>;
            P
            #declare K = K + 1;
          #end
          <1, 0>
          #if (1) translate y #end
        }
        mesh {
          #for (I, 0, 3)
            triangle { <I, 0, 0>, <I + 1, 0, 0>, <I, 1, 0> }
          #end
          translate x
        }"#);
    let [polygon, mesh] = &graph.objects[..] else { panic!("{:?}", graph.objects.len()) };
    let ShapeNode::Polygon { points } = &polygon.shape else { panic!("{:?}", polygon.shape) };
    assert!(points.len() >= 3, "{points:?}");
    assert!((points[1] - Vec3::new(-0.5, 0.75f32.sqrt(), 0.0)).length() < 1e-6, "{points:?}");
    assert_eq!(polygon.transforms.len(), 1, "the `#if` after the points is the polygon's");
    let ShapeNode::Extrusion(made) = &mesh.shape else { panic!("{:?}", mesh.shape) };
    assert_eq!(made.triangles.len(), 4);
    assert_eq!(mesh.transforms.len(), 1, "the `translate` after the triangles is the mesh's");
    // A value that is not a point is refused where it stands.
    let error = pov_error(r#"prism { 0, 1, 3, #declare S = "a"; <0, 0>, S, <1, 0> }"#);
    assert!(error.contains("1:44") && error.contains("not a string"), "{error}");
}

#[test]
fn macros_may_make_a_mesh_s_triangles_and_items() {
    // A macro's triangles, alone, in `#for`, after a triangle; a macro's transform after them.
    let graph = pov(r#"
        #macro Tri(X) triangle { <X, 0, 0>, <X + 1, 0, 0>, <X, 1, 0> } #end
        #macro Placed() translate 2*y #end
        mesh { Tri(0) Tri(1) }
        mesh { #for (I, 0, 2) Tri(I) #end Placed() }
        mesh { triangle { 0, x, y } Tri(1) #declare D = 3; Tri(D) Placed() scale 2 }
        #declare M = mesh { Tri(0) }
        mesh { M translate x }"#);
    let triangles = |k: usize| match &graph.objects[k].shape {
        ShapeNode::Extrusion(made) => made.triangles.len(),
        other => panic!("{k}: not a mesh: {other:?}"),
    };
    assert_eq!([triangles(0), triangles(1), triangles(2)], [2, 3, 3]);
    let ShapeNode::Extrusion(made) = &graph.objects[2].shape else { panic!() };
    assert!(made.positions.contains(&Vec3::new(4.0, 0.0, 0.0)), "{:?}", made.positions);
    assert_eq!(graph.objects[1].transforms.len(), 1, "the macro's `translate` is the mesh's");
    assert_eq!(graph.objects[2].transforms.len(), 2);
    // `mesh { Declared_Mesh items }` is that mesh, as `object { }` is (POV-Ray's).
    let ShapeNode::Instance(declared) = &graph.objects[3].shape else { panic!("not an instance") };
    assert!(matches!(&declared.shape, ShapeNode::Extrusion(m) if m.triangles.len() == 1));
    assert_eq!(graph.objects[3].transforms.len(), 1);
    // A triangle after the mesh's items, from a macro or not, is refused where it stands; so
    // is a mesh that gets no triangle, and a value that is not an object or a file's name.
    let late =
        pov_error("#macro Tri() triangle { 0, x, y } #end\nmesh { Tri() translate x Tri() }");
    assert!(late.starts_with("tests/inline.pov:1:14:"), "{late}");
    assert!(late.contains("after the mesh's items") && late.contains("2:26"), "{late}");
    let none = pov_error("#macro Nothing() #end\nmesh { Nothing() pigment { rgb 1 } }");
    assert!(none.starts_with("tests/inline.pov:2:1:") && none.contains("no triangles"), "{none}");
    let number = pov_error("mesh { 3 }");
    assert!(number.starts_with("tests/inline.pov:1:8:") && number.contains("a string"), "{number}");
    let scn = scn_error("mesh { }");
    assert!(scn.starts_with("tests/inline.scn:1:1:") && scn.contains("POV-Ray's"), "{scn}");
    // A triangle that an include brings among a shape's points is refused there too.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.inc"), "triangle { 0, x, y }").unwrap();
    let scene = dir.path().join("points.pov");
    let text = "polygon { 4, <0, 0>, <1, 0>, #include \"tri.inc\" <0, 1>, <0, 0> }";
    let among = parse_scene(&scene, text).map(|_| ()).unwrap_err().to_string();
    assert!(among.contains("tri.inc:1:1:") && among.contains("among a shape's points"), "{among}");
}

#[test]
fn a_mesh_s_triangles_read_their_uv_vectors_with_a_warning() {
    // allobjects.pov's smooth triangles, and uv made by a loop.
    let graph = pov(r#"
        mesh {
          smooth_triangle {
            <0.56, 0, -1> <0.73, -0.24, 0.64> <0.16, 0.49, -1> <-0.08, 0.82, 0.57>
            <0.23, 0.71, -0.6> <0.62, 0.79, 0.02>
            uv_vectors <0, -1> <1.25664, -1> <1.25664, -0.6>
          }
          #for (I, 0, 1) triangle { 0, x, y uv_vectors <I, 0>, <I + 1, 0>, <I, 1> } #end
        }"#);
    let ShapeNode::Extrusion(made) = &graph.objects[0].shape else { panic!("not a mesh") };
    assert_eq!(made.triangles.len(), 3);
    let warned = graph.warnings.iter().filter(|w| w.contains("uv_vectors are read but not used"));
    assert_eq!(warned.count(), 1, "one warning a mesh: {:?}", graph.warnings);
    // A uv is a 2-vector; `uv_vectors` stand only in a mesh's triangle, and only in `.pov`.
    let three = pov_error("mesh { triangle { 0, x, y uv_vectors <0, 0>, <1, 0, 0>, <0, 1> } }");
    assert!(three.contains("1:46") && three.contains("2-vector"), "{three}");
    let alone = pov_error("triangle { 0, x, y uv_vectors <0, 0>, <1, 0>, <0, 1> }");
    assert!(alone.contains("1:20") && alone.contains("`uv_vectors`"), "{alone}");
    let scn =
        scn_error("triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> uv_vectors <0, 0>, <1, 0>, <0, 1> }");
    assert!(scn.contains("1:44") && scn.contains("POV-Ray"), "{scn}");
}

#[test]
fn uv_mapping_is_read_with_a_warning_and_mesh_camera_is_refused_by_name() {
    let graph = pov("sphere { 0, 1 uv_mapping pigment { uv_mapping checker rgb 0, rgb 1 } \
         texture { uv_mapping pigment { rgb 1 } } }");
    let warned = graph.warnings.iter().filter(|w| w.contains("`uv_mapping` is not honoured"));
    assert_eq!(warned.count(), 3, "{:?}", graph.warnings);
    let error = pov_error("camera { mesh_camera { 1 0 mesh { triangle { 0, x, y } } } }");
    assert!(error.contains("1:10") && error.contains("`mesh_camera`"), "{error}");
}

#[test]
fn a_macro_takes_a_block_as_its_argument() {
    // The sample scenes' `Correct_Pigment_Gamma(pigment { ... }, G)`: a pigment passed to a
    // macro, made a colour function there and read by component.
    let red = "#macro Red_Of(P)\n\
               #local F = function { pigment { P } };\n\
               #declare G = function { F(x, y, z).x * 2 };\n\
               #end\n\
               Red_Of(pigment { rgb <0.25, 0.5, 1> })";
    assert_eq!(sphere_of("G(0, 0, 0)", red), 0.5);
    let graph = pov("#macro Second(A, B) object { B } #end\n\
                     Second(sphere { 0, 1 }, sphere { x, 3 pigment { rgb 1 } })");
    let ShapeNode::Instance(second) = &graph.objects[0].shape else { panic!("not an instance") };
    assert!(matches!(second.shape, ShapeNode::Sphere { radius: 3.0, .. }), "{:?}", second.shape);
    // math.pov's `Graph(function (x) { x * x }, 300, Green)`.
    let at = "#macro At(F, X) F(X) #end";
    assert_eq!(sphere_of("At(function (x) { x * 2 }, 1.5)", at), 3.0);
    let block = scn_error("#macro M(P) #end\nM(pigment { rgb 1 })");
    assert!(block.starts_with("tests/inline.scn:2:3:"), "{block}");
    assert!(block.contains("`pigment`"), "{block}");
}

#[test]
fn a_polygon_takes_3_vectors_in_any_plane() {
    // media3.pov's square, and one standing in the plane x = 2.
    let graph = pov("polygon { 5, <-1, -1, 0>, <1, -1, 0>, <1, 1, 0>, <-1, 1, 0>, <-1, -1, 0> }\n\
                     polygon { 4, <2, 0, 0>, <2, 1, 0>, <2, 0, 1>, <2, 0, 0> }");
    let points = |n: usize| match &graph.objects[n].shape {
        ShapeNode::Polygon { points } => points.clone(),
        other => panic!("not a polygon: {other:?}"),
    };
    assert_eq!(points(0)[2], Vec3::new(1.0, 1.0, 0.0));
    assert!(points(1).iter().all(|p| p.x == 2.0), "{:?}", points(1));
    assert_eq!(points(1)[2], Vec3::new(2.0, 0.0, 1.0));
}
