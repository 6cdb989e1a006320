//! The scene language: snapshots of the scene graph of every construct, and of the error text
//! of every scene in a corpus of bad ones.

use std::path::Path;

fn graph(name: &str) -> raydiance::graph::SceneGraph {
    let path = format!("tests/scenes/{name}.scn");
    raydiance::lang::load_scene(Path::new(&path)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn lexical_forms() {
    insta::assert_debug_snapshot!(graph("lexical"));
}

#[test]
fn expressions_and_declarations() {
    insta::assert_debug_snapshot!(graph("expressions"));
}

#[test]
fn include() {
    insta::assert_debug_snapshot!(graph("include"));
}

#[test]
fn settings() {
    insta::assert_debug_snapshot!(graph("settings"));
}

#[test]
fn lab_camera_with_thin_lens() {
    insta::assert_debug_snapshot!(graph("cameras"));
}

#[test]
fn objects_transforms_groups_instances() {
    insta::assert_debug_snapshot!(graph("objects"));
}

#[test]
fn solids_cones_tori_and_csg() {
    insta::assert_debug_snapshot!(graph("solids"));
}

#[test]
fn materials() {
    insta::assert_debug_snapshot!(graph("materials"));
}

#[test]
fn textures() {
    insta::assert_debug_snapshot!(graph("textures"));
}

/// Every shipped scene builds from the repository alone; the one whose mesh is generated rather
/// than shipped builds once it is made, and until then says how to make it.
#[test]
fn comparisons_logic_ternary_functions_and_unit_vectors() {
    insta::assert_debug_snapshot!(graph("operators"));
}

#[test]
fn conditionals_loops_and_directives_among_items() {
    insta::assert_debug_snapshot!(graph("control_flow"));
}

#[test]
fn macros() {
    insta::assert_debug_snapshot!(graph("macros"));
}

#[test]
fn arrays_strings_and_random_streams() {
    insta::assert_debug_snapshot!(graph("arrays_strings_random"));
}

/// The syntax tree itself: directives folded into blocks, operators by precedence.
#[test]
fn syntax_tree_of_directives_and_operators() {
    let text = r#"#macro M(A, B) #local C = A * B; (C > 1 ? C : -C) #end
#if (1 | 0 & 1) #while (0) #end #elseif (2 >= 1) #for (I, 0, 2, 1) M(I, 2) #end #else #undef M #end
#ifdef (M) #declare V[1] = !2 + 3 * -4 <= 5; #end
#debug concat("a\n", str(1, 0, 0))
"#;
    let tree =
        raydiance::lang::parse_tree(Path::new("tree.scn"), text).unwrap_or_else(|e| panic!("{e}"));
    insta::assert_debug_snapshot!(tree);
}

#[test]
fn shipped_scenes_parse_and_build() {
    for entry in std::fs::read_dir("scenes").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "scn") {
            match raydiance::load(&path, &Default::default()) {
                Ok(_) => {}
                Err(e) if !Path::new("scenes/data/bumpy.ply").exists() => {
                    let text = e.to_string();
                    assert!(path.ends_with("mesh-heavy.scn"), "{text}");
                    assert!(
                        text.contains("run `cargo run --release --example bumpy_sphere`"),
                        "says how to make the mesh:\n{text}"
                    );
                }
                Err(e) => panic!("{e}"),
            }
        }
    }
}

/// Every bad scene fails with a located message (never a panic); the message is snapshotted.
#[test]
fn bad_scenes_give_located_errors() {
    insta::glob!("bad_scenes/*.scn", |absolute| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let path = absolute.strip_prefix(root).unwrap();
        let error = raydiance::load(path, &Default::default()).expect_err("a bad scene must fail");
        let text = error.to_string();
        assert!(text.starts_with("tests/bad_scenes/"), "names its file:\n{text}");
        insta::assert_snapshot!(text);
    });
}

/// POV-Ray's spellings get answers in POV-Ray's terms: the error points at the POV-Ray word,
/// names it, and says what raydiance writes instead.
#[test]
fn povray_habits_name_the_povray_word_and_ours() {
    let cases = [
        ("pigment", "`pigment`", "diffuse rgb"),
        ("finish", "`finish`", "specular rgb"),
        ("texture", "`texture`", "material {"),
        ("normal", "`normal`", "in a material"),
        ("interior", "`interior`", "transmission rgb 1  ior 1.5"),
        ("light_color", "`color`", "power rgb"),
        ("diffuse_color", "`color`", "`rgb <r, g, b>` alone"),
        ("diffuse_colour", "`colour`", "`rgb <r, g, b>` alone"),
        ("background", "`background`", "settings { background rgb"),
        ("switch", "`#switch`", "#elseif"),
        ("area_light", "`area_light`", "emission rgb"),
        ("camera_right", "`right`", "resolution"),
        ("hollow", "`hollow`", "not supported"),
        ("parametric", "`parametric`", "a `.pov` scene's) word"),
    ];
    for (name, povray, ours) in cases {
        let path = format!("tests/bad_scenes/povray_{name}.scn");
        let text = std::fs::read_to_string(&path).unwrap();
        let error = raydiance::load(Path::new(&path), &Default::default()).unwrap_err();
        let message = error.to_string();
        assert!(message.contains(povray) && message.contains(ours), "{path}:\n{message}");
        // The caret is under the POV-Ray word.
        let (line, col) =
            message.split(": error").next().unwrap().rsplit_once(':').map_or(
                (0, 0),
                |(rest, col)| {
                    (rest.rsplit(':').next().unwrap().parse().unwrap(), col.parse().unwrap())
                },
            );
        let word = povray.trim_matches('`').trim_start_matches('#');
        let at = &text.lines().nth(line - 1).unwrap()[col - 1..];
        assert!(at.trim_start_matches('#').starts_with(word), "{path}: points at `{at}`");
    }
}

/// `#version` and `global_settings` are read, with a warning each that they change nothing.
#[test]
fn povray_version_and_global_settings_are_accepted_with_warnings() {
    let text = "#version 3.7;\nglobal_settings { assumed_gamma 1.0  radiosity { count 100 } }\n\
                camera { location <0, 1, -4>  look_at <0, 0, 0> }\n\
                light_source { <0, 5, 0>  power rgb 10 }\n";
    let graph = raydiance::lang::parse_scene(Path::new("v.scn"), text).unwrap();
    assert_eq!(graph.warnings.len(), 2, "{:?}", graph.warnings);
    assert!(graph.warnings[0].starts_with("v.scn:1:1: warning: `#version` has no effect"));
    assert!(graph.warnings[1].starts_with("v.scn:2:1: warning: POV-Ray's `global_settings`"));
    let without = &text[text.find("camera").unwrap()..];
    let without = raydiance::lang::parse_scene(Path::new("v.scn"), without);
    assert!(without.is_ok_and(|g| g.warnings.is_empty()));
}
