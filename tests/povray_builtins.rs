//! POV-Ray's string and vector built-ins (`docs/language.md`, Strings, messages and random
//! numbers): each against its definition, and each misuse refused where it is written.

use std::path::Path;

use raydiance::graph::ShapeNode;
use raydiance::lang::parse_scene;

/// The radius of `sphere { 0, value }` after `declarations`: where a test puts a number.
fn number(value: &str, declarations: &str) -> f64 {
    let text = format!("{declarations}\nsphere {{ 0, {value} }}");
    let graph = parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
    match graph.objects[0].shape {
        ShapeNode::Sphere { radius, .. } => f64::from(radius),
        ref other => panic!("not a sphere: {other:?}"),
    }
}

fn error(value: &str) -> String {
    let text = format!("sphere {{ 0, {value} }}");
    parse_scene(Path::new("tests/inline.pov"), &text).map(|_| ()).unwrap_err().to_string()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-6
}

#[test]
fn string_functions_count_cut_and_convert_characters() {
    assert_eq!(number("strlen(\"héllo\")", ""), 5.0);
    assert_eq!(number("asc(substr(\"hello\", 2, 3))", ""), f64::from(b'e'));
    assert_eq!(number("strlen(substr(\"hello\", 2, 3))", ""), 3.0);
    assert_eq!(number("asc(substr(\"hello\", 5, 1))", ""), f64::from(b'o'));
    assert_eq!(number("asc(strupr(\"q\"))", ""), f64::from(b'Q'));
    assert_eq!(number("asc(strlwr(\"Q\"))", ""), f64::from(b'q'));
    assert_eq!(number("asc(chr(65))", ""), 65.0);
    assert_eq!(number("1 + asc(\"\")", ""), 1.0);
    assert!(close(number("val(\"  12.5abc\")", ""), 12.5));
    assert!(close(number("val(\"2e-1\")", ""), 0.2));
    assert_eq!(number("1 + val(\"abc\")", ""), 1.0);
    // "1.0, 2.0, 3.0": 13 characters, the second number from the 6th.
    assert_eq!(number("strlen(vstr(3, <1, 2, 3>, \", \", 0, 1))", ""), 13.0);
    assert!(close(number("val(substr(vstr(3, <1, 2, 3>, \", \", 0, 1), 6, 3))", ""), 2.0));
    assert_eq!(number("strlen(vstr(2, <1, 2, 3>, \"/\", 0, 0))", ""), 3.0);
}

#[test]
fn atan2_and_vaxis_rotate_follow_their_definitions() {
    assert!(close(number("atan2(1, -1)", ""), 0.75 * std::f64::consts::PI));
    assert!(close(number("1 + atan2(0, 1)", ""), 1.0));
    // About a coordinate axis it is `rotate`'s turn.
    let same =
        "1 + vlength(vaxis_rotate(<1, 2, 3>, <2, 0, 0>, 30) - vrotate(<1, 2, 3>, <30, 0, 0>))";
    assert!(close(number(same, ""), 1.0));
    let same = "1 + vlength(vaxis_rotate(<1, 2, 3>, z, -70) - vrotate(<1, 2, 3>, <0, 0, -70>))";
    assert!(close(number(same, ""), 1.0));
    // A third of a turn about the diagonal takes x to y.
    let turned = "1 + vlength(vaxis_rotate(<1, 0, 0>, <1, 1, 1>, 120) - <0, 1, 0>)";
    assert!(close(number(turned, ""), 1.0));
}

#[test]
fn defined_and_file_exists_answer_zero_or_one() {
    assert_eq!(number("1 + defined(A) + 2 * defined(B)", "#declare A = 1;"), 2.0);
    // The built-in library, a file beside the scene, and a file nowhere.
    assert_eq!(number("file_exists(\"colors.inc\")", ""), 1.0);
    assert_eq!(number("file_exists(\"povray_builtins.rs\")", ""), 1.0);
    assert_eq!(number("1 + file_exists(\"nowhere.inc\")", ""), 1.0);
}

#[test]
fn misuse_is_refused_where_it_is_written() {
    let message = error("strlen(substr(\"abc\", 3, 2))");
    assert!(message.contains("inline.pov:1:20:") && message.contains("`substr`"), "{message}");
    assert!(error("asc(chr(0))").contains("`chr` of 0: no character"));
    assert!(error("defined(1 + 2)").contains("`defined` takes a name"));
    assert!(error("strlen(vstr(4, <1, 2, 3>, \",\", 0, 0))").contains("a vector has 1 to 3"));
    assert!(error("vlength(vaxis_rotate(x, 0, 10))").contains("zero axis"));
    assert!(error("strlen(3)").contains("`strlen` needs a string"));
}
