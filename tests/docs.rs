//! Every `scn` example in `docs/language.md` and `docs/coming-from-povray.md` parses, builds and
//! renders, so the pages cannot drift from the renderer.

use std::path::Path;

fn examples(page: &str) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(page).unwrap();
    let mut examples = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (number, line) in text.lines().enumerate() {
        match (&mut current, line.trim_end()) {
            (None, "```scn") => current = Some((number + 2, String::new())),
            (Some(_), "```") => examples.push(current.take().unwrap()),
            (Some((_, body)), _) => {
                body.push_str(line);
                body.push('\n');
            }
            _ => {}
        }
    }
    examples
}

#[test]
fn every_example_in_the_language_reference_renders() {
    let examples = examples("docs/language.md");
    assert!(examples.len() >= 15, "found {} examples", examples.len());
    renders("docs/language.md", examples);
}

#[test]
fn every_example_in_coming_from_povray_renders() {
    let examples = examples("docs/coming-from-povray.md");
    assert!(examples.len() >= 2, "found {} examples", examples.len());
    renders("docs/coming-from-povray.md", examples);
}

/// Renders each example of `page` at 8×8 pixels, as if it were written in `docs/`.
fn renders(page: &str, examples: Vec<(usize, String)>) {
    for (line, body) in examples {
        let text = if body.contains("camera") || body.contains("#include") {
            body.clone()
        } else {
            format!("camera {{ location <0, 1, -5>  look_at <0, 0, 0> }}\n{body}")
        };
        // As if it were written in docs/, so relative paths resolve from there.
        let mut graph = raydiance::lang::parse_scene(Path::new(page), &text)
            .unwrap_or_else(|e| panic!("the example at {page}:{line} does not parse:\n{e}"));
        graph.settings.width = 8;
        graph.settings.height = 8;
        graph.settings.samples = 1;
        let scene = raydiance::scene::build(&graph)
            .unwrap_or_else(|e| panic!("the example at {page}:{line} does not build:\n{e}"));
        let image = raydiance::render::render(&scene, &raydiance::progress::Silent).0.image();
        assert!(image.pixels.iter().all(|p| p.is_finite()), "{page}:{line}");
    }
}
