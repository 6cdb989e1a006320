//! The pest parser, and pest's errors turned into located `SceneError`s that say what was
//! expected (and, for a misspelt keyword, what was probably meant).

use std::sync::Arc;

use pest::Parser;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pairs;

use super::dialect::Dialect;
use super::{hints, keywords, povray};
use crate::diagnostic::{SceneError, SourceFile, Span};

pub use scn_grammar::{Rule, ScnParser};

/// Deepest nesting of brackets and blocks accepted (counted by `lang::tree` on the pairs): the
/// tree is walked recursively, so deeper text is an error instead. The parser itself stops on a
/// nearly exhausted stack (pest's stack guard), which is reported as the same error.
pub const MAX_NESTING: usize = 64;

/// Parses a whole file, read in `dialect`, into its statements.
pub fn parse(file: &Arc<SourceFile>, dialect: Dialect) -> Result<Pairs<'_, Rule>, SceneError> {
    check_comments_and_strings(file)?;
    match ScnParser::parse(Rule::scene, &file.text) {
        Ok(mut pairs) => Ok(pairs.next().expect("`scene` matched: one pair").into_inner()),
        Err(error) => Err(convert(file, error, dialect)),
    }
}

pub fn span_at(file: &Arc<SourceFile>, offset: usize) -> Span {
    let (line, col) = file.position(offset);
    Span { file: file.clone(), line, col, context: None }
}

/// Finds unterminated comments and strings before pest sees the text, so that they are reported
/// where they start rather than at the end of the file.
fn check_comments_and_strings(file: &Arc<SourceFile>) -> Result<(), SceneError> {
    let text = file.text.as_bytes();
    let mut i = 0;
    while i < text.len() {
        match hints::skip_comment_or_string(text, i) {
            Some(Ok(end)) => i = end,
            Some(Err(())) => {
                let what = if text[i] == b'"' {
                    "unterminated string"
                } else {
                    "unterminated block comment (no `*/`)"
                };
                return Err(SceneError::at(&span_at(file, i), what));
            }
            None => i += 1,
        }
    }
    Ok(())
}

fn convert(
    file: &Arc<SourceFile>,
    error: pest::error::Error<Rule>,
    dialect: Dialect,
) -> SceneError {
    let offset = match error.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((start, _)) => start,
    };
    if let ErrorVariant::CustomError { message } = &error.variant {
        // pest's guards: the only custom errors it raises.
        let message = match message.as_str() {
            "stack limit reached" => format!("nesting deeper than {MAX_NESTING} brackets"),
            other => other.to_string(),
        };
        return SceneError::at(&span_at(file, offset), message);
    }
    if let Some(error) = malformed_directive(file, offset) {
        return error;
    }
    let found = token_at(&file.text[offset..]);
    // A misspelt keyword or a POV-Ray word is often only noticed at the token after it (it
    // reads as a name): look at the word before too.
    let (word_start, previous) = hints::word_before(&file.text, offset);
    let blocks = hints::open_blocks(&file.text, offset);
    let inside = blocks.last().map(|b| b.word);
    // The word before is a POV-Ray word, not a user's name, when a block follows it or when it
    // is reserved (`color`).
    let previous_is_word = found == "{" || keywords::lookup(previous).is_some();
    let words = [(offset, found), (word_start, if previous_is_word { previous } else { "" })];
    for (at, word) in words {
        if let Some(message) = povray::message_in(dialect, word, inside) {
            return SceneError::at(&span_at(file, at), message);
        }
    }
    if previous.starts_with(|c: char| c.is_alphabetic() || c == '_')
        && keywords::lookup(previous).is_none()
        && let Some(guess) = closest(previous, keywords::words())
    {
        let message = format!("unexpected `{previous}`; did you mean `{guess}`?");
        return SceneError::at(&span_at(file, word_start), message);
    }
    if let Some(error) = unclosed_block(file, offset, found, previous, &blocks) {
        return error;
    }
    let span = span_at(file, offset);
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
    let misspelt = keywords::lookup(found).is_none().then(|| closest(found, keywords::words()));
    if let Some(guess) = misspelt.flatten() {
        message.push_str(&format!("; did you mean `{guess}`?"));
    } else if expected.contains(&"an operator") && found == "}" {
        // A complete value, then the end of the block: a construct short of its arguments.
        match inside.and_then(hints::form) {
            Some(form) => {
                message = format!("an argument is missing before `}}`: it is written `{form}`")
            }
            None => message.push_str(" (is an argument missing?)"),
        }
    } else if expected.contains(&"an operator")
        && found.starts_with(|c: char| c.is_alphanumeric() || "<(-.".contains(c))
    {
        message.push_str(" (is a `,` missing?)");
    }
    SceneError::at(&span, message)
}

/// The words that begin a statement of their own, which cannot stand inside another's block.
const STATEMENTS: [&str; 3] = ["camera", "light_source", "settings"];

/// The words that begin an object, and those of the blocks objects may stand in.
const OBJECTS: [&str; 34] = [
    "bicubic_patch",
    "blob",
    "box",
    "cone",
    "cubic",
    "cylinder",
    "difference",
    "disk",
    "height_field",
    "intersection",
    "julia_fractal",
    "lathe",
    "lemon",
    "merge",
    "mesh",
    "mesh2",
    "object",
    "ovus",
    "parametric",
    "plane",
    "poly",
    "polygon",
    "prism",
    "quad",
    "quadric",
    "quartic",
    "smooth_triangle",
    "sor",
    "sphere",
    "sphere_sweep",
    "superellipsoid",
    "torus",
    "triangle",
    "union",
];
const OBJECT_CONTAINERS: [&str; 4] = ["union", "difference", "intersection", "merge"];

/// A parse error that is a `{` left open: the file ends inside a block, or a statement (or an
/// object, outside a union or CSG) stands inside another's block. Reported with where the block
/// opened.
fn unclosed_block(
    file: &Arc<SourceFile>,
    offset: usize,
    found: &str,
    previous: &str,
    blocks: &[hints::OpenBlock],
) -> Option<SceneError> {
    let block = blocks.last()?;
    let (line, col) = file.position(block.offset);
    let opened = match block.word {
        "" => format!("the `{{` at line {line}, column {col}"),
        word => format!("the `{{` of `{word}` at line {line}, column {col}"),
    };
    if found.is_empty() {
        let message = format!("the file ends inside a block: {opened} is not closed");
        return Some(SceneError::at(&span_at(file, offset), message));
    }
    let misplaced = |w: &&str| {
        STATEMENTS.contains(w) || (OBJECTS.contains(w) && !OBJECT_CONTAINERS.contains(&block.word))
    };
    let statement = [found, previous].into_iter().find(misplaced)?;
    let message =
        format!("`{statement}` cannot stand in a block: is the `}}` of {opened} missing?");
    let at = if statement == found { offset } else { hints::word_before(&file.text, offset).0 };
    Some(SceneError::at(&span_at(file, at), message))
}

/// The directives, each with its parse rule and the form it takes, for messages.
const DIRECTIVES: [(&str, Rule, &str); 24] = [
    ("#declare", Rule::declare, "#declare Name = value"),
    ("#local", Rule::local, "#local Name = value"),
    ("#undef", Rule::undef, "#undef Name"),
    ("#include", Rule::include, "#include \"file\""),
    ("#if", Rule::if_start, "#if (condition)"),
    ("#ifdef", Rule::ifdef_start, "#ifdef (Name)"),
    ("#ifndef", Rule::ifndef_start, "#ifndef (Name)"),
    ("#elseif", Rule::elseif, "#elseif (condition)"),
    ("#else", Rule::else_, "#else"),
    ("#while", Rule::while_start, "#while (condition)"),
    ("#for", Rule::for_start, "#for (Name, start, end) or #for (Name, start, end, step)"),
    ("#macro", Rule::macro_start, "#macro Name(Parameter, ...)"),
    ("#end", Rule::end, "#end"),
    ("#switch", Rule::switch_start, "#switch (value)"),
    ("#case", Rule::case, "#case (value)"),
    ("#range", Rule::range, "#range (low, high)"),
    ("#break", Rule::break_, "#break"),
    ("#debug", Rule::message, "#debug \"text\""),
    ("#warning", Rule::message, "#warning \"text\""),
    ("#error", Rule::message, "#error \"text\""),
    ("#fopen", Rule::fopen, "#fopen Handle \"file\" read (or write, append)"),
    ("#read", Rule::fread, "#read (Handle, Name, ...)"),
    ("#write", Rule::fwrite, "#write (Handle, value, ...)"),
    ("#fclose", Rule::fclose, "#fclose Handle"),
];

/// A parse error at a `#`: an unknown directive (with a suggestion), or a known one whose own
/// form is broken. `None` when the directive is well formed (it stands where it may not).
fn malformed_directive(file: &Arc<SourceFile>, offset: usize) -> Option<SceneError> {
    let rest = file.text.get(offset..)?.strip_prefix('#')?;
    let length = rest.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(rest.len());
    let word = format!("#{}", &rest[..length]);
    let span = span_at(file, offset);
    match DIRECTIVES.iter().find(|d| d.0 == word) {
        Some((name, rule, form)) => {
            let well_formed = ScnParser::parse(*rule, &file.text[offset..]).is_ok();
            (!well_formed).then(|| {
                SceneError::at(&span, format!("malformed `{name}`: it is written `{form}`"))
            })
        }
        None => {
            if let Some(message) = povray::message(&word, None) {
                return Some(SceneError::at(&span, message));
            }
            let mut message = format!("unknown directive `{word}`");
            let names = DIRECTIVES.iter().map(|d| d.0.trim_start_matches('#'));
            if let Some(guess) = closest(word.trim_start_matches('#'), names) {
                message.push_str(&format!("; did you mean `#{guess}`?"));
            }
            Some(SceneError::at(&span, message))
        }
    }
}

/// The word or symbol at the start of `text`.
fn token_at(text: &str) -> &str {
    let word =
        text.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.')).unwrap_or(text.len());
    if word > 0 { &text[..word] } else { text.chars().next().map_or("", |c| &text[..c.len_utf8()]) }
}

/// Names longer than this get no suggestion: the edit distance takes time in the product of
/// the lengths, for every name in scope.
const MAX_SUGGESTED_LENGTH: usize = 64;

/// The candidate within edit distance 2 (and less than half the word) of `word`, if any.
pub fn closest<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    if word.is_empty()
        || word.len() > MAX_SUGGESTED_LENGTH
        || !word.chars().all(|c| c.is_alphanumeric() || c == '_')
    {
        return None;
    }
    // Lengths (in bytes, at most 4 a character) that differ by more than 8 differ by more
    // than 2 characters: the distance is above 2.
    candidates
        .filter(|c| c.len().abs_diff(word.len()) <= 8)
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
        Rule::scene => "a scene",
        Rule::declare
        | Rule::local
        | Rule::undef
        | Rule::include
        | Rule::if_start
        | Rule::ifdef_start
        | Rule::ifndef_start
        | Rule::elseif
        | Rule::else_
        | Rule::while_start
        | Rule::for_start
        | Rule::macro_start
        | Rule::macro_def
        | Rule::end
        | Rule::message
        | Rule::default
        | Rule::switch_start
        | Rule::case
        | Rule::range
        | Rule::break_
        | Rule::fopen
        | Rule::fread
        | Rule::fwrite
        | Rule::fclose
        | Rule::message_kind => "a directive (`#declare`, `#if`, ...)",
        Rule::open_mode => "`read`, `write` or `append`",
        Rule::write_item => "a value to write",
        Rule::binary_word => "a binary word type (`uint8`, `sint16be`, ...)",
        Rule::settings => "`settings`",
        Rule::resolution => "`resolution`",
        Rule::samples => "`samples`",
        Rule::integrator => "`integrator`",
        Rule::max_depth => "`max_depth`",
        Rule::seed => "`seed`",
        Rule::background => "`background`",
        Rule::photons => "`photons`",
        Rule::photon_k => "`photon_k`",
        Rule::photon_radius => "`photon_radius`",
        Rule::camera => "`camera`",
        Rule::camera_item | Rule::camera_key => {
            "a camera parameter (`origin`, `left`, `up`, `forward`, `location`, `look_at`, `angle`, `aperture`, `focal_distance`)"
        }
        Rule::camera_projection | Rule::wide_projection => {
            "a projection (`perspective`, `orthographic`, `fisheye`, `cylinder 1`, ...)"
        }
        Rule::light_source => "`light_source`",
        Rule::light_colour | Rule::light_modifier => "a light's colour",
        Rule::pov_background => "`background`",
        Rule::sky_sphere => "`sky_sphere`",
        Rule::sky_emission => "a sky's `emission`",
        Rule::pigment => "`pigment`",
        Rule::finish => "`finish`",
        Rule::pov_texture | Rule::layered_texture => "`texture`",
        Rule::tiles | Rule::tile | Rule::tiles_word => "`tiles`",
        Rule::tile2_word => "`tile2`",
        Rule::interior => "`interior`",
        Rule::normal => "`normal`",
        Rule::pattern => "a pattern (`checker`, `gradient`, `marble`, `wood`, `bozo`)",
        Rule::fractal_parameter | Rule::fractal_word => {
            "a fractal pattern's `interior`, `exterior` or `exponent`"
        }
        Rule::finish_item => "a finish item (`ambient`, `diffuse`, `reflection`, ...)",
        Rule::reflection_item => "`fresnel`, `metallic`, `falloff` or `exponent`",
        Rule::interior_item => "`ior`",
        Rule::light_option
        | Rule::light_number
        | Rule::light_flag
        | Rule::light_area
        | Rule::looks_like
        | Rule::looks_like_key => {
            "a light's modifier (`spotlight`, `parallel`, `radius`, `falloff`, `tightness`, \
             `point_at`, ...)"
        }
        Rule::clipped_by => "`clipped_by`",
        Rule::arg_comma => "`,`",
        Rule::object_modifier | Rule::truth_value | Rule::truth_word => {
            "an object modifier (`hollow`, `no_shadow`, ...)"
        }
        Rule::light_item => "`power`",
        Rule::object => "an object",
        Rule::plane => "`plane`",
        Rule::sphere => "`sphere`",
        Rule::box_shape => "`box`",
        Rule::triangle => "`triangle`",
        Rule::quad => "`quad`",
        Rule::disk => "`disk`",
        Rule::cylinder => "`cylinder`",
        Rule::cone => "`cone`",
        Rule::torus => "`torus`",
        Rule::mesh => "`mesh`",
        Rule::quadric => "`quadric`",
        Rule::cubic => "`cubic`",
        Rule::quartic => "`quartic`",
        Rule::poly => "`poly`",
        Rule::blob => "`blob`",
        Rule::blob_component => "a blob's component (`sphere`, `cylinder`, `component`)",
        Rule::blob_setting => "`threshold`",
        Rule::prism => "`prism`",
        Rule::superellipsoid => "`superellipsoid`",
        Rule::bicubic_patch => "`bicubic_patch`",
        Rule::smooth_triangle => "`smooth_triangle`",
        Rule::mesh2 => "`mesh2`",
        Rule::julia_fractal => "`julia_fractal`",
        Rule::julia_setting
        | Rule::julia_algebra
        | Rule::julia_function
        | Rule::julia_pwr
        | Rule::julia_max_iteration
        | Rule::julia_precision
        | Rule::julia_slice => {
            "a julia_fractal setting (`quaternion`, `sqr`, `max_iteration`, `precision`, `slice`)"
        }
        Rule::mesh2_list
        | Rule::mesh2_vertices
        | Rule::mesh2_normals
        | Rule::mesh2_uvs
        | Rule::mesh2_faces
        | Rule::mesh2_normal_indices
        | Rule::mesh2_uv_indices => "a mesh2 list (`vertex_vectors`, `face_indices`, ...)",
        Rule::patch_setting
        | Rule::patch_type
        | Rule::patch_flatness
        | Rule::patch_u_steps
        | Rule::patch_v_steps => "a patch setting (`type`, `flatness`, `u_steps`, `v_steps`)",
        Rule::triangle_uv | Rule::uv_vectors => "`uv_vectors`",
        Rule::prism_spline => "a spline (`linear_spline`, ...)",
        Rule::prism_sweep => "a sweep (`linear_sweep`, `conic_sweep`)",
        Rule::lathe => "`lathe`",
        Rule::sor => "`sor`",
        Rule::ovus => "`ovus`",
        Rule::parametric => "`parametric`",
        Rule::parametric_setting | Rule::parametric_word | Rule::precompute_word => {
            "a parametric setting (`max_gradient`, `accuracy`, `precompute`)"
        }
        Rule::lemon => "`lemon`",
        Rule::polygon => "`polygon`",
        Rule::height_field => "`height_field`",
        Rule::sphere_sweep => "`sphere_sweep`",
        Rule::sweep_spline | Rule::sweep_b_spline => {
            "a sweep's spline (`linear_spline`, `b_spline`, `cubic_spline`)"
        }
        Rule::sweep_tolerance => "`tolerance`",
        Rule::hf_function => "a height field's `function W, H { }`",
        Rule::hf_image | Rule::hf_type | Rule::hf_gamma | Rule::hf_premultiplied => {
            "a height field's image (`png \"file.png\"`)"
        }
        Rule::pov_image_map => "`image_map`",
        Rule::bump_map | Rule::bump_map_word => "`bump_map`",
        Rule::image_option | Rule::image_option_word | Rule::image_all => {
            "an image_map option (`map_type`, `once`, `interpolate`, `gamma`, `filter`, `transmit`)"
        }
        Rule::hf_setting | Rule::hf_smooth | Rule::hf_water_level => {
            "a height field setting (`smooth`, `water_level`, `hierarchy`)"
        }
        Rule::union => "`union`",
        Rule::intersection => "`intersection`",
        Rule::difference => "`difference`",
        Rule::merge => "`merge`",
        Rule::instance => "`object`",
        Rule::material => "`material`",
        Rule::material_name | Rule::base_material => "a material's name",
        Rule::transform | Rule::transform_key => {
            "a transform (`translate`, `rotate`, `scale`, `matrix`)"
        }
        Rule::material_item | Rule::colour_key => {
            "a material parameter (`diffuse`, `specular`, `transmission`, `emission`, `ior`, `fresnel`)"
        }
        Rule::texture | Rule::texture_arg => "a texture",
        Rule::checker => "`checker`",
        Rule::stripes => "`stripes`",
        Rule::gradient => "`gradient`",
        Rule::noise => "`noise`",
        Rule::marble => "`marble`",
        Rule::wood => "`wood`",
        Rule::image_map => "`image_map`",
        Rule::mix => "`mix`",
        Rule::texture_parameter => "a texture parameter (`axis`, `octaves`, `turbulence`)",
        Rule::color_map => "`color_map`",
        Rule::map_entry | Rule::map_end => "a color_map entry (`[position colour]`)",
        Rule::colour_part | Rule::colour_channel => {
            "a colour's component (`red`, `green`, `blue`, `filter`, `transmit`)"
        }
        Rule::colour | Rule::rgb_colour | Rule::kw_rgb | Rule::colour_word => {
            "a colour (`rgb <r, g, b>`)"
        }
        Rule::array | Rule::array_init => "an array",
        Rule::declared_if => "`#if`",
        Rule::dimension => "an array's size (`[n]`)",
        Rule::macro_call => "a macro call",
        Rule::expr
        | Rule::operand
        | Rule::argument
        | Rule::arithmetic_expr
        | Rule::number
        | Rule::vector
        | Rule::call
        | Rule::paren
        | Rule::negate
        | Rule::plus
        | Rule::not => "a number or vector",
        Rule::add
        | Rule::subtract
        | Rule::multiply
        | Rule::divide
        | Rule::less
        | Rule::less_equal
        | Rule::greater
        | Rule::greater_equal
        | Rule::equal
        | Rule::not_equal
        | Rule::and
        | Rule::or => "an operator",
        Rule::component => "a component (`.x`, `.y`, `.z`)",
        Rule::index => "an index (`[i]`)",
        Rule::string | Rule::string_text => "a file name in quotes",
        Rule::ident | Rule::name => "a name",
        // The `kw_` rules: each reads as its word, from the one list of keywords.
        keyword => keyword_shown(keyword),
    }
}

/// A `kw_` rule as its word in backquotes.
fn keyword_shown(rule: Rule) -> &'static str {
    let name = format!("{rule:?}");
    let word = name.strip_prefix("kw_").unwrap_or(&name);
    keywords::lookup(word).map_or("a keyword", |k| k.shown)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_keyword_rule_reads_as_its_word() {
        for k in keywords::KEYWORDS.iter().filter(|k| k.kind == keywords::KeywordKind::Syntax) {
            let parsed = ScnParser::parse(Rule::ident, k.word).map(|p| p.as_str().len());
            assert_eq!(parsed, Ok(k.word.len()));
        }
        assert_eq!(describe(Rule::kw_translate), "`translate`");
        assert_eq!(describe(Rule::kw_colour_map), "`colour_map`");
    }

    #[test]
    fn errors_after_multibyte_characters_do_not_panic() {
        // Found by fuzzing: a byte-order mark in the middle of a scene, before a parse error.
        let text = "camera { origin <0, \u{feff}era { origin <0, 0, -3.5>  left <-1,specularup";
        let file = Arc::new(SourceFile::new("x.scn".into(), text.into()));
        let error = parse(&file, Dialect::Scn).map(|_| ()).unwrap_err();
        assert!(error.to_string().starts_with("x.scn:1:"), "{error}");
    }

    #[test]
    fn closest_suggests_near_misses_only() {
        assert_eq!(closest("tranlate", keywords::words()), Some("translate"));
        assert_eq!(closest("sphre", keywords::words()), Some("sphere"));
        assert_eq!(closest("banana", keywords::words()), None);
    }
}
