//! `material { ... }` and the texture nodes `diffuse` takes.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;

use super::expression::colour_of;
use super::pattern::PatternState;
use super::{Body, Evaluator, Look, Stop, resolve};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ImageLook, MaterialDesc, Pattern, TextureNode, Transform};
use crate::lang::dialect::Dialect;
use crate::lang::syntax::{
    self, AppearanceKind, Colour, Expr, ExprKind, Item, MaterialParamKind, TextureArg, TextureKind,
    TextureParamKind,
};
use crate::lang::value::Value;

/// A texture node's items as they are read.
pub struct TextureState {
    kind: TextureKind,
    /// `pattern { }`'s pattern and modifiers.
    pattern: PatternState,
    transforms: Vec<Transform>,
    map: Option<Vec<Stop>>,
    axis: Option<Vec3>,
    octaves: Option<u32>,
    turbulence: Option<f32>,
}

/// The most nodes one texture may hold, and how deeply they may nest.
pub const MAX_TEXTURE_NODES: usize = 65_536;
pub const MAX_TEXTURE_DEPTH: u32 = 64;
/// The most texture nodes made or copied in one scene.
pub const MAX_SCENE_TEXTURE_NODES: u64 = 1 << 20;

impl Evaluator {
    pub(super) fn material(
        &mut self,
        m: &syntax::Material,
        name: Option<&str>,
    ) -> Result<Arc<MaterialDesc>, SceneError> {
        let span = m.span.clone();
        let base = m.base.as_ref().map(|b| self.material_named(b)).transpose()?;
        if m.items.is_empty()
            && name.is_none()
            && let Some(base) = base
        {
            return Ok(base); // `material { White }`: the declared material itself, shared
        }
        let mut material = match base {
            Some(base) => MaterialDesc { name: None, span: self.here(&span), ..(*base).clone() },
            None => MaterialDesc::new(self.here(&span)),
        };
        material.name = name.map(str::to_string);
        self.exec(&m.items, &mut Body::Material(&mut material))?;
        // A coated base scatters at most the larger of its albedo and the coat's strength.
        let (base, base_name) = if material.coat > 0.0 {
            (material.diffuse.max_value().max(Vec3::splat(material.coat)), "max(diffuse, coat)")
        } else {
            (material.diffuse.max_value(), "diffuse")
        };
        let total = base + material.specular + material.transmission;
        if let Some(channel) = (0..3).find(|&c| total[c] > 1.0 + 1e-6) {
            let who = material
                .name
                .as_ref()
                .map_or("this material".to_string(), |n| format!("material `{n}`"));
            return Err(SceneError::at(
                &span,
                format!(
                    "{who} reflects more light than it receives: {base_name} + specular + transmission = {} in the {} channel (at most 1)",
                    total[channel],
                    ["red", "green", "blue"][channel]
                ),
            ));
        }
        Ok(Arc::new(material))
    }

    /// A material as a value: raydiance's, or in `.pov` POV-Ray's (a look).
    pub(super) fn material_value(
        &mut self,
        m: &syntax::Material,
        name: Option<&str>,
    ) -> Result<Value, SceneError> {
        Ok(match self.dialect {
            Dialect::Scn => Value::Material(self.material(m, name)?),
            Dialect::Pov => Value::Look(Arc::new(self.pov_material(m)?)),
        })
    }

    /// POV-Ray's `material { [M] texture { ... } interior { ... } }`: a look, from the declared
    /// material `M` or else the default texture.
    pub(super) fn pov_material(&mut self, m: &syntax::Material) -> Result<Look, SceneError> {
        let mut look = match &m.base {
            None => self.default_look.clone(),
            Some(base) => match self.value(base)? {
                Value::Look(look) => (*look).clone(),
                other => return Err(not_a_material(base, &other)),
            },
        };
        self.exec(&m.items, &mut Body::Look(&mut look))?;
        Ok(look)
    }

    pub(super) fn material_item(
        &mut self,
        item: &Item,
        material: &mut MaterialDesc,
    ) -> Result<(), SceneError> {
        let param = match item {
            Item::MaterialParam(param) => param,
            Item::Appearance(a) if a.kind == AppearanceKind::Normal => {
                material.normal = self.normal(a, material.normal.as_ref())?;
                return Ok(());
            }
            Item::PovParam { key, items, .. } if key.name == "medium" => {
                material.interior = Some(Arc::new(self.medium(items, &key.span)?));
                return Ok(());
            }
            _ => return Err(Self::misplaced(item, &Body::Material(material))),
        };
        match &param.kind {
            MaterialParamKind::Fresnel => material.fresnel = true,
            MaterialParamKind::Ior(e) => material.ior = self.positive(e, "ior")?,
            MaterialParamKind::Roughness(e) => material.roughness = self.roughness(e)?,
            MaterialParamKind::Coat(e) => material.coat = self.coat(e)?,
            MaterialParamKind::CoatRoughness(e) => {
                material.coat_roughness = self.coat_roughness(e)?
            }
            MaterialParamKind::Diffuse(arg) => material.diffuse = self.texture_arg(arg)?,
            MaterialParamKind::Specular(c) => material.specular = self.colour(c)?,
            MaterialParamKind::Transmission(c) => material.transmission = self.colour(c)?,
            MaterialParamKind::Emission(c) => material.emission = self.colour(c)?,
        }
        Ok(())
    }

    /// A colour or a texture node, where `diffuse` takes one.
    pub(super) fn texture_arg(&mut self, arg: &TextureArg) -> Result<TextureNode, SceneError> {
        match arg {
            TextureArg::Texture(t) => self.texture(t),
            TextureArg::Colour(colour) => {
                // A declared texture's name reads as a colour expression (evaluated once: it
                // may draw random numbers).
                if matches!(colour.value.kind, ExprKind::Rgb(_)) {
                    return Ok(TextureNode::solid(self.colour(colour)?));
                }
                match self.value(&colour.value)? {
                    Value::Texture(texture) => {
                        self.count_texture_nodes(texture.size_and_depth().0, &colour.span)?;
                        Ok((*texture).clone())
                    }
                    other => Ok(TextureNode::solid(colour_of(other, &colour.span)?)),
                }
            }
        }
    }

    /// Counts texture nodes made or copied in the scene against `MAX_SCENE_TEXTURE_NODES`.
    fn count_texture_nodes(&mut self, nodes: usize, at: &Span) -> Result<(), SceneError> {
        self.texture_nodes += nodes as u64;
        if self.texture_nodes > MAX_SCENE_TEXTURE_NODES {
            return Err(SceneError::at(
                at,
                format!(
                    "the scene's textures hold more than {MAX_SCENE_TEXTURE_NODES} nodes (each \
                     use of a declared texture copies it)"
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn texture(&mut self, t: &syntax::Texture) -> Result<TextureNode, SceneError> {
        let mut args = Vec::new();
        for arg in &t.arguments {
            args.push(Box::new(self.texture_arg(arg)?));
        }
        let path: Option<PathBuf> = match &t.file {
            Some(file) => {
                let name = self.string(file, "`image_map`")?;
                Some(resolve(&file.span.file.path, &name))
            }
            None => None,
        };
        let mut state = TextureState {
            kind: t.kind,
            pattern: PatternState::default(),
            transforms: Vec::new(),
            map: None,
            axis: None,
            octaves: None,
            turbulence: None,
        };
        self.exec(&t.items, &mut Body::Texture(&mut state))?;
        // Black to white when no map is given.
        let map = state
            .map
            .filter(|m| !m.is_empty())
            .map(|stops| stops.iter().map(|s| (s.position, s.colour)).collect())
            .unwrap_or_else(|| vec![(0.0, Vec3::ZERO), (1.0, Vec3::ONE)]);
        let mut args = args.into_iter();
        let mut arg = || args.next().expect("the grammar gives the arguments");
        let octaves = state.octaves.unwrap_or(4);
        let turbulence = state.turbulence.unwrap_or(0.0);
        let pattern = match t.kind {
            TextureKind::Checker => Pattern::Checker(arg(), arg()),
            TextureKind::Stripes => {
                Pattern::Stripes { a: arg(), b: arg(), axis: state.axis.unwrap_or(Vec3::X) }
            }
            TextureKind::Gradient => Pattern::Gradient { axis: state.axis.unwrap_or(Vec3::Y), map },
            TextureKind::Noise => Pattern::Noise { octaves, map },
            TextureKind::Marble => Pattern::Marble { turbulence, octaves, map },
            TextureKind::Wood => Pattern::Wood { turbulence, octaves, map },
            TextureKind::ImageMap => {
                let path = path.expect("the grammar gives image_map a file");
                Pattern::Image { path, look: ImageLook::colour() }
            }
            TextureKind::Mix => Pattern::Mix { a: arg(), b: arg(), t: arg() },
            TextureKind::Pattern => {
                let (kind, arguments, at) =
                    state.pattern.word.clone().expect("the grammar gives the pattern first");
                self.pattern_texture(kind, &arguments, &state.pattern, &at)?.0.colour.pattern
            }
        };
        self.count_texture_nodes(1, &t.span)?;
        let node = TextureNode { pattern, transforms: state.transforms };
        // Checked as each node is made, so no texture grows past the bounds: every use of a
        // declared texture copies it, and rendering evaluates it by recursion.
        let (size, depth) = node.size_and_depth();
        if size > MAX_TEXTURE_NODES || depth > MAX_TEXTURE_DEPTH {
            return Err(SceneError::at(
                &t.span,
                format!(
                    "this texture has {size} nodes nested {depth} deep; at most \
                     {MAX_TEXTURE_NODES} nodes nested {MAX_TEXTURE_DEPTH} deep are supported"
                ),
            ));
        }
        Ok(node)
    }

    pub(super) fn texture_item(
        &mut self,
        item: &Item,
        state: &mut TextureState,
    ) -> Result<(), SceneError> {
        let kind = state.kind;
        if kind == TextureKind::Pattern && self.pattern_item(item, &mut state.pattern)? {
            return Ok(());
        }
        match item {
            Item::Transform(t) => state.transforms.push(self.transform(t)?),
            Item::ColorMap { entries, span } => {
                let takes_map = matches!(
                    kind,
                    TextureKind::Gradient
                        | TextureKind::Noise
                        | TextureKind::Marble
                        | TextureKind::Wood
                );
                if !takes_map {
                    return Err(SceneError::at(span, "`color_map` has no effect on this texture"));
                }
                let mut map = Vec::new();
                self.exec(entries, &mut Body::ColorMap(&mut map))?;
                if state.map.replace(map).is_some() {
                    return Err(SceneError::at(span, "a second color_map"));
                }
            }
            Item::TextureParam(param) => {
                let applies = match param.kind {
                    TextureParamKind::Axis => {
                        matches!(kind, TextureKind::Stripes | TextureKind::Gradient)
                    }
                    TextureParamKind::Octaves => {
                        matches!(kind, TextureKind::Noise | TextureKind::Marble | TextureKind::Wood)
                    }
                    TextureParamKind::Turbulence => {
                        matches!(kind, TextureKind::Marble | TextureKind::Wood)
                    }
                };
                if !applies {
                    return Err(SceneError::at(
                        &param.span,
                        format!("`{}` has no effect on this texture", param.kind.word()),
                    ));
                }
                match param.kind {
                    TextureParamKind::Axis => {
                        state.axis = Some(self.nonzero(&param.value, "the axis")?)
                    }
                    TextureParamKind::Octaves => {
                        state.octaves = Some(self.integer(&param.value, 1, 16)? as u32)
                    }
                    TextureParamKind::Turbulence => {
                        let t = self.single(&param.value)?;
                        if t < 0.0 {
                            return Err(SceneError::at(
                                &param.value.span,
                                format!("turbulence {t} is negative"),
                            ));
                        }
                        state.turbulence = Some(t);
                    }
                }
            }
            _ => return Err(Self::misplaced(item, &Body::Texture(state))),
        }
        Ok(())
    }

    pub(super) fn map_entry(
        &mut self,
        item: &Item,
        entries: &mut Vec<Stop>,
    ) -> Result<(), SceneError> {
        let (position, colour, end) = match item {
            Item::MapEntry { position, colour, end } => (position, colour, end),
            // A declared map's name (`.pov`): its entries.
            Item::Value(expr) => {
                return match self.value(expr)? {
                    Value::ColorMap(map) => {
                        entries.extend(map.iter().copied());
                        Ok(())
                    }
                    other => Err(SceneError::at(
                        &expr.span,
                        format!("a color_map names a declared color_map, not {}", other.kind()),
                    )),
                };
            }
            _ => return Err(Self::misplaced(item, &Body::ColorMap(entries))),
        };
        self.map_stop(position, colour, entries)?;
        if let Some((end, colour)) = end {
            self.map_stop(end, colour, entries)?;
        }
        Ok(())
    }

    /// A colour at a position of a color_map, after those before it, with its filter and
    /// transmit in `.pov`.
    fn map_stop(
        &mut self,
        position: &Expr,
        colour: &Colour,
        entries: &mut Vec<Stop>,
    ) -> Result<(), SceneError> {
        let at = position.span.clone();
        let position = self.single(position)?;
        let (colour, filter, transmit) = match self.dialect {
            Dialect::Scn => (self.colour(colour)?, 0.0, 0.0),
            Dialect::Pov => self.pov_colour(colour)?,
        };
        // POV-Ray interpolates between positions outside [0, 1] too: they shape the map inside.
        let (low, high) = match self.dialect {
            Dialect::Scn => (0.0, 1.0),
            Dialect::Pov => (f32::MIN, f32::MAX),
        };
        let previous = entries.last().map_or(low, |e| e.position);
        if !(previous..=high).contains(&position) {
            let range = match self.dialect {
                Dialect::Scn => "in [0, 1] and ",
                Dialect::Pov => "",
            };
            return Err(SceneError::at(
                &at,
                format!("color_map position {position} must be {range}not below the one before"),
            ));
        }
        entries.push(Stop { position, colour, filter, transmit });
        Ok(())
    }

    pub(super) fn material_named(&mut self, base: &Expr) -> Result<Arc<MaterialDesc>, SceneError> {
        match self.value(base)? {
            Value::Material(m) => Ok(m),
            other => Err(not_a_material(base, &other)),
        }
    }
}

/// `base` (a declared name or an array's element) holds `value`, which is not a material.
fn not_a_material(base: &Expr, value: &Value) -> SceneError {
    let what = match &base.kind {
        ExprKind::Ident(name) => format!("`{name}`"),
        _ => "this element".to_string(),
    };
    SceneError::at(&base.span, format!("{what} is {}, not a material", value.kind()))
}
