//! The same scene written with transforms, declarations, instances, expressions and `matrix`
//! renders the same image as the plain form.

mod common;

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
