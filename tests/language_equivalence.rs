//! The same scene written with transforms, declarations, instances, expressions and `matrix`
//! renders the same image as the plain form.

use crate::common;

use common::{LAB_BOX, max_abs_difference, render_image, scene};

const PLAIN: &str = r#"
light_source { <0, 0.5, 0> power rgb 1 }
sphere { <-0.5, -0.7, 0.25>, 0.3  material { diffuse rgb <0.2, 0.4, 0.8> } }
sphere { <0.5, -0.7, -0.25>, 0.3  material { diffuse rgb <0.8, 0.7, 0.2> } }
box { <-0.2, -1, -0.6>, <0, -0.6, -0.4>  material { diffuse rgb 0.5 } }
"#;

fn render(body: &str) -> raydiance::image::Image {
    render_image(&scene(&format!(
        "{LAB_BOX} settings {{ resolution 32, 32  samples 4  integrator direct }} {body}"
    )))
}

#[test]
fn transforms_declarations_expressions_and_matrix_match_the_plain_scene() {
    let plain = render(PLAIN);
    let variants = [
        // transforms in written order: scale first, then translate
        r#"light_source { <0, 0.5, 0> power rgb 1 }
           sphere { <0, 0, 0>, 1  scale 0.3  translate <-0.5, -0.7, 0.25>
                    material { diffuse rgb <0.2, 0.4, 0.8> } }
           sphere { <0, 0, 0>, 0.3  translate <0.5, 0, 0>  translate <0, -0.7, -0.25>
                    material { diffuse rgb <0.8, 0.7, 0.2> } }
           box { <-1, -1, -1>, <1, 1, 1>  scale <0.1, 0.2, 0.1>  rotate <0, 90, 0>
                 translate <-0.1, -0.8, -0.5>  material { diffuse rgb 0.5 } }"#,
        // declarations, instances, expressions and component access
        r#"#declare P = <0, 0.5, 0>;
           #declare R = 0.6 / 2;
           #declare Ball = sphere { <0, 0, 0>, R }
           #declare Grey = material { diffuse rgb 0.25 * 2 }
           light_source { P power rgb 1 }
           object { Ball  translate <-0.5, P.y - 1.2, 0.25>  material { diffuse rgb <0.2, 0.4, 0.8> } }
           union { object { Ball }  translate <1, 0, 0> * 0.5 + <0, -0.7, -0.25>
                   material { diffuse rgb <0.8, 0.7, 0.2> } }
           box { <-0.2, -1, -0.6>, <0, -0.6, -0.4>  material { Grey } }"#,
        // matrix: a uniform scale of 0.3 and a translation, in POV-Ray's order
        r#"light_source { <0, 0.5, 0> power rgb 1 }
           sphere { <0, 0, 0>, 1  matrix <0.3, 0, 0,  0, 0.3, 0,  0, 0, 0.3,  -0.5, -0.7, 0.25>
                    material { diffuse rgb <0.2, 0.4, 0.8> } }
           sphere { <0.5, -0.7, -0.25>, 0.3  material { diffuse rgb <0.8, 0.7, 0.2> } }
           box { <0, 0, 0>, <1, 1, 1>  matrix <0.2, 0, 0,  0, 0.4, 0,  0, 0, 0.2,  -0.2, -1, -0.6>
                 material { diffuse rgb 0.5 } }"#,
    ];
    for (i, variant) in variants.iter().enumerate() {
        let difference = max_abs_difference(&plain, &render(variant));
        assert!(difference < 1e-4, "variant {i} differs by {difference}");
    }
}

#[test]
fn a_different_scene_does_differ() {
    // Guards the test above against comparing images that cannot differ.
    let moved = PLAIN.replace("<-0.5, -0.7, 0.25>", "<-0.45, -0.7, 0.25>");
    assert!(max_abs_difference(&render(PLAIN), &render(&moved)) > 1e-2);
}

/// Four small spheres in a row, a disk and a box, written out by hand.
const UNROLLED: &str = r#"
light_source { <0, 0.5, 0> power rgb 1 }
sphere { <-0.6, -0.8, 0>, 0.15  material { diffuse rgb <0.2, 0.4, 0.8> } }
sphere { <-0.2, -0.8, 0>, 0.15  material { diffuse rgb <0.2, 0.4, 0.8> } }
sphere { <0.2, -0.8, 0>, 0.15  material { diffuse rgb <0.2, 0.4, 0.8> } }
sphere { <0.6, -0.8, 0>, 0.15  material { diffuse rgb <0.2, 0.4, 0.8> } }
sphere { <-0.6, -0.4, 0.3>, 0.1  material { diffuse rgb <0.8, 0.7, 0.2> } }
sphere { <0, -0.4, 0.3>, 0.1  material { diffuse rgb <0.8, 0.7, 0.2> } }
sphere { <0.6, -0.4, 0.3>, 0.1  material { diffuse rgb <0.8, 0.7, 0.2> } }
box { <-0.2, -1, -0.6>, <0, -0.6, -0.4>  material { diffuse rgb 0.5 } }
"#;

#[test]
fn loops_and_macros_render_the_same_image_as_their_unrolled_text() {
    let unrolled = render(UNROLLED);
    let variants = [
        // #while and #for
        r#"light_source { <0, 0.5, 0> power rgb 1 }
           #declare I = 0;
           #while (I < 4)
             sphere { <-0.6 + 0.4 * I, -0.8, 0>, 0.15  material { diffuse rgb <0.2, 0.4, 0.8> } }
             #declare I = I + 1;
           #end
           #for (X, -0.6, 0.6, 0.6)
             sphere { <X, -0.4, 0.3>, 0.1  material { diffuse rgb <0.8, 0.7, 0.2> } }
           #end
           box { <-0.2, -1, -0.6>, <0, -0.6, -0.4>  material { diffuse rgb 0.5 } }"#,
        // macros: as statements, in a union, as modifiers, as values; recursion; #if
        r#"#macro Blue() material { diffuse rgb <0.2, 0.4, 0.8> } #end
           #macro Ball(C, R, M)  sphere { C, R  M }  #end
           #macro Row(N)
             #local K = N - 1;
             #if (K > 0) Row(K) #end
             Ball(<-0.6 + 0.4 * K, -0.8, 0>, 0.15, Blue())
           #end
           #macro Half(V) (V / 2) #end
           light_source { <0, Half(1), 0> power rgb 1 }
           union { Row(4) }
           #declare Gold = material { diffuse rgb <0.8, 0.7, 0.2> }
           #for (J, 2, 0, -1)
             #if (J = 1) sphere { <0, -0.4, 0.3>, 0.1  Gold }
             #else Ball(<J * 0.6 - 0.6, -0.4, 0.3>, 0.1, Gold)
             #end
           #end
           #declare Corner = array[2] { <-0.2, -1, -0.6>, <0, -0.6, -0.4> };
           box { Corner[0], Corner[1]  material { diffuse rgb 0.5 } }"#,
    ];
    for (i, variant) in variants.iter().enumerate() {
        let difference = max_abs_difference(&unrolled, &render(variant));
        assert_eq!(difference, 0.0, "variant {i} differs by {difference}");
    }
    // Guards against comparing images that cannot differ.
    let moved = UNROLLED.replace("<0.6, -0.8, 0>", "<0.65, -0.8, 0>");
    assert!(max_abs_difference(&unrolled, &render(&moved)) > 1e-3);
}

/// The radius of the first sphere of a scene's graph.
fn radii(body: &str) -> Vec<f32> {
    let text = format!("camera {{ location <0, 0, -5>  look_at <0, 0, 0> }}\n{body}");
    let graph = raydiance::lang::parse_scene(std::path::Path::new("tests/inline.scn"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    graph
        .objects
        .iter()
        .map(|o| match o.shape {
            raydiance::graph::ShapeNode::Sphere { radius, .. } => radius,
            _ => panic!("a sphere"),
        })
        .collect()
}

#[test]
fn local_hides_a_declared_name_until_the_macro_ends() {
    let radii = radii(
        r#"#declare R = 1;
           #macro M()
             #local R = 2;
             sphere { 0, R }
           #end
           M()
           sphere { 0, R }"#,
    );
    assert_eq!(radii, [2.0, 1.0]);
}

#[test]
fn declare_in_a_macro_binds_for_the_text_after_the_call() {
    let radii = radii(
        r#"#macro M()
             #declare Made = 3;
             #local Kept = 4;
           #end
           M()
           sphere { 0, Made }
           #ifdef (Kept) sphere { 0, 99 } #end"#,
    );
    assert_eq!(radii, [3.0]);
}

#[test]
fn declare_in_a_macro_changes_a_local_it_can_see_and_a_parameter_passed_by_reference() {
    let radii = radii(
        r#"#declare R = 1;
           #macro M()
             #local R = 2;
             #declare R = 5;      // the local R: POV-Ray changes the nearest
             sphere { 0, R }
           #end
           M()
           sphere { 0, R }
           #macro Set(V) #declare V = 7; #end
           #declare Out = 1;
           Set(Out)              // a lone identifier: by reference
           sphere { 0, Out }
           Set(Out + 0)          // an expression: by value
           #declare Out2 = 6;
           Set(Out2 * 1)
           sphere { 0, Out2 }"#,
    );
    assert_eq!(radii, [5.0, 1.0, 7.0, 6.0]);
}

#[test]
fn a_local_in_an_included_file_ends_with_the_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("part.scn"), "#local Hidden = 2;\n#declare Shown = 3;\n")
        .unwrap();
    let main = dir.path().join("main.scn");
    std::fs::write(
        &main,
        "camera { location <0, 0, -5>  look_at <0, 0, 0> }\n#include \"part.scn\"\n\
         sphere { 0, Shown }\n#ifdef (Hidden) sphere { 0, 99 } #end\n",
    )
    .unwrap();
    let graph = raydiance::lang::load_scene(&main).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(graph.objects.len(), 1);
}

#[test]
fn random_streams_do_not_depend_on_the_settings_seed() {
    let centres = |settings_seed: u32| {
        let text = format!(
            "camera {{ location <0, 0, -5>  look_at <0, 0, 0> }}
             settings {{ seed {settings_seed} }}
             #declare S = seed(7);
             #for (I, 1, 5) sphere {{ <rand(S), rand(S), rand(S)>, 0.1 }} #end"
        );
        let graph = raydiance::lang::parse_scene(std::path::Path::new("tests/inline.scn"), &text)
            .unwrap_or_else(|e| panic!("{e}"));
        let centres: Vec<[f32; 3]> = graph
            .objects
            .iter()
            .map(|o| match o.shape {
                raydiance::graph::ShapeNode::Sphere { center, .. } => center.to_array(),
                _ => panic!("a sphere"),
            })
            .collect();
        centres
    };
    let first = centres(0);
    assert_eq!(first, centres(12345));
    // The numbers differ from each other (a stream, not a constant).
    assert!(first.windows(2).all(|w| w[0] != w[1]));
}

/// A block pierced by four holes and crowned by a merge of spheres, written out by hand.
const CSG_UNROLLED: &str = r#"
light_source { <0, 0.5, -0.5> power rgb 1 }
difference {
  box { <-0.8, -1, -0.3>, <0.8, -0.5, 0.3> }
  cylinder { <-0.6, -0.75, -0.4>, <-0.6, -0.75, 0.4>, 0.12 }
  cylinder { <-0.2, -0.75, -0.4>, <-0.2, -0.75, 0.4>, 0.12  material { diffuse rgb 0.1 } }
  cylinder { <0.2, -0.75, -0.4>, <0.2, -0.75, 0.4>, 0.12 }
  cylinder { <0.6, -0.75, -0.4>, <0.6, -0.75, 0.4>, 0.12  material { diffuse rgb 0.1 } }
  cone { <0, -1.1, 0>, 0.15, <0, -0.4, 0>, 0.05 }
  material { diffuse rgb <0.2, 0.4, 0.8> }
}
merge {
  sphere { <-0.4, -0.3, 0>, 0.2 }
  sphere { <-0.2, -0.3, 0>, 0.2 }
  sphere { <0, -0.3, 0>, 0.2 }
  sphere { <0.2, -0.3, 0>, 0.2 }
  torus { 0.3, 0.05 }
  material { diffuse rgb <0.8, 0.7, 0.2> }
}
intersection { sphere { <0.6, 0.2, 0>, 0.2 }  plane { y, -0.2 }  material { diffuse rgb 0.5 } }
"#;

#[test]
fn loops_and_macros_making_csg_render_the_same_image_as_their_unrolled_text() {
    let unrolled = render(CSG_UNROLLED);
    let variants = [
        // #for and #if among a difference's operands, #while among a merge's
        r#"light_source { <0, 0.5, -0.5> power rgb 1 }
           difference {
             box { <-0.8, -1, -0.3>, <0.8, -0.5, 0.3> }
             #for (I, 0, 3)
               #if (mod(I, 2) = 0)
                 cylinder { <-0.6 + 0.4 * I, -0.75, -0.4>, <-0.6 + 0.4 * I, -0.75, 0.4>, 0.12 }
               #else
                 cylinder { <-0.6 + 0.4 * I, -0.75, -0.4>, <-0.6 + 0.4 * I, -0.75, 0.4>, 0.12
                            material { diffuse rgb 0.1 } }
               #end
             #end
             cone { <0, -1.1, 0>, 0.15, <0, -0.4, 0>, 0.05 }
             material { diffuse rgb <0.2, 0.4, 0.8> }
           }
           merge {
             #declare I = 0;
             #while (I < 4) sphere { <-0.4 + 0.2 * I, -0.3, 0>, 0.2 } #declare I = I + 1; #end
             torus { 0.3, 0.05 }
             material { diffuse rgb <0.8, 0.7, 0.2> }
           }
           intersection { sphere { <0.6, 0.2, 0>, 0.2 }  plane { y, -0.2 }  material { diffuse rgb 0.5 } }"#,
        // macros giving operands and whole CSG objects, a declared CSG object instanced, x y z
        r#"#macro Hole(X, M) cylinder { <X, -0.75, -0.4>, <X, -0.75, 0.4>, 0.12  M } #end
           #macro Dark() material { diffuse rgb 0.1 } #end
           #macro Block(Holes)
             difference {
               box { <-0.8, -1, -0.3>, <0.8, -0.5, 0.3> }
               #for (I, 0, Holes - 1)
                 #if (mod(I, 2) = 0) cylinder { <-0.6 + 0.4 * I, -0.75, -0.4>, <-0.6 + 0.4 * I, -0.75, 0.4>, 0.12 }
                 #else Hole(-0.6 + 0.4 * I, Dark())
                 #end
               #end
               cone { <0, -1.1, 0>, 0.15, <0, -0.4, 0>, 0.05 }
               material { diffuse rgb <0.2, 0.4, 0.8> }
             }
           #end
           light_source { <0, 0.5, -0.5> power rgb 1 }
           Block(4)
           #macro Ball(X) sphere { <X, -0.3, 0>, 0.2 } #end
           #declare Crown = merge {
             #for (I, 0, 3) Ball(-0.4 + 0.2 * I) #end
             torus { 0.3, 0.05 }
           }
           object { Crown  material { diffuse rgb <0.8, 0.7, 0.2> } }
           intersection { sphere { 0.6*x + 0.2*y, 0.2 }  plane { y, -0.2 }  material { diffuse rgb 0.5 } }"#,
    ];
    for (i, variant) in variants.iter().enumerate() {
        let difference = max_abs_difference(&unrolled, &render(variant));
        assert_eq!(difference, 0.0, "variant {i} differs by {difference}");
    }
    // Guards against comparing images that cannot differ.
    let moved = CSG_UNROLLED.replace(
        "<0.2, -0.75, -0.4>, <0.2, -0.75, 0.4>",
        "<0.25, -0.75, -0.4>, <0.25, -0.75, 0.4>",
    );
    assert!(max_abs_difference(&unrolled, &render(&moved)) > 1e-3);
}
