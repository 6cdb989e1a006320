//! The parser's pairs to the owned syntax tree (`lang::syntax`): directives folded into blocks,
//! operators into a tree by precedence, names told apart from keywords, and nesting bounded so
//! that walking the tree cannot overflow a stack.

use std::sync::Arc;

use pest::iterators::Pair;

use super::dialect::Dialect;
use super::keywords::{self, KeywordKind};
use super::parser::{self, MAX_NESTING, Rule};
use super::povray;
use super::syntax::*;
use crate::diagnostic::{SceneError, SourceFile, Span};

/// Parses a file into its items, read in `dialect`.
pub fn parse_file(file: &Arc<SourceFile>, dialect: Dialect) -> Result<Vec<Item>, SceneError> {
    let pairs = parser::parse(file, dialect)?;
    let mut builder = Builder { file: file.clone(), depth: 0, dialect };
    builder.items(pairs.filter(|p| p.as_rule() != Rule::EOI))
}

struct Builder {
    file: Arc<SourceFile>,
    /// Brackets and blocks open around what is being built.
    depth: usize,
    /// POV-Ray's words are read only in `.pov` scenes; in `.scn` each is refused with advice.
    dialect: Dialect,
}

/// A block being filled while its directives are folded (a few at a time: their size does not
/// matter).
#[allow(clippy::large_enum_variant)]
enum Open {
    If {
        branches: Vec<(Condition, Vec<Item>)>,
        condition: Condition,
        /// The items after `#else`, once it is seen.
        otherwise: Option<Vec<Item>>,
        span: Span,
    },
    While {
        condition: Expr,
        span: Span,
    },
    For {
        variable: Ident,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
        span: Span,
    },
    Macro {
        name: Ident,
        parameters: Vec<Ident>,
        span: Span,
    },
    Switch {
        value: Expr,
        clauses: Vec<SwitchClause>,
        /// The test of the clause being gathered (`None` before the first and after a `#break`).
        current: Option<CaseTest>,
        /// After a `#break`: items up to the next clause are skipped, as POV-Ray skips them.
        skipping: bool,
        /// The items after `#else`, once it is seen.
        otherwise: Option<Vec<Item>>,
        span: Span,
    },
}

impl Open {
    fn describe(&self) -> &'static str {
        match self {
            Open::If { .. } => "`#if`",
            Open::While { .. } => "`#while`",
            Open::For { .. } => "`#for`",
            Open::Macro { .. } => "`#macro`",
            Open::Switch { .. } => "`#switch`",
        }
    }

    fn span(&self) -> &Span {
        match self {
            Open::If { span, .. }
            | Open::While { span, .. }
            | Open::For { span, .. }
            | Open::Macro { span, .. }
            | Open::Switch { span, .. } => span,
        }
    }
}

impl Builder {
    /// Refuses POV-Ray's `pair` outside a `.pov` scene, with what to write instead.
    fn pov_only(&self, pair: &Pair<'_, Rule>, inside: Option<&str>) -> Result<(), SceneError> {
        match self.dialect {
            Dialect::Pov => Ok(()),
            Dialect::Scn => {
                let word = pair.as_str();
                let message = povray::message(word, inside)
                    .unwrap_or_else(|| format!("`{word}` is POV-Ray's (a `.pov` scene's) word"));
                Err(self.error(pair, message))
            }
        }
    }

    /// From the file's line index: pest's `line_col` counts the columns from the line's start
    /// every time, quadratic in the length of a long line.
    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        super::parser::span_at(&self.file, pair.as_span().start())
    }

    fn error(&self, pair: &Pair<'_, Rule>, message: impl Into<String>) -> SceneError {
        SceneError::at(&self.span(pair), message)
    }

    /// Counts one more level of nesting at `pair`.
    fn enter(&mut self, pair: &Pair<'_, Rule>) -> Result<(), SceneError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(self.error(pair, format!("nesting deeper than {MAX_NESTING} brackets")));
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.depth -= 1;
    }

    /// A body's pairs to its items, folding `#if ... #end` and the other blocks.
    fn items<'i>(
        &mut self,
        pairs: impl Iterator<Item = Pair<'i, Rule>>,
    ) -> Result<Vec<Item>, SceneError> {
        // The open blocks, each with the items gathered so far; the bottom one is the body.
        let mut stack: Vec<(Option<Open>, Vec<Item>)> = vec![(None, Vec::new())];
        let mut pending: Vec<Pair<'i, Rule>> = pairs.collect();
        pending.reverse();
        while let Some(pair) = pending.pop() {
            let blocks = stack.len() - 1;
            let opened = match pair.as_rule() {
                Rule::macro_def => {
                    // Its pieces are flat: the `#macro`, the body's items, maybe an `#end`.
                    let mut inner: Vec<Pair<'i, Rule>> = pair.into_inner().collect();
                    inner.reverse();
                    pending.extend(inner);
                    continue;
                }
                Rule::if_start => Some(Open::If {
                    condition: Condition::Expr(self.first_expr(&pair)?),
                    branches: Vec::new(),
                    otherwise: None,
                    span: self.span(&pair),
                }),
                Rule::ifdef_start | Rule::ifndef_start => Some(Open::If {
                    condition: self.defined_condition(&pair)?,
                    branches: Vec::new(),
                    otherwise: None,
                    span: self.span(&pair),
                }),
                Rule::while_start => {
                    Some(Open::While { condition: self.first_expr(&pair)?, span: self.span(&pair) })
                }
                Rule::for_start => {
                    let span = self.span(&pair);
                    let mut inner = pair.clone().into_inner();
                    let variable = self.name(inner.next().expect("the loop's name"))?;
                    let from = self.expr(inner.next().expect("the start"))?;
                    let to = self.expr(inner.next().expect("the end"))?;
                    let step = inner.next().map(|p| self.expr(p)).transpose()?;
                    Some(Open::For { variable, from, to, step, span })
                }
                Rule::macro_start => {
                    let span = self.span(&pair);
                    let mut inner = pair.clone().into_inner();
                    let name = self.name(inner.next().expect("the macro's name"))?;
                    let parameters = inner.map(|p| self.name(p)).collect::<Result<_, _>>()?;
                    Some(Open::Macro { name, parameters, span })
                }
                Rule::switch_start => {
                    self.pov_directive(&pair, "#switch")?;
                    Some(Open::Switch {
                        value: self.first_expr(&pair)?,
                        clauses: Vec::new(),
                        current: None,
                        skipping: false,
                        otherwise: None,
                        span: self.span(&pair),
                    })
                }
                Rule::case | Rule::range | Rule::break_ => {
                    self.switch_clause(&pair, stack.last_mut().expect("the body"))?;
                    continue;
                }
                Rule::else_ if matches!(stack.last(), Some((Some(Open::Switch { .. }), _))) => {
                    self.switch_clause(&pair, stack.last_mut().expect("the body"))?;
                    continue;
                }
                Rule::elseif | Rule::else_ => {
                    let (open, items) = stack.last_mut().expect("the body");
                    let Some(Open::If { branches, condition, otherwise, .. }) = open else {
                        let word = if pair.as_rule() == Rule::elseif { "#elseif" } else { "#else" };
                        return Err(self.error(&pair, format!("`{word}` without an `#if`")));
                    };
                    if otherwise.is_some() {
                        return Err(self.error(&pair, "this comes after the `#else` of its `#if`"));
                    }
                    let gathered = std::mem::take(items);
                    if pair.as_rule() == Rule::elseif {
                        let next = Condition::Expr(self.first_expr(&pair)?);
                        branches.push((std::mem::replace(condition, next), gathered));
                    } else {
                        // The last condition's items are complete; gather the `#else` ones.
                        let last = std::mem::replace(
                            condition,
                            Condition::Expr(Expr {
                                kind: ExprKind::Number(0.0),
                                span: self.span(&pair),
                            }),
                        );
                        branches.push((last, gathered));
                        *otherwise = Some(Vec::new());
                    }
                    continue;
                }
                Rule::end => {
                    let (open, items) = stack.pop().expect("the body");
                    if let (Some(Open::Switch { current: None, skipping: false, .. }), Some(item)) =
                        (&open, items.first())
                    {
                        return Err(SceneError::at(
                            item.span(),
                            "this stands in a `#switch` before its first `#case` or `#range`",
                        ));
                    }
                    let Some(open) = open else {
                        return Err(self.error(
                            &pair,
                            "`#end` without an `#if`, `#while`, `#for` or `#macro` to close",
                        ));
                    };
                    gather(&mut stack, close(open, items));
                    continue;
                }
                _ => None,
            };
            match opened {
                Some(open) => {
                    if self.depth + blocks + 1 > MAX_NESTING {
                        return Err(SceneError::at(
                            open.span(),
                            format!("directives and brackets nested deeper than {MAX_NESTING}"),
                        ));
                    }
                    stack.push((Some(open), Vec::new()));
                }
                None => {
                    self.depth += blocks;
                    let item = self.item(pair);
                    self.depth -= blocks;
                    gather(&mut stack, item?);
                }
            }
        }
        let (open, items) = stack.pop().expect("the body");
        match open {
            None => Ok(items),
            // The innermost block left open is reported where it opened.
            Some(open) => {
                Err(SceneError::at(open.span(), format!("{} without its `#end`", open.describe())))
            }
        }
    }

    /// Refuses POV-Ray's directive `word` outside a `.pov` scene, with what to write instead.
    fn pov_directive(&self, pair: &Pair<'_, Rule>, word: &str) -> Result<(), SceneError> {
        match self.dialect {
            Dialect::Pov => Ok(()),
            Dialect::Scn => Err(self.error(
                pair,
                povray::message(word, None)
                    .unwrap_or_else(|| format!("`{word}` is POV-Ray's (a `.pov` scene's) word")),
            )),
        }
    }

    /// A `#case`, `#range`, `#break` or (in a `#switch`) `#else`: the clause gathered so far is
    /// complete, and the next one starts.
    fn switch_clause(
        &mut self,
        pair: &Pair<'_, Rule>,
        (open, items): &mut (Option<Open>, Vec<Item>),
    ) -> Result<(), SceneError> {
        let word = match pair.as_rule() {
            Rule::case => "#case",
            Rule::range => "#range",
            Rule::break_ => "#break",
            _ => "#else",
        };
        self.pov_directive(pair, word)?;
        let Some(Open::Switch { clauses, current, skipping, otherwise, .. }) = open else {
            return Err(self.error(
                pair,
                format!(
                    "`{word}` stands only among a `#switch`'s clauses (not inside an `#if` or a \
                     loop within them)"
                ),
            ));
        };
        if otherwise.is_some() && pair.as_rule() != Rule::break_ {
            return Err(self.error(pair, "this comes after the `#else` of its `#switch`"));
        }
        let gathered = std::mem::take(items);
        match current.take() {
            Some(test) => {
                let breaks = pair.as_rule() == Rule::break_;
                clauses.push(SwitchClause { test, items: gathered, breaks });
            }
            None if !*skipping && otherwise.is_none() && !gathered.is_empty() => {
                return Err(SceneError::at(
                    gathered[0].span(),
                    "this stands in a `#switch` before its first `#case` or `#range`",
                ));
            }
            None if pair.as_rule() == Rule::break_ && otherwise.is_none() && !*skipping => {
                return Err(self.error(pair, "`#break` before the `#switch`'s first `#case`"));
            }
            None => {}
        }
        *skipping = pair.as_rule() == Rule::break_;
        let mut inner = pair.clone().into_inner();
        match pair.as_rule() {
            Rule::case => *current = Some(CaseTest::Case(self.expr(inner.next().expect("v"))?)),
            Rule::range => {
                let low = self.expr(inner.next().expect("the low end"))?;
                *current = Some(CaseTest::Range(low, self.expr(inner.next().expect("high"))?));
            }
            Rule::break_ => {}
            _ => *otherwise = Some(Vec::new()),
        }
        Ok(())
    }

    fn first_expr(&mut self, pair: &Pair<'_, Rule>) -> Result<Expr, SceneError> {
        self.expr(inner_pair(pair))
    }

    /// `#ifdef (Name)` or `#ifndef (Name)`, of a name or an array's element (`A[i]`).
    fn defined_condition(&mut self, pair: &Pair<'_, Rule>) -> Result<Condition, SceneError> {
        let mut inner = pair.clone().into_inner();
        let name = self.name(inner.next().expect("the name"))?;
        let indices = inner.map(|index| self.first_expr(&index)).collect::<Result<_, _>>()?;
        Ok(Condition::Defined { name, indices, defined: pair.as_rule() == Rule::ifdef_start })
    }

    /// A name being bound or looked up as such: not a keyword.
    fn name(&self, pair: Pair<'_, Rule>) -> Result<Ident, SceneError> {
        let name = pair.as_str();
        if keywords::lookup(name).is_some() {
            return Err(self.error(&pair, format!("`{name}` is a keyword, not a name")));
        }
        Ok(Ident { name: name.to_string(), span: self.span(&pair) })
    }

    /// `#fopen`, `#read`, `#write` or `#fclose` (`.pov`).
    fn file_directive(&mut self, pair: Pair<'_, Rule>) -> Result<FileDirective, SceneError> {
        if self.dialect == Dialect::Scn {
            let word = pair.as_str().split(|c: char| !(c == '#' || c.is_alphabetic())).next();
            let message =
                format!("`{}` is POV-Ray's (a `.pov` scene's) directive", word.unwrap_or(""));
            return Err(self.error(&pair, message));
        }
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let handle = self.name(inner.next().expect("the handle"))?;
        let action = match rule {
            Rule::fopen => {
                let name = self.expr(inner.next().expect("the file's name"))?;
                let mode = match inner.next().expect("the mode").as_str() {
                    "read" => OpenMode::Read,
                    "write" => OpenMode::Write,
                    "append" => OpenMode::Append,
                    other => unreachable!("no open mode `{other}`"),
                };
                FileAction::Open { name, mode }
            }
            Rule::fread => FileAction::Read(inner.map(|p| self.name(p)).collect::<Result<_, _>>()?),
            Rule::fwrite => {
                let mut items = Vec::new();
                for item in inner {
                    let mut parts = item.into_inner().peekable();
                    let word =
                        parts.next_if(|p| p.as_rule() == Rule::binary_word).map(|word| match word
                            .as_str()
                        {
                            "uint8" => BinaryWord::Uint8,
                            "sint8" => BinaryWord::Sint8,
                            "uint16be" => BinaryWord::Uint16Be,
                            "uint16le" => BinaryWord::Uint16Le,
                            "sint16be" => BinaryWord::Sint16Be,
                            "sint16le" => BinaryWord::Sint16Le,
                            "sint32be" => BinaryWord::Sint32Be,
                            "sint32le" => BinaryWord::Sint32Le,
                            other => unreachable!("no binary word `{other}`"),
                        });
                    let value = self.expr(parts.next().expect("the value"))?;
                    items.push(WriteItem { word, value });
                }
                FileAction::Write(items)
            }
            Rule::fclose => FileAction::Close,
            other => unreachable!("no file directive {other:?}"),
        };
        Ok(FileDirective { handle, action, span })
    }

    fn item(&mut self, pair: Pair<'_, Rule>) -> Result<Item, SceneError> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        Ok(match rule {
            Rule::declare | Rule::local => Item::Declare(self.declare(pair)?),
            Rule::undef => Item::Undef(self.name(inner_pair(&pair))?),
            Rule::include => Item::Include { file: self.first_expr(&pair)?, span },
            Rule::message => {
                let mut inner = pair.into_inner();
                let kind = inner.next().expect("the kind");
                let kind = kind.as_str().trim_start_matches('#').trim_start();
                let kind = match kind {
                    "debug" => MessageKind::Debug,
                    "warning" => MessageKind::Warning,
                    "error" => MessageKind::Error,
                    other => unreachable!("no message `{other}`"),
                };
                Item::Message { kind, text: self.expr(inner.next().expect("the text"))?, span }
            }
            Rule::fopen | Rule::fread | Rule::fwrite | Rule::fclose => {
                Item::File(self.file_directive(pair)?)
            }
            Rule::version => Item::Ignored { what: Ignored::Version, span },
            Rule::stray_hash => {
                self.pov_only(&pair, None)?;
                Item::Ignored { what: Ignored::StrayHash, span }
            }
            Rule::global_settings => {
                let (mut ambient_light, mut assumed_gamma, mut others) = (None, None, false);
                for part in pair.into_inner().skip(1) {
                    match part.as_rule() {
                        Rule::ambient_light => {
                            ambient_light =
                                Some(self.colour(part.into_inner().nth(1).expect("a colour"))?)
                        }
                        Rule::assumed_gamma => {
                            assumed_gamma =
                                Some(self.expr(part.into_inner().nth(1).expect("a gamma"))?)
                        }
                        Rule::global_other => others = true,
                        rule => unreachable!("no `{rule:?}` in global_settings"),
                    }
                }
                Item::GlobalSettings { ambient_light, assumed_gamma, others, span }
            }
            Rule::media_flag => {
                self.pov_only(&inner_pair(&pair), Some("light_source"))?;
                Item::Ignored { what: Ignored::LightMedia, span }
            }
            Rule::photons_block => {
                self.pov_only(&inner_pair(&pair), Some("object"))?;
                Item::Ignored { what: Ignored::Photons, span }
            }
            Rule::macro_call => {
                let call = self.call(pair)?;
                match call {
                    ExprKind::Call(call) => Item::Call(call),
                    other => Item::Value(Expr { kind: other, span }),
                }
            }
            Rule::settings => {
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::Settings { items, span }
            }
            Rule::resolution
            | Rule::samples
            | Rule::integrator
            | Rule::max_depth
            | Rule::seed
            | Rule::background
            | Rule::photons
            | Rule::photon_k
            | Rule::photon_radius => Item::Setting(self.setting(pair)?),
            Rule::pov_background => {
                let word = inner_pair(&pair);
                self.pov_only(&word, None)?;
                let colour = self.colour(pair.into_inner().nth(1).expect("the colour"))?;
                Item::Setting(Setting { kind: SettingKind::Background(colour), span })
            }
            Rule::sky_sphere => {
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::SkySphere { items, span }
            }
            Rule::sky_emission => {
                let mut inner = pair.into_inner();
                let key = inner.next().expect("the word");
                let key = Ident { name: key.as_str().to_string(), span: self.span(&key) };
                let value = Some(self.colour(inner.next().expect("the colour"))?);
                Item::PovParam { key, value, items: Vec::new() }
            }
            Rule::camera => {
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::Camera { items, span }
            }
            Rule::camera_projection => {
                self.pov_only(&pair, Some("camera"))?;
                let word = inner_pair(&pair);
                let projection = match word.as_rule() {
                    Rule::kw_perspective => ProjectionWord::Perspective,
                    Rule::kw_orthographic => ProjectionWord::Orthographic,
                    Rule::kw_cylinder => ProjectionWord::Cylinder(
                        self.expr(pair.clone().into_inner().nth(1).expect("the type"))?,
                    ),
                    _ => match word.as_str() {
                        "fisheye" => ProjectionWord::Fisheye,
                        "ultra_wide_angle" => ProjectionWord::UltraWideAngle,
                        "omnimax" => ProjectionWord::Omnimax,
                        "panoramic" => ProjectionWord::Panoramic,
                        _ => ProjectionWord::Spherical,
                    },
                };
                Item::CameraProjection { projection, span }
            }
            Rule::camera_item => {
                let mut inner = pair.into_inner();
                let key = inner.next().expect("the key");
                let pov_only = matches!(
                    inner_pair(&key).as_rule(),
                    Rule::kw_right
                        | Rule::kw_direction
                        | Rule::kw_sky
                        | Rule::kw_focal_point
                        | Rule::kw_blur_samples
                        | Rule::blur_sampling_key
                );
                if pov_only {
                    self.pov_only(&key, Some("camera"))?;
                }
                let key = Ident { name: key.as_str().to_string(), span: self.span(&key) };
                let mut value = self.expr(inner.next().expect("the value"))?;
                if let Some(second) = inner.next() {
                    // `angle H, V`: POV-Ray's spherical camera's two angles, as a 2-vector.
                    if key.name != "angle" {
                        return Err(self.error(&second, format!("`{}` takes one value", key.name)));
                    }
                    self.pov_only(&second, Some("camera"))?;
                    let span = value.span.clone();
                    value = Expr { kind: ExprKind::Vector(vec![value, self.expr(second)?]), span };
                }
                Item::CameraParam { key, value }
            }
            Rule::light_source => {
                let (position, items) = self.light_source(pair)?;
                Item::Light { position, items, span }
            }
            Rule::light_colour => {
                if self.dialect == Dialect::Scn {
                    let message = povray::message("color", Some("light_source"))
                        .expect("a light's colour has advice");
                    return Err(self.error(&pair, message));
                }
                Item::LightPower { key: span, colour: self.colour(inner_pair(&pair))? }
            }
            Rule::light_item => {
                let mut inner = pair.into_inner();
                let key_pair = inner.next().expect("the key");
                if key_pair.as_rule() != Rule::kw_power && self.dialect == Dialect::Scn {
                    let message = povray::message(key_pair.as_str(), Some("light_source"))
                        .expect("`color` and `colour` have advice");
                    return Err(self.error(&key_pair, message));
                }
                let key = self.span(&key_pair);
                Item::LightPower { key, colour: self.colour(inner.next().expect("the colour"))? }
            }
            // A mesh's triangles stand as their own rules, not as `object`s.
            Rule::object | Rule::triangle | Rule::smooth_triangle => {
                Item::Object(self.object(pair)?)
            }
            Rule::material => Item::Material(self.material(pair)?),
            Rule::material_name => {
                let name = inner_pair(&pair);
                if name.as_str() == "open" {
                    return Err(self.error(
                        &name,
                        "`open` stands only in a cone or cylinder, right after its arguments",
                    ));
                }
                Item::MaterialName(self.name(name)?)
            }
            Rule::transform => Item::Transform(self.transform(pair)?),
            Rule::material_item => Item::MaterialParam(self.material_param(pair)?),
            Rule::texture => Item::Texture(self.texture(pair)?),
            Rule::texture_parameter => Item::TextureParam(self.texture_param(pair)?),
            Rule::color_map => {
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::ColorMap { entries: items, span }
            }
            Rule::triangle_uv => {
                let mut inner = pair.into_inner().filter(|p| p.as_rule() != Rule::arg_comma);
                self.pov_only(&inner.next().expect("the word"), Some("triangle"))?;
                let mut next = || self.expr(inner.next().expect("the grammar gives three uv"));
                let corners = Box::new([next()?, next()?, next()?]);
                Item::UvVectors { corners, span }
            }
            Rule::map_entry => {
                let mut inner = pair.into_inner().peekable();
                let position = self.arithmetic(inner.next().expect("the position"))?;
                let end = inner.next_if(|p| p.as_rule() == Rule::map_end);
                let colour = self.colour(inner.next().expect("the colour"))?;
                let second = inner.next();
                let end = match (end, second) {
                    (None, None) => None,
                    (Some(end), Some(second)) => {
                        self.pov_only(&end, Some("color_map"))?;
                        Some((self.arithmetic(inner_pair(&end))?, self.colour(second)?))
                    }
                    (Some(end), None) => {
                        return Err(self.error(
                            &end,
                            "a color_map entry with a range (`[start, end colour colour]`) \
                             needs two colours",
                        ));
                    }
                    (None, Some(second)) => {
                        return Err(self.error(
                            &second,
                            "a second colour in a color_map entry needs the range's end \
                             (`[start, end colour colour]`)",
                        ));
                    }
                };
                Item::MapEntry { position, colour, end }
            }
            Rule::rgb_colour | Rule::expr | Rule::colour => Item::Value(self.value_expr(pair)?),
            Rule::default => {
                self.pov_only(&pair, None)?;
                self.enter(&pair)?;
                let items =
                    self.items(pair.into_inner().filter(|p| p.as_rule() != Rule::default_word))?;
                self.leave();
                Item::Default { items, span }
            }
            Rule::pigment | Rule::finish | Rule::pov_texture | Rule::interior | Rule::normal => {
                Item::Appearance(self.appearance(pair)?)
            }
            Rule::tiles => Item::Appearance(self.tiles(pair)?),
            Rule::pattern => {
                let mut inner = pair.into_inner();
                let word = inner.next().expect("the pattern's word");
                let (kind, function) = match word.as_rule() {
                    Rule::float_function => {
                        (PatternKind::Function, Some(Box::new(self.float_function(word)?)))
                    }
                    Rule::pigment_pattern => {
                        (PatternKind::PigmentPattern, Some(Box::new(self.pigment_pattern(word)?)))
                    }
                    _ => (
                        PatternKind::named(word.as_str()).expect("the grammar names only patterns"),
                        None,
                    ),
                };
                let mut kind = kind;
                let mut arguments = Vec::new();
                for argument in inner {
                    // `magnet n mandel` / `magnet n julia`: the set's word after the type.
                    match argument.as_rule() {
                        Rule::pattern_julia => {
                            kind = PatternKind::MagnetJulia;
                            continue;
                        }
                        Rule::pattern_mandel => continue,
                        _ => {}
                    }
                    let span = self.span(&argument);
                    let value = match argument.as_rule() {
                        Rule::colour => self.value_expr(argument)?,
                        _ => self.expr(argument)?,
                    };
                    arguments.push(Colour { value, span });
                }
                Item::Pattern { kind, arguments, function, span }
            }
            Rule::pattern_map => {
                let mut inner = pair.clone().into_inner();
                let kind = match inner.next().expect("the map's word").as_str() {
                    "pigment_map" => MapKind::Pigment,
                    "normal_map" => MapKind::Normal,
                    "texture_map" => MapKind::Texture,
                    "slope_map" => MapKind::Slope,
                    word => unreachable!("no map `{word}`"),
                };
                self.enter(&pair)?;
                let entries = self.items(inner)?;
                self.leave();
                Item::PatternMap { kind, entries, span }
            }
            Rule::map_block => {
                let mut inner = pair.into_inner().peekable();
                let position = match inner.next_if(|p| p.as_rule() == Rule::map_position) {
                    Some(position) => Some(self.arithmetic(inner_pair(&position))?),
                    None => None,
                };
                let items = self.items(inner)?;
                Item::MapBlock { position, items, span }
            }
            Rule::warp => {
                let mut inner = pair.into_inner();
                let word = inner.next().expect("`warp`");
                let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                let items = self.items(inner)?;
                Item::PovParam { key, value: None, items }
            }
            Rule::blob_component => Item::Object(self.blob_component(pair)?),
            Rule::blob_setting => {
                let mut inner = pair.into_inner();
                let word = inner.next().expect("the setting");
                let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                let value = match inner.next() {
                    Some(value) if value.as_rule() == Rule::truth_value => None,
                    Some(value) => {
                        let span = self.span(&value);
                        Some(Colour { value: self.expr(value)?, span })
                    }
                    None => None,
                };
                Item::PovParam { key, value, items: Vec::new() }
            }
            Rule::pov_image_map | Rule::bump_map => {
                if pair.as_rule() == Rule::pov_image_map {
                    self.pov_only(&inner_pair(&pair), Some("pigment"))?;
                }
                self.enter(&pair)?;
                let mut inner = pair.into_inner().skip(1).peekable();
                // The file's type names no decoder: the file's own bytes say what it is.
                inner.next_if(|p| p.as_rule() == Rule::hf_type);
                let file = self.expr(inner.next().expect("the file"))?;
                let options = self.items(inner)?;
                self.leave();
                Item::ImageMap { file, options, span }
            }
            // `filter all 0.5` is the option `filter all`; `filter 3, 0.5` keeps its second
            // value as an item.
            Rule::image_option => {
                let mut inner = pair.into_inner().peekable();
                let word = inner.next().expect("the option");
                let all = inner.next_if(|p| p.as_rule() == Rule::image_all).is_some();
                let name =
                    if all { format!("{} all", word.as_str()) } else { word.as_str().into() };
                let key = Ident { name, span: self.span(&word) };
                let value = match inner.next() {
                    Some(value) => {
                        let span = self.span(&value);
                        Some(Colour { value: self.expr(value)?, span })
                    }
                    None => None,
                };
                let items = match inner.next() {
                    Some(second) => vec![Item::Value(self.expr(second)?)],
                    None => Vec::new(),
                };
                Item::PovParam { key, value, items }
            }
            Rule::clipped_by => {
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::ClippedBy { items, span }
            }
            // `inverse` in a transform block (`.pov`): the block inverted.
            Rule::transform_inverse => {
                let word = inner_pair(&pair);
                let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                Item::PovParam { key, value: None, items: Vec::new() }
            }
            Rule::object_modifier => {
                let mut inner = pair.into_inner();
                let word = inner.next().expect("the modifier");
                self.pov_only(&word, None)?;
                let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                let value = match inner.next() {
                    Some(truth) => {
                        let truth = inner_pair(&truth);
                        let on = match truth.as_str() {
                            "off" | "false" | "no" => 0.0,
                            "on" | "true" | "yes" => 1.0,
                            number => number.parse().expect("the grammar gives a number"),
                        };
                        let span = self.span(&truth);
                        let value = Expr { kind: ExprKind::Number(on), span: span.clone() };
                        Some(Colour { value, span })
                    }
                    None => None,
                };
                Item::PovParam { key, value, items: Vec::new() }
            }
            Rule::light_option if inner_pair(&pair).as_rule() == Rule::looks_like => {
                let looks_like = inner_pair(&pair);
                self.pov_only(&looks_like, Some("light_source"))?;
                let key = Ident { name: "looks_like".to_string(), span: self.span(&looks_like) };
                let object = Item::Object(self.object(looks_like)?);
                Item::PovParam { key, value: None, items: vec![object] }
            }
            Rule::atmosphere | Rule::medium | Rule::pov_fog | Rule::media => {
                let word = inner_pair(&pair);
                if matches!(rule, Rule::pov_fog | Rule::media) {
                    self.pov_only(&word, None)?;
                }
                let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Item::PovParam { key, value: None, items }
            }
            // The colour of POV-Ray's `scattering { type, colour ... }`, as an item of its own.
            Rule::scattering_colour => {
                let key = Ident { name: "colour".to_string(), span: span.clone() };
                let value = Some(Colour { value: self.value_expr(inner_pair(&pair))?, span });
                Item::PovParam { key, value, items: Vec::new() }
            }
            Rule::finish_item
            | Rule::reflection_item
            | Rule::interior_item
            | Rule::pattern_parameter
            | Rule::fractal_parameter
            | Rule::warp_item
            | Rule::medium_item
            | Rule::fog_item
            | Rule::media_item
            | Rule::scattering_item
            | Rule::light_option => {
                if rule == Rule::light_option {
                    let word = inner_pair(&pair);
                    // The spotlight and the parallel light are raydiance's own lights too.
                    let shared = matches!(
                        word.as_str(),
                        "spotlight" | "parallel" | "radius" | "falloff" | "tightness" | "point_at"
                    );
                    if !shared {
                        self.pov_only(&word, Some("light_source"))?;
                    }
                }
                let mut inner = pair.into_inner();
                let key = inner.next().expect("the key");
                let key = Ident { name: key.as_str().to_string(), span: self.span(&key) };
                let mut value = None;
                let mut items = Vec::new();
                for part in inner {
                    match part.as_rule() {
                        Rule::colour | Rule::expr if value.is_none() => {
                            let span = self.span(&part);
                            value = Some(Colour { value: self.value_expr(part)?, span });
                        }
                        _ => items.push(self.item(part)?),
                    }
                }
                Item::PovParam { key, value, items }
            }
            _ => unreachable!("the grammar gives no other item: {rule:?}"),
        })
    }

    /// `pigment`, `finish`, `texture`, `interior` or `normal { }` (`.pov`; refused in `.scn`).
    fn appearance(&mut self, pair: Pair<'_, Rule>) -> Result<Appearance, SceneError> {
        let span = self.span(&pair);
        let kind = match pair.as_rule() {
            Rule::pigment => AppearanceKind::Pigment,
            Rule::finish => AppearanceKind::Finish,
            Rule::pov_texture => AppearanceKind::Texture,
            Rule::interior => AppearanceKind::Interior,
            Rule::normal => AppearanceKind::Normal,
            rule => unreachable!("no appearance {rule:?}"),
        };
        let unread = pair.clone().into_inner().any(|p| p.as_rule() == Rule::normal_unread);
        // Bump mapping is raydiance's too (in a material); the rest is POV-Ray's alone.
        if kind != AppearanceKind::Normal || unread {
            self.pov_only(&inner_pair(&pair), None)?;
        }
        if unread {
            // Read whole and not rendered: its items are not parsed.
            return Ok(Appearance { kind, items: Vec::new(), span });
        }
        self.enter(&pair)?;
        let items = self.items(pair.into_inner().skip(1))?;
        self.leave();
        Ok(Appearance { kind, items, span })
    }

    /// POV-Ray's `tiles { A tile2 B }` as what it is: `texture { checker texture { A }
    /// texture { B } }` (each tile's textures in a texture of their own).
    fn tiles(&mut self, pair: Pair<'_, Rule>) -> Result<Appearance, SceneError> {
        let span = self.span(&pair);
        self.pov_only(&inner_pair(&pair), None)?;
        let mut items = vec![Item::Pattern {
            kind: PatternKind::Checker,
            arguments: Vec::new(),
            function: None,
            span: span.clone(),
        }];
        for tile in pair.into_inner().filter(|p| p.as_rule() == Rule::tile) {
            let tile_span = self.span(&tile);
            self.enter(&tile)?;
            let textures = self.items(tile.into_inner())?;
            self.leave();
            items.push(Item::Appearance(Appearance {
                kind: AppearanceKind::Texture,
                items: textures,
                span: tile_span,
            }));
        }
        Ok(Appearance { kind: AppearanceKind::Texture, items, span })
    }

    /// A vector literal's components. Its commas are optional in `.pov`, and a last one may
    /// follow the components; `.scn` has one between each two and none after.
    fn vector_components(&mut self, pair: Pair<'_, Rule>) -> Result<Vec<Expr>, SceneError> {
        let mut components = Vec::new();
        let mut comma = None;
        for part in pair.into_inner() {
            if part.as_rule() == Rule::arg_comma {
                comma = Some(part);
                continue;
            }
            if self.dialect == Dialect::Scn && !components.is_empty() && comma.is_none() {
                return Err(self.error(&part, "a `,` is missing before this vector component"));
            }
            comma = None;
            components.push(self.arithmetic(part)?);
        }
        match comma {
            Some(last) if self.dialect == Dialect::Scn => {
                Err(self.error(&last, "a vector ends with its last component, not a `,`"))
            }
            _ => Ok(components),
        }
    }

    fn declare(&mut self, pair: Pair<'_, Rule>) -> Result<Declare, SceneError> {
        let span = self.span(&pair);
        let local = pair.as_rule() == Rule::local;
        let mut inner = pair.into_inner().peekable();
        let name = self.name(inner.next().expect("the name"))?;
        let mut indices = Vec::new();
        while let Some(index) = inner.next_if(|p| p.as_rule() == Rule::index) {
            indices.push(self.first_expr(&index)?);
        }
        let value = self.declared(inner.next().expect("the value"))?;
        Ok(Declare { local, name, indices, value, span })
    }

    fn declared(&mut self, pair: Pair<'_, Rule>) -> Result<Declared, SceneError> {
        Ok(match pair.as_rule() {
            Rule::material => Declared::Material(self.material(pair)?),
            Rule::object => Declared::Object(Box::new(self.object(pair)?)),
            Rule::texture => Declared::Texture(self.texture(pair)?),
            Rule::array => Declared::Array(self.array(pair)?),
            Rule::rgb_colour | Rule::expr => Declared::Value(self.value_expr(pair)?),
            Rule::layered_texture => {
                let span = self.span(&pair);
                let layers =
                    pair.into_inner().map(|p| self.appearance(p)).collect::<Result<_, _>>()?;
                Declared::LayeredTexture { layers, span }
            }
            Rule::color_map => {
                let span = self.span(&pair);
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let entries = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Declared::ColorMap { entries, span }
            }
            Rule::pigment | Rule::finish | Rule::pov_texture | Rule::interior | Rule::normal => {
                Declared::Appearance(self.appearance(pair)?)
            }
            Rule::media => {
                let span = self.span(&pair);
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Declared::Media { items, span }
            }
            Rule::camera => {
                let span = self.span(&pair);
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Declared::Camera { items, span }
            }
            Rule::sky_sphere => {
                let span = self.span(&pair);
                self.pov_only(&inner_pair(&pair), None)?;
                self.enter(&pair)?;
                let items = self.items(pair.into_inner().skip(1))?;
                self.leave();
                Declared::Sky { items, span }
            }
            Rule::float_function => Declared::Function(self.float_function(pair)?),
            Rule::light_source => {
                let span = self.span(&pair);
                self.pov_only(&inner_pair(&pair), None)?;
                let (position, items) = self.light_source(pair)?;
                Declared::Light { position, items, span }
            }
            Rule::transform => {
                let transform = self.transform(pair)?;
                if !matches!(transform.kind, TransformKind::Block(_) | TransformKind::Value(_)) {
                    return Err(SceneError::at(
                        &transform.span,
                        "a transform is declared as `transform { ... }`",
                    ));
                }
                Declared::Transform(transform)
            }
            Rule::declared_if => {
                let span = self.span(&pair);
                self.enter(&pair)?;
                let mut branches = Vec::new();
                let mut otherwise = None;
                let mut parts = pair.into_inner();
                while let Some(directive) = parts.next() {
                    match directive.as_rule() {
                        Rule::if_start | Rule::elseif => {
                            let condition = Condition::Expr(self.first_expr(&directive)?);
                            let value = self.declared(parts.next().expect("a value"))?;
                            branches.push((condition, value));
                        }
                        Rule::ifdef_start | Rule::ifndef_start => {
                            let condition = self.defined_condition(&directive)?;
                            let value = self.declared(parts.next().expect("a value"))?;
                            branches.push((condition, value));
                        }
                        Rule::else_ => {
                            otherwise =
                                Some(Box::new(self.declared(parts.next().expect("a value"))?));
                        }
                        Rule::end => {}
                        rule => unreachable!("no {rule:?} in a value's #if"),
                    }
                }
                self.leave();
                Declared::If { branches, otherwise, span }
            }
            rule => unreachable!("the grammar declares no other value: {rule:?}"),
        })
    }

    fn array(&mut self, pair: Pair<'_, Rule>) -> Result<ArrayLiteral, SceneError> {
        let span = self.span(&pair);
        let mut dimensions = Vec::new();
        let mut elements = None;
        for part in pair.into_inner().skip(1) {
            match part.as_rule() {
                Rule::dimension => dimensions.push(self.first_expr(&part)?),
                Rule::array_init => elements = Some(self.array_row(part)?),
                rule => unreachable!("an array has no {rule:?}"),
            }
        }
        Ok(ArrayLiteral { dimensions, elements, span })
    }

    fn array_row(&mut self, pair: Pair<'_, Rule>) -> Result<Vec<ArrayElement>, SceneError> {
        self.enter(&pair)?;
        let mut row = Vec::new();
        let mut comma = false;
        for element in pair.into_inner() {
            if element.as_rule() == Rule::arg_comma {
                comma = true;
                continue;
            }
            if self.dialect == Dialect::Scn && !row.is_empty() && !comma {
                return Err(self.error(&element, "a `,` is missing before this array element"));
            }
            comma = false;
            let span = self.span(&element);
            row.push(match element.as_rule() {
                Rule::array_init => ArrayElement::Row(self.array_row(element)?, span),
                _ => ArrayElement::Value(Box::new(self.declared(element)?), span),
            });
        }
        self.leave();
        Ok(row)
    }

    fn setting(&mut self, pair: Pair<'_, Rule>) -> Result<Setting, SceneError> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut args = pair.into_inner().skip(1);
        let mut next = || args.next().expect("the grammar gives every setting its value");
        let kind = match rule {
            Rule::resolution => {
                let (w, h) = (next(), next());
                SettingKind::Resolution(self.expr(w)?, self.expr(h)?)
            }
            Rule::samples => SettingKind::Samples(self.expr(next())?),
            Rule::integrator => {
                let name = next();
                SettingKind::Integrator(Ident {
                    name: name.as_str().to_string(),
                    span: self.span(&name),
                })
            }
            Rule::max_depth => SettingKind::MaxDepth(self.expr(next())?),
            Rule::seed => SettingKind::Seed(self.expr(next())?),
            Rule::background => SettingKind::Background(self.colour(next())?),
            Rule::photons => SettingKind::Photons(self.expr(next())?),
            Rule::photon_k => SettingKind::PhotonK(self.expr(next())?),
            Rule::photon_radius => SettingKind::PhotonRadius(self.expr(next())?),
            rule => unreachable!("no setting {rule:?}"),
        };
        Ok(Setting { kind, span })
    }

    fn object(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        let pair = match pair.as_rule() {
            Rule::object => inner_pair(&pair),
            _ => pair,
        };
        let span = self.span(&pair);
        let rule = pair.as_rule();
        if matches!(rule, Rule::instance | Rule::looks_like)
            && pair.clone().into_inner().nth(1).is_some_and(|p| p.as_rule() == Rule::object)
        {
            // `object { shape ... items }`: the shape, with the items after it added to its own.
            self.enter(&pair)?;
            let mut inner = pair.into_inner().skip(1);
            let mut object = self.object(inner.next().expect("the shape"))?;
            object.items.extend(self.items(inner)?);
            self.leave();
            return Ok(object);
        }
        if rule == Rule::isosurface {
            return self.isosurface(pair, span);
        }
        if rule == Rule::height_field {
            return self.height_field(pair, span);
        }
        if rule == Rule::parametric {
            return self.parametric(pair, span);
        }
        if rule == Rule::sphere_sweep {
            return self.sphere_sweep(pair, span);
        }
        if matches!(
            rule,
            Rule::quadric
                | Rule::cubic
                | Rule::quartic
                | Rule::poly
                | Rule::blob
                | Rule::prism
                | Rule::superellipsoid
                | Rule::ovus
                | Rule::lemon
                | Rule::bicubic_patch
                | Rule::smooth_triangle
                | Rule::mesh2
                | Rule::julia_fractal
                | Rule::lathe
                | Rule::sor
                | Rule::polygon
        ) {
            self.pov_only(&inner_pair(&pair), None)?;
        }
        if rule == Rule::prism {
            return self.prism(pair);
        }
        if rule == Rule::bicubic_patch {
            return self.bicubic_patch(pair);
        }
        if rule == Rule::mesh2 {
            return self.mesh2(pair);
        }
        if rule == Rule::julia_fractal {
            return self.julia_fractal(pair);
        }
        if rule == Rule::mesh {
            // A mesh of a file names it where a mesh of triangles has its first triangle, a
            // directive or item, or (`.pov`) a macro's call that may make triangles.
            let Some(head) = pair.clone().into_inner().nth(1).filter(|p| p.as_rule() == Rule::expr)
            else {
                return self.triangle_mesh(pair, None);
            };
            if self.dialect == Dialect::Pov
                && let ExprKind::Call(call) = self.expr(head)?.kind
            {
                return self.triangle_mesh(pair, Some(call));
            }
        }
        if matches!(rule, Rule::lathe | Rule::sor | Rule::polygon) {
            return self.point_list_shape(pair);
        }
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let internal_font = inner.next_if(|p| p.as_rule() == Rule::internal_font).is_some();
        inner.next_if(|p| p.as_rule() == Rule::kw_ttf);
        let mut first = true;
        let mut take = |b: &mut Self| {
            let comma = inner.next_if(|p| p.as_rule() == Rule::arg_comma).is_some();
            let argument = inner.next().expect("the grammar gives the arguments");
            if !comma && !first {
                let text = argument.as_str();
                let word = &text
                    [..text.find(|c: char| !c.is_alphanumeric() && c != '_').unwrap_or(text.len())];
                if keywords::lookup(word).is_some_and(|k| k.kind == KeywordKind::Syntax) {
                    let message = format!("an argument of the shape is missing before `{word}`");
                    return Err(b.error(&argument, message));
                }
                if b.dialect == Dialect::Scn {
                    return Err(b.error(
                        &argument,
                        "a `,` must separate the shape's arguments (is a `,` missing?)",
                    ));
                }
            }
            first = false;
            b.expr(argument)
        };
        let mut shape = match rule {
            Rule::plane => Shape::Plane { normal: take(self)?, offset: take(self)? },
            Rule::sphere => Shape::Sphere { center: take(self)?, radius: take(self)? },
            Rule::box_shape => Shape::Box { corner_a: take(self)?, corner_b: take(self)? },
            Rule::triangle => Shape::Triangle { a: take(self)?, b: take(self)?, c: take(self)? },
            Rule::quad => {
                Shape::Quad { corner: take(self)?, edge1: take(self)?, edge2: take(self)? }
            }
            Rule::disk => Shape::Disk {
                center: take(self)?,
                normal: take(self)?,
                radius: take(self)?,
                hole: None,
            },
            Rule::cylinder => Shape::Cylinder {
                base: take(self)?,
                cap: take(self)?,
                radius: take(self)?,
                open: false,
            },
            Rule::cone => Shape::Cone {
                base: take(self)?,
                base_radius: take(self)?,
                cap: take(self)?,
                cap_radius: take(self)?,
                open: false,
            },
            Rule::torus => Shape::Torus { major: take(self)?, minor: take(self)? },
            Rule::mesh => Shape::Mesh { file: take(self)? },
            Rule::text => Shape::Text {
                font: match take(self)? {
                    name if internal_font => FontName::Internal(name),
                    name => FontName::File(name),
                },
                string: take(self)?,
                thickness: take(self)?,
                offset: take(self)?,
            },
            Rule::quadric => Shape::Quadric {
                squares: take(self)?,
                products: take(self)?,
                linear: take(self)?,
                constant: take(self)?,
            },
            Rule::cubic => Shape::Poly { order: PolyOrder::Cubic, coefficients: take(self)? },
            Rule::quartic => Shape::Poly { order: PolyOrder::Quartic, coefficients: take(self)? },
            Rule::poly => {
                Shape::Poly { order: PolyOrder::Written(take(self)?), coefficients: take(self)? }
            }
            Rule::blob => Shape::Blob,
            Rule::superellipsoid => Shape::Superellipsoid { exponents: take(self)? },
            Rule::ovus => Shape::Ovus { bottom: take(self)?, top: take(self)? },
            Rule::lemon => Shape::Lemon {
                base: take(self)?,
                base_radius: take(self)?,
                cap: take(self)?,
                cap_radius: take(self)?,
                inner_radius: take(self)?,
                open: false,
            },
            Rule::prism => unreachable!("read by `prism`"),
            Rule::bicubic_patch => unreachable!("read by `bicubic_patch`"),
            Rule::mesh2 => unreachable!("read by `mesh2`"),
            Rule::julia_fractal => unreachable!("read by `julia_fractal`"),
            Rule::smooth_triangle => {
                let mut six = Vec::with_capacity(6);
                for _ in 0..6 {
                    six.push(take(self)?);
                }
                let mut six = six.into_iter();
                let mut next = || six.next().expect("six arguments");
                let [p1, n1, p2, n2, p3, n3] = std::array::from_fn(|_| next());
                Shape::SmoothTriangle {
                    corners: Box::new([p1, p2, p3]),
                    normals: Box::new([n1, n2, n3]),
                }
            }
            Rule::lathe | Rule::sor | Rule::polygon => unreachable!("read by `point_list_shape`"),
            Rule::instance | Rule::looks_like => Shape::Instance { of: take(self)? },
            Rule::union => Shape::Union,
            Rule::intersection => Shape::Intersection,
            Rule::difference => Shape::Difference,
            Rule::merge => Shape::Merge,
            Rule::isosurface | Rule::height_field | Rule::sphere_sweep | Rule::parametric => {
                unreachable!("read above")
            }
            rule => unreachable!("no object {rule:?}"),
        };
        if let Shape::Cylinder { open, .. } | Shape::Cone { open, .. } | Shape::Lemon { open, .. } =
            &mut shape
        {
            *open = inner.next_if(|p| p.as_rule() == Rule::kw_open).is_some();
        }
        if let Shape::Disk { hole, .. } = &mut shape
            && let Some(comma) = inner.next_if(|p| p.as_rule() == Rule::arg_comma)
        {
            if self.dialect == Dialect::Scn {
                return Err(self.error(&comma, "a disk has no hole radius (POV-Ray's `disc` has)"));
            }
            *hole = Some(self.expr(inner.next().expect("the grammar gives the hole radius"))?);
        }
        let items = self.items(inner)?;
        self.leave();
        Ok(Object { shape, items, span })
    }

    /// POV-Ray's `prism { [spline] [sweep] h1, h2, count, points... [open] items }`.
    fn prism(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        use crate::geometry::{SplineKind, Sweep};
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let (mut spline, mut sweep) = (SplineKind::Linear, Sweep::Linear);
        while let Some(word) =
            inner.next_if(|p| matches!(p.as_rule(), Rule::prism_spline | Rule::prism_sweep))
        {
            match inner_pair(&word).as_rule() {
                Rule::kw_linear_spline => spline = SplineKind::Linear,
                Rule::kw_quadratic_spline => spline = SplineKind::Quadratic,
                Rule::kw_cubic_spline => spline = SplineKind::Cubic,
                Rule::kw_bezier_spline => spline = SplineKind::Bezier,
                Rule::kw_linear_sweep => sweep = Sweep::Linear,
                Rule::kw_conic_sweep => sweep = Sweep::Conic,
                rule => unreachable!("no prism word {rule:?}"),
            }
        }
        let mut next = || self.leading_argument(&mut inner);
        let heights = [next()?, next()?];
        let count = next()?;
        let (open, points, items) = self.open_points_and_items(inner)?;
        self.leave();
        let shape = Shape::Prism { spline, sweep, heights, count, points, open };
        Ok(Object { shape, items, span })
    }

    /// `light_source { position items }`: its position and its items.
    fn light_source(&mut self, pair: Pair<'_, Rule>) -> Result<(Expr, Vec<Item>), SceneError> {
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1);
        let position = self.expr(inner.next().expect("the position"))?;
        let items = self.items(inner)?;
        self.leave();
        Ok((position, items))
    }

    /// A shape's next leading argument (a height, a count), past the commas.
    fn leading_argument<'i>(
        &mut self,
        inner: &mut std::iter::Peekable<impl Iterator<Item = Pair<'i, Rule>>>,
    ) -> Result<Expr, SceneError> {
        inner.next_if(|p| p.as_rule() == Rule::arg_comma);
        self.expr(inner.next().expect("the grammar gives the shape's leading arguments"))
    }

    /// A point-list shape's `open` word (anywhere among its items), its points and its items.
    fn open_points_and_items<'i>(
        &mut self,
        inner: impl Iterator<Item = Pair<'i, Rule>>,
    ) -> Result<(bool, Vec<Item>, Vec<Item>), SceneError> {
        let mut open = false;
        let rest: Vec<_> = inner
            .filter(|p| {
                let word = p.as_rule() == Rule::kw_open;
                open |= word;
                !word
            })
            .collect();
        let (points, items) = self.listed_and_items(rest, is_value)?;
        Ok((open, points, items))
    }

    /// A shape's listed points (or a mesh's triangles) and its items, which POV-Ray lets
    /// directives run through (`#while` around the points, `#declare` between them): all are
    /// folded together, and the list ends with the last item that holds one of its members
    /// (`member`), the items after it being the object's.
    fn listed_and_items(
        &mut self,
        pairs: Vec<Pair<'_, Rule>>,
        member: fn(&Item) -> bool,
    ) -> Result<(Vec<Item>, Vec<Item>), SceneError> {
        let mut listed =
            self.items(pairs.into_iter().filter(|p| p.as_rule() != Rule::arg_comma))?;
        let end = listed.iter().rposition(|item| holds(item, member)).map_or(0, |i| i + 1);
        let items = listed.split_off(end);
        Ok((listed, items))
    }

    /// POV-Ray's `bicubic_patch { settings... 16 points items }`.
    fn bicubic_patch(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let mut patch = BicubicPatch {
            patch_type: None,
            flatness: None,
            u_steps: None,
            v_steps: None,
            uv_vectors: Vec::new(),
            points: Vec::new(),
        };
        while let Some(setting) = inner.next_if(|p| p.as_rule() == Rule::patch_setting) {
            let mut parts = setting.into_inner().filter(|p| p.as_rule() != Rule::arg_comma);
            let word = parts.next().expect("the setting's word");
            if word.as_rule() == Rule::uv_vectors {
                patch.uv_vectors.clear();
                for corner in parts {
                    patch.uv_vectors.push(self.expr(corner)?);
                }
                continue;
            }
            let value = Some(self.expr(parts.next().expect("the setting's value"))?);
            match word.as_rule() {
                Rule::patch_type => patch.patch_type = value,
                Rule::patch_flatness => patch.flatness = value,
                Rule::patch_u_steps => patch.u_steps = value,
                Rule::patch_v_steps => patch.v_steps = value,
                Rule::uv_vectors => unreachable!("read above"),
                rule => unreachable!("no patch setting {rule:?}"),
            }
        }
        while let Some(p) = inner.next_if(|p| matches!(p.as_rule(), Rule::expr | Rule::arg_comma)) {
            if p.as_rule() == Rule::expr {
                patch.points.push(self.expr(p)?);
            }
        }
        let items = self.items(inner)?;
        self.leave();
        Ok(Object { shape: Shape::BicubicPatch(Box::new(patch)), items, span })
    }

    /// POV-Ray's `mesh { triangle { } smooth_triangle { } ... items }`; `call`, a macro's call
    /// that stands first, in the place of a mesh's file (whose `expr` it was read from).
    fn triangle_mesh(
        &mut self,
        pair: Pair<'_, Rule>,
        call: Option<Call>,
    ) -> Result<Object, SceneError> {
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().peekable();
        let word = inner.next().expect("the grammar gives `mesh`");
        if self.dialect == Dialect::Scn {
            return Err(self.error(
                inner.peek().unwrap_or(&word),
                "a mesh of `triangle` blocks is POV-Ray's (a `.pov` scene's); a `.scn` mesh reads \
                 a file: `mesh { \"file.ply\" }`",
            ));
        }
        if call.is_some() {
            inner.next();
        }
        let (mut triangles, items) = self.listed_and_items(inner.collect(), is_triangle)?;
        if let Some(call) = call {
            triangles.insert(0, Item::Call(call));
        }
        self.leave();
        Ok(Object { shape: Shape::TriangleMesh { triangles }, items, span })
    }

    /// POV-Ray's `julia_fractal { <c> settings... items }`, settings and items in any order.
    fn julia_fractal(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        use crate::geometry::Algebra;
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1);
        let parameter = self.expr(inner.next().expect("the grammar gives the parameter"))?;
        let mut fractal = JuliaFractal {
            parameter,
            algebra: Algebra::Quaternion,
            function: None,
            max_iteration: None,
            precision: None,
            slice: None,
        };
        let mut rest = Vec::new();
        for part in inner {
            if part.as_rule() != Rule::julia_setting {
                rest.push(part);
                continue;
            }
            let mut parts = part.into_inner().filter(|p| p.as_rule() != Rule::arg_comma);
            let word = parts.next().expect("the setting's word");
            let mut value = |b: &mut Self| b.expr(parts.next().expect("the setting's value"));
            match word.as_rule() {
                Rule::julia_algebra => {
                    fractal.algebra = match word.as_str() {
                        "quaternion" => Algebra::Quaternion,
                        "hypercomplex" => Algebra::Hypercomplex,
                        other => unreachable!("no algebra {other}"),
                    }
                }
                Rule::julia_function | Rule::julia_pwr => {
                    let name = word.as_str().to_string();
                    fractal.function = Some(Ident { name, span: self.span(&word) });
                }
                Rule::julia_max_iteration => fractal.max_iteration = Some(value(self)?),
                Rule::julia_precision => fractal.precision = Some(value(self)?),
                Rule::julia_slice => fractal.slice = Some((value(self)?, value(self)?)),
                rule => unreachable!("no julia_fractal setting {rule:?}"),
            }
        }
        let items = self.items(rest.into_iter())?;
        self.leave();
        Ok(Object { shape: Shape::JuliaFractal(Box::new(fractal)), items, span })
    }

    /// POV-Ray's `mesh2 { lists... items }`.
    fn mesh2(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let mut mesh = Mesh2 {
            vertices: None,
            normals: None,
            uvs: None,
            faces: None,
            normal_indices: None,
            uv_indices: None,
        };
        while let Some(list) = inner.next_if(|p| p.as_rule() == Rule::mesh2_list) {
            let mut parts = list.into_inner();
            let word = parts.next().expect("the list's word");
            let mut entries = Vec::new();
            for part in parts.filter(|p| p.as_rule() == Rule::expr) {
                entries.push(self.expr(part)?);
            }
            let count = entries.remove(0);
            let list = Some(VectorList { count, entries });
            match word.as_rule() {
                Rule::mesh2_vertices => mesh.vertices = list,
                Rule::mesh2_normals => mesh.normals = list,
                Rule::mesh2_uvs => mesh.uvs = list,
                Rule::mesh2_faces => mesh.faces = list,
                Rule::mesh2_normal_indices => mesh.normal_indices = list,
                Rule::mesh2_uv_indices => mesh.uv_indices = list,
                rule => unreachable!("no mesh2 list {rule:?}"),
            }
        }
        let items = self.items(inner)?;
        self.leave();
        Ok(Object { shape: Shape::Mesh2(Box::new(mesh)), items, span })
    }

    /// POV-Ray's `lathe { [spline] count, points... items }`, `sor { count, points... [open]
    /// items }` and `polygon { count, points... items }`.
    fn point_list_shape(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        use crate::geometry::SplineKind;
        let span = self.span(&pair);
        let rule = pair.as_rule();
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let mut spline = SplineKind::Linear;
        while let Some(word) = inner.next_if(|p| p.as_rule() == Rule::prism_spline) {
            let word = inner_pair(&word);
            spline = match word.as_rule() {
                Rule::kw_linear_spline => SplineKind::Linear,
                Rule::kw_quadratic_spline => SplineKind::Quadratic,
                Rule::kw_cubic_spline => SplineKind::Cubic,
                Rule::kw_bezier_spline => SplineKind::Bezier,
                rule => unreachable!("no spline word {rule:?}"),
            };
        }
        let count = self.leading_argument(&mut inner)?;
        let (open, points, items) = self.open_points_and_items(inner)?;
        self.leave();
        let shape = match rule {
            Rule::lathe => Shape::Lathe { spline, count, points },
            Rule::sor => Shape::Sor { count, points, open },
            Rule::polygon => Shape::Polygon { count, points },
            rule => unreachable!("no point list shape {rule:?}"),
        };
        Ok(Object { shape, items, span })
    }

    /// A blob's `sphere { c, r, [strength] s items }`, `cylinder { a, b, r, [strength] s items }`
    /// or `component s, r, c`.
    fn blob_component(&mut self, pair: Pair<'_, Rule>) -> Result<Object, SceneError> {
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().peekable();
        let word = inner.next().expect("the component's word");
        let mut take = |b: &mut Self| {
            inner.next_if(|p| matches!(p.as_rule(), Rule::arg_comma | Rule::kw_strength));
            inner.next_if(|p| p.as_rule() == Rule::kw_strength);
            b.expr(inner.next().expect("the grammar gives the arguments"))
        };
        let shape = match word.as_rule() {
            Rule::kw_sphere => Shape::BlobSphere {
                center: take(self)?,
                radius: take(self)?,
                strength: take(self)?,
            },
            Rule::kw_cylinder => Shape::BlobCylinder {
                a: take(self)?,
                b: take(self)?,
                radius: take(self)?,
                strength: take(self)?,
            },
            Rule::kw_component => {
                let strength = take(self)?;
                let radius = take(self)?;
                Shape::BlobSphere { center: take(self)?, radius, strength }
            }
            rule => unreachable!("no blob component {rule:?}"),
        };
        let items = self.items(inner)?;
        self.leave();
        Ok(Object { shape, items, span })
    }

    fn transform(&mut self, pair: Pair<'_, Rule>) -> Result<Transform, SceneError> {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let key = inner.next().expect("the key");
        let value = inner.next().expect("the value");
        if value.as_rule() == Rule::transform_block {
            self.pov_only(&key, None)?;
            self.enter(&value)?;
            let items = self.items(value.into_inner())?;
            self.leave();
            return Ok(Transform { kind: TransformKind::Block(items), span });
        }
        let word = inner_pair(&key);
        let value = self.expr(value)?;
        let kind = match word.as_rule() {
            Rule::kw_translate => TransformKind::Translate(value),
            Rule::kw_rotate => TransformKind::Rotate(value),
            Rule::kw_scale => TransformKind::Scale(value),
            Rule::kw_matrix => TransformKind::Matrix(value),
            Rule::kw_transform => {
                self.pov_only(&word, None)?;
                TransformKind::Value(value)
            }
            rule => unreachable!("no transform {rule:?}"),
        };
        Ok(Transform { kind, span })
    }

    fn material(&mut self, pair: Pair<'_, Rule>) -> Result<Material, SceneError> {
        let span = self.span(&pair);
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let base = match inner.next_if(|p| p.as_rule() == Rule::base_material) {
            Some(base) => Some(self.base_material(base)?),
            None => None,
        };
        let items = self.items(inner)?;
        self.leave();
        Ok(Material { base, items, span })
    }

    /// A declared material's name, with the indices that pick an array's element.
    fn base_material(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        let mut inner = pair.into_inner();
        let name = self.name(inner.next().expect("the name"))?;
        let mut base = Expr::from(name);
        for index in inner {
            let index = self.first_expr(&index)?;
            let span = base.span.clone();
            base = Expr {
                kind: ExprKind::Index { array: Box::new(base), index: Box::new(index) },
                span,
            };
        }
        Ok(base)
    }

    fn material_param(&mut self, pair: Pair<'_, Rule>) -> Result<MaterialParam, SceneError> {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let key = inner.next().expect("the key");
        let key_rule = match key.as_rule() {
            Rule::colour_key => inner_pair(&key).as_rule(),
            rule => rule,
        };
        let mut value = || inner.next().expect("the value");
        let kind = match key_rule {
            Rule::kw_fresnel => MaterialParamKind::Fresnel,
            Rule::kw_ior => MaterialParamKind::Ior(self.expr(value())?),
            Rule::kw_roughness => MaterialParamKind::Roughness(self.expr(value())?),
            Rule::kw_coat => MaterialParamKind::Coat(self.expr(value())?),
            Rule::kw_coat_roughness => MaterialParamKind::CoatRoughness(self.expr(value())?),
            Rule::kw_diffuse => MaterialParamKind::Diffuse(self.texture_arg(value())?),
            Rule::kw_specular => MaterialParamKind::Specular(self.colour(value())?),
            Rule::kw_transmission => MaterialParamKind::Transmission(self.colour(value())?),
            Rule::kw_emission => MaterialParamKind::Emission(self.colour(value())?),
            rule => unreachable!("no material parameter {rule:?}"),
        };
        Ok(MaterialParam { kind, span })
    }

    fn texture_arg(&mut self, pair: Pair<'_, Rule>) -> Result<TextureArg, SceneError> {
        let pair = match pair.as_rule() {
            Rule::texture_arg => inner_pair(&pair),
            _ => pair,
        };
        Ok(match pair.as_rule() {
            Rule::texture => TextureArg::Texture(self.texture(pair)?),
            Rule::colour => TextureArg::Colour(self.colour(pair)?),
            rule => unreachable!("no texture argument {rule:?}"),
        })
    }

    /// `function [(parameters)] { expr | pattern { } | pigment { } }` (`.pov`).
    fn float_function(&mut self, pair: Pair<'_, Rule>) -> Result<FunctionDef, SceneError> {
        let span = self.span(&pair);
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let mut parameters = Vec::new();
        let mut body = None;
        for part in pair.into_inner().skip(1) {
            match part.as_rule() {
                // `x`, `y` and `z` are keywords elsewhere, and names here.
                Rule::function_parameters => {
                    for name in part.into_inner() {
                        let span = self.span(&name);
                        parameters.push(Ident { name: name.as_str().to_string(), span });
                    }
                }
                Rule::pattern_texture | Rule::function_pigment | Rule::transform | Rule::expr => {
                    body = Some(self.function_body(part)?)
                }
                rule => unreachable!("no {rule:?} in a function"),
            }
        }
        self.leave();
        let body = body.expect("the grammar gives a function its body");
        Ok(FunctionDef { parameters, body, span })
    }

    /// A function's body: `pattern { }`, `pigment { }` or an expression.
    fn function_body(&mut self, part: Pair<'_, Rule>) -> Result<FunctionBody, SceneError> {
        Ok(match part.as_rule() {
            Rule::pattern_texture => {
                let span = self.span(&part);
                FunctionBody::Pattern(self.texture_node(part, span)?)
            }
            Rule::function_pigment => FunctionBody::Pigment(self.appearance(inner_pair(&part))?),
            Rule::transform => FunctionBody::Transform(self.transform(part)?),
            Rule::expr => FunctionBody::Expr(self.expr(part)?),
            rule => unreachable!("no {rule:?} in a function"),
        })
    }

    /// `sphere_sweep { spline count, points... [tolerance t] items }` (`.pov`).
    fn sphere_sweep(&mut self, pair: Pair<'_, Rule>, span: Span) -> Result<Object, SceneError> {
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let mut inner = pair.into_inner().skip(1).peekable();
        let spline = match inner_pair(&inner.next().expect("the spline")).as_rule() {
            Rule::kw_linear_spline => SweepSpline::Linear,
            Rule::kw_cubic_spline => SweepSpline::Cubic,
            Rule::sweep_b_spline => SweepSpline::BSpline,
            rule => unreachable!("no sweep spline {rule:?}"),
        };
        let count = self.leading_argument(&mut inner)?;
        let mut rest = Vec::new();
        let mut tolerance = None;
        while let Some(p) = inner.next() {
            match p.as_rule() {
                Rule::sweep_tolerance => {
                    tolerance = Some(self.expr(inner.next().expect("the tolerance"))?);
                }
                _ => rest.push(p),
            }
        }
        let (points, items) = self.listed_and_items(rest, is_value)?;
        self.leave();
        let shape = Shape::SphereSweep { spline, count, points, tolerance };
        Ok(Object { shape, items, span })
    }

    /// `height_field { ... }` (`.pov`): where its heights come from, its settings, and the
    /// object's other items.
    fn height_field(&mut self, pair: Pair<'_, Rule>, span: Span) -> Result<Object, SceneError> {
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let mut parts = pair.into_inner().skip(1);
        let source = parts.next().expect("the grammar gives the heights");
        let ident =
            |b: &Self, p: &Pair<'_, Rule>| Ident { name: p.as_str().to_string(), span: b.span(p) };
        let source = match source.as_rule() {
            Rule::hf_function => {
                let at = self.span(&source);
                let mut inner =
                    source.into_inner().skip(1).filter(|p| p.as_rule() != Rule::arg_comma);
                let mut next = || inner.next().expect("the grammar gives the function's parts");
                let (width, height, body) = (next(), next(), next());
                let (width, height) = (self.expr(width)?, self.expr(height)?);
                let body = Box::new(FunctionDef {
                    parameters: Vec::new(),
                    body: self.function_body(body)?,
                    span: at,
                });
                HeightSource::Function { width, height, body }
            }
            Rule::hf_image => {
                let mut inner = source.into_inner().peekable();
                let format =
                    inner.next_if(|p| p.as_rule() == Rule::hf_type).map(|p| ident(self, &p));
                let file = self.expr(inner.next().expect("the grammar gives the file"))?;
                let mut options = Vec::new();
                while let Some(word) = inner.next() {
                    let value = inner.next_if(|p| p.as_rule() == Rule::expr);
                    let value = value.map(|v| self.expr(v)).transpose()?;
                    inner.next_if(|p| p.as_rule() == Rule::truth_value);
                    options.push((ident(self, &word), value));
                }
                HeightSource::Image { format, file, options }
            }
            rule => unreachable!("no height field source {rule:?}"),
        };
        let mut shape = HeightField { source, flags: Vec::new(), water_level: None };
        let mut rest = Vec::new();
        for part in parts {
            if part.as_rule() != Rule::hf_setting {
                rest.push(part);
                continue;
            }
            let mut inner = part.into_inner();
            let word = inner.next().expect("the word");
            match (word.as_rule(), inner.next()) {
                (Rule::hf_water_level, Some(level)) => shape.water_level = Some(self.expr(level)?),
                (_, truth) => {
                    let on = truth.is_none_or(|t| truth_of(&inner_pair(&t)));
                    shape.flags.push((ident(self, &word), on));
                }
            }
        }
        let items = self.items(rest.into_iter())?;
        self.leave();
        Ok(Object { shape: Shape::HeightField(Box::new(shape)), items, span })
    }

    /// `pigment_pattern { ... }` (`.pov`): its pigment, as the colour function whose gray is the
    /// pattern.
    fn pigment_pattern(&mut self, pair: Pair<'_, Rule>) -> Result<FunctionDef, SceneError> {
        let span = self.span(&pair);
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let items = self.items(pair.into_inner().skip(1))?;
        self.leave();
        let pigment = Appearance { kind: AppearanceKind::Pigment, items, span: span.clone() };
        Ok(FunctionDef { parameters: Vec::new(), body: FunctionBody::Pigment(pigment), span })
    }

    /// `isosurface { ... }` (`.pov`): its function, container and settings, and the object's
    /// other items.
    fn parametric(&mut self, pair: Pair<'_, Rule>, span: Span) -> Result<Object, SceneError> {
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let (mut functions, mut uv) = (Vec::new(), Vec::new());
        let (mut container, mut settings, mut rest) = (None, Vec::new(), Vec::new());
        for part in pair.into_inner().skip(1) {
            match part.as_rule() {
                Rule::float_function => functions.push(self.float_function(part)?),
                Rule::arg_comma => {}
                Rule::expr if uv.len() < 2 => uv.push(self.expr(part)?),
                Rule::contained_by => {
                    let object = part.into_inner().nth(1).expect("the container");
                    container = Some(self.object(object)?);
                }
                Rule::parametric_setting => {
                    let mut inner = part.into_inner();
                    let word = inner.next().expect("the word");
                    let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                    let values = inner.map(|value| self.expr(value)).collect::<Result<_, _>>()?;
                    settings.push((key, values));
                }
                _ => rest.push(part),
            }
        }
        let items = self.items(rest.into_iter())?;
        self.leave();
        let functions: [FunctionDef; 3] =
            functions.try_into().expect("the grammar gives three functions");
        let uv: [Expr; 2] = uv.try_into().expect("the grammar gives two corners");
        let shape = Parametric { functions: Box::new(functions), uv, container, settings };
        Ok(Object { shape: Shape::Parametric(Box::new(shape)), items, span })
    }

    fn isosurface(&mut self, pair: Pair<'_, Rule>, span: Span) -> Result<Object, SceneError> {
        self.pov_only(&inner_pair(&pair), None)?;
        self.enter(&pair)?;
        let mut shape = Isosurface { function: None, container: None, settings: Vec::new() };
        let mut rest = Vec::new();
        for part in pair.into_inner().skip(1) {
            match part.as_rule() {
                Rule::float_function => shape.function = Some(self.float_function(part)?),
                Rule::contained_by => {
                    let object = part.into_inner().nth(1).expect("the container");
                    shape.container = Some(self.object(object)?);
                }
                Rule::isosurface_setting => {
                    let mut inner = part.into_inner();
                    let word = inner.next().expect("the word");
                    let key = Ident { name: word.as_str().to_string(), span: self.span(&word) };
                    let mut values = Vec::new();
                    for value in inner {
                        match value.as_rule() {
                            // `max_trace all_intersections`: the flag alone.
                            Rule::isosurface_flag => {
                                let span = self.span(&value);
                                let flag = Ident { name: value.as_str().to_string(), span };
                                shape.settings.push((flag, Vec::new()));
                            }
                            _ => values.push(self.expr(value)?),
                        }
                    }
                    let flag_alone = word.as_rule() == Rule::isosurface_flag;
                    if flag_alone || !values.is_empty() {
                        shape.settings.push((key, values));
                    }
                }
                _ => rest.push(part),
            }
        }
        let items = self.items(rest.into_iter())?;
        self.leave();
        Ok(Object { shape: Shape::Isosurface(Box::new(shape)), items, span })
    }

    fn texture(&mut self, pair: Pair<'_, Rule>) -> Result<Texture, SceneError> {
        let span = self.span(&pair);
        self.texture_node(inner_pair(&pair), span)
    }

    /// A texture node's pair (`checker`, `pattern_texture`, ...) starting at `span`.
    fn texture_node(&mut self, node: Pair<'_, Rule>, span: Span) -> Result<Texture, SceneError> {
        self.enter(&node)?;
        let kind = match node.as_rule() {
            Rule::checker => TextureKind::Checker,
            Rule::stripes => TextureKind::Stripes,
            Rule::gradient => TextureKind::Gradient,
            Rule::noise => TextureKind::Noise,
            Rule::marble => TextureKind::Marble,
            Rule::wood => TextureKind::Wood,
            Rule::image_map => TextureKind::ImageMap,
            Rule::mix => TextureKind::Mix,
            Rule::pattern_texture => TextureKind::Pattern,
            rule => unreachable!("no texture {rule:?}"),
        };
        let mut inner = node.into_inner().skip(1).peekable();
        let mut arguments = Vec::new();
        while let Some(arg) = inner.next_if(|p| p.as_rule() == Rule::texture_arg) {
            arguments.push(self.texture_arg(arg)?);
        }
        let file = match kind {
            TextureKind::ImageMap => Some(self.expr(inner.next().expect("the file"))?),
            _ => None,
        };
        let items = self.items(inner)?;
        self.leave();
        Ok(Texture { kind, arguments, file, items, span })
    }

    fn texture_param(&mut self, pair: Pair<'_, Rule>) -> Result<TextureParam, SceneError> {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let kind = match inner.next().expect("the key").as_rule() {
            Rule::kw_axis => TextureParamKind::Axis,
            Rule::kw_octaves => TextureParamKind::Octaves,
            Rule::kw_turbulence => TextureParamKind::Turbulence,
            rule => unreachable!("no texture parameter {rule:?}"),
        };
        Ok(TextureParam { kind, value: self.expr(inner.next().expect("the value"))?, span })
    }

    /// A `colour` pair: `rgb e` or an expression.
    fn colour(&mut self, pair: Pair<'_, Rule>) -> Result<Colour, SceneError> {
        let span = self.span(&pair);
        Ok(Colour { value: self.value_expr(pair)?, span })
    }

    /// An `expr`, or an `rgb e` (a `colour`, `rgb_colour` or `argument` pair).
    fn value_expr(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        match pair.as_rule() {
            Rule::expr => self.expr(pair),
            Rule::rgb_colour | Rule::colour | Rule::argument => {
                let span = self.span(&pair);
                let mut inner = pair.into_inner().peekable();
                if let Some(word) = inner.next_if(|p| p.as_rule() == Rule::colour_word) {
                    self.pov_only(&inner_pair(&word), None)?;
                }
                let first = inner.next_if(|p| p.as_rule() != Rule::colour_part);
                let base = match first {
                    None => None,
                    Some(first) => Some(match first.as_rule() {
                        Rule::kw_rgb => {
                            let value = self.expr(inner.next().expect("the colour's value"))?;
                            Expr { kind: ExprKind::Rgb(Box::new(value)), span: span.clone() }
                        }
                        Rule::kw_rgbf | Rule::kw_rgbt | Rule::kw_rgbft | Rule::kw_srgb => {
                            let pov_kind = match first.as_rule() {
                                Rule::kw_rgbf => PovColourKind::Rgbf,
                                Rule::kw_rgbt => PovColourKind::Rgbt,
                                Rule::kw_rgbft => PovColourKind::Rgbft,
                                _ => PovColourKind::Srgb,
                            };
                            self.pov_only(&first, None)?;
                            let value = self.expr(inner.next().expect("the colour's value"))?;
                            let kind = ExprKind::PovColour(pov_kind, Box::new(value));
                            Expr { kind, span: span.clone() }
                        }
                        _ => self.value_expr(first)?,
                    }),
                };
                let mut parts = Vec::new();
                for part in inner {
                    let mut pieces = part.into_inner();
                    let channel = pieces.next().expect("the component");
                    self.pov_only(&channel, None)?;
                    let which = match channel.as_str() {
                        "red" => ColourChannel::Red,
                        "green" => ColourChannel::Green,
                        "blue" => ColourChannel::Blue,
                        "filter" => ColourChannel::Filter,
                        "transmit" => ColourChannel::Transmit,
                        other => unreachable!("no colour component `{other}`"),
                    };
                    parts.push((which, self.expr(pieces.next().expect("its value"))?));
                }
                match (base, parts.is_empty()) {
                    (Some(base), true) => Ok(base),
                    (base, _) => Ok(Expr {
                        kind: ExprKind::ColourParts { base: base.map(Box::new), parts },
                        span,
                    }),
                }
            }
            // A macro's argument that is a block (`.pov`).
            Rule::pigment
            | Rule::finish
            | Rule::pov_texture
            | Rule::interior
            | Rule::normal
            | Rule::object
            | Rule::color_map
            | Rule::float_function => {
                let span = self.span(&pair);
                let word = match pair.as_rule() {
                    Rule::object => inner_pair(&inner_pair(&pair)),
                    _ => inner_pair(&pair),
                };
                self.pov_only(&word, None)?;
                Ok(Expr { kind: ExprKind::Block(Box::new(self.declared(pair)?)), span })
            }
            rule => unreachable!("no value {rule:?}"),
        }
    }

    /// An `expr` pair: operands and operators by precedence, then `? :`.
    fn expr(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        let mut inner = pair.into_inner().peekable();
        let mut parts = Vec::new();
        while let Some(part) = inner.next_if(|p| p.as_rule() != Rule::expr) {
            parts.push(part);
        }
        let condition = self.operation(parts)?;
        match (inner.next(), inner.next()) {
            (Some(then), Some(otherwise)) => {
                let span = condition.span.clone();
                self.enter(&then)?;
                let then = self.expr(then)?;
                let otherwise = self.expr(otherwise)?;
                self.leave();
                Ok(Expr {
                    kind: ExprKind::Ternary {
                        condition: Box::new(condition),
                        then: Box::new(then),
                        otherwise: Box::new(otherwise),
                    },
                    span,
                })
            }
            _ => Ok(condition),
        }
    }

    /// An `arithmetic_expr` pair (a vector's component, a color_map position).
    fn arithmetic(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        self.operation(pair.into_inner().collect())
    }

    /// Operands between infix operators, combined by precedence (left to right within a level).
    fn operation(&mut self, parts: Vec<Pair<'_, Rule>>) -> Result<Expr, SceneError> {
        let mut operands: Vec<Expr> = Vec::new();
        let mut operators: Vec<(BinaryOp, Span)> = Vec::new();
        fn reduce(operands: &mut Vec<Expr>, operators: &mut Vec<(BinaryOp, Span)>) {
            let (op, op_span) = operators.pop().expect("an operator");
            let right = operands.pop().expect("a right operand");
            let left = operands.pop().expect("a left operand");
            let span = left.span.clone();
            operands.push(Expr {
                kind: ExprKind::Binary {
                    op,
                    op_span,
                    left: Box::new(left),
                    right: Box::new(right),
                },
                span,
            });
        }
        for part in parts {
            let op = match part.as_rule() {
                Rule::operand => {
                    operands.push(self.operand(part)?);
                    continue;
                }
                Rule::or => BinaryOp::Or,
                Rule::and => BinaryOp::And,
                Rule::less => BinaryOp::Less,
                Rule::less_equal => BinaryOp::LessEqual,
                Rule::greater => BinaryOp::Greater,
                Rule::greater_equal => BinaryOp::GreaterEqual,
                Rule::equal => BinaryOp::Equal,
                Rule::not_equal => BinaryOp::NotEqual,
                Rule::add => BinaryOp::Add,
                Rule::subtract => BinaryOp::Subtract,
                Rule::multiply => BinaryOp::Multiply,
                Rule::divide => BinaryOp::Divide,
                rule => unreachable!("no operator {rule:?}"),
            };
            while operators.last().is_some_and(|(top, _)| top.precedence() >= op.precedence()) {
                reduce(&mut operands, &mut operators);
            }
            operators.push((op, self.span(&part)));
        }
        while !operators.is_empty() {
            reduce(&mut operands, &mut operators);
        }
        Ok(operands.pop().expect("an operand"))
    }

    /// Prefix signs, a primary, then components and indices.
    fn operand(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        let mut prefixes: Vec<(UnaryOp, Span)> = Vec::new();
        let mut value: Option<Expr> = None;
        for part in pair.into_inner() {
            let rule = part.as_rule();
            let unary = match rule {
                Rule::negate => Some(UnaryOp::Negate),
                Rule::plus => Some(UnaryOp::Plus),
                Rule::not => Some(UnaryOp::Not),
                _ => None,
            };
            if let Some(op) = unary {
                if prefixes.len() == MAX_NESTING {
                    return Err(
                        self.error(&part, format!("more than {MAX_NESTING} signs in a row"))
                    );
                }
                prefixes.push((op, self.span(&part)));
                continue;
            }
            value = Some(match (rule, value) {
                (Rule::component, Some(v)) => {
                    let axis = match part.as_str() {
                        ".x" | ".u" | ".red" => 0,
                        ".y" | ".v" | ".green" => 1,
                        ".z" | ".blue" => 2,
                        ".filter" | ".t" => 3,
                        ".transmit" => 4,
                        ".gray" => crate::function::GRAY,
                        other => unreachable!("no component `{other}`"),
                    };
                    if !matches!(part.as_str(), ".x" | ".y" | ".z") {
                        self.pov_only(&part, None)?;
                    }
                    let span = v.span.clone();
                    Expr {
                        kind: ExprKind::Component {
                            value: Box::new(v),
                            axis,
                            span: self.span(&part),
                        },
                        span,
                    }
                }
                (Rule::index, Some(v)) => {
                    self.enter(&part)?;
                    let index = self.first_expr(&part)?;
                    self.leave();
                    let span = v.span.clone();
                    Expr {
                        kind: ExprKind::Index { array: Box::new(v), index: Box::new(index) },
                        span,
                    }
                }
                (_, None) => self.primary(part)?,
                (rule, Some(_)) => unreachable!("no postfix {rule:?}"),
            });
        }
        let mut value = value.expect("an operand has a primary");
        for (op, span) in prefixes.into_iter().rev() {
            value = Expr { kind: ExprKind::Unary { op, operand: Box::new(value) }, span };
        }
        Ok(value)
    }

    fn primary(&mut self, pair: Pair<'_, Rule>) -> Result<Expr, SceneError> {
        let span = self.span(&pair);
        let kind =
            match pair.as_rule() {
                Rule::number => ExprKind::Number(pair.as_str().parse().map_err(|_| {
                    self.error(&pair, format!("`{}` is not a number", pair.as_str()))
                })?),
                Rule::string => ExprKind::String(self.string(&pair)?),
                Rule::paren => {
                    self.enter(&pair)?;
                    let inner = self.first_expr(&pair)?;
                    self.leave();
                    return Ok(inner);
                }
                Rule::vector => {
                    self.enter(&pair)?;
                    let components = self.vector_components(pair)?;
                    self.leave();
                    ExprKind::Vector(components)
                }
                Rule::call => {
                    self.enter(&pair)?;
                    let call = self.call(pair)?;
                    self.leave();
                    call
                }
                Rule::ident => {
                    let name = pair.as_str();
                    match keywords::lookup(name).map(|k| k.kind) {
                        None => ExprKind::Ident(name.to_string()),
                        Some(KeywordKind::Constant(c)) => ExprKind::Constant(c),
                        Some(KeywordKind::Function(_)) => {
                            return Err(self.error(
                                &pair,
                                format!("`{name}` is a function: call it as `{name}(...)`"),
                            ));
                        }
                        Some(KeywordKind::Syntax) => {
                            return Err(
                                self.error(&pair, format!("`{name}` is a keyword, not a value"))
                            );
                        }
                    }
                }
                rule => unreachable!("no primary {rule:?}"),
            };
        Ok(Expr { kind, span })
    }

    /// A `call` or `macro_call` pair: a built-in function or a macro, told apart by the name.
    fn call(&mut self, pair: Pair<'_, Rule>) -> Result<ExprKind, SceneError> {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let name = inner.next().expect("the name");
        let arguments: Vec<Expr> = inner.map(|a| self.value_expr(a)).collect::<Result<_, _>>()?;
        match keywords::lookup(name.as_str()).map(|k| k.kind) {
            None => Ok(ExprKind::Call(Call {
                name: Ident { name: name.as_str().to_string(), span: self.span(&name) },
                arguments,
                span,
            })),
            Some(KeywordKind::Function(f)) => {
                let (least, most) = f.arity();
                let given = arguments.len();
                if given < least || most.is_some_and(|most| given > most) {
                    let plural = if most.unwrap_or(least) == 1 { "" } else { "s" };
                    let count = match most {
                        Some(most) if most == least => format!("{least}"),
                        Some(most) => format!("{least} or {most}"),
                        None => format!("at least {least}"),
                    };
                    return Err(SceneError::at(
                        &span,
                        format!("`{}` takes {count} argument{plural}, not {given}", f.name()),
                    ));
                }
                Ok(ExprKind::Function(f, arguments))
            }
            Some(KeywordKind::Constant(_) | KeywordKind::Syntax) => Err(self.error(
                &name,
                format!("`{}` is a keyword, not a function or macro", name.as_str()),
            )),
        }
    }

    /// The text of a `string` pair, escapes resolved.
    fn string(&self, pair: &Pair<'_, Rule>) -> Result<String, SceneError> {
        let raw = pair.clone().into_inner().next().map_or("", |p| p.as_str());
        let mut text = String::with_capacity(raw.len());
        let mut chars = raw.chars();
        while let Some(c) = chars.next() {
            if c != '\\' {
                text.push(c);
                continue;
            }
            match chars.next() {
                Some('n') => text.push('\n'),
                Some('t') => text.push('\t'),
                Some('"') => text.push('"'),
                Some('\\') => text.push('\\'),
                other => {
                    let shown = other.map_or(String::new(), String::from);
                    return Err(self.error(
                        pair,
                        format!(
                            "unknown escape `\\{shown}` in a string (known: \\n \\t \\\" \\\\)"
                        ),
                    ));
                }
            }
        }
        Ok(text)
    }
}

/// Adds an item to the innermost open block (after an `#else`, to its `otherwise` items).
fn gather(stack: &mut [(Option<Open>, Vec<Item>)], item: Item) {
    let (open, items) = stack.last_mut().expect("the body");
    match open {
        Some(Open::Switch { skipping: true, .. }) => {}
        Some(
            Open::If { otherwise: Some(rest), .. } | Open::Switch { otherwise: Some(rest), .. },
        ) => rest.push(item),
        _ => items.push(item),
    }
}

/// A block's item, once its `#end` is seen.
fn close(open: Open, items: Vec<Item>) -> Item {
    match open {
        Open::If { mut branches, condition, otherwise, span } => match otherwise {
            // Items after `#else` were gathered into `otherwise`; `items` is then empty.
            Some(rest) => Item::If { branches, otherwise: Some(rest), span },
            None => {
                branches.push((condition, items));
                Item::If { branches, otherwise: None, span }
            }
        },
        Open::While { condition, span } => Item::While { condition, body: items, span },
        Open::For { variable, from, to, step, span } => {
            Item::For { variable, from, to, step, body: items, span }
        }
        Open::Macro { name, parameters, span } => {
            Item::Macro(Arc::new(MacroDef { name, parameters, body: items, span }))
        }
        Open::Switch { value, mut clauses, current, otherwise, span, .. } => {
            if let Some(test) = current {
                clauses.push(SwitchClause { test, items, breaks: false });
            }
            Item::Switch { value, clauses, otherwise, span }
        }
    }
}

/// The first inner pair of `pair`.
/// A truth value as written (`on`, `off`, `true`, ..., or a number: true unless 0).
fn truth_of(truth: &Pair<'_, Rule>) -> bool {
    match truth.as_str() {
        "off" | "false" | "no" => false,
        "on" | "true" | "yes" => true,
        number => number.parse::<f64>().is_ok_and(|n| n != 0.0),
    }
}

fn inner_pair<'i>(pair: &Pair<'i, Rule>) -> Pair<'i, Rule> {
    pair.clone().into_inner().next().expect("the grammar gives an inner pair")
}

/// Whether `item` is, or a directive's block around it holds, an item for which `member` holds.
fn holds(item: &Item, member: fn(&Item) -> bool) -> bool {
    let any = |items: &[Item]| items.iter().any(|item| holds(item, member));
    match item {
        Item::If { branches, otherwise, .. } => {
            branches.iter().any(|(_, items)| any(items)) || otherwise.as_deref().is_some_and(any)
        }
        Item::Switch { clauses, otherwise, .. } => {
            clauses.iter().any(|clause| any(&clause.items)) || otherwise.as_deref().is_some_and(any)
        }
        Item::While { body, .. } | Item::For { body, .. } => any(body),
        item => member(item),
    }
}

/// A listed point (a value standing alone).
fn is_value(item: &Item) -> bool {
    matches!(item, Item::Value(_))
}

/// A mesh's `triangle` or `smooth_triangle`.
fn is_triangle(item: &Item) -> bool {
    matches!(
        item,
        Item::Object(Object { shape: Shape::Triangle { .. } | Shape::SmoothTriangle { .. }, .. })
    )
}
