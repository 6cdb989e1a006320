//! POV-Ray's transforms as values (`transform { }`, `inverse`, transform functions),
//! transforms.inc's macros, an object's geometry asked while reading (`min_extent`,
//! `max_extent`, `trace`, `inside`) and `#ifdef` of an array's element (`docs/povray.md`):
//! each against hand-worked values, and against POV-Ray 3.7 itself where it is installed.

use crate::common;

use std::path::Path;
use std::process::Command;

use raydiance::graph::ShapeNode;
use raydiance::lang::parse_scene;

/// The centre of `sphere { value, 1 }` after `declarations`: where a test puts a vector.
fn vector(value: &str, declarations: &str) -> [f64; 3] {
    let text = format!("{declarations}\nsphere {{ {value}, 1 }}");
    let graph = parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
    match graph.objects.last().map(|o| &o.shape) {
        Some(ShapeNode::Sphere { center, .. }) => center.as_dvec3().to_array(),
        other => panic!("not a sphere: {other:?}"),
    }
}

fn near(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(b).all(|(a, b)| (a - b).abs() < 1e-5)
}

fn error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.pov"), text).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn a_transform_block_composes_in_order_and_inverse_inverts_the_whole_block() {
    let t = "#include \"transforms.inc\"\n";
    // translate then scale: <1, 1, 1> -> <2, 1, 1> -> <4, 2, 2>.
    let forward = format!("{t}#declare T = transform {{ translate x scale 2 }}");
    assert!(near(vector("vtransform(<1, 1, 1>, T)", &forward), [4.0, 2.0, 2.0]));
    // POV-Ray inverts the whole block, wherever `inverse` stands in it (POV-Ray 3.7 prints
    // <-0.5, 0.5, 0.5> and <0, 0.5, 0.5> for these two).
    let inverted = format!("{t}#declare T = transform {{ translate x inverse scale 2 }}");
    assert!(near(vector("vtransform(<1, 1, 1>, T)", &inverted), [-0.5, 0.5, 0.5]));
    let inverted = format!("{t}#declare T = transform {{ scale 2 inverse translate x }}");
    assert!(near(vector("vtransform(<1, 1, 1>, T)", &inverted), [0.0, 0.5, 0.5]));
    // A declared transform in another, then turned 30° about y (POV-Ray: <0.25, 0.5, 0.433013>),
    // and undone by vinv_transform (POV-Ray: <1.732051, 2, 2.732051>).
    let nested = format!("{inverted}\n#declare T2 = transform {{ T rotate 30*y }}");
    assert!(near(vector("vtransform(<1, 1, 1>, T2)", &nested), [0.25, 0.5, 0.4330127]));
    let undone = vector("vinv_transform(<1, 1, 1>, T2)", &nested);
    assert!(near(undone, [1.7320508, 2.0, 2.7320508]), "{undone:?}");
}

#[test]
fn a_declared_transform_moves_objects_textures_lights_and_cameras() {
    let text = r#"
#declare T = transform { scale 2 translate <1, 0, 0> }
#macro Up(D) transform { translate D*y } #end
camera { location <0, 0, -5> look_at 0 transform T }
light_source { <0, 1, 0> rgb 1 transform { T } }
sphere { 0, 1 transform T Up(3) pigment { checker transform T } }
sphere { 0, 1 transform { Up(1) T inverse } }
"#;
    let graph = parse_scene(Path::new("tests/inline.pov"), text).unwrap_or_else(|e| panic!("{e}"));
    let placed = |k: usize| raydiance::graph::compose(&graph.objects[k].transforms);
    let moved = placed(0).transform_point3(glam::Vec3::ZERO);
    assert!((moved - glam::Vec3::new(1.0, 3.0, 0.0)).length() < 1e-6, "{moved}");
    // The inverse of (translate y, scale 2, translate x) takes <1, 2, 0> back to the origin.
    let back = placed(1).transform_point3(glam::Vec3::new(1.0, 2.0, 0.0));
    assert!(back.length() < 1e-6, "{back}");
    let light = graph.lights[0].position;
    assert!((light - glam::Vec3::new(1.0, 2.0, 0.0)).length() < 1e-6, "{light}");
}

#[test]
fn transforms_inc_macros_match_hand_worked_values() {
    let t = "#include \"transforms.inc\"\n";
    let image = |transform: &str, point: &str| {
        let declared = format!("{t}#declare B = box {{ <1, 2, 3>, <3, 6, 4> }}");
        vector(&format!("vtransform({point}, {transform})"), &declared)
    };
    // The axes go to A, B, C: x + 2y + 3z goes to A + 2B + 3C.
    let shear = image("Shear_Trans(<1, 0, 0>, <1, 1, 0>, <0, 0, 2>)", "<1, 2, 3>");
    assert!(near(shear, [3.0, 2.0, 6.0]), "{shear:?}");
    let matrix = image("Matrix_Trans(x, y, z, <5, 6, 7>)", "<1, 2, 3>");
    assert!(near(matrix, [6.0, 8.0, 10.0]), "{matrix:?}");
    // Stretched by 3 along the diagonal: the diagonal's part triples, the rest stays.
    let stretched = image("Axial_Scale_Trans(<1, 1, 0>, 3)", "<1, 0, 0>");
    assert!(near(stretched, [2.0, 1.0, 0.0]), "{stretched:?}");
    let turned = image("Axis_Rotate_Trans(<1, 1, 1>, 120)", "<1, 0, 0>");
    assert!(near(turned, [0.0, 1.0, 0.0]), "{turned:?}");
    let around = image("Rotate_Around_Trans(<0, 0, 90>, <1, 1, 0>)", "<2, 1, 0>");
    assert!(near(around, [1.0, 2.0, 0.0]), "{around:?}");
    let reoriented = image("Reorient_Trans(x, <0, 0, 2>)", "<3, 0, 0>");
    assert!(near(reoriented, [0.0, 0.0, 3.0]), "{reoriented:?}");
    let opposite = image("Reorient_Trans(x, -x)", "<3, 0, 0>");
    assert!(near(opposite, [-3.0, 0.0, 0.0]), "{opposite:?}");
    // y to the direction, x to math.inc's VPerp_To_Vector of it (here x cross z = -y), z to x
    // cross y, as POV-Ray's does.
    let pointed = image("Point_At_Trans(<2, 0, 0>)", "<1, 2, 3>");
    assert!(near(pointed, [2.0, -1.0, 3.0]), "{pointed:?}");
    let centred = image("Center_Trans(B, x+z)", "<0, 0, 0>");
    assert!(near(centred, [-2.0, 0.0, -3.5]), "{centred:?}");
    let aligned = image("Align_Trans(B, <-1, 1, 0>, <10, 10, 10>)", "<0, 0, 0>");
    assert!(near(aligned, [9.0, 4.0, 0.0]), "{aligned:?}");
}

#[test]
fn extents_trace_and_inside_ask_the_object_s_geometry() {
    // POV-Ray 3.7 prints these extents (a sphere turned about x keeps its box about the
    // turned centre; a difference takes its first operand's box, an intersection the
    // intersection of its operands'; a plane is ±1e10).
    let shapes = "#declare S = sphere { <1, 2, 3>, 2 rotate 30*x }\n\
                  #declare D = difference { box { -1, 1 } sphere { 0, 1.2 } }\n\
                  #declare I = intersection { box { -1, 1 } sphere { <1, 0, 0>, 1 } }\n\
                  #declare P = plane { y, 1 }\n#declare N = <9, 9, 9>;";
    assert!(near(vector("min_extent(S)", shapes), [-1.0, -1.767949, 1.598076]));
    assert!(near(vector("max_extent(S)", shapes), [3.0, 2.232051, 5.598076]));
    assert!(near(vector("min_extent(D)", shapes), [-1.0, -1.0, -1.0]));
    assert!(near(vector("min_extent(I)", shapes), [0.0, -1.0, -1.0]));
    assert_eq!(vector("max_extent(P)", shapes), [1e10; 3]);
    // The sphere's surface along z from <1, 2, -10>, and its outward normal there.
    let hit = vector("trace(S, <1, 2, -10>, z, N)", shapes);
    assert!(near(hit, [1.0, 2.0, 2.663006]), "{hit:?}");
    let normal = vector("N", &format!("{shapes}\n#declare H = trace(S, <1, 2, -10>, 2*z, N);"));
    assert!(near(normal, [0.0, 0.883975, -0.467535]), "{normal:?}");
    // Missing (the difference is hollow along the axis): both the origin.
    let missed = format!("{shapes}\n#declare H = trace(D, <0, 0, -10>, z, N);");
    assert_eq!((vector("H", &missed), vector("N", &missed)), ([0.0; 3], [0.0; 3]));
    let inside = "<inside(S, <1, 2, 3>), inside(S, <10, 2, 3>), inside(P, 0)>";
    assert_eq!(vector(inside, shapes), [1.0, 0.0, 1.0]);
    // shapes.inc's interfaces to them.
    let isect = format!(
        "#include \"shapes.inc\"\n{shapes}\n#declare Q = <7, 7, 7>;\n\
         #declare Found = <IsectN(<1, 2, -10>, z, S, Q, N), Isect(<0, 0, -10>, z, D, Q), 0>;"
    );
    assert_eq!(vector("Found", &isect), [1.0, 0.0, 0.0]);
    assert!(near(vector("Q", &isect), [1.0, 2.0, 2.663006]), "a miss leaves the point");
}

#[test]
fn ifdef_and_defined_tell_whether_an_array_s_element_is_set() {
    let declared = "#declare A = array[3]\n#declare A[1] = 5;\n\
                    #declare V = <0, 0, 0>;\n\
                    #ifdef (A[1]) #declare V = V + x; #end\n\
                    #ifndef (A[2]) #declare V = V + y; #end\n\
                    #declare V = V + z * (defined(A[0]) + 2 * defined(A[1]));";
    assert_eq!(vector("V", declared), [1.0, 1.0, 2.0]);
    let message = error("#declare A = array[3]\n#ifdef (A[3]) #end");
    assert!(message.contains("inline.pov:2:11:") && message.contains("out of bounds"), "{message}");
}

#[test]
fn misused_transforms_and_probes_are_refused_where_they_are_written() {
    let message = error("sphere { 0, 1 transform 3 }");
    assert!(message.contains("inline.pov:1:25:") && message.contains("not a number"), "{message}");
    let message = error("#declare T = translate x;");
    assert!(message.contains("inline.pov:1:14:"), "{message}");
    assert!(message.contains("declared as `transform { ... }`"), "{message}");
    let message = error("#declare S = sphere { 0, 1 }\n#declare H = trace(S, <0, 0, -5>, z, 2);");
    assert!(message.contains("inline.pov:2:38:"), "{message}");
    assert!(message.contains("receives the normal"), "{message}");
    let message = error("#declare H = min_extent(3);");
    assert!(message.contains("`min_extent` takes an object, not a number"), "{message}");
    let message = error("#declare H = trace(S, 0);");
    assert!(message.contains("`trace` takes 3 or 4 arguments, not 2"), "{message}");
    let message = error("#include \"transforms.inc\"\nsphere { 0, 1 Spline_Trans(S, 0, y, 0, 0) }");
    assert!(message.contains("inline.pov:2:15:") && message.contains("`spline`"), "{message}");
}

/// Each of transforms.inc's macros and the probes, written by POV-Ray 3.7 (with its own
/// transforms.inc) and by raydiance (with its own) to a file, agree to 1e-4.
#[test]
fn transforms_inc_and_the_probes_agree_with_povray() {
    let test = "transforms_inc_and_the_probes_agree_with_povray";
    if !common::outside_tool("povray", "povray", test) {
        return;
    }
    let values = [
        "vtransform(<1, 2, 3>, Shear_Trans(<1, 0.2, 0>, <0.3, 1, 0.1>, <0, -0.4, 2>))",
        "vtransform(<1, 2, 3>, Matrix_Trans(<1, 0.2, 0>, <0.3, 1, 0.1>, <0, -0.4, 2>, <4, 5, 6>))",
        "vtransform(<1, 2, 3>, Axial_Scale_Trans(<1, 2, -0.5>, 2.5))",
        "vtransform(<1, 2, 3>, Axis_Rotate_Trans(<1, 2, -0.5>, 37))",
        "vtransform(<1, 2, 3>, Rotate_Around_Trans(<10, 20, 30>, <-1, 0.5, 2>))",
        "vtransform(<1, 2, 3>, Reorient_Trans(<1, 0.5, 0.2>, <-0.3, 1, 0.7>))",
        "vtransform(<1, 2, 3>, Point_At_Trans(<0.3, -1, 0.7>))",
        "vtransform(<1, 2, 3>, Center_Trans(B, x+z))",
        "vtransform(<1, 2, 3>, Align_Trans(B, <-1, 1, 0>, <5, 5, 5>))",
        "vinv_transform(<1, 2, 3>, T)",
        "min_extent(B)",
        "max_extent(B)",
        "trace(B, <0.5, 3, -10>, <0.1, 0, 1>, N)",
        "N",
        "<inside(B, <0.5, 2, 3.5>), inside(B, <0, 0, 0>), 0>",
    ];
    let mut scene = String::from(
        "#include \"transforms.inc\"\n#declare B = box { <1, 2, 3>, <3, 6, 4> rotate 10*y }\n\
         #declare T = transform { rotate <10, 20, 30> scale <1, 2, 3> translate x }\n\
         #declare N = <0, 0, 0>;\n#fopen Out \"values.txt\" write\n",
    );
    for value in values {
        scene +=
            &format!("#declare V = {value};\n#write (Out, vstr(3, V, \" \", 0, 6), \"\\n\")\n");
    }
    scene += "#fclose Out\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pov");
    std::fs::write(&path, &scene).unwrap();
    let povray = Command::new("povray")
        .current_dir(dir.path())
        .args(["+Iscene.pov", "+W8", "+H6", "-D", "-GA", "-F"])
        .output()
        .expect("POV-Ray is the oracle: install Debian's `povray`");
    assert!(povray.status.success(), "{}", String::from_utf8_lossy(&povray.stderr));
    let theirs = std::fs::read_to_string(dir.path().join("values.txt")).unwrap();
    raydiance::lang::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let ours = std::fs::read_to_string(dir.path().join("values.txt")).unwrap();
    let numbers = |text: &str| -> Vec<Vec<f64>> {
        text.lines().map(|l| l.split(' ').map(|n| n.parse().unwrap()).collect()).collect()
    };
    let (theirs, ours) = (numbers(&theirs), numbers(&ours));
    assert_eq!(theirs.len(), values.len());
    for ((value, a), b) in values.iter().zip(&theirs).zip(&ours) {
        let agree = a.iter().zip(b).all(|(a, b)| (a - b).abs() < 1e-4 * a.abs().max(1.0));
        assert!(agree, "{value}: POV-Ray {a:?}, raydiance {b:?}");
    }
}
