//! raydiance's own versions of POV-Ray's standard include files, built into the binary so that a
//! `.pov` scene needs nothing beside it (`docs/povray.md`). Searched after the including file's
//! folder and the include path; only names whose every declaration raydiance can honour are here.

/// The text of the built-in include file `name`, if there is one.
pub fn file(name: &str) -> Option<&'static str> {
    match name {
        "colors.inc" => Some(include_str!("library/colors.inc")),
        "consts.inc" => Some(include_str!("library/consts.inc")),
        "finish.inc" => Some(include_str!("library/finish.inc")),
        "golds.inc" => Some(include_str!("library/golds.inc")),
        "metals.inc" => Some(include_str!("library/metals.inc")),
        "shapes.inc" => Some(include_str!("library/shapes.inc")),
        "shapes2.inc" => Some(include_str!("library/shapes2.inc")),
        "shapes_old.inc" => Some(include_str!("library/shapes_old.inc")),
        "textures.inc" => Some(include_str!("library/textures.inc")),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    const NAMES: [&str; 9] = [
        "colors.inc",
        "consts.inc",
        "finish.inc",
        "golds.inc",
        "metals.inc",
        "shapes.inc",
        "shapes2.inc",
        "shapes_old.inc",
        "textures.inc",
    ];

    fn pov(text: &str) -> crate::graph::SceneGraph {
        crate::lang::parse_scene(Path::new("library.pov"), text).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn every_built_in_include_reads_in_a_pov_scene() {
        for name in NAMES {
            assert!(super::file(name).is_some(), "{name} is built in");
            let graph = pov(&format!("#include \"{name}\""));
            assert!(graph.objects.is_empty(), "{name} declares, and makes nothing");
        }
        assert!(super::file("functions.inc").is_none());
    }

    #[test]
    fn the_built_in_declarations_make_what_they_name() {
        let graph = pov(r#"
#include "shapes.inc"
#include "shapes2.inc"
#include "textures.inc"
#include "metals.inc"
object { Round_Box(<-1, -1, -1>, <1, 1, 1>, 0.2, 1) texture { T_Gold_3C } }
object { Wire_Box_Union(<-1, -1, -1>, <1, 1, 1>, 0.05) texture { Polished_Chrome } }
object { Spheroid(<0, 1, 0>, <1, 2, 3>) pigment { Jade } finish { Shiny } }
Quad(<0, 0, 0>, <1, 0, 0>, <1, 1, 0>, <0, 1, 0>)
object { Octahedron texture { T_Silver_5E } }
object { Disk_Y texture { Glass } interior { ior Crown_Glass_Ior } }
"#);
        // Round_Box, Wire_Box, Spheroid, Quad's two triangles, Octahedron, Disk_Y.
        assert_eq!(graph.objects.len(), 7);
        let gold = graph.objects[0].material.clone().expect("a material");
        assert!(gold.specular.x > gold.specular.z, "gold tints its reflection");
        let glass = graph.objects[6].material.clone().expect("a material");
        assert_eq!(glass.ior, 1.51);
        assert!(glass.transmission.min_element() > 0.5, "{:?}", glass.transmission);
    }
}
