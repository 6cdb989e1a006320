//! raydiance's own versions of POV-Ray's standard include files, built into the binary so that a
//! `.pov` scene needs nothing beside it (`docs/povray.md`). Searched after the including file's
//! folder and the include path; only names whose every declaration raydiance can honour are here.

/// The text of the built-in include file `name`, if there is one.
pub fn file(name: &str) -> Option<&'static str> {
    match name {
        "colors.inc" => Some(include_str!("library/colors.inc")),
        "consts.inc" => Some(include_str!("library/consts.inc")),
        "finish.inc" => Some(include_str!("library/finish.inc")),
        "functions.inc" => Some(include_str!("library/functions.inc")),
        "glass.inc" => Some(include_str!("library/glass.inc")),
        "glass_old.inc" => Some(include_str!("library/glass_old.inc")),
        "golds.inc" => Some(include_str!("library/golds.inc")),
        "metals.inc" => Some(include_str!("library/metals.inc")),
        "rad_def.inc" => Some(include_str!("library/rad_def.inc")),
        "shapes.inc" => Some(include_str!("library/shapes.inc")),
        "shapes2.inc" => Some(include_str!("library/shapes2.inc")),
        "shapes_old.inc" => Some(include_str!("library/shapes_old.inc")),
        "skies.inc" => Some(include_str!("library/skies.inc")),
        "stones.inc" => Some(include_str!("library/stones.inc")),
        "stones1.inc" => Some(include_str!("library/stones1.inc")),
        "stones2.inc" => Some(include_str!("library/stones2.inc")),
        "textures.inc" => Some(include_str!("library/textures.inc")),
        "woodmaps.inc" => Some(include_str!("library/woodmaps.inc")),
        "woods.inc" => Some(include_str!("library/woods.inc")),
        _ => None,
    }
}

/// POV-Ray's functions.inc's names that raydiance's leaves out.
const FUNCTIONS_LEFT_OUT: [&str; 68] = [
    "f_algbr_cyl1",
    "f_algbr_cyl2",
    "f_algbr_cyl3",
    "f_algbr_cyl4",
    "f_bicorn",
    "f_bifolia",
    "f_blob",
    "f_blob2",
    "f_boy_surface",
    "f_comma",
    "f_cross_ellipsoids",
    "f_crossed_trough",
    "f_cubic_saddle",
    "f_cushion",
    "f_devils_curve",
    "f_devils_curve_2d",
    "f_dupin_cyclid",
    "f_enneper",
    "f_flange_cover",
    "f_folium_surface",
    "f_folium_surface_2d",
    "f_glob",
    "f_heart",
    "f_helical_torus",
    "f_helix1",
    "f_helix2",
    "f_hetero_mf",
    "f_hex_x",
    "f_hex_y",
    "f_hunt_surface",
    "f_hyperbolic_torus",
    "f_isect_ellipsoids",
    "f_kampyle_of_eudoxus",
    "f_kampyle_of_eudoxus_2d",
    "f_klein_bottle",
    "f_kummer_surface_v1",
    "f_kummer_surface_v2",
    "f_lemniscate_of_gerono",
    "f_lemniscate_of_gerono_2d",
    "f_mesh1",
    "f_mitre",
    "f_nodal_cubic",
    "f_noise_generator",
    "f_odd",
    "f_ovals_of_cassini",
    "f_parabolic_torus",
    "f_pillow",
    "f_piriform",
    "f_piriform_2d",
    "f_poly4",
    "f_polytubes",
    "f_quantum",
    "f_quartic_cylinder",
    "f_quartic_paraboloid",
    "f_quartic_saddle",
    "f_ridge",
    "f_ridged_mf",
    "f_spikes",
    "f_spikes_2d",
    "f_spiral",
    "f_steiners_roman",
    "f_strophoid",
    "f_strophoid_2d",
    "f_torus2",
    "f_torus_gumdrop",
    "f_umbrella",
    "f_witch_of_agnesi",
    "f_witch_of_agnesi_2d",
];

/// Why raydiance's version of a standard include file leaves out POV-Ray's `name`, if it does
/// and a scene is likely to name it: said where a scene names it and nothing declares it.
pub fn left_out(name: &str) -> Option<&'static str> {
    match name {
        "P_Cloud1" | "S_Cloud5" | "T_Cloud1" | "T_Cloud2" | "T_Cloud3" | "O_Cloud1"
        | "O_Cloud2" => Some(
            "POV-Ray's skies.inc declares it with transparent colours in a color_map, which \
             raydiance's pigments do not have: raydiance's skies.inc leaves it out (it has \
             P_Cloud2 to P_Cloud4 and S_Cloud1 to S_Cloud4)",
        ),
        "Cylinder_X" | "Cylinder_Y" | "Cylinder_Z" | "QCone_X" | "QCone_Y" | "QCone_Z"
        | "Paraboloid_X" | "Paraboloid_Y" | "Paraboloid_Z" | "Hyperboloid" | "Hyperboloid_Y" => {
            Some(
                "POV-Ray's shapes_old.inc declares it as an infinite quadric, a shape raydiance \
                 does not have (its one unbounded shape is the plane): raydiance's shapes_old.inc \
                 leaves it out (a finite `cylinder` or `cone` may stand for it)",
            )
        }
        name if FUNCTIONS_LEFT_OUT.contains(&name) => Some(
            "POV-Ray's functions.inc declares it as one of its internal functions, which \
             raydiance does not build in: raydiance's functions.inc leaves it out (docs/povray.md \
             lists the f_ functions it has)",
        ),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    const NAMES: [&str; 19] = [
        "colors.inc",
        "consts.inc",
        "finish.inc",
        "functions.inc",
        "glass.inc",
        "glass_old.inc",
        "golds.inc",
        "metals.inc",
        "rad_def.inc",
        "shapes.inc",
        "shapes2.inc",
        "shapes_old.inc",
        "skies.inc",
        "stones.inc",
        "stones1.inc",
        "stones2.inc",
        "textures.inc",
        "woodmaps.inc",
        "woods.inc",
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
    }

    #[test]
    fn functions_inc_s_left_out_functions_are_named_as_such() {
        let text = "#include \"functions.inc\"\n#declare F = function { f_helix1(x, y, z, 1, 1, 1, 1, 1, 1, 1) }";
        let message = crate::lang::parse_scene(Path::new("f.pov"), text).unwrap_err().to_string();
        assert!(message.contains("internal functions"), "{message}");
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

    #[test]
    fn glass_inc_holds_povray_s_glass_colours_with_their_values() {
        // A scene that checks the values itself: `#error` stops it where one differs.
        pov(r#"
#include "glass.inc"
#macro Expect(C, R, G, B, F)
  #if (C.red != R | C.green != G | C.blue != B | C.filter != F) #error "wrong colour" #end
#end
Expect(Col_Glass_Clear, 1, 1, 1, 1)
Expect(Col_Glass_Ruby, 0.9, 0.1, 0.2, 0.8)
Expect(Col_Glass_Vicksbottle, 0.1, 0.15, 0.5, 0.9)
Expect(Col_Glass_Bluish, 0.9, 0.94, 1, 0.8)
Expect(Col_Red_03, 0.75, 0.2, 0.25, 0)
Expect(Col_Amethyst_01, 0.4392, 0.1765, 0.3137, 0)
Expect(Col_Amber_09, 0.5294, 0.2431, 0.1529, 0)
Expect(Col_Tourmaline_06, 0.0196, 0.2706, 0.1961, 0)
#if (Crown_Glass_Ior != 1.51) #error "glass.inc includes consts.inc" #end
"#);
        let wrong = crate::lang::parse_scene(
            Path::new("library.pov"),
            "#include \"glass.inc\"\n#if (Col_Ruby.red != 0.5) #error \"checked\" #end",
        );
        assert!(wrong.is_err(), "the check can fail");
    }

    #[test]
    fn glass_inc_s_glasses_are_dielectrics_of_ior_1_5() {
        let graph = pov(r#"
#include "glass.inc"
sphere { 0, 1 pigment { Col_Glass_Clear } finish { F_Glass5 } interior { I_Glass1 } }
sphere { 0, 1 texture { T_Glass4 } interior { I_Glass } }
sphere { 0, 1 pigment { Col_Glass_Clear } finish { F_Glass9 } interior { I_Glass_Exp(2) } }
sphere { 0, 1 pigment { Col_Glass_Ruby } finish { F_Glass1 } interior { I_Glass_Caustics2 } }
"#);
        let materials: Vec<_> =
            graph.objects.iter().map(|o| o.material.clone().expect("a material")).collect();
        for m in &materials {
            assert_eq!(m.ior, 1.5);
            assert!(m.transmission.min_element() > 0.0, "{m:?}");
            assert!(m.specular.min_element() > 0.0, "it reflects: {m:?}");
            assert_eq!(m.coat, 0.0, "no highlight takes light from the glass");
        }
        // F_Glass5 and F_Glass9: Fresnel's law shares all the light of a clear glass.
        for m in [&materials[0], &materials[2]] {
            assert!(m.fresnel);
            let total = m.specular + m.transmission;
            assert!((total - glam::Vec3::ONE).abs().max_element() < 1e-6, "{total}");
        }
        // T_Glass4: filter 0.75 of <0.98, 1, 0.99> passes, three times its reflection 0.25.
        let t_glass4 = &materials[1];
        assert!(!t_glass4.fresnel);
        let ratio = t_glass4.transmission.y / t_glass4.specular.x;
        assert!((ratio - 3.0).abs() < 1e-5, "{t_glass4:?}");
        // A ruby glass passes red.
        let ruby = &materials[3].transmission;
        assert!(ruby.x > 4.0 * ruby.y, "{ruby}");
    }

    #[test]
    fn skies_inc_s_rainy_sky_is_dark_at_the_horizon_with_clouds_above() {
        let graph = pov("#include \"skies.inc\"\nsky_sphere { S_Cloud4 }");
        let sky = graph.sky.expect("S_Cloud4 is the scene's sky");
        let texture = crate::texture::Texture::new(&sky.pigment, &mut |_| Err("no image".into()));
        let texture = texture.expect("a texture without images");
        let horizon = texture.eval(glam::Vec3::new(0.6, 0.0, 0.8));
        assert!((horizon - glam::Vec3::new(0.184, 0.184, 0.309)).abs().max_element() < 1e-6);
        // Above 0.45 of the way up only P_Cloud3's colours, greys to dark blues.
        let overhead = texture.eval(glam::Vec3::new(0.0, 0.6, 0.8));
        assert!(overhead.min_element() >= 0.1 - 1e-6 && overhead.max_element() <= 0.85 + 1e-6);
        assert!(overhead.z >= overhead.x, "bluish or grey: {overhead}");
    }

    #[test]
    fn skies_inc_s_wrinkled_skies_start_from_their_horizon_colour() {
        let sky_of = |name: &str| {
            let graph = pov(&format!("#include \"skies.inc\"\nsky_sphere {{ {name} }}"));
            let sky = graph.sky.expect("the scene's sky");
            let texture =
                crate::texture::Texture::new(&sky.pigment, &mut |_| Err("no image".into()));
            texture.expect("a texture without images")
        };
        let pink = glam::Vec3::new(0.847, 0.749, 0.847);
        let dusk = glam::Vec3::new(0.258, 0.258, 0.435);
        for (name, horizon) in [("S_Cloud1", pink), ("S_Cloud2", pink), ("S_Cloud3", dusk)] {
            let seen = sky_of(name).eval(glam::Vec3::new(0.6, 0.0, 0.8));
            assert!((seen - horizon).abs().max_element() < 1e-6, "{name}: {seen}");
        }
        // High up S_Cloud3 is P_Cloud2 alone: its greys and dusky blue.
        let overhead = sky_of("S_Cloud3").eval(glam::Vec3::new(0.0, 0.6, 0.8));
        assert!(overhead.min_element() >= 0.258 - 1e-6 && overhead.max_element() <= 0.85 + 1e-6);
        assert!(overhead.z >= overhead.x, "bluish or grey: {overhead}");
    }

    #[test]
    fn names_the_library_leaves_out_are_refused_with_the_reason() {
        for (name, why) in [("S_Cloud5", "transparent colours"), ("Cylinder_X", "infinite quadric")]
        {
            let text = format!("#include \"skies.inc\"\nsky_sphere {{ {name} }}");
            let error = crate::lang::parse_scene(Path::new("library.pov"), &text)
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(error.contains(":2:14:") && error.contains(why), "{error}");
        }
        // A scene's own declaration of the name is its own.
        let own =
            pov("#declare S_Cloud5 = sky_sphere { pigment { rgb 1 } }\nsky_sphere { S_Cloud5 }");
        assert!(own.sky.is_some());
    }

    /// Every name POV-Ray's stones1.inc and stones2.inc declare, in a scene that uses each.
    fn stones_scene() -> String {
        let mut names: Vec<String> = (0..=29).map(|n| format!("T_Grnt{n}")).collect();
        names.extend((0..=24).map(|n| format!("T_Grnt{n}a")));
        names.extend((1..=4).map(|n| format!("T_Crack{n}")));
        names.extend((1..=44).map(|n| format!("T_Stone{n}")));
        let mut scene = String::from("#include \"stones.inc\"\n");
        for name in &names {
            scene += &format!("sphere {{ 0, 1 texture {{ {name} }} }}\n");
        }
        for green in ["g1", "g2", "g3", "g4"] {
            scene += &format!("sphere {{ 0, 1 pigment {{ {green} }} }}\n");
        }
        scene
    }

    #[test]
    fn stones_inc_declares_every_stone_of_povray_s() {
        let graph = pov(&stones_scene());
        assert_eq!(graph.objects.len(), 30 + 25 + 4 + 44 + 4);
        // Each half reads on its own, as scenes that include one of them expect.
        for (part, last) in [("stones1.inc", "T_Stone24"), ("stones2.inc", "T_Stone44")] {
            let one = pov(&format!("#include \"{part}\"\nsphere {{ 0, 1 texture {{ {last} }} }}"));
            assert_eq!(one.objects.len(), 1, "{part}");
        }
    }

    #[test]
    fn stones_inc_s_colours_are_povray_s() {
        let graph = pov(r#"
#include "stones.inc"
sphere { 0, 1 texture { T_Grnt0 finish { diffuse 1 } } }
sphere { 0, 1 texture { T_Stone7 finish { diffuse 1 } } }
#if (g1.red != 0.26 | g1.green != 0.41 | g1.blue != 0.31) #error "T_Grnt21's green" #end
"#);
        let texture = |i: usize| {
            let material = graph.objects[i].material.clone().expect("a material");
            let texture = crate::texture::Texture::new(&material.diffuse, &mut |_| Err("".into()));
            texture.expect("a texture without images")
        };
        // T_Grnt0's granite runs through five colours, back to the first: every value lies on
        // the line between two successive ones.
        let map = [
            glam::Vec3::new(0.729, 0.502, 0.451),
            glam::Vec3::new(0.769, 0.686, 0.592),
            glam::Vec3::new(0.843, 0.753, 0.718),
            glam::Vec3::new(0.780, 0.667, 0.561),
            glam::Vec3::new(0.741, 0.659, 0.576),
            glam::Vec3::new(0.729, 0.502, 0.451),
        ];
        let granite = texture(0);
        for i in 0..200 {
            let seen = granite.eval(glam::Vec3::new(i as f32 * 0.037, 0.5, i as f32 * -0.023));
            let on_the_map = map.windows(2).any(|pair| {
                let along = pair[1] - pair[0];
                let t = ((seen - pair[0]).dot(along) / along.length_squared()).clamp(0.0, 1.0);
                (pair[0] + t * along - seen).length() < 1e-4
            });
            assert!(on_the_map, "{seen}");
        }
        // T_Stone7 is its base layer: colors.inc's Salmon, everywhere.
        let salmon = texture(1).eval(glam::Vec3::new(0.3, -0.2, 0.7));
        assert!(
            (salmon - glam::Vec3::new(0.435294, 0.258824, 0.258824)).abs().max_element() < 1e-6,
            "{salmon}"
        );
    }

    /// The colour (times POV-Ray's default `diffuse` 0.6) of the texture of `scene`'s object.
    fn object_texture(scene: &str) -> crate::texture::Texture {
        let graph = pov(scene);
        let material = graph.objects[0].material.clone().expect("a material");
        crate::texture::Texture::new(&material.diffuse, &mut |_| Err("no image".into()))
            .expect("a texture without images")
    }

    #[test]
    fn woods_inc_declares_every_povray_wood_name() {
        let mut scene = String::from("#include \"woods.inc\"\n");
        for n in 1..=35 {
            scene += &format!("sphere {{ 0, 1 texture {{ T_Wood{n} }} }}\n");
        }
        for n in 1..=19 {
            for layer in ["A", "B"] {
                scene += &format!("sphere {{ 0, 1 pigment {{ P_WoodGrain{n}{layer} }} }}\n");
                let map = format!("M_Wood{n}{layer}");
                scene +=
                    &format!("sphere {{ 0, 1 pigment {{ gradient x color_map {{ {map} }} }} }}\n");
            }
        }
        let graph = pov(&scene);
        assert_eq!(graph.objects.len(), 35 + 4 * 19);
        for object in &graph.objects {
            let material = object.material.clone().expect("a material");
            assert!(!matches!(material.diffuse.pattern, crate::graph::Pattern::Solid(_)));
        }
    }

    #[test]
    fn woodmaps_inc_s_maps_hold_povray_s_colours() {
        // Halfway along M_Wood1A's blend from <0.88, 0.6, 0.4> at 0.1 to <0.6, 0.3, 0.2> at 0.9;
        // M_Wood2A's colours are POV-Ray's halved; M_Wood19B's clear white is opaque here.
        for (map, at, expected) in [
            ("M_Wood1A", 0.5, glam::Vec3::new(0.74, 0.45, 0.3)),
            ("M_Wood2A", 0.05, glam::Vec3::new(0.175, 0.08, 0.06)),
            ("M_Wood19B", 0.5, glam::Vec3::ONE),
        ] {
            let scene = format!(
                "#include \"woodmaps.inc\"\nsphere {{ 0, 1 pigment {{ gradient x color_map {{ {map} }} }} }}"
            );
            let seen = object_texture(&scene).eval(glam::Vec3::new(at, 0.0, 0.0)) / 0.6;
            assert!((seen - expected).abs().max_element() < 1e-5, "{map} at {at}: {seen}");
        }
    }

    #[test]
    fn woods_inc_s_textures_are_their_base_grain_in_its_colours() {
        // T_Wood2 is M_Wood2A's dark browns, red from 0.175 to 0.23; T_Wood34 is T_Wood32.
        let two = object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood2 } }");
        let rosewood =
            object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood32 } }");
        let orange = object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood34 } }");
        // A declared grain takes the colours given with it, as in POV-Ray's sample scenes.
        let grain = object_texture(
            "#include \"woods.inc\"\nsphere { 0, 1 pigment { P_WoodGrain2A color_map { M_Wood2A } } }",
        );
        let mut reds = Vec::new();
        for i in 0..50 {
            let p = glam::Vec3::new(i as f32 * 0.037, (i % 7) as f32 * 0.05, i as f32 * 0.1);
            let seen = two.eval(p) / 0.6;
            assert!(seen.x >= 0.175 - 1e-5 && seen.x <= 0.23 + 1e-5, "{seen} at {p}");
            assert!(seen.x > seen.y && seen.y > seen.z - 1e-5, "brown: {seen}");
            reds.push(seen.x);
            assert_eq!(orange.eval(p), rosewood.eval(p));
            assert_eq!(grain.eval(p), two.eval(p));
        }
        let (low, high) = reds.iter().fold((1f32, 0f32), |(l, h), r| (l.min(*r), h.max(*r)));
        assert!(high - low > 0.02, "the grain shows: reds {low} to {high}");
    }

    /// The outward unit normals of a solid's faces, and their distances from the origin.
    fn faces(solid: &crate::graph::ObjectNode) -> Vec<(glam::Vec3, f32)> {
        use crate::graph::{ShapeNode, Transform};
        let ShapeNode::Instance(declared) = &solid.shape else {
            panic!("the declared solid: {:?}", solid.shape);
        };
        let ShapeNode::Csg { operands, .. } = &declared.shape else {
            panic!("an intersection: {:?}", declared.shape);
        };
        let face = |plane: &crate::graph::ObjectNode| {
            let ShapeNode::Plane { normal, offset } = plane.shape else {
                panic!("a plane: {:?}", plane.shape);
            };
            let turn = plane.transforms.iter().fold(glam::Mat3::IDENTITY, |m, t| match t {
                Transform::Rotate(d) => {
                    let r = d * std::f32::consts::PI / 180.0;
                    glam::Mat3::from_rotation_z(r.z)
                        * glam::Mat3::from_rotation_y(r.y)
                        * glam::Mat3::from_rotation_x(r.x)
                        * m
                }
                other => panic!("only rotations: {other:?}"),
            });
            ((turn * normal).normalize(), -offset / normal.length())
        };
        operands.iter().map(face).collect()
    }

    #[test]
    fn shapes2_inc_s_dodecahedron_and_icosahedron_are_regular_with_faces_at_distance_1() {
        let graph =
            pov("#include \"shapes2.inc\"\nobject { Dodecahedron }\nobject { Icosahedron }");
        // Regular: every face has as many neighbours as its sides, all at the same angle.
        for (solid, count, sides, cos) in [
            (&graph.objects[0], 12, 5, 1.0 / 5f32.sqrt()),
            (&graph.objects[1], 20, 3, 5f32.sqrt() / 3.0),
        ] {
            let faces = faces(solid);
            assert_eq!(faces.len(), count);
            for (n, d) in &faces {
                assert!((d - 1.0).abs() < 1e-5, "distance {d}");
                let neighbours = faces.iter().filter(|(m, _)| (n.dot(*m) - cos).abs() < 1e-4);
                assert_eq!(neighbours.count(), sides, "{n}");
            }
        }
    }
}
