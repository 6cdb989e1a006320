//! The pest parser, and pest's errors turned into located `SceneError`s that say what was
//! expected (and, for a misspelt keyword, what was probably meant).

use std::sync::Arc;

use pest::Parser;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pairs;

use crate::diagnostic::{SceneError, SourceFile, Span};

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/scn.pest"]
pub struct ScnParser;

/// Deepest nesting of brackets accepted: beyond it the parser's recursion could overflow a
/// thread's stack, so deeper text is an error instead.
pub const MAX_NESTING: usize = 64;

/// Parses a whole file into its statements.
pub fn parse(file: &Arc<SourceFile>) -> Result<Pairs<'_, Rule>, SceneError> {
    check_nesting(file)?;
    match ScnParser::parse(Rule::scene, &file.text) {
        Ok(mut pairs) => Ok(pairs.next().expect("`scene` matched: one pair").into_inner()),
        Err(error) => Err(convert(file, error)),
    }
}

pub fn span_at(file: &Arc<SourceFile>, offset: usize) -> Span {
    let before = &file.text[..offset.min(file.text.len())];
    let line = before.matches('\n').count() as u32 + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = before[line_start..].chars().count() as u32 + 1;
    Span { file: file.clone(), line, col }
}

/// Finds brackets nested deeper than `MAX_NESTING` (and runs of signs longer than it), and
/// unterminated comments and strings, before pest sees the text.
fn check_nesting(file: &Arc<SourceFile>) -> Result<(), SceneError> {
    let text = file.text.as_bytes();
    let mut depth = 0usize;
    // Unary signs nest too (`- - - 1`): a run of them is limited like brackets.
    let mut signs = 0usize;
    let mut i = 0;
    while i < text.len() {
        match text[i] {
            b'+' | b'-' => {
                signs += 1;
                if signs > MAX_NESTING {
                    return Err(SceneError::at(
                        &span_at(file, i),
                        format!("more than {MAX_NESTING} signs in a row"),
                    ));
                }
            }
            b' ' | b'\t' | b'\r' | b'\n' => {}
            _ => signs = 0,
        }
        match text[i] {
            b'/' if text.get(i + 1) == Some(&b'/') => {
                while i < text.len() && text[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if text.get(i + 1) == Some(&b'*') => {
                let end = file.text[i + 2..].find("*/").ok_or_else(|| {
                    SceneError::at(&span_at(file, i), "unterminated block comment (no `*/`)")
                })?;
                i += end + 3;
            }
            b'"' => {
                let end = file.text[i + 1..].find(['"', '\n']);
                match end.map(|e| text[i + 1 + e]) {
                    Some(b'"') => i += end.unwrap_or(0) + 1,
                    _ => return Err(SceneError::at(&span_at(file, i), "unterminated string")),
                }
            }
            b'(' | b'<' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(SceneError::at(
                        &span_at(file, i),
                        format!("nesting deeper than {MAX_NESTING} brackets"),
                    ));
                }
            }
            b')' | b'>' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        i += 1;
    }
    Ok(())
}

fn convert(file: &Arc<SourceFile>, error: pest::error::Error<Rule>) -> SceneError {
    let offset = match error.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((start, _)) => start,
    };
    // A misspelt keyword is often only noticed at the token after it (it reads as a name):
    // point at the word itself when it is close to a keyword.
    let before = file.text[..offset].trim_end();
    let word_start = before
        .char_indices()
        .rev()
        .find(|&(_, c)| !(c.is_alphanumeric() || c == '_'))
        .map_or(0, |(i, c)| i + c.len_utf8());
    let previous = &before[word_start..];
    if previous.starts_with(|c: char| c.is_alphabetic() || c == '_')
        && !KEYWORDS.contains(&previous)
    {
        if let Some(guess) = closest(previous, KEYWORDS.iter().copied()) {
            let message = format!("unexpected `{previous}`; did you mean `{guess}`?");
            return SceneError::at(&span_at(file, word_start), message);
        }
    }
    let span = span_at(file, offset);
    let found = token_at(&file.text[offset..]);
    let expected: Vec<&'static str> = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            let mut names: Vec<&str> = positives.iter().map(|r| describe(*r)).collect();
            names.sort_unstable();
            names.dedup();
            names
        }
        ErrorVariant::CustomError { .. } => Vec::new(),
    };
    let found_text =
        if found.is_empty() { "the end of the file".to_string() } else { format!("`{found}`") };
    let mut message = match expected.as_slice() {
        [] => format!("unexpected {found_text}"),
        [one] => format!("expected {one}, found {found_text}"),
        [init @ .., last] => format!("expected {} or {last}, found {found_text}", init.join(", ")),
    };
    if let Some(guess) = closest(found, KEYWORDS.iter().copied()) {
        message.push_str(&format!("; did you mean `{guess}`?"));
    } else if expected.contains(&"an operator")
        && found.starts_with(|c: char| c.is_alphanumeric() || "<(-.".contains(c))
    {
        message.push_str(" (is a `,` missing?)");
    }
    SceneError::at(&span, message)
}

/// The language's keywords (the grammar's `keyword` rule; a test keeps the two the same).
const KEYWORDS: [&str; 70] = [
    "settings",
    "resolution",
    "samples",
    "integrator",
    "max_depth",
    "seed",
    "background",
    "camera",
    "origin",
    "left",
    "up",
    "forward",
    "location",
    "look_at",
    "angle",
    "aperture",
    "focal_distance",
    "light_source",
    "power",
    "colour",
    "color",
    "plane",
    "sphere",
    "box",
    "triangle",
    "quad",
    "disk",
    "cylinder",
    "mesh",
    "union",
    "object",
    "material",
    "translate",
    "rotate",
    "scale",
    "matrix",
    "diffuse",
    "specular",
    "transmission",
    "emission",
    "ior",
    "fresnel",
    "rgb",
    "pi",
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "sqrt",
    "pow",
    "abs",
    "min",
    "max",
    "radians",
    "degrees",
    "checker",
    "stripes",
    "gradient",
    "noise",
    "marble",
    "wood",
    "image_map",
    "mix",
    "axis",
    "octaves",
    "turbulence",
    "color_map",
    "colour_map",
];

/// The word or symbol at the start of `text`.
fn token_at(text: &str) -> &str {
    let word =
        text.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.')).unwrap_or(text.len());
    if word > 0 { &text[..word] } else { text.chars().next().map_or("", |c| &text[..c.len_utf8()]) }
}

/// The candidate within edit distance 2 (and less than half the word) of `word`, if any.
pub fn closest<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    if word.is_empty() || !word.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return None;
    }
    candidates
        .map(|c| (edit_distance(word, c), c))
        .filter(|&(d, c)| d > 0 && d <= 2 && 2 * d < word.len().max(c.len()))
        .min()
        .map(|(_, c)| c)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            current[j + 1] =
                (previous[j] + usize::from(ca != cb)).min(previous[j + 1] + 1).min(current[j] + 1);
        }
        previous = current;
    }
    previous[b.len()]
}

/// How a rule reads in "expected ..." messages.
fn describe(rule: Rule) -> &'static str {
    match rule {
        Rule::EOI => "the end of the file",
        Rule::declare => "`#declare`",
        Rule::include => "`#include`",
        Rule::settings | Rule::kw_settings => "`settings`",
        Rule::resolution | Rule::kw_resolution => "`resolution`",
        Rule::samples | Rule::kw_samples => "`samples`",
        Rule::integrator | Rule::kw_integrator => "`integrator`",
        Rule::max_depth | Rule::kw_max_depth => "`max_depth`",
        Rule::seed | Rule::kw_seed => "`seed`",
        Rule::background | Rule::kw_background => "`background`",
        Rule::camera | Rule::kw_camera => "`camera`",
        Rule::camera_item | Rule::camera_key => {
            "a camera parameter (`origin`, `left`, `up`, `forward`, `location`, `look_at`, `angle`, `aperture`, `focal_distance`)"
        }
        Rule::kw_origin => "`origin`",
        Rule::kw_left => "`left`",
        Rule::kw_up => "`up`",
        Rule::kw_forward => "`forward`",
        Rule::kw_location => "`location`",
        Rule::kw_look_at => "`look_at`",
        Rule::kw_angle => "`angle`",
        Rule::kw_aperture => "`aperture`",
        Rule::kw_focal_distance => "`focal_distance`",
        Rule::light_source | Rule::kw_light_source => "`light_source`",
        Rule::kw_power => "`power`",
        Rule::kw_color => "`color`",
        Rule::kw_colour => "`colour`",
        Rule::plane | Rule::kw_plane => "`plane`",
        Rule::sphere | Rule::kw_sphere => "`sphere`",
        Rule::box_shape | Rule::kw_box => "`box`",
        Rule::triangle | Rule::kw_triangle => "`triangle`",
        Rule::quad | Rule::kw_quad => "`quad`",
        Rule::disk | Rule::kw_disk => "`disk`",
        Rule::cylinder | Rule::kw_cylinder => "`cylinder`",
        Rule::mesh | Rule::kw_mesh => "`mesh`",
        Rule::union | Rule::kw_union => "`union`",
        Rule::instance | Rule::kw_object => "`object`",
        Rule::material | Rule::kw_material => "`material`",
        Rule::material_name | Rule::base_material => "a material's name",
        Rule::transform | Rule::transform_key => {
            "a transform (`translate`, `rotate`, `scale`, `matrix`)"
        }
        Rule::kw_translate => "`translate`",
        Rule::kw_rotate => "`rotate`",
        Rule::kw_scale => "`scale`",
        Rule::kw_matrix => "`matrix`",
        Rule::material_item | Rule::colour_key => {
            "a material parameter (`diffuse`, `specular`, `transmission`, `emission`, `ior`, `fresnel`)"
        }
        Rule::kw_diffuse => "`diffuse`",
        Rule::kw_specular => "`specular`",
        Rule::kw_transmission => "`transmission`",
        Rule::kw_emission => "`emission`",
        Rule::kw_ior => "`ior`",
        Rule::kw_fresnel => "`fresnel`",
        Rule::colour | Rule::rgb_colour | Rule::kw_rgb => "a colour (`rgb <r, g, b>`)",
        Rule::expr
        | Rule::number
        | Rule::vector
        | Rule::call
        | Rule::function
        | Rule::kw_pi
        | Rule::negate
        | Rule::plus => "a number or vector",
        Rule::add | Rule::subtract | Rule::multiply | Rule::divide => "an operator",
        Rule::component => "a component (`.x`, `.y`, `.z`)",
        Rule::string | Rule::string_text => "a file name in quotes",
        Rule::ident | Rule::name => "a name",
        _ => "something else",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyword_list_matches_the_grammar() {
        for word in KEYWORDS {
            let parsed = ScnParser::parse(Rule::keyword, word).map(|p| p.as_str().len());
            assert_eq!(parsed, Ok(word.len()), "`{word}` is a keyword of the grammar");
        }
        let grammar = include_str!("../../grammar/scn.pest");
        let rule = &grammar[grammar.find("keyword = @{").unwrap()..];
        let rule = &rule[..rule.find('}').unwrap()];
        assert_eq!(rule.matches('"').count(), 2 * KEYWORDS.len(), "the grammar has no others");
    }

    #[test]
    fn errors_after_multibyte_characters_do_not_panic() {
        // Found by fuzzing: a byte-order mark in the middle of a scene, before a parse error.
        let text = "camera { origin <0, \u{feff}era { origin <0, 0, -3.5>  left <-1,specularup";
        let file = Arc::new(SourceFile { path: "x.scn".into(), text: text.into() });
        let error = parse(&file).map(|_| ()).unwrap_err();
        assert!(error.to_string().starts_with("x.scn:1:"), "{error}");
    }

    #[test]
    fn closest_suggests_near_misses_only() {
        assert_eq!(closest("tranlate", KEYWORDS.iter().copied()), Some("translate"));
        assert_eq!(closest("sphre", KEYWORDS.iter().copied()), Some("sphere"));
        assert_eq!(closest("banana", KEYWORDS.iter().copied()), None);
    }
}
