//! POV-Ray's file directives (`#fopen`, `#read`, `#write`, `#fclose`), `clock_on` and
//! `clock_delta`, `div`, `dimensions` and `.gray` (`docs/povray.md`, Language): each against its
//! definition in POV-Ray's manual, and each misuse refused where it is written.

use std::path::{Path, PathBuf};

use raydiance::animation::{Frame, Frames};
use raydiance::graph::{SceneGraph, ShapeNode};
use raydiance::lang::{load_scene_at, parse_scene};

/// A fresh folder of this test's own.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raydiance-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The scene `text` written as `scene.pov` in `dir`, loaded at `frame`.
fn load_in(dir: &Path, text: &str, frame: Frame) -> Result<SceneGraph, String> {
    let scene = dir.join("scene.pov");
    std::fs::write(&scene, text).unwrap();
    load_scene_at(&scene, frame).map(|(graph, _)| graph).map_err(|e| e.to_string())
}

/// The radii of the scene's spheres: where a test puts the numbers it computes.
fn radii(graph: &SceneGraph) -> Vec<f64> {
    let radius = |shape: &ShapeNode| match shape {
        ShapeNode::Sphere { radius, .. } => f64::from(*radius),
        other => panic!("not a sphere: {other:?}"),
    };
    graph.objects.iter().map(|o| radius(&o.shape)).collect()
}

fn number(value: &str, declarations: &str) -> f64 {
    let text = format!("{declarations}\nsphere {{ 0, {value} }}");
    let graph = parse_scene(Path::new("tests/inline.pov"), &text).unwrap_or_else(|e| panic!("{e}"));
    radii(&graph)[0]
}

fn error(text: &str) -> String {
    parse_scene(Path::new("tests/inline.pov"), text).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn what_write_writes_read_reads_back_as_the_manual_shows() {
    let dir = folder("fileio");
    // The manual's example: a string in quotes, a float and a vector, separated by commas.
    let graph = load_in(
        &dir,
        r#"
#declare Val1 = -123.45;
#declare Vect1 = <1, 2, -3>;
#fopen F "data.txt" write
#write (F, "\"A quote delimited string\",", Val1, ",", Vect1, "\n")
#fclose F
#fopen F "data.txt" read
#read (F, MyString, MyFloat, MyVect)
#fclose F
sphere { 0, strlen(MyString) }
sphere { 0, -MyFloat }
sphere { 0, MyVect.z + 4 }
"#,
        Frame::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let written = std::fs::read_to_string(dir.join("data.txt")).unwrap();
    assert_eq!(written, "\"A quote delimited string\",-123.45,<1,2,-3>\n");
    assert_eq!(radii(&graph), [24.0, 123.45, 1.0].map(|r: f64| f64::from(r as f32)));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn reading_past_the_end_closes_the_file_and_undefines_its_handle() {
    let dir = folder("fileio-end");
    std::fs::write(dir.join("list.txt"), "1, 2,\n3,").unwrap();
    // Append adds to what the file holds.
    let graph = load_in(
        &dir,
        r#"
#fopen G "list.txt" append
#write (G 4)
#fclose G
#declare Sum = 0;
#declare Count = 0;
#fopen F "list.txt" read
#while (defined(F))
  #read (F, V)
  #if (defined(F))
    #declare Sum = Sum + V;
    #declare Count = Count + 1;
  #end
#end
sphere { 0, Sum }
sphere { 0, Count }
"#,
        Frame::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(radii(&graph), [10.0, 4.0]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn binary_words_write_rounded_integers_in_their_byte_order() {
    let dir = folder("fileio-binary");
    load_in(
        &dir,
        r#"
#fopen F "out.bin" write
#write (F, uint8 254.6, sint16be <1, -1, 258>, uint16le 258)
#fclose F
sphere { 0, 1 }
"#,
        Frame::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let bytes = std::fs::read(dir.join("out.bin")).unwrap();
    assert_eq!(bytes, [255, 0, 1, 0xff, 0xff, 1, 2, 2, 1]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_scene_writes_only_in_its_own_folder() {
    let dir = folder("fileio-bounds");
    std::fs::create_dir(dir.join("sub")).unwrap();
    for name in ["../escape.txt", "sub/inner.txt", "/tmp/raydiance-absolute.txt", "sub"] {
        let text = format!("sphere {{ 0, 1 }}\n#fopen F \"{name}\" write\n");
        let e = load_in(&dir, &text, Frame::default()).unwrap_err();
        assert!(e.contains("scene.pov:2:10: error: cannot write"), "{name}: {e}");
    }
    assert!(!dir.parent().unwrap().join("escape.txt").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn file_misuse_is_refused_where_it_is_written() {
    let dir = folder("fileio-misuse");
    std::fs::write(dir.join("words.txt"), "\"a\", oops").unwrap();
    let cases = [
        ("#read (F, A)", "2:8: error: `F` is not an open file"),
        ("#fopen F \"missing.txt\" read", "2:10: error: cannot read"),
        ("#fopen F \"words.txt\" read\n#read (F, A, B)", "3:1: error:"),
        ("#fopen F \"w.txt\" write\n#read (F, A)", "3:8: error: `F` is open for writing"),
        ("#fopen F \"words.txt\" read\n#write (F, 1)", "3:9: error: `F` is open for reading"),
        (
            "#declare A = 1;\n#fopen F \"words.txt\" read\n#read (F, A)",
            "4:11: error: `#read` gives",
        ),
        (
            "#declare S = sphere { 0, 1 }\n#fopen F \"w.txt\" write\n#write (F, S)",
            "4:12: error: `#write` writes strings, numbers and vectors, not an object",
        ),
        ("#fclose F", "2:9: error: `F` is not an open file"),
    ];
    for (text, expected) in cases {
        let e =
            load_in(&dir, &format!("sphere {{ 0, 1 }}\n{text}\n"), Frame::default()).unwrap_err();
        assert!(e.contains(expected), "{text}: {e}");
    }
    let bad_data = load_in(
        &dir,
        "sphere { 0, 1 }\n#fopen F \"words.txt\" read\n#read (F, A, B)\n",
        Frame::default(),
    )
    .unwrap_err();
    assert!(bad_data.contains("words.txt` line 1: expected a string"), "{bad_data}");
    let scn = parse_scene(Path::new("tests/inline.scn"), "#fopen F \"x\" write\n").unwrap_err();
    assert!(scn.to_string().contains("`#fopen` is POV-Ray's"), "{scn}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn clock_on_and_clock_delta_tell_an_animation_from_a_still() {
    let dir = folder("clock");
    let text = "sphere { 0, 1 + clock_on }\nsphere { 0, 1 + clock_delta }\n";
    let still = load_in(&dir, text, Frame::default()).unwrap();
    assert_eq!(radii(&still), [1.0, 1.0]);
    let frames = Frames { first: 0, last: 4, clock: (0.0, 2.0) };
    let frame = load_in(&dir, text, frames.frame(3).unwrap()).unwrap();
    assert_eq!(radii(&frame), [2.0, 1.5]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn div_dimensions_and_gray_follow_the_manual() {
    // "Integer division. The integer part of (A/B)."
    assert_eq!(number("div(7, 2)", ""), 3.0);
    assert_eq!(number("-div(-7, 2)", ""), 3.0);
    assert_eq!(number("div(7.5, 2.5)", ""), 3.0);
    assert!(error("sphere { 0, div(1, 0) }").contains("1:13: error: `div` by zero"));
    assert_eq!(number("dimensions(A)", "#declare A = array[6][10];"), 2.0);
    assert_eq!(number("dimensions(A)", "#declare A = array[3] { 1, 2, 3 };"), 1.0);
    let not_array = error("sphere { 0, dimensions(1) }");
    assert!(
        not_array.contains("1:24: error: `dimensions` takes an array, not a number"),
        "{not_array}"
    );
    // POV-Ray 3.7's weights: 0.297, 0.589, 0.114.
    let gray = number("C.gray", "#declare C = rgb <1, 0.5, 0.25>;");
    assert!((gray - (0.297 + 0.589 * 0.5 + 0.114 * 0.25)).abs() < 1e-6, "{gray}");
    assert!((number("C.gray", "#declare C = rgb 1;") - 1.0).abs() < 1e-6);
    let string = error("#declare S = \"a\";\nsphere { 0, S.gray }");
    assert!(string.contains("2:14: error: a string has no `.gray`"), "{string}");
}
