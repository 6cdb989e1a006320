//! Property: any mutation of a valid scene gives an error or an image, never a panic.

use proptest::prelude::*;

/// Pieces that stress the parser and evaluator when spliced into a scene.
const FRAGMENTS: [&str; 24] = [
    "{",
    "}",
    "<",
    ">",
    ",",
    "(",
    ")",
    "-",
    "/ 0",
    "* 1e38",
    "1e39",
    "nan",
    "0",
    "-1",
    "#declare X = ",
    "sphere { 0, 1 }",
    "scale 0",
    "matrix <1,2,3>",
    "\"",
    "/*",
    "//",
    "rgb",
    "material { W }",
    "#include \"lab-box.inc\"",
];

#[derive(Debug, Clone)]
enum Mutation {
    Delete { at: usize, len: usize },
    Insert { at: usize, fragment: usize },
    Replace { at: usize, len: usize, fragment: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1..20usize).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), 0..FRAGMENTS.len())
            .prop_map(|(at, fragment)| Mutation::Insert { at, fragment }),
        (any::<usize>(), 1..8usize, 0..FRAGMENTS.len())
            .prop_map(|(at, len, fragment)| Mutation::Replace { at, len, fragment }),
    ]
}

fn apply(text: &str, mutations: &[Mutation]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for m in mutations {
        let n = chars.len().max(1);
        match *m {
            Mutation::Delete { at, len } => {
                let at = at % n;
                chars.drain(at..(at + len).min(chars.len()));
            }
            Mutation::Insert { at, fragment } => {
                let at = at % (chars.len() + 1);
                chars.splice(at..at, FRAGMENTS[fragment].chars());
            }
            Mutation::Replace { at, len, fragment } => {
                let at = at % n;
                chars.splice(at..(at + len).min(chars.len()), FRAGMENTS[fragment].chars());
            }
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_give_an_error_or_an_image(mutations in proptest::collection::vec(mutation(), 1..4)) {
        let original = std::fs::read_to_string("scenes/cornell-specular.scn").unwrap();
        let text = apply(&original, &mutations);
        // As if it were the scene file itself, so its #include resolves.
        let path = std::path::Path::new("scenes/mutated.scn");
        if let Ok(mut graph) = raydiance::lang::parse_scene(path, &text) {
            graph.settings.width = 4;
            graph.settings.height = 4;
            graph.settings.samples = 1;
            if let Ok(scene) = raydiance::scene::build(&graph) {
                let (film, _) = raydiance::render::render(&scene, &raydiance::progress::Silent);
                prop_assert!(film.image().pixels.iter().all(|p| p.is_finite()));
            }
        }
    }
}

/// Pieces of directives, for mutating a scene with macros, loops and arrays (no unbounded
/// `#while`: a scene that loops to the limit is an error, but a slow one).
const DIRECTIVE_FRAGMENTS: [&str; 22] = [
    "#if (1)",
    "#if (0)",
    "#else",
    "#elseif (1)",
    "#end",
    "#for (I, 0, 3)",
    "#macro M(A)",
    "M(1)",
    "Ball(<0, 0, 0>, 1)",
    "Tree(3)",
    "#local Q = 1;",
    "#declare R = ",
    "#undef White",
    "array[2] { 1, 2 }",
    "[1]",
    " ? 1 : 0",
    " & ",
    "(",
    ")",
    ",",
    "\"",
    "#debug \"\"",
];

fn directive_mutation() -> impl Strategy<Value = (usize, usize, usize)> {
    (any::<usize>(), 0..8usize, 0..DIRECTIVE_FRAGMENTS.len())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn mutated_directives_give_an_error_or_a_scene(
        mutations in proptest::collection::vec(directive_mutation(), 1..4)
    ) {
        let mut text: Vec<char> =
            std::fs::read_to_string("tests/scenes/macros.scn").unwrap().chars().collect();
        for (at, len, fragment) in mutations {
            let at = at % (text.len() + 1);
            let end = (at + len).min(text.len());
            text.splice(at..end, DIRECTIVE_FRAGMENTS[fragment].chars());
        }
        let text: String = text.into_iter().collect();
        let path = std::path::Path::new("tests/scenes/mutated.scn");
        // Never a panic or a hang; an error is located and shows its line.
        match raydiance::lang::parse_scene(path, &text) {
            Ok(_) => {}
            Err(e) => prop_assert!(e.span.is_some() && e.to_string().contains(" | "), "{e}"),
        }
    }
}
