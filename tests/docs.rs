//! Every `scn` example in `docs/language.md` parses, builds and renders, so the reference cannot
//! drift from the renderer.

use std::path::Path;

fn examples() -> Vec<(usize, String)> {
    let text = std::fs::read_to_string("docs/language.md").unwrap();
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
    let examples = examples();
    assert!(examples.len() >= 15, "found {} examples", examples.len());
    for (line, body) in examples {
        let text = if body.contains("camera") || body.contains("#include") {
            body.clone()
        } else {
            format!("camera {{ location <0, 1, -5>  look_at <0, 0, 0> }}\n{body}")
        };
        // As if it were written in docs/, so relative paths resolve from there.
        let mut graph = raydiance::lang::parse_scene(Path::new("docs/language.md"), &text)
            .unwrap_or_else(|e| {
                panic!("the example at docs/language.md:{line} does not parse:\n{e}")
            });
        graph.settings.width = 8;
        graph.settings.height = 8;
        graph.settings.samples = 1;
        let scene = raydiance::scene::build(&graph).unwrap_or_else(|e| {
            panic!("the example at docs/language.md:{line} does not build:\n{e}")
        });
        let image = raydiance::render::render(&scene, &raydiance::render::Silent).0.image();
        assert!(image.pixels.iter().all(|p| p.is_finite()), "docs/language.md:{line}");
    }
}
