//! The scene language: snapshots of the scene graph of every construct, and of the error text
//! of every scene in a corpus of bad ones.

use std::path::Path;

fn graph(name: &str) -> raydiance::scene::graph::SceneGraph {
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
