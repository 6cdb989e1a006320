//! POV-Ray's patterns and their modifiers (`turbulence octaves omega lambda`, `frequency phase`,
//! the wave types, `warp { }`, the pattern's own parameters and its map), read the same in a
//! pigment, a normal, a texture and `.scn`'s `pattern { }` (`docs/language.md`, Patterns).

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::appearance::Finish;
use super::pigment::{Pigment, Stop};
use super::{Body, Evaluator};
use crate::diagnostic::{SceneError, Span};
use crate::function::FloatFunction;
use crate::graph::{
    BlackHole, Crackle, Field, FieldShape, Fractal, FractalColouring, FractalSet, Mapping,
    MappingSurface, NormalNode, Pattern, PatternFunction, SlopeMap, Transform, Turbulence, Warp,
    Wave, compose,
};
use crate::lang::dialect::Dialect;
use crate::lang::syntax::{
    Colour, FunctionBody, FunctionDef, Item, MapKind, PatternKind, TextureArg, TextureParamKind,
};
use crate::lang::value::Value;
use crate::texture::default_wave;

/// A pattern map's entries as they are read (each evaluated where it stands, so that a `#for`
/// loop's variable is the one of its turn).
#[derive(Debug)]
pub struct MapState {
    pub kind: MapKind,
    /// `average`'s map: positions are weights (> 0), in any order.
    pub weights: bool,
    /// A pigment or texture map's pigments.
    pub textures: Vec<(f32, Pigment)>,
    pub normals: Vec<(f32, NormalNode)>,
    pub slopes: SlopeMap,
    /// A `.pov` texture_map's textures' one finish.
    pub finish: Option<Finish>,
}

/// A pattern's items as they are read.
#[derive(Debug, Clone, Default)]
pub struct PatternState {
    /// The pattern's word, its arguments (colours, axis, count, amount) and where it stands.
    pub word: Option<(PatternKind, Vec<Colour>, Span)>,
    turbulence: Option<Vec3>,
    octaves: Option<u32>,
    omega: Option<f32>,
    lambda: Option<f32>,
    frequency: Option<f32>,
    phase: Option<f32>,
    wave: Option<Wave>,
    brick_size: Option<Vec3>,
    mortar: Option<f32>,
    control0: Option<f32>,
    control1: Option<f32>,
    agate_turb: Option<f32>,
    /// crackle's `form`, `metric`, `offset` and `solid`.
    crackle_form: Option<Vec3>,
    metric: Option<f32>,
    offset: Option<f32>,
    solid: bool,
    /// A normal's `accuracy`: the span of the differences that take its gradient.
    pub accuracy: Option<f32>,
    /// A normal's `bump_size`: its amount, as the number after the pattern's word.
    pub bump_size: Option<f32>,
    /// A fractal's `interior`, `exterior` and `exponent`.
    interior: Option<FractalColouring>,
    exterior: Option<FractalColouring>,
    exponent: Option<u32>,
    /// The `warp { }`s in the order written (POV-Ray applies the last written first).
    pub warps: Vec<Warp>,
    /// The function pattern's compiled function.
    function: Option<Arc<FloatFunction>>,
    /// A `color_map`'s entries.
    pub color_map: Option<Vec<Stop>>,
    /// A pigment, normal, texture or slope map: its kind, entries (read by the caller) and span.
    pub map: Option<(MapKind, Vec<Item>, Span)>,
    /// The pattern a new word replaces (`pigment { P_Declared granite }`, `normal { N dents }`):
    /// POV-Ray's word changes only the pattern's type, so what the new one is not given is this
    /// one's (`field_shape`).
    pub base: Option<FieldShape>,
}

impl PatternState {
    /// Adds `warp`, written after the transforms `before`: POV-Ray applies those to the point
    /// the warp gives (its transforms and warps are one list, walked from the last written), so
    /// `gradient x scale 2 warp { repeat x*0.5 }` repeats every 0.5 of the object's space.
    pub fn warp_after(&mut self, before: &[Transform], warp: Warp) {
        if !before.is_empty() {
            self.warps.push(Warp::Transform(compose(before).inverse()));
        }
        self.warps.push(warp);
    }
}

impl Evaluator {
    /// Reads `item` into `state` if it is part of a pattern; `false` if it is not.
    pub(super) fn pattern_item(
        &mut self,
        item: &Item,
        state: &mut PatternState,
    ) -> Result<bool, SceneError> {
        match item {
            Item::Pattern { kind, arguments, function, span } => {
                state.word = Some((*kind, arguments.clone(), span.clone()));
                state.function = match (kind, function.as_deref()) {
                    (
                        PatternKind::PigmentPattern,
                        Some(FunctionDef { body: FunctionBody::Pigment(pigment), .. }),
                    ) => Some(self.gray_function(pigment)?),
                    (_, Some(def)) => Some(self.float_function(def)?),
                    (_, None) => None,
                };
            }
            Item::TextureParam(param) => match param.kind {
                TextureParamKind::Turbulence => {
                    let amount = self.splat_vec3(&param.value)?;
                    if amount.min_element() < 0.0 {
                        return Err(SceneError::at(
                            &param.value.span,
                            format!("turbulence {amount} is negative"),
                        ));
                    }
                    state.turbulence = Some(amount);
                }
                TextureParamKind::Octaves => {
                    state.octaves = Some(self.integer(&param.value, 1, 16)? as u32)
                }
                TextureParamKind::Axis => return Ok(false),
            },
            Item::ColorMap { entries, span } => {
                let mut map = Vec::new();
                self.exec(entries, &mut super::Body::ColorMap(&mut map))?;
                if state.color_map.replace(map).is_some() || state.map.is_some() {
                    return Err(SceneError::at(span, "a second map"));
                }
            }
            Item::PatternMap { kind, entries, span } => {
                if state.color_map.is_some() || state.map.is_some() {
                    return Err(SceneError::at(span, "a second map"));
                }
                state.map = Some((*kind, entries.clone(), span.clone()));
            }
            Item::PovParam { key, value, items } => {
                let number = |e: &mut Self| -> Result<f32, SceneError> {
                    match value {
                        Some(v) => e.single(&v.value),
                        None => {
                            Err(SceneError::at(&key.span, format!("`{}` needs a value", key.name)))
                        }
                    }
                };
                let positive = |e: &mut Self, what: &str| -> Result<f32, SceneError> {
                    match value {
                        Some(v) => e.positive(&v.value, what),
                        None => number(e),
                    }
                };
                match key.name.as_str() {
                    "frequency" => state.frequency = Some(number(self)?),
                    "phase" => state.phase = Some(number(self)?),
                    "omega" => state.omega = Some(number(self)?),
                    "lambda" => state.lambda = Some(number(self)?),
                    "mortar" => state.mortar = Some(number(self)?.max(0.0)),
                    "control0" => state.control0 = Some(number(self)?),
                    "control1" => state.control1 = Some(number(self)?),
                    "agate_turb" => state.agate_turb = Some(number(self)?),
                    "offset" => state.offset = Some(number(self)?),
                    "solid" => state.solid = true,
                    "accuracy" => state.accuracy = Some(positive(self, "a normal's accuracy")?),
                    "bump_size" => state.bump_size = Some(number(self)?),
                    "metric" => state.metric = Some(positive(self, "crackle's metric")?),
                    "form" => {
                        let v = value
                            .as_ref()
                            .ok_or_else(|| SceneError::at(&key.span, "`form` needs a vector"))?;
                        state.crackle_form = Some(self.vec3(&v.value)?);
                    }
                    "brick_size" => {
                        let v = value.as_ref().ok_or_else(|| {
                            SceneError::at(&key.span, "`brick_size` needs a size")
                        })?;
                        let size = self.splat_vec3(&v.value)?;
                        if size.min_element() <= 0.0 {
                            return Err(SceneError::at(
                                &v.span,
                                format!("brick_size {size} must be positive"),
                            ));
                        }
                        state.brick_size = Some(size);
                    }
                    "ramp_wave" => state.wave = Some(Wave::Ramp),
                    "sine_wave" => state.wave = Some(Wave::Sine),
                    "triangle_wave" => state.wave = Some(Wave::Triangle),
                    "scallop_wave" => state.wave = Some(Wave::Scallop),
                    "cubic_wave" => state.wave = Some(Wave::Cubic),
                    "poly_wave" => {
                        let exponent = match value {
                            Some(v) => self.single(&v.value)?,
                            None => 1.0,
                        };
                        state.wave = Some(Wave::Poly(exponent));
                    }
                    "warp" => state.warps.push(self.warp(items, &key.span)?),
                    "interior" | "exterior" => {
                        let v = value.as_ref().expect("the grammar gives the type");
                        let kind = self.integer(&v.value, 0, 6)? as u32;
                        let factor = match items.first() {
                            Some(Item::Value(factor)) => self.single(factor)?,
                            _ => 1.0,
                        };
                        let colouring = Some(FractalColouring { kind, factor });
                        if key.name == "interior" {
                            state.interior = colouring;
                        } else {
                            state.exterior = colouring;
                        }
                    }
                    "exponent" => {
                        let v = value.as_ref().expect("the grammar gives the exponent");
                        state.exponent = Some(self.integer(&v.value, 2, 4)? as u32);
                    }
                    // The colour of POV-Ray's quick previews (`+Q5` and below), which a full
                    // render ignores: checked, not used.
                    "uv_mapping" => self.warn_uv_mapping(&key.span),
                    "quick_color" | "quick_colour" => {
                        if let Some(colour) = value {
                            self.pov_colour(colour)?;
                        }
                    }
                    _ => return Ok(false),
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// `warp { turbulence ... | repeat ... | black_hole ... }`: the first of those three words
    /// names the warp, as in POV-Ray, and the other items are that warp's (a black hole's
    /// `repeat <r>` and `turbulence <t>` are its own: holes repeated in blocks of r, each moved
    /// by up to t).
    fn warp(&mut self, items: &[Item], at: &Span) -> Result<Warp, SceneError> {
        let kind = items
            .iter()
            .find_map(|item| match item {
                Item::PovParam { key, .. }
                    if matches!(
                        key.name.as_str(),
                        "turbulence"
                            | "repeat"
                            | "black_hole"
                            | "planar"
                            | "cylindrical"
                            | "spherical"
                            | "toroidal"
                    ) =>
                {
                    Some(key.name.clone())
                }
                _ => None,
            })
            .ok_or_else(|| {
                SceneError::at(
                    at,
                    "a warp needs `turbulence`, `repeat`, `black_hole`, `planar`, `cylindrical`, \
                     `spherical` or `toroidal`",
                )
            })?;
        let mut turbulence = Turbulence { amount: Vec3::ZERO, octaves: 6, omega: 0.5, lambda: 2.0 };
        let (mut repeat, mut offset, mut flip) = (None, Vec3::ZERO, Vec3::ZERO);
        let mut hole = BlackHole::default();
        let (mut orientation, mut dist_exp) = (Vec3::Z, 0.0);
        let (mut offset_along, mut major_radius) = (0.0, 1.0);
        for item in items {
            let Item::PovParam { key, value, items: rest } = item else {
                return Err(Self::misplaced_in_warp(item));
            };
            let value = value.as_ref().map(|v| &v.value);
            let needs =
                |what: &str| SceneError::at(&key.span, format!("`{}` needs {what}", key.name));
            let belongs = |warp: &str| {
                SceneError::at(
                    &key.span,
                    format!("`{}` belongs to a `{warp}` warp, not to a `{kind}` warp", key.name),
                )
            };
            match (kind.as_str(), key.name.as_str()) {
                ("turbulence", "turbulence") => {
                    turbulence.amount = self.splat_vec3(value.ok_or_else(|| needs("an amount"))?)?
                }
                ("turbulence", "octaves") => {
                    turbulence.octaves =
                        self.integer(value.ok_or_else(|| needs("a count"))?, 1, 16)? as u32
                }
                ("turbulence", "omega") => {
                    turbulence.omega = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                ("turbulence", "lambda") => {
                    turbulence.lambda = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                ("repeat", "repeat") => {
                    let v = value.ok_or_else(|| needs("a direction"))?;
                    let direction = self.nonzero(v, "the repeat's direction")?;
                    let axis = direction.abs().max_position();
                    if direction.abs().cmpgt(Vec3::ZERO).bitmask().count_ones() != 1 {
                        return Err(SceneError::at(
                            &v.span,
                            format!("repeat {direction} must lie along x, y or z"),
                        ));
                    }
                    repeat = Some((axis, direction[axis].abs()));
                }
                ("repeat", "offset") => {
                    offset = self.vec3(value.ok_or_else(|| needs("a vector"))?)?
                }
                ("repeat", "flip") => flip = self.vec3(value.ok_or_else(|| needs("a vector"))?)?,
                ("black_hole", "black_hole") => {
                    hole.centre = self.vec3(value.ok_or_else(|| needs("a centre"))?)?;
                    let Some(Item::Value(radius)) = rest.first() else {
                        return Err(needs("a centre and a radius (`black_hole <c>, r`)"));
                    };
                    hole.radius = self.positive(radius, "the black hole's radius")?;
                }
                ("black_hole", "strength") => {
                    hole.strength = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                ("black_hole", "falloff") => {
                    hole.falloff = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                ("black_hole", "inverse") => hole.inverse = true,
                ("black_hole", "repeat") => {
                    let v = value.ok_or_else(|| needs("the size of the blocks"))?;
                    hole.repeat = self.splat_vec3(v)?;
                    if hole.repeat.min_element() < 0.0 {
                        return Err(SceneError::at(
                            &v.span,
                            format!(
                                "repeat {}: a black hole's blocks have no negative size \
                                 (0: not repeated along that axis)",
                                hole.repeat
                            ),
                        ));
                    }
                }
                ("black_hole", "turbulence") => {
                    let v = value.ok_or_else(|| needs("an amount"))?;
                    hole.jitter = self.splat_vec3(v)?;
                }
                ("planar", "planar") => {
                    // `planar [<orientation>, offset]`.
                    if let Some(v) = value {
                        orientation = self.nonzero(v, "the planar warp's orientation")?.normalize();
                        let Some(Item::Value(offset)) = rest.first() else {
                            return Err(needs("an orientation and an offset (`planar z, 0`)"));
                        };
                        offset_along = self.single(offset)?;
                    }
                }
                (
                    "cylindrical" | "spherical" | "toroidal",
                    "cylindrical" | "spherical" | "toroidal",
                ) if key.name == kind => {}
                ("cylindrical" | "spherical" | "toroidal", "orientation") => {
                    let v = value.ok_or_else(|| needs("a vector"))?;
                    orientation = self.nonzero(v, "the warp's orientation")?.normalize();
                }
                ("cylindrical" | "spherical" | "toroidal", "dist_exp") => {
                    dist_exp = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                ("toroidal", "major_radius") => {
                    major_radius = self.single(value.ok_or_else(|| needs("a value"))?)?
                }
                (_, "orientation" | "dist_exp") => {
                    return Err(belongs("cylindrical`, `spherical` or `toroidal"));
                }
                (_, "major_radius") => return Err(belongs("toroidal")),
                (_, "octaves" | "omega" | "lambda") => return Err(belongs("turbulence")),
                (_, "offset" | "flip") => return Err(belongs("repeat")),
                (_, "strength" | "falloff" | "inverse") => return Err(belongs("black_hole")),
                (
                    _,
                    "turbulence" | "repeat" | "black_hole" | "planar" | "cylindrical" | "spherical"
                    | "toroidal",
                ) => {
                    return Err(SceneError::at(
                        &key.span,
                        format!(
                            "`{}` in a `{kind}` warp: a warp is of one kind (write a second \
                             `warp {{ }}`)",
                            key.name
                        ),
                    ));
                }
                (_, other) => unreachable!("the grammar gives no warp item `{other}`"),
            }
        }
        match kind.as_str() {
            "turbulence" => Ok(Warp::Turbulence(turbulence)),
            "repeat" => {
                let (axis, width) = repeat.expect("a repeat warp has its `repeat`");
                Ok(Warp::Repeat { axis, width, offset, flip })
            }
            "black_hole" => Ok(Warp::BlackHole(hole)),
            "planar" => Ok(Warp::Mapping(Mapping {
                surface: MappingSurface::Planar { offset: offset_along },
                orientation,
                dist_exp,
            })),
            "cylindrical" => Ok(Warp::Mapping(Mapping {
                surface: MappingSurface::Cylindrical,
                orientation,
                dist_exp,
            })),
            "spherical" => Ok(Warp::Mapping(Mapping {
                surface: MappingSurface::Spherical,
                orientation,
                dist_exp,
            })),
            "toroidal" => Ok(Warp::Mapping(Mapping {
                surface: MappingSurface::Toroidal { major_radius },
                orientation,
                dist_exp,
            })),
            other => unreachable!("a warp's kind is one of three words, not `{other}`"),
        }
    }

    /// The pigment of the pattern `kind`: its value through its map (the color_map, a map of
    /// pigments or textures, a block pattern's colours, or black to white), or `average`'s
    /// mean, with the filter and transmit of the map's entries; and the finish of a `.pov`
    /// texture_map's textures.
    pub(super) fn pattern_texture(
        &mut self,
        kind: PatternKind,
        arguments: &[Colour],
        state: &PatternState,
        at: &Span,
    ) -> Result<(Pigment, Option<Finish>), SceneError> {
        let average = kind == PatternKind::Average;
        let mut finish = None;
        let mut map: Vec<(f32, Pigment)> = match (&state.color_map, &state.map) {
            (Some(stops), _) if !stops.is_empty() => {
                stops.iter().map(|s| (s.position, Pigment::of_stop(s))).collect()
            }
            (_, Some((map_kind, entries, span))) => match map_kind {
                MapKind::Pigment | MapKind::Texture => {
                    let map = self.map_entries(*map_kind, entries, average)?;
                    finish = map.finish;
                    map.textures
                }
                MapKind::Normal | MapKind::Slope => {
                    return Err(SceneError::at(
                        span,
                        format!("a {} stands in a normal", map_kind.word()),
                    ));
                }
            },
            _ => Vec::new(),
        };
        if average {
            if map.is_empty() {
                return Err(SceneError::at(at, "`average` needs a map of what it averages"));
            }
            let averaged = Pigment::mapped(map, Pattern::Average);
            let pigment = state.warps.iter().fold(averaged, |pigment, warp| pigment.warped(*warp));
            return Ok((pigment, finish));
        }
        if map.is_empty() {
            map = match block_colours(kind) {
                Some(defaults) => {
                    let given = &arguments[own_arguments(kind).min(arguments.len())..];
                    let last = (defaults.len() - 1) as f32;
                    let mut entries = Vec::new();
                    for (i, default) in defaults.into_iter().enumerate() {
                        let pigment = match given.get(i) {
                            Some(c) => self.dialect_pigment(c)?,
                            None => Pigment::solid(default, 0.0, 0.0),
                        };
                        entries.push((i as f32 / last, pigment));
                    }
                    entries
                }
                None => vec![
                    (0.0, Pigment::solid(Vec3::ZERO, 0.0, 0.0)),
                    (1.0, Pigment::solid(Vec3::ONE, 0.0, 0.0)),
                ],
            };
        }
        let shape = Box::new(self.field_shape(kind, arguments, state, at)?);
        let pigment = Pigment::mapped(map, |map| Pattern::Field { shape: shape.clone(), map });
        Ok((pigment, finish))
    }

    /// A block pattern's colour as the dialect reads it: with its filter and transmit in
    /// `.pov`.
    fn dialect_pigment(&mut self, colour: &Colour) -> Result<Pigment, SceneError> {
        match self.dialect {
            Dialect::Scn => Ok(Pigment::solid(self.colour(colour)?, 0.0, 0.0)),
            Dialect::Pov => {
                let (rgb, filter, transmit) = self.pov_colour(colour)?;
                Ok(Pigment::solid(rgb, filter, transmit))
            }
        }
    }

    /// A map's entries, each read where it stands.
    pub(super) fn map_entries(
        &mut self,
        kind: MapKind,
        entries: &[Item],
        weights: bool,
    ) -> Result<MapState, SceneError> {
        let mut state = MapState {
            kind,
            weights,
            textures: Vec::new(),
            normals: Vec::new(),
            slopes: Vec::new(),
            finish: None,
        };
        self.exec(entries, &mut Body::PatternMap(&mut state))?;
        Ok(state)
    }

    /// One `[position items]` of a map.
    pub(super) fn map_block(
        &mut self,
        item: &Item,
        state: &mut MapState,
    ) -> Result<(), SceneError> {
        let Item::MapBlock { position, items, span } = item else {
            return Err(Self::misplaced(item, &Body::PatternMap(state)));
        };
        let (at, position) = match position {
            Some(position) => (position.span.clone(), self.single(position)?),
            None if state.weights => (span.clone(), 1.0),
            None => {
                return Err(SceneError::at(
                    span,
                    format!("a {} entry needs its position: `[position ...]`", state.kind.word()),
                ));
            }
        };
        let previous = [
            state.textures.last().map(|e| e.0),
            state.normals.last().map(|e| e.0),
            state.slopes.last().map(|e| e.0),
        ]
        .into_iter()
        .flatten()
        .next()
        .unwrap_or(0.0);
        if state.weights {
            if position <= 0.0 {
                return Err(SceneError::at(
                    &at,
                    format!("average weight {position} must be positive"),
                ));
            }
        } else if !(previous..=1.0).contains(&position) {
            return Err(SceneError::at(
                &at,
                format!(
                    "{} position {position} must be in [0, 1] and not below the one before",
                    state.kind.word()
                ),
            ));
        }
        match state.kind {
            MapKind::Pigment => {
                let pigment = self.pigment_of(items, &Pigment::black())?;
                state.textures.push((position, pigment));
            }
            MapKind::Texture => {
                let node = match (self.dialect, items.as_slice()) {
                    (Dialect::Scn, [Item::Texture(t)]) => Pigment::opaque(self.texture(t)?),
                    (Dialect::Scn, [Item::Value(expr)]) => {
                        let colour = Colour { value: expr.clone(), span: expr.span.clone() };
                        Pigment::opaque(self.texture_arg(&TextureArg::Colour(colour))?)
                    }
                    (Dialect::Scn, _) => {
                        return Err(SceneError::at(
                            span,
                            "a texture_map entry is `[position texture]`",
                        ));
                    }
                    (Dialect::Pov, _) => {
                        let mut look = self.default_look.clone();
                        self.exec(items, &mut Body::Look(&mut look))?;
                        let first = state.finish.get_or_insert_with(|| look.finish.clone());
                        if (look.finish != *first || look.normal.is_some())
                            && !self.warned_map_finish
                        {
                            self.warned_map_finish = true;
                            let here = self.here(span);
                            self.warnings.push(format!(
                                "{here:?}: warning: the textures of a pattern differ in their \
                                 finish or normal: raydiance's materials vary only their diffuse \
                                 colour across a surface, so the first texture's finish is used \
                                 everywhere and the normals are not rendered (said once a scene)"
                            ));
                        }
                        look.pigment
                    }
                };
                state.textures.push((position, node));
            }
            MapKind::Normal => {
                let normal = self.normal_of(items, None)?.unwrap_or_else(NormalNode::flat);
                state.normals.push((position, normal));
            }
            MapKind::Slope => {
                let [Item::Value(expr)] = items.as_slice() else {
                    return Err(SceneError::at(
                        span,
                        "a slope_map entry is `[position <height, slope>]`",
                    ));
                };
                let (height, slope) = match self.value(expr)? {
                    Value::Numbers(n) if n.len() == 2 => (n[0], n[1]),
                    Value::Float(f) => (f, 0.0),
                    other => {
                        return Err(SceneError::at(
                            &expr.span,
                            format!("a slope_map entry is <height, slope>, not {}", other.kind()),
                        ));
                    }
                };
                state.slopes.push((position, height as f32, slope as f32));
            }
        }
        Ok(())
    }

    /// A fractal pattern from its arguments (`magnet`'s formula, `julia`'s c, the iterations)
    /// and its `interior`, `exterior` and `exponent` (POV-Ray's defaults: interior 0, 1;
    /// exterior 1, 1; exponent 2).
    fn fractal(
        &mut self,
        kind: PatternKind,
        arguments: &[Colour],
        state: &PatternState,
    ) -> Result<Fractal, SceneError> {
        let mut arguments = arguments.iter().map(|a| &a.value);
        let mut next = || arguments.next().expect("the grammar gives the fractal's arguments");
        let formula = match kind {
            PatternKind::Magnet | PatternKind::MagnetJulia => Some(self.integer(next(), 1, 2)?),
            _ => None,
        };
        let julia = match kind {
            PatternKind::Julia | PatternKind::MagnetJulia => {
                let c = next();
                match self.value(c)? {
                    Value::Numbers(n) if n.len() == 2 => Some(Vec2::new(n[0] as f32, n[1] as f32)),
                    other => {
                        return Err(SceneError::at(
                            &c.span,
                            format!(
                                "a julia pattern's c is a 2-vector <re, im>, not {}",
                                other.kind()
                            ),
                        ));
                    }
                }
            }
            _ => None,
        };
        let iterations = self.integer(next(), 1, 100_000)? as u32;
        let set = match (formula, julia) {
            (Some(formula), julia) => FractalSet::Magnet { formula: formula as u32, julia },
            (None, Some(c)) => FractalSet::Julia(c),
            (None, None) => FractalSet::Mandel,
        };
        Ok(Fractal {
            set,
            exponent: state.exponent.unwrap_or(2),
            iterations,
            interior: state.interior.unwrap_or(FractalColouring { kind: 0, factor: 1.0 }),
            exterior: state.exterior.unwrap_or(FractalColouring { kind: 1, factor: 1.0 }),
        })
    }

    fn misplaced_in_warp(item: &Item) -> SceneError {
        SceneError::at(item.span(), format!("{} cannot stand in a warp", item.describe()))
    }

    /// The shape of the pattern `kind` from the items read: its field (with its own
    /// parameters and arguments), turbulence, warps and wave.
    pub(super) fn field_shape(
        &mut self,
        kind: PatternKind,
        arguments: &[Colour],
        state: &PatternState,
        at: &Span,
    ) -> Result<FieldShape, SceneError> {
        let argument = |i: usize| arguments.get(i);
        let field = match kind {
            PatternKind::Agate => Field::Agate { turbulence: state.agate_turb.unwrap_or(1.0) },
            PatternKind::Bozo => Field::Bozo,
            PatternKind::Brick => Field::Brick {
                size: state.brick_size.unwrap_or(Vec3::new(8.0, 3.0, 4.5)),
                mortar: state.mortar.unwrap_or(0.5),
            },
            PatternKind::Bumps => Field::Bumps,
            PatternKind::Cells => Field::Cells,
            PatternKind::Checker => Field::Checker,
            PatternKind::Crackle => Field::Crackle(Crackle {
                form: state.crackle_form.unwrap_or(Crackle::DEFAULT.form),
                metric: state.metric.unwrap_or(Crackle::DEFAULT.metric),
                offset: state.offset.unwrap_or(Crackle::DEFAULT.offset),
                solid: state.solid,
            }),
            PatternKind::Dents => Field::Dents,
            PatternKind::Function | PatternKind::PigmentPattern => {
                let function =
                    state.function.clone().expect("a function pattern's item gives its function");
                Field::Function(PatternFunction(function))
            }
            PatternKind::Gradient => {
                let axis = argument(0).expect("the grammar gives gradient its axis");
                Field::Gradient(self.nonzero(&axis.value, "the gradient's axis")?.normalize())
            }
            PatternKind::Granite => Field::Granite,
            PatternKind::Hexagon => Field::Hexagon,
            PatternKind::Leopard => Field::Leopard,
            PatternKind::Mandel
            | PatternKind::Julia
            | PatternKind::Magnet
            | PatternKind::MagnetJulia => Field::Fractal(self.fractal(kind, arguments, state)?),
            PatternKind::Planar => Field::Planar,
            PatternKind::Spherical => Field::Spherical,
            PatternKind::Cylindrical => Field::Cylindrical,
            PatternKind::Boxed => Field::Boxed,
            PatternKind::Marble => Field::Marble,
            PatternKind::Onion => Field::Onion,
            PatternKind::Quilted => Field::Quilted {
                control0: state.control0.unwrap_or(1.0),
                control1: state.control1.unwrap_or(1.0),
            },
            PatternKind::Radial => Field::Radial,
            PatternKind::Ripples => Field::Ripples,
            PatternKind::Spiral1 | PatternKind::Spiral2 => {
                let arms = argument(0).expect("the grammar gives a spiral its arms");
                let arms = self.single(&arms.value)?;
                if kind == PatternKind::Spiral1 {
                    Field::Spiral1 { arms }
                } else {
                    Field::Spiral2 { arms }
                }
            }
            PatternKind::Spotted => Field::Spotted,
            PatternKind::Waves => Field::Waves,
            PatternKind::Wood => Field::Wood,
            PatternKind::Wrinkles => Field::Wrinkles,
            PatternKind::Average => {
                return Err(SceneError::at(
                    at,
                    "`average` has no value of its own: it takes a map",
                ));
            }
        };
        // Over a base (POV-Ray 3.7's Parse_Pattern sets the new type and keeps the rest): its
        // warps and transforms first, its turbulence, frequency and phase unless given, and its
        // wave unless given or the word has its own (marble's and wood's triangle).
        let base = state.base.as_ref();
        let kept = base.and_then(|b| b.turbulence);
        let turbulence = state.turbulence.or(kept.map(|t| t.amount)).map(|amount| Turbulence {
            amount,
            octaves: state.octaves.or(kept.map(|t| t.octaves)).unwrap_or(6),
            omega: state.omega.or(kept.map(|t| t.omega)).unwrap_or(0.5),
            lambda: state.lambda.or(kept.map(|t| t.lambda)).unwrap_or(2.0),
        });
        let own_wave = default_wave(&field);
        let kept_wave = base.map(|b| b.wave).filter(|_| own_wave == Wave::Ramp);
        let kept_warps = base.map_or(&[][..], |b| &b.warps[..]);
        Ok(FieldShape {
            wave: state.wave.or(kept_wave).unwrap_or(own_wave),
            field,
            turbulence,
            warps: kept_warps.iter().chain(&state.warps).copied().collect(),
            frequency: state.frequency.or(base.map(|b| b.frequency)).unwrap_or(1.0),
            phase: state.phase.or(base.map(|b| b.phase)).unwrap_or(0.0),
        })
    }
}

/// How many values a block pattern takes (its colours stand at 0, 1/(n-1), ..., 1), and their
/// colours when not given (POV-Ray's); `None` for the other patterns, which take a map.
pub fn block_colours(kind: PatternKind) -> Option<Vec<Vec3>> {
    match kind {
        PatternKind::Checker => Some(vec![Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0)]),
        // Mortar, then brick.
        PatternKind::Brick => Some(vec![Vec3::splat(1.0), Vec3::new(1.0, 0.0, 0.0)]),
        PatternKind::Hexagon => {
            Some(vec![Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0)])
        }
        PatternKind::Agate
        | PatternKind::Average
        | PatternKind::Bozo
        | PatternKind::Bumps
        | PatternKind::Cells
        | PatternKind::Crackle
        | PatternKind::Dents
        | PatternKind::Function
        | PatternKind::Gradient
        | PatternKind::Granite
        | PatternKind::Leopard
        | PatternKind::Mandel
        | PatternKind::Julia
        | PatternKind::Magnet
        | PatternKind::MagnetJulia
        | PatternKind::Planar
        | PatternKind::Spherical
        | PatternKind::Cylindrical
        | PatternKind::Boxed
        | PatternKind::Marble
        | PatternKind::Onion
        | PatternKind::PigmentPattern
        | PatternKind::Quilted
        | PatternKind::Radial
        | PatternKind::Ripples
        | PatternKind::Spiral1
        | PatternKind::Spiral2
        | PatternKind::Spotted
        | PatternKind::Waves
        | PatternKind::Wood
        | PatternKind::Wrinkles => None,
    }
}

/// How many of a pattern's arguments are its own (the axis, the count); the rest are colours
/// in a pigment and the amount in a normal.
pub fn own_arguments(kind: PatternKind) -> usize {
    match kind {
        PatternKind::Gradient
        | PatternKind::Mandel
        | PatternKind::Spiral1
        | PatternKind::Spiral2 => 1,
        // The set's: `julia`'s c and iterations, `magnet`'s formula and iterations (and c).
        PatternKind::Julia | PatternKind::Magnet => 2,
        PatternKind::MagnetJulia => 3,
        PatternKind::Planar
        | PatternKind::Spherical
        | PatternKind::Cylindrical
        | PatternKind::Boxed => 0,
        PatternKind::Agate
        | PatternKind::Average
        | PatternKind::Bozo
        | PatternKind::Brick
        | PatternKind::Bumps
        | PatternKind::Cells
        | PatternKind::Checker
        | PatternKind::Crackle
        | PatternKind::Dents
        | PatternKind::Function
        | PatternKind::Granite
        | PatternKind::Hexagon
        | PatternKind::Leopard
        | PatternKind::Marble
        | PatternKind::Onion
        | PatternKind::PigmentPattern
        | PatternKind::Quilted
        | PatternKind::Radial
        | PatternKind::Ripples
        | PatternKind::Spotted
        | PatternKind::Waves
        | PatternKind::Wood
        | PatternKind::Wrinkles => 0,
    }
}
