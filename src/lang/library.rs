//! raydiance's own versions of POV-Ray's standard include files, built into the binary so that a
//! `.pov` scene needs nothing beside it (`docs/povray.md`). Searched after the including file's
//! folder and the include path; only names whose every declaration raydiance can honour are here.

/// The text of the built-in include file `name`, if there is one.
pub fn file(name: &str) -> Option<&'static str> {
    match name {
        "arrays.inc" => Some(include_str!("library/arrays.inc")),
        "ash.map" => Some(include_str!("library/ash.map")),
        "benediti.map" => Some(include_str!("library/benediti.map")),
        "bubinga.map" => Some(include_str!("library/bubinga.map")),
        "cedar.map" => Some(include_str!("library/cedar.map")),
        "colors.inc" => Some(include_str!("library/colors.inc")),
        "consts.inc" => Some(include_str!("library/consts.inc")),
        "debug.inc" => Some(include_str!("library/debug.inc")),
        "finish.inc" => Some(include_str!("library/finish.inc")),
        "functions.inc" => Some(include_str!("library/functions.inc")),
        "glass.inc" => Some(include_str!("library/glass.inc")),
        "glass_old.inc" => Some(include_str!("library/glass_old.inc")),
        "golds.inc" => Some(include_str!("library/golds.inc")),
        "marbteal.map" => Some(include_str!("library/marbteal.map")),
        "math.inc" => Some(include_str!("library/math.inc")),
        "metals.inc" => Some(include_str!("library/metals.inc")),
        "orngwood.map" => Some(include_str!("library/orngwood.map")),
        "pinkmarb.map" => Some(include_str!("library/pinkmarb.map")),
        "rad_def.inc" => Some(include_str!("library/rad_def.inc")),
        "rand.inc" => Some(include_str!("library/rand.inc")),
        "rdgranit.map" => Some(include_str!("library/rdgranit.map")),
        "shapes.inc" => Some(include_str!("library/shapes.inc")),
        "shapes2.inc" => Some(include_str!("library/shapes2.inc")),
        "shapes_old.inc" => Some(include_str!("library/shapes_old.inc")),
        "shapesq.inc" => Some(include_str!("library/shapesq.inc")),
        "skies.inc" => Some(include_str!("library/skies.inc")),
        "stars.inc" => Some(include_str!("library/stars.inc")),
        "stdcam.inc" => Some(include_str!("library/stdcam.inc")),
        "stdinc.inc" => Some(include_str!("library/stdinc.inc")),
        "stones.inc" => Some(include_str!("library/stones.inc")),
        "stones1.inc" => Some(include_str!("library/stones1.inc")),
        "stones2.inc" => Some(include_str!("library/stones2.inc")),
        "sunpos.inc" => Some(include_str!("library/sunpos.inc")),
        "teak.map" => Some(include_str!("library/teak.map")),
        "textures.inc" => Some(include_str!("library/textures.inc")),
        "transforms.inc" => Some(include_str!("library/transforms.inc")),
        "woodmaps.inc" => Some(include_str!("library/woodmaps.inc")),
        "whiteash.map" => Some(include_str!("library/whiteash.map")),
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
        "T_Cloud1" | "T_Cloud2" | "T_Cloud3" | "O_Cloud1" | "O_Cloud2" => Some(
            "POV-Ray's skies.inc declares it to glow (`ambient` without `diffuse`) through \
             transparent colours, T_Cloud1 and T_Cloud3 (and the objects made of them) in two \
             layers whose glows differ, which raydiance's layered textures do not keep apart: \
             raydiance's skies.inc does not declare it yet (it has P_Cloud1 to P_Cloud4 and \
             S_Cloud1 to S_Cloud5)",
        ),
        "Spline_Trans" => Some(
            "POV-Ray's transforms.inc declares it as a macro that follows a `spline`, which \
             raydiance does not have: raydiance's transforms.inc leaves it out",
        ),
        "fn_Gradient" | "fn_Gradient_Directional" | "fn_Divergence" => Some(
            "POV-Ray's math.inc declares it as a macro that makes a function, which raydiance's \
             macros cannot: raydiance's math.inc leaves it out (vGradient, vCurl and Divergence \
             give the values at a point)",
        ),
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

    use crate::graph::MaterialDesc;

    const NAMES: [&str; 36] = [
        "arrays.inc",
        "ash.map",
        "benediti.map",
        "bubinga.map",
        "cedar.map",
        "colors.inc",
        "consts.inc",
        "debug.inc",
        "finish.inc",
        "functions.inc",
        "glass.inc",
        "glass_old.inc",
        "golds.inc",
        "marbteal.map",
        "math.inc",
        "metals.inc",
        "orngwood.map",
        "pinkmarb.map",
        "rad_def.inc",
        "rdgranit.map",
        "shapes.inc",
        "shapes2.inc",
        "shapes_old.inc",
        "shapesq.inc",
        "skies.inc",
        "stars.inc",
        "stones.inc",
        "stones1.inc",
        "stones2.inc",
        "sunpos.inc",
        "teak.map",
        "textures.inc",
        "transforms.inc",
        "whiteash.map",
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

    /// The spheres' radii of `scene`, in the order they were made.
    fn radii(scene: &str) -> Vec<f32> {
        let graph = pov(scene);
        let radius = |object: &crate::graph::ObjectNode| match object.shape {
            crate::graph::ShapeNode::Sphere { radius, .. } => radius,
            ref other => panic!("a sphere, not {other:?}"),
        };
        graph.objects.iter().map(radius).collect()
    }

    #[test]
    fn arrays_inc_sorts_reverses_resizes_and_picks() {
        // 57 draws (duplicates among them) sorted, then written out as radii: the radii ascend
        // and are the draws, each as often.
        let header = r#"#include "arrays.inc"
#declare S = seed(3);
#declare A = array[57];
#for (I, 0, 56) #declare A[I] = 1 + int(20 * rand(S)); #end
#declare Drawn = A;
"#;
        let drawn = radii(&format!("{header}#for (I, 0, 56) sphere {{ 0, Drawn[I] }} #end"));
        let sorted = radii(&format!(
            "{header}Sort_Array(A)
#for (I, 0, 56) sphere {{ 0, A[I] }} #end"
        ));
        let mut expected = drawn.clone();
        expected.sort_by(f32::total_cmp);
        assert_eq!(sorted, expected);
        assert!(drawn != expected, "the draws were not already in order");
        // Only items 10 to 20 sorted; a redefined Sort_Compare sorts largest first.
        let partial = radii(&format!(
            "{header}#macro Sort_Compare(Array, IdxA, IdxB) (Array[IdxA] > Array[IdxB]) #end
Sort_Partial_Array(A, 10, 20)
#for (I, 0, 56) sphere {{ 0, A[I] }} #end"
        ));
        let mut expected = drawn.clone();
        expected[10..=20].sort_by(|a, b| b.total_cmp(a));
        assert_eq!(partial, expected);
        // Reversed (odd and even lengths), resized shorter and longer.
        for n in [5, 6] {
            let reversed = radii(&format!(
                "#include \"arrays.inc\"\n#declare A = array[{n}];\n#for (I, 0, {n} - 1) #declare A[I] = I + 1; #end
Reverse_Array(A)\n#for (I, 0, {n} - 1) sphere {{ 0, A[I] }} #end"
            ));
            let expected: Vec<f32> = (1..=n).rev().map(|r| r as f32).collect();
            assert_eq!(reversed, expected);
        }
        let resized = radii(
            r#"#include "arrays.inc"
#declare A = array[4] {1, 2, 3, 4}
Resize_Array(A, 2)
#declare B = A;
Resize_Array(A, 3)
#if (defined(A[2])) #error "a new item is unset" #end
#for (I, 0, dimension_size(B, 1) - 1) sphere { 0, B[I] } #end
sphere { 0, dimension_size(A, 1) }"#,
        );
        assert_eq!(resized, [1.0, 2.0, 3.0]);
        // A picked item is one of the array's, and every item is picked in 200 draws.
        let picked = radii(
            r#"#include "arrays.inc"
#declare A = array[4] {1, 2, 3, 4}
#declare S = seed(1);
#for (I, 1, 200) sphere { 0, Rand_Array_Item(A, S) } #end"#,
        );
        for item in [1.0, 2.0, 3.0, 4.0] {
            assert!(picked.contains(&item), "{item} never picked");
        }
        assert!(picked.iter().all(|r| [1.0, 2.0, 3.0, 4.0].contains(r)));
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
            // The highlight is a coat over the glass, which takes from it only what it reflects.
            assert!(m.coat > 0.0 && m.coat_covers == crate::graph::Covers::Everything, "{m:?}");
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
        // The interiors fade to black over their fade_distance: sigma_a = 1 / distance.
        let absorption = |m: &MaterialDesc| m.interior.as_ref().map(|i| i.absorption);
        assert_eq!(absorption(&materials[0]), Some(glam::Vec3::ONE), "I_Glass1: 1");
        assert_eq!(absorption(&materials[2]), Some(glam::Vec3::splat(0.5)), "I_Glass_Exp(2)");
        assert_eq!(absorption(&materials[3]), Some(glam::Vec3::ONE), "I_Glass_Caustics2: 1");
    }

    #[test]
    fn skies_inc_s_rainy_sky_is_dark_at_the_horizon_with_clouds_above() {
        let graph = pov("#include \"skies.inc\"\nsky_sphere { S_Cloud4 }");
        let sky = graph.sky.expect("S_Cloud4 is the scene's sky");
        let texture = crate::texture::Texture::new(&sky.pigment, &mut |_| unreachable!("no image"));
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
                crate::texture::Texture::new(&sky.pigment, &mut |_| unreachable!("no image"));
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
        for (name, why) in [("T_Cloud2", "transparent colours"), ("f_bicorn", "internal functions")]
        {
            let text = format!("#include \"skies.inc\"\nsphere {{ 0, 1 texture {{ {name} }} }}");
            let error = crate::lang::parse_scene(Path::new("library.pov"), &text)
                .map(|_| ())
                .unwrap_err()
                .to_string();
            assert!(error.contains(":2:25:") && error.contains(why), "{error}");
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
sphere { 0, 1 texture { T_Grnt6a scale <1, 3, 2> rotate <0, 0, 40> } }
sphere { 0, 1 texture { T_Grnt9a scale <3.5, 5, 4> rotate <0, 0, 60> } }
#if (g1.red != 0.26 | g1.green != 0.41 | g1.blue != 0.31) #error "T_Grnt21's green" #end
"#);
        let material = |i: usize| graph.objects[i].material.clone().expect("a material");
        let eval = |node: &crate::graph::TextureNode| {
            let texture = crate::texture::Texture::new(node, &mut |_| unreachable!("no image"));
            texture.expect("a texture without images")
        };
        let texture = |i: usize| eval(&material(i).diffuse);
        // A layer's light through (filter + transmit), grey.
        let through =
            |i: usize| eval(&material(i).pigment.clone().expect("a see-through pigment").through);
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
        // T_Stone7 is colors.inc's Salmon under T_Grnt6a's and T_Grnt9a's see-through veins:
        // each layer's colour c shows with weight 1 - t, the one under it with t (its transmit).
        let salmon = glam::Vec3::new(0.435294, 0.258824, 0.258824);
        let (stone, veins, top) = (texture(1), [texture(2), texture(3)], [through(2), through(3)]);
        let mut salmon_seen = 0.0f32;
        for i in 0..200 {
            let p = glam::Vec3::new(i as f32 * 0.037, 0.5, i as f32 * -0.023);
            let expected = veins.iter().zip(&top).fold(salmon, |under, (colour, through)| {
                let t = through.eval(p).x;
                colour.eval(p) * (1.0 - t) + under * t
            });
            let seen = stone.eval(p);
            assert!((seen - expected).abs().max_element() < 1e-5, "{seen} {expected}");
            salmon_seen = salmon_seen.max(top[0].eval(p).x * top[1].eval(p).x);
        }
        // The veins let some of the salmon show (and the test would see a wrong weight).
        assert!(salmon_seen > 0.3, "{salmon_seen}");
    }

    /// The colour (times POV-Ray's default `diffuse` 0.6) of the texture of `scene`'s object.
    fn object_texture(scene: &str) -> crate::texture::Texture {
        let graph = pov(scene);
        let material = graph.objects[0].material.clone().expect("a material");
        crate::texture::Texture::new(&material.diffuse, &mut |_| unreachable!("no image"))
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
        // M_Wood2A's colours are POV-Ray's halved; M_Wood19B's clear part is white (`rgbf 1`).
        for (map, at, expected) in [
            ("M_Wood1A", 0.5, glam::Vec3::new(0.74, 0.45, 0.3)),
            ("M_Wood2A", 0.05, glam::Vec3::new(0.175, 0.08, 0.06)),
            ("M_Wood19B", 0.5, glam::Vec3::ONE),
        ] {
            let scene = format!(
                "#include \"woodmaps.inc\"\nsphere {{ 0, 1 pigment {{ gradient x color_map {{ {map} }} }} }}"
            );
            let seen = object_texture(&scene).eval(glam::Vec3::new(at, 0.0, 0.0));
            assert!((seen - expected).abs().max_element() < 1e-5, "{map} at {at}: {seen}");
        }
    }

    #[test]
    fn woods_inc_s_textures_are_their_base_grain_under_a_see_through_grain() {
        // T_Wood2's base is M_Wood2A's dark browns, red from 0.175 to 0.23, under M_Wood2B's
        // see-through browns (red 0.5): where the top lets light through the base shows.
        let two = object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood2 } }");
        let rosewood =
            object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood32 } }");
        let orange = object_texture("#include \"woods.inc\"\nsphere { 0, 1 texture { T_Wood34 } }");
        // A declared grain takes the colours given with it, as in POV-Ray's sample scenes.
        let grain = object_texture(
            "#include \"woods.inc\"\nsphere { 0, 1 pigment { P_WoodGrain2A color_map { M_Wood2A } } }",
        );
        let (mut reds, mut layered, mut onion) = (Vec::new(), 0, 0);
        for i in 0..50 {
            let p = glam::Vec3::new(i as f32 * 0.037, (i % 7) as f32 * 0.05, i as f32 * 0.1);
            let base = grain.eval(p);
            assert!(base.x >= 0.175 - 1e-5 && base.x <= 0.23 + 1e-5, "{base} at {p}");
            assert!(base.x > base.y && base.y > base.z - 1e-5, "brown: {base}");
            reds.push(base.x);
            let seen = two.eval(p);
            assert!(seen.x >= 0.175 - 1e-5 && seen.x <= 0.5 + 1e-5, "{seen} at {p}");
            layered += usize::from((seen - base).abs().max_element() > 1e-3);
            onion += usize::from(orange.eval(p) != rosewood.eval(p));
        }
        let (low, high) = reds.iter().fold((1f32, 0f32), |(l, h), r| (l.min(*r), h.max(*r)));
        assert!(high - low > 0.02, "the grain shows: reds {low} to {high}");
        assert!(layered > 0 && onion > 0, "the top layers show: {layered}, {onion}");
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

    #[test]
    fn math_inc_s_macros_and_functions_agree_with_their_formulas() {
        // Each value against its formula worked out by hand; `Near` stops the scene where one
        // differs, and the last line shows that it can.
        let checks = r#"
#include "math.inc"
#macro Near(A, B, What)
  #if (abs(A - B) > 1e-9 * max(1, abs(B))) #error concat(What, " differs: ", str(A, 0, 12), " ", str(B, 0, 12)) #end
#end
#declare Arr = array[4] { 1, 2, 4, 9 }
Near(Mean(Arr), 4, "Mean")
Near(Std_Dev(Arr, 4), sqrt((9 + 4 + 0 + 25) / 4), "Std_Dev")
GetStats(Arr)
Near(StatisticsArray[0], 4, "N") Near(StatisticsArray[2], 1, "min") Near(StatisticsArray[3], 9, "max")
Near(StatisticsArray[4], sqrt((9 + 4 + 0 + 25) / 4), "stddev")
Histogram(Arr, 2)
Near(HistogramArray[0][1], 3, "hist0") Near(HistogramArray[1][1], 1, "hist1") Near(HistogramArray[1][0], 7, "hist c")
Near(sind(30), 0.5, "sind") Near(acosd(0.5), 60, "acosd") Near(atan2d(1, 1), 45, "atan2d")
Near(even(4), 1, "even") Near(odd(4), 0, "odd") Near(odd(-3), 1, "odd-3") Near(sgn(-2), -1, "sgn")
Near(clip(5, 0, 2), 2, "clip") Near(clamp(5, 0, 2), 1, "clamp") Near(adj_range(0.5, 2, 4), 3, "adj")
Near(adj_range2(3, 2, 4, 10, 20), 15, "adj2")
Near(Interpolate(0.5, 0, 1, 10, 20, 0), 15, "interp0") Near(Interpolate(0.5, 0, 1, 10, 20, 2), 12.5, "interp2")
Near(Interpolate(0.25, 0, 1, 10, 20, 0), 10 + 10 * (1 - cos(pi / 4)) / 2, "interp0b")
Near(VLength5D(rgbft <1, 2, 2, 0, 4>), 5, "vlen5")
Near(VAngleD(x, y), 90, "angle") Near(VRotationD(x, y, -z), -90, "rot")
#if (!VEq(VPerp_To_Vector(<1, 2, 3>), vnormalize(vcross(<1, 2, 3>, x)))) #error "perp" #end
#if (!VEq(VPerp_To_Vector(<3, 2, 1>), vnormalize(vcross(<3, 2, 1>, z)))) #error "perp2" #end
#if (!VZero(VPerp_To_Vector(0))) #error "perp0" #end
#declare GF = function { x * x + 3 * y }
#declare G = vGradient(GF, <2, 0, 0>);
Near(G.x, 4, "grad x") Near(G.y, 3, "grad y")
#declare FX = function { x * y } #declare FY = function { y * z } #declare FZ = function { z * x }
Near(Divergence(FX, FY, FZ, <1, 2, 3>), 2 + 3 + 1, "div")
#declare Curl = vCurl(FX, FY, FZ, <1, 2, 3>);
Near(Curl.x, -2, "curl x") Near(Curl.y, -3, "curl y") Near(Curl.z, -1, "curl z")
Near(Gradient_Length(FX, <1, 2, 3>), sqrt(5), "glen")
Near(VMax(<1, 7, 3>), 7, "vmax")
"#;
        pov(checks);
        let wrong = format!("{checks}\nNear(Mean(Arr), 5, \"Mean\")");
        let message = crate::lang::parse_scene(Path::new("m.pov"), &wrong).map(|_| ()).unwrap_err();
        assert!(message.to_string().contains("Mean differs"), "{message}");
        let left_out =
            "#include \"math.inc\"\n#declare F = function { x }\n#declare G = fn_Gradient(F);";
        let message =
            crate::lang::parse_scene(Path::new("m.pov"), left_out).map(|_| ()).unwrap_err();
        assert!(message.to_string().contains("makes a function"), "{message}");
    }

    #[test]
    fn sunpos_inc_places_the_sun_where_povray_does() {
        // Altitude and azimuth that POV-Ray 3.7 prints for its own sunpos.inc at these dates,
        // times and places (#debug with str(.., 0, 6)).
        for (call, altitude, azimuth) in [
            ("SunPos(2000, 6, 21, 12, 0, 0, 23.44, 0)", 89.579727, 90.102753),
            ("SunPos(2000, 3, 20, 6, 0, 0, 0, 0)", -1.864872, 90.021484),
            ("SunPos(2004, 11, 3, 15, 30, 15, 52, 5)", 11.549895, 225.677236),
        ] {
            pov(&format!(
                "#include \"sunpos.inc\"\n#declare P = {call};\n\
                 #if (abs(Al - {altitude}) > 2e-6 | abs(Az - {azimuth}) > 2e-6) #error \"Al, Az\" #end\n\
                 #if (vlength(P - vrotate(<0, 0, 1e9>, <-Al, Az, 0>)) > 1) #error \"P\" #end"
            ));
        }
    }

    #[test]
    fn debug_inc_s_macros_speak_only_on_their_condition() {
        let scene = |condition: &str| {
            let text = format!("#include \"debug.inc\"\nError({condition}, \"stopped\")");
            crate::lang::parse_scene(Path::new("d.pov"), &text).map(|_| ())
        };
        assert!(scene("0").is_ok());
        let message = scene("1").unwrap_err().to_string();
        assert!(message.contains("stopped"), "{message}");
    }

    #[test]
    fn stdcam_inc_sets_a_camera_a_light_and_a_plum_floor() {
        let graph = pov("#include \"colors.inc\"\n#include \"stdcam.inc\"");
        assert_eq!(graph.objects.len(), 1);
        assert_eq!(graph.lights.len(), 1);
        let floor = object_texture("#include \"colors.inc\"\n#include \"stdcam.inc\"");
        let plum = glam::Vec3::new(0.917647, 0.678431, 0.917647) * 0.6;
        assert!((floor.eval(glam::Vec3::ZERO) - plum).abs().max_element() < 1e-5);
    }

    /// stars.inc's six starfields glow (ambient 1 over diffuse 0) in their pigment's colour at
    /// each point: black sky with pale stars, none of them white everywhere.
    #[test]
    fn stars_inc_s_starfields_glow_point_by_point() {
        for n in 1..=6 {
            let text =
                format!("#include \"stars.inc\"\nsphere {{ 0, 1 texture {{ Starfield{n} }} }}");
            let graph = pov(&text);
            let material = graph.objects[0].material.clone().expect("a material");
            let glow = material.pigment.as_ref().map(|p| p.glow);
            assert_eq!(glow, Some(glam::Vec3::ONE), "Starfield{n} glows with its pigment");
            let sky = object_texture(&text);
            let points = (0..4000).map(|i| glam::Vec3::new(i as f32 * 0.0137, 0.3, -0.2));
            let colours: Vec<glam::Vec3> = points.map(|p| sky.eval(p)).collect();
            let dark = colours.iter().filter(|c| c.max_element() == 0.0).count();
            let stars = colours.iter().filter(|c| c.min_element() > 0.39).count();
            assert!(
                dark > colours.len() / 2 && stars > 0,
                "Starfield{n}: {dark} dark, {stars} stars"
            );
        }
    }

    #[test]
    fn the_map_files_hold_povray_s_colour_maps() {
        // The first colour of three, as POV-Ray's files give it; each holds 255 colours.
        for (file, map, first) in [
            ("ash.map", "M_Ash", glam::Vec3::new(0.298039, 0.188235, 0.125490)),
            ("rdgranit.map", "M_RedGranite", glam::Vec3::new(0.439216, 0.407843, 0.454902)),
            ("whiteash.map", "M_WhiteAsh", glam::Vec3::new(0.345098, 0.219608, 0.109804)),
        ] {
            let scene = format!(
                "#include \"{file}\"\nsphere {{ 0, 1 pigment {{ gradient x color_map {{ {map} }} }} }}"
            );
            let seen = object_texture(&scene).eval(glam::Vec3::new(0.0, 0.0, 0.0));
            assert!((seen - first).abs().max_element() < 1e-5, "{map}: {seen}");
        }
        for file in NAMES.iter().filter(|name| name.ends_with(".map")) {
            let text = super::file(file).expect("built in");
            assert_eq!(text.matches("rgb <").count(), 255, "{file}");
        }
    }

    #[test]
    fn textures_inc_declares_every_name_of_povray_s() {
        // POV-Ray's names the tests above do not name, by what each declares, each on a sphere.
        let added: [(&str, &[&str]); 6] = [
            (
                "color_map",
                &[
                    "Brown_Agate_Map",
                    "Pink_Granite_Map",
                    "Blue_Sky_Map",
                    "Lightning_CMap1",
                    "Lightning_CMap2",
                ][..],
            ),
            (
                "pigment",
                &[
                    "Brown_Agate",
                    "Pink_Granite",
                    "Blue_Sky",
                    "Bright_Blue_Sky",
                    "Blue_Sky2",
                    "Blue_Sky3",
                    "Blood_Sky",
                    "Apocalypse",
                    "Clouds",
                    "FBM_Clouds",
                    "Cherry_Wood",
                    "Pine_Wood",
                    "Dark_Wood",
                    "Tan_Wood",
                    "Candy_Cane",
                    "Peel",
                ][..],
            ),
            (
                "texture",
                &[
                    "Shadow_Clouds",
                    "EMBWood1",
                    "Yellow_Pine",
                    "Rosewood",
                    "Sandalwood",
                    "Glass3",
                    "Green_Glass",
                    "NBglass",
                    "NBoldglass",
                    "NBwinebottle",
                    "NBbeerbottle",
                    "Ruby_Glass",
                    "Dark_Green_Glass",
                    "Yellow_Glass",
                    "Orange_Glass",
                    "Vicks_Bottle_Glass",
                    "Brushed_Aluminum",
                    "Brass_Valley",
                    "Rust",
                    "Rusty_Iron",
                    "Soft_Silver",
                    "New_Penny",
                    "Gold_Nugget",
                    "Aluminum",
                    "Bright_Bronze",
                    "Water",
                    "Cork",
                    "Lightning1",
                    "Lightning2",
                    "Starfield",
                ][..],
            ),
            ("finish", &["Metallic_Finish"][..]),
            ("interior", &["Water_Int"][..]),
            (
                "material",
                &[
                    "M_Glass2",
                    "M_Glass3",
                    "M_Green_Glass",
                    "M_NB_Glass",
                    "M_NB_Old_Glass",
                    "M_NB_Winebottle_Glass",
                    "M_NB_Beerbottle_Glass",
                    "M_Ruby_Glass",
                    "M_Dark_Green_Glass",
                    "M_Yellow_Glass",
                    "M_Orange_Glass",
                    "M_Vicks_Bottle_Glass",
                    "M_Water",
                ][..],
            ),
        ];
        let mut scene = String::from("#include \"textures.inc\"\n");
        for (kind, names) in added {
            for name in names {
                scene += &match kind {
                    "color_map" => format!(
                        "sphere {{ 0, 1 pigment {{ gradient x color_map {{ {name} }} }} }}\n"
                    ),
                    _ => format!("sphere {{ 0, 1 {kind} {{ {name} }} }}\n"),
                };
            }
        }
        let graph = pov(&scene);
        assert_eq!(graph.objects.len(), 66);
        // Including the file says nothing: a texture's warnings come where an object wears it.
        assert!(pov("#include \"textures.inc\"").warnings.is_empty());
    }

    #[test]
    fn textures_inc_s_added_names_hold_povray_s_colours() {
        let wood =
            object_texture("#include \"textures.inc\"\nsphere { 0, 1 pigment { DMFWood5 } }");
        let scene = "#include \"textures.inc\"\nsphere { 0, 1 pigment { Red_Marble } }\n\
                     sphere { 0, 1 pigment { Sapphire_Agate } }\nsphere { 0, 1 texture { New_Brass } }";
        assert_eq!(pov(scene).objects.len(), 3);
        for i in 0..50 {
            let seen = wood.eval(glam::Vec3::new(i as f32 * 0.013, i as f32 * 0.007, 0.0));
            // Between <0.3, 0.1, 0.05> and <0.25, 0.07, 0.038>.
            assert!(seen.x >= 0.25 - 1e-5 && seen.x <= 0.3 + 1e-5, "{seen}");
            assert!(seen.z >= 0.038 - 1e-5 && seen.z <= 0.05 + 1e-5, "{seen}");
        }
    }

    #[test]
    fn shapesq_inc_s_torus_is_the_torus_polynomial() {
        let names = [
            "Bicorn",
            "Crossed_Trough",
            "Cubic_Cylinder",
            "Cubic_Saddle_1",
            "Devils_Curve",
            "Folium",
            "Glob_5",
            "Twin_Glob",
            "Helix",
            "Helix_1",
            "Hyperbolic_Torus_40_12",
            "Lemniscate",
            "Quartic_Loop_1",
            "Monkey_Saddle",
            "Parabolic_Torus_40_12",
            "Piriform",
            "Quartic_Paraboloid",
            "Quartic_Cylinder",
            "Steiner_Surface",
            "Torus_40_12",
            "Witch_Hat",
            "Sinsurf",
        ];
        let mut scene = String::from("#include \"shapesq.inc\"\n");
        for name in names {
            scene += &format!("object {{ {name} }}\n");
        }
        let graph = pov(&scene);
        assert_eq!(graph.objects.len(), names.len());
        let torus = &graph.objects[19];
        let crate::graph::ShapeNode::Instance(declared) = &torus.shape else {
            panic!("the declared torus: {:?}", torus.shape);
        };
        let crate::graph::ShapeNode::Algebraic { terms } = &declared.shape else {
            panic!("a quartic: {:?}", declared.shape);
        };
        // (x² + y² + z² + R² − r²)² − 4R²(x² + z²), R² = 40, r² = 12, is the quartic's value
        // up to one factor at every point.
        let p = |x: f64, y: f64, z: f64| {
            terms
                .iter()
                .map(|t| {
                    let [i, j, k] = t.powers;
                    t.coefficient * x.powi(i as i32) * y.powi(j as i32) * z.powi(k as i32)
                })
                .sum::<f64>()
        };
        let formula = |x: f64, y: f64, z: f64| {
            (x * x + y * y + z * z + 28.0).powi(2) - 160.0 * (x * x + z * z)
        };
        let factor = p(0.0, 0.0, 0.0) / formula(0.0, 0.0, 0.0);
        for (x, y, z) in [(1.0, 2.0, 3.0), (-4.0, 0.5, 2.5), (6.0, -1.0, 0.0), (0.3, 3.0, -7.0)] {
            let (seen, expected) = (p(x, y, z), factor * formula(x, y, z));
            assert!((seen - expected).abs() < 1e-9 * expected.abs().max(1.0), "{seen} {expected}");
        }
    }
}
