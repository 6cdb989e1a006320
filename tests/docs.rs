//! The documentation cannot drift from the renderer or point outside the repository: every `scn`
//! example in `docs/language.md` and `docs/coming-from-povray.md` parses, builds and renders;
//! every option of the command line is on `docs/cli.md`; every Markdown link resolves inside the
//! repository; and the README's first screen holds the two commands a clone starts with.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};
use std::process::Command;

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

/// The repository's Markdown files (outside build output and hidden folders).
fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy();
            if path.is_dir() {
                if !name.starts_with('.') && name != "target" {
                    walk(&path, found);
                }
            } else if name.ends_with(".md") {
                found.push(path);
            }
        }
    }
    let mut found = Vec::new();
    walk(Path::new("."), &mut found);
    found.sort();
    found
}

/// `path` with `.` and `..` resolved by their text alone; `None` when it climbs above its start.
fn normalised(path: &Path) -> Option<PathBuf> {
    let mut parts: Vec<Component> = Vec::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                parts.pop().filter(|p| matches!(p, Component::Normal(_)))?;
            }
            Component::Normal(_) => parts.push(part),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(parts.iter().collect())
}

/// GitHub's anchor for a heading: lower case, punctuation dropped, spaces as hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(page: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(page).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix('#'))
        .map(|h| anchor(h.trim_start_matches('#')))
        .collect()
}

/// The targets of `[text](target)` links and `![](target)` images in `text`.
fn link_targets(text: &str) -> Vec<String> {
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            rest.find(')').map(|end| rest[..end].to_string())
        })
        .collect()
}

#[test]
fn every_markdown_link_resolves_inside_the_repository() {
    let pages = markdown_files();
    assert!(pages.len() >= 10, "found {} Markdown files", pages.len());
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        let folder = page.parent().unwrap();
        for target in link_targets(&text) {
            if target.starts_with("https://") || target.starts_with("http://") {
                continue;
            }
            let (file, fragment) = target.split_once('#').unwrap_or((&target, ""));
            let linked = if file.is_empty() { page.clone() } else { folder.join(file) };
            let inside = normalised(&linked).unwrap_or_else(|| {
                panic!("{}: `{target}` is outside the repository", page.display())
            });
            assert!(inside.exists(), "{}: `{target}` does not exist", page.display());
            if !fragment.is_empty() {
                assert!(
                    anchors(&inside).iter().any(|a| a == fragment),
                    "{}: `{target}`: no heading of {} has the anchor #{fragment}",
                    page.display(),
                    inside.display()
                );
            }
        }
    }
}

#[test]
fn no_markdown_file_or_source_comment_refers_to_a_path_outside_the_repository() {
    // Paths that exist only beside a working copy of the repository, never in a clone.
    let outside = [concat!("shared", "/"), concat!("../", "shared")];
    let mut files = markdown_files();
    for folder in ["src", "grammar", "examples", "tests", "fuzz/fuzz_targets", "scenes"] {
        collect_sources(Path::new(folder), &mut files);
    }
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for needle in outside {
            assert!(!text.contains(needle), "{} names `{needle}...`", file.display());
        }
    }
    // Every `../` path in a page (a link, a code span, an `#include` in an example) stays inside.
    let path_char = |c: char| c.is_alphanumeric() || "_./-".contains(c);
    for page in markdown_files() {
        let text = std::fs::read_to_string(&page).unwrap();
        for (at, _) in text.match_indices("../") {
            let start = text[..at].rfind(|c| !path_char(c)).map_or(0, |i| i + 1);
            let end = text[at..].find(|c| !path_char(c)).map_or(text.len(), |i| at + i);
            let path = &text[start..end];
            let resolved = normalised(&page.parent().unwrap().join(path));
            assert!(
                resolved.is_some_and(|p| p.exists()),
                "{}: `{path}` is not a path inside the repository",
                page.display()
            );
        }
    }
}

fn collect_sources(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect_sources(&path, found);
        } else if path
            .extension()
            .is_some_and(|e| ["rs", "pest", "scn", "inc"].contains(&e.to_str().unwrap()))
        {
            found.push(path);
        }
    }
}

#[test]
fn the_readme_opens_with_the_two_commands() {
    let readme = std::fs::read_to_string("README.md").unwrap();
    let first_screen: Vec<&str> = readme.lines().take(40).collect();
    let fences: Vec<usize> =
        (0..first_screen.len()).filter(|&i| first_screen[i].starts_with("```")).collect();
    assert_eq!(fences.len(), 2, "one code block on the README's first screen: {fences:?}");
    let block: Vec<&str> = first_screen[fences[0] + 1..fences[1]].to_vec();
    assert_eq!(
        block,
        ["cargo run --release -- render scenes/lab4-direct.scn -o lab4.png", "cargo test"]
    );
}

/// The options of each command as `raydiance COMMAND --help` lists them (an option with a short
/// form by its short form, as the synopsis writes it).
fn options_in_help(command: &str) -> BTreeSet<String> {
    let output =
        Command::new(env!("CARGO_BIN_EXE_raydiance")).args([command, "--help"]).output().unwrap();
    assert!(output.status.success());
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .filter(|l| l.trim_start().starts_with('-'))
        .filter_map(|l| options(l).into_iter().next())
        .filter(|o| !["-h", "--help", "-V", "--version"].contains(&o.as_str()))
        .collect()
}

/// The options written in `text`: `--long` ones, and `-x` short ones.
fn options(text: &str) -> Vec<String> {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '-';
    text.match_indices('-')
        .filter(|(at, _)| !text[..*at].ends_with(word))
        .filter_map(|(at, _)| {
            let rest = &text[at..];
            let end = rest.find(|c: char| !word(c)).unwrap_or(rest.len());
            let option = &rest[..end];
            let long = option.len() > 2 && option.starts_with("--");
            let short = option.len() == 2 && option.as_bytes()[1].is_ascii_alphabetic();
            (long || short).then(|| option.to_string())
        })
        .collect()
}

#[test]
fn the_command_line_page_lists_every_option_of_every_command() {
    let page = std::fs::read_to_string("docs/cli.md").unwrap();
    let synopsis = page.split("```").nth(1).expect("docs/cli.md opens with the synopsis");
    let mut documented: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut command = String::new();
    for line in synopsis.lines().filter(|l| !l.trim().is_empty()) {
        if let Some(rest) = line.strip_prefix("raydiance ") {
            command = rest.split_whitespace().next().unwrap().to_string();
        }
        documented.entry(command.clone()).or_default().extend(options(line));
    }
    let commands: Vec<&str> = documented.keys().map(String::as_str).collect();
    assert_eq!(
        commands,
        ["bench", "check", "denoise", "merge", "preview", "render", "snapshot", "tonemap"]
    );
    for (command, listed) in &documented {
        assert_eq!(listed, &options_in_help(command), "`raydiance {command}` in docs/cli.md");
    }
}

/// Every bound the limits page cites by its path in the code (`module::NAME`, a constant, or
/// `module::function` where the check is written) is declared there: the page names the code's
/// own bounds.
#[test]
fn the_limits_page_cites_bounds_the_code_declares() {
    let page = std::fs::read_to_string("docs/limits.md").unwrap();
    let (mut cited, mut undeclared) = (0, Vec::new());
    for path in page.split('`').skip(1).step_by(2).filter(|s| s.contains("::")) {
        let (module, item) = path.rsplit_once("::").unwrap();
        let folder = Path::new("src").join(module.replace("::", "/"));
        let files = [folder.with_extension("rs"), folder.join("mod.rs")];
        let module_file = folder.join(format!("{item}.rs"));
        let declared = |text: &str| {
            let is_const = item.chars().all(|c| c.is_ascii_uppercase() || c == '_');
            let declaration =
                if is_const { format!("const {item}: ") } else { format!("fn {item}(") };
            text.contains(&declaration)
        };
        let found = module_file.exists()
            || folder.join(item).is_dir()
            || files.iter().any(|f| std::fs::read_to_string(f).is_ok_and(|text| declared(&text)));
        if !found {
            undeclared.push(path);
        }
        cited += 1;
    }
    assert!(
        undeclared.is_empty(),
        "docs/limits.md cites what src/ does not declare: {undeclared:?}"
    );
    assert!(cited > 30, "{cited} bounds cited");
}
