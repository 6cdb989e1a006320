//! POV-Ray's appearance (`.pov`): `pigment`, `finish`, `texture`, `interior`, `normal` and
//! `#default`, read as POV-Ray reads them and turned into a physically based material as
//! `docs/povray.md` states.

use std::sync::Arc;

use glam::{DVec3, Vec3};

use super::expression::single;
use super::medium::Interior;
use super::pattern::{PatternState, block_colours};
use super::pigment::Pigment;
use super::{Body, Evaluator};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{
    Covers, MaterialDesc, NormalNode, Pattern, PigmentDesc, PovFinish, TextureNode, Transform,
};
use crate::lang::syntax::{
    Appearance, AppearanceKind, Colour, Expr, ExprKind, Ident, Item, MapKind,
};
use crate::lang::value::Value;
use crate::light::pov_glow;
use crate::material::pov_shares;

/// A finish, with POV-Ray's defaults for what is not given.
#[derive(Debug, Clone, PartialEq)]
pub struct Finish {
    pub ambient: Vec3,
    pub diffuse: f32,
    pub emission: Vec3,
    /// Mirror reflection (POV-Ray's `reflection`, the largest when a range is given).
    pub reflection: Vec3,
    /// `metallic`: the reflection is tinted by the pigment.
    pub metallic: bool,
    /// `reflection { ... fresnel }`: the reflection follows Fresnel's law.
    pub fresnel: bool,
    /// POV-Ray's Phong highlight, (R.L)^phong_size.
    pub phong: f32,
    pub phong_size: f32,
    /// POV-Ray's Blinn highlight, (N.H)^(1 / roughness).
    pub specular: f32,
    pub roughness: f32,
}

/// POV-Ray's default finish: `ambient 0.1 diffuse 0.6`, no highlight (`phong_size 40`,
/// `roughness 0.05` when one is given), no reflection.
pub const POV_FINISH: Finish = Finish {
    ambient: Vec3::splat(0.1),
    diffuse: 0.6,
    emission: Vec3::ZERO,
    reflection: Vec3::ZERO,
    metallic: false,
    fresnel: false,
    phong: 0.0,
    phong_size: 40.0,
    specular: 0.0,
    roughness: 0.05,
};

/// The narrowest highlight's GGX alpha: sharper ones are read as this (f32 keeps the visible
/// normals' sampling accurate down to it).
const MIN_HIGHLIGHT_ALPHA: f32 = 0.01;

impl Finish {
    /// The glossy reflection its highlights stand for: their amount (`phong` + `specular`)
    /// and the GGX alpha of the same width, the amount-weighted mean of each highlight's.
    /// A Blinn-Phong lobe (N.H)^n is about GGX of alpha = sqrt(2 / (n + 2)) (Walter et al.
    /// 2007, sec. 5.2); POV-Ray's `specular` is Blinn's with n = 1 / `roughness`, and its
    /// `phong` is Phong's (R.L)^s, close to Blinn's with n = 4 s. `None` without highlights.
    pub fn highlight(&self) -> Option<(f32, f32)> {
        let blinn_alpha = |n: f32| (2.0 / (n.max(0.0) + 2.0)).sqrt();
        let (phong, specular) = (self.phong.max(0.0), self.specular.max(0.0));
        let amount = phong + specular;
        if amount <= 0.0 {
            return None;
        }
        let phong_alpha = blinn_alpha(4.0 * self.phong_size);
        let specular_alpha = blinn_alpha(1.0 / self.roughness.max(f32::MIN_POSITIVE));
        let alpha = (phong * phong_alpha + specular * specular_alpha) / amount;
        Some((amount, alpha.clamp(MIN_HIGHLIGHT_ALPHA, 1.0)))
    }
}

/// A texture (POV-Ray's `texture { pigment finish normal }`) with the object's interior: what
/// an object looks like.
#[derive(Debug, Clone)]
pub struct Look {
    pub pigment: Pigment,
    pub finish: Finish,
    /// `normal { }`: bump mapping, if any.
    pub normal: Option<NormalNode>,
    /// `interior { }`: `ior 1` and empty when not given.
    pub interior: Interior,
    /// Where a layer over another with a different finish was flattened (the top's finish
    /// applies to both): warned about when the look is given to an object, so that a declared
    /// texture no object wears (the library's) says nothing.
    pub finish_flattened_at: Option<String>,
}

impl Look {
    /// Moves what `kind` of appearance makes of it: a pigment's pattern, a normal's bumps, or
    /// both for a texture (a finish and an interior lie nowhere in particular).
    pub fn push_transform(&mut self, kind: AppearanceKind, transform: Transform) {
        let (pigment, normal) = match kind {
            AppearanceKind::Pigment => (true, false),
            AppearanceKind::Normal => (false, true),
            AppearanceKind::Texture => (true, true),
            AppearanceKind::Finish | AppearanceKind::Interior => (false, false),
        };
        if pigment {
            self.pigment.push_transform(transform);
        }
        if let Some(normal) = self.normal.as_mut().filter(|_| normal) {
            normal.transforms.push(transform);
        }
    }
}

impl Default for Look {
    /// POV-Ray's default texture: a black pigment and the default finish.
    fn default() -> Self {
        Look {
            pigment: Pigment::black(),
            finish: POV_FINISH,
            normal: None,
            interior: Interior::default(),
            finish_flattened_at: None,
        }
    }
}

/// A pigment's items as they are read.
pub struct PigmentState {
    pigment: Pigment,
    pattern: PatternState,
}

impl Evaluator {
    /// The look of a `#default` or an object after `appearance`, starting from `look`.
    pub(super) fn apply_appearance(
        &mut self,
        appearance: &Appearance,
        look: &mut Look,
    ) -> Result<(), SceneError> {
        match appearance.kind {
            AppearanceKind::Pigment => look.pigment = self.pigment(appearance, &look.pigment)?,
            AppearanceKind::Finish => {
                self.exec(&appearance.items, &mut Body::Finish(&mut look.finish))?
            }
            AppearanceKind::Texture => {
                // A texture starts from the default one, as POV-Ray's does.
                let mut texture = self.default_look.clone();
                if appearance.items.iter().any(|item| matches!(item, Item::Pattern { .. })) {
                    // A patterned texture (`texture { P texture_map { ... } }`): its pattern,
                    // modifiers and transforms make its pigment (`pattern_texture` reads the
                    // map's textures).
                    let black = Look::default().pigment;
                    let items = blocks_as_map(&appearance.items, AppearanceKind::Texture)?;
                    let (pigment, finish) = self.patterned(&items, &black)?;
                    texture.pigment = pigment;
                    texture.finish = finish.unwrap_or(texture.finish);
                } else {
                    self.exec(&appearance.items, &mut Body::Look(&mut texture))?;
                }
                look.pigment = texture.pigment;
                look.finish = texture.finish;
                look.normal = texture.normal;
                look.finish_flattened_at = texture.finish_flattened_at;
            }
            AppearanceKind::Interior => {
                self.exec(&appearance.items, &mut Body::Interior(&mut look.interior))?
            }
            AppearanceKind::Normal => {
                look.normal = self.normal(appearance, look.normal.as_ref())?;
            }
        }
        Ok(())
    }

    pub(super) fn warn_normal(&mut self, span: &Span) {
        let at = self.here(span);
        self.warnings.push(format!(
            "{at:?}: warning: `normal` (POV-Ray's bump mapping) is read but not rendered: \
             surfaces are shaded with their geometric normals"
        ));
    }

    /// A declared pigment, finish, texture or interior.
    pub(super) fn declared_appearance(
        &mut self,
        appearance: &Appearance,
    ) -> Result<Value, SceneError> {
        let mut look = self.default_look.clone();
        Ok(match appearance.kind {
            AppearanceKind::Pigment => {
                Value::Pigment(Arc::new(self.pigment(appearance, &look.pigment)?))
            }
            AppearanceKind::Finish => {
                self.exec(&appearance.items, &mut Body::Finish(&mut look.finish))?;
                Value::Finish(Arc::new(look.finish))
            }
            AppearanceKind::Texture => {
                self.apply_appearance(appearance, &mut look)?;
                Value::Look(Arc::new(look))
            }
            AppearanceKind::Interior => {
                self.exec(&appearance.items, &mut Body::Interior(&mut look.interior))?;
                Value::Interior(Arc::new(look.interior))
            }
            AppearanceKind::Normal => Value::Normal(self.normal(appearance, None)?.map(Arc::new)),
        })
    }

    pub(super) fn pigment(
        &mut self,
        appearance: &Appearance,
        base: &Pigment,
    ) -> Result<Pigment, SceneError> {
        self.pigment_of(&appearance.items, base)
    }

    /// The pigment `items` make, starting from `base`.
    pub(super) fn pigment_of(
        &mut self,
        items: &[Item],
        base: &Pigment,
    ) -> Result<Pigment, SceneError> {
        let items = blocks_as_map(items, AppearanceKind::Pigment)?;
        Ok(self.patterned(&items, base)?.0)
    }

    /// The pigment `items` make, starting from `base`, and the finish of the textures of a
    /// texture_map among them.
    fn patterned(
        &mut self,
        items: &[Item],
        base: &Pigment,
    ) -> Result<(Pigment, Option<Finish>), SceneError> {
        let mut state = PigmentState { pigment: base.clone(), pattern: PatternState::default() };
        self.exec(items, &mut Body::Pigment(&mut state))?;
        let transforms = state.pigment.colour.transforms.clone();
        let Some((kind, arguments, at)) = state.pattern.word.clone() else {
            return Ok((state.pigment, None));
        };
        // A new word over a pattern (`pigment { P_Declared granite }`) changes only its type, as
        // in POV-Ray: its warps, transforms and modifiers stay (`field_shape`), and so does its
        // map unless one is given or the word is a block pattern's, which has its own colours.
        state.pattern.base = state.pigment.pattern_shape().cloned();
        let new_map = state.pattern.color_map.is_some() || state.pattern.map.is_some();
        if state.pattern.base.is_some() && !new_map && block_colours(kind).is_none() {
            let shape = self.field_shape(kind, &arguments, &state.pattern, &at)?;
            return Ok((state.pigment.reshaped(&shape), None));
        }
        let (mut pigment, finish) = self.pattern_texture(kind, &arguments, &state.pattern, &at)?;
        pigment.set_transforms(transforms);
        Ok((pigment, finish))
    }

    pub(super) fn pigment_item(
        &mut self,
        item: &Item,
        state: &mut PigmentState,
    ) -> Result<(), SceneError> {
        let warp = matches!(item, Item::PovParam { key, .. } if key.name == "warp");
        let map = matches!(item, Item::ColorMap { .. } | Item::PatternMap { .. });
        if self.pattern_item(item, &mut state.pattern)? {
            if map && state.pattern.word.is_none() {
                // `pigment { P_Declared color_map { ... } }` (or `pigment_map`): the declared
                // pattern in new colours, its warps and transforms kept.
                if let Some(entries) = self.declared_pattern_map(&state.pattern)?
                    && let Some(pigment) = state.pigment.remapped(entries)
                {
                    state.pigment = pigment;
                }
            }
            let last = if warp { state.pattern.warps.pop() } else { None };
            match (&state.pattern.word, last) {
                (None, Some(last)) => {
                    // `pigment { P_Declared warp { } }`: the declared pigment, warped (were a
                    // pattern's word to follow, it would take the warp instead).
                    state.pigment = state.pigment.clone().warped(last);
                    state.pattern.warps.push(last);
                }
                (Some(_), Some(last)) => {
                    // The transforms written so far apply to the point after this warp.
                    let before = std::mem::take(&mut state.pigment.colour.transforms);
                    state.pigment.set_transforms(Vec::new());
                    state.pattern.warp_after(&before, last);
                }
                (_, None) => {}
            }
            return Ok(());
        }
        match item {
            Item::Value(expr) => match self.value(expr)? {
                Value::Pigment(p) => {
                    state.pigment = (*p).clone();
                    state.pattern.word = None;
                }
                other => {
                    let other = self.clamped_colour(other, &expr.span);
                    let (colour, filter, transmit) = pov_colour(other, &expr.span)?;
                    state.pigment = Pigment::solid(colour, filter, transmit);
                    state.pattern.word = None;
                }
            },
            Item::Transform(t) => {
                let transform = self.transform(t)?;
                state.pigment.push_transform(transform);
            }
            Item::ImageMap { file, options, span } => {
                state.pigment = self.image_pigment(file, options, span)?;
                state.pattern.word = None;
            }
            _ => return Err(Self::misplaced(item, &Body::Pigment(state))),
        }
        Ok(())
    }

    /// The entries of a pigment's new color_map or pigment_map, if it has one (a normal's or
    /// texture's map has no colours to give a declared pigment).
    fn declared_pattern_map(
        &mut self,
        pattern: &PatternState,
    ) -> Result<Option<Vec<(f32, Pigment)>>, SceneError> {
        Ok(match (&pattern.color_map, &pattern.map) {
            (Some(stops), _) if !stops.is_empty() => {
                Some(stops.iter().map(|s| (s.position, Pigment::of_stop(s))).collect())
            }
            (_, Some((MapKind::Pigment, entries, _))) => {
                Some(self.map_entries(MapKind::Pigment, entries, false)?.textures)
            }
            _ => None,
        })
    }

    pub(super) fn finish_item(
        &mut self,
        item: &Item,
        finish: &mut Finish,
    ) -> Result<(), SceneError> {
        match item {
            Item::Value(expr) => match self.value(expr)? {
                Value::Finish(f) => *finish = (*f).clone(),
                other => {
                    return Err(SceneError::at(
                        &expr.span,
                        format!("a finish names a declared finish, not {}", other.kind()),
                    ));
                }
            },
            Item::PovParam { key, value, items } => {
                let colour = |e: &mut Self| -> Result<Vec3, SceneError> {
                    let v = value.as_ref().expect("the grammar gives the value");
                    Ok(e.pov_colour(v)?.0)
                };
                match key.name.as_str() {
                    "ambient" => finish.ambient = colour(self)?,
                    "emission" => finish.emission = colour(self)?,
                    "diffuse" => finish.diffuse = colour(self)?.x,
                    "phong" => finish.phong = colour(self)?.x,
                    "phong_size" => finish.phong_size = colour(self)?.x,
                    "specular" => finish.specular = colour(self)?.x,
                    "roughness" => finish.roughness = colour(self)?.x,
                    "metallic" => {
                        finish.metallic = match value {
                            Some(v) => self.pov_colour(v)?.0.x > 0.0,
                            None => true,
                        }
                    }
                    "reflection" => {
                        finish.reflection = colour(self)?;
                        for item in items {
                            self.reflection_item(item, finish)?;
                        }
                    }
                    // Energy is always conserved here.
                    "conserve_energy" => {}
                    // The diffuse falloff, grain and thin-film interference: shading here is
                    // physically based and has none.
                    "brilliance" | "crand" | "irid" => self.warn_unrendered(key),
                    other => unreachable!("no finish item `{other}`"),
                }
            }
            _ => return Err(Self::misplaced(item, &Body::Finish(finish))),
        }
        Ok(())
    }

    /// A finish's word that changes nothing here: a warning naming it, once a scene.
    fn warn_unrendered(&mut self, key: &Ident) {
        if !self.warned_finish.insert(key.name.clone()) {
            return;
        }
        let at = self.here(&key.span);
        self.warnings.push(format!(
            "{at:?}: warning: the finish's `{}` is read but not rendered (shading is physically \
             based: docs/povray.md)",
            key.name
        ));
    }

    /// `reflection { min, max  fresnel  metallic }`: the largest reflection is kept.
    fn reflection_item(&mut self, item: &Item, finish: &mut Finish) -> Result<(), SceneError> {
        match item {
            Item::Value(expr) => {
                let max =
                    self.pov_colour(&Colour { value: expr.clone(), span: expr.span.clone() })?;
                finish.reflection = finish.reflection.max(max.0);
            }
            Item::PovParam { key, value, .. } => {
                let on = match value {
                    Some(v) => self.pov_colour(v)?.0.x > 0.0,
                    None => true,
                };
                match key.name.as_str() {
                    "fresnel" => finish.fresnel = on,
                    "metallic" => finish.metallic = on,
                    "falloff" | "exponent" => self.warn_unrendered(key),
                    other => unreachable!("no reflection item `{other}`"),
                }
            }
            _ => return Err(Self::misplaced(item, &Body::Finish(finish))),
        }
        Ok(())
    }

    pub(super) fn look_item(&mut self, item: &Item, look: &mut Look) -> Result<(), SceneError> {
        match item {
            Item::Appearance(a) => self.apply_appearance(a, look)?,
            Item::PovParam { key, value: None, .. } if key.name == "uv_mapping" => {
                self.warn_uv_mapping(&key.span)
            }
            Item::Transform(t) => {
                let transform = self.transform(t)?;
                look.push_transform(AppearanceKind::Texture, transform);
            }
            Item::Value(expr) => match self.value(expr)? {
                Value::Look(l) => {
                    look.pigment = l.pigment.clone();
                    look.finish = l.finish.clone();
                    look.normal = l.normal.clone();
                    look.finish_flattened_at = l.finish_flattened_at.clone();
                }
                other => {
                    return Err(SceneError::at(
                        &expr.span,
                        format!("a texture names a declared texture, not {}", other.kind()),
                    ));
                }
            },
            _ => return Err(Self::misplaced(item, &Body::Look(look))),
        }
        Ok(())
    }

    /// `global_settings { ambient_light C }`: POV-Ray's glow by `ambient` is ambient × C
    /// (its manual, 3.4.1.2: Ambient = Finish_Ambient × Global_Ambient; `emission` is not
    /// multiplied). A glow is made with the light known then, so a different one written after
    /// a surface that glows by its `ambient` is refused, naming that surface.
    pub(super) fn set_ambient_light(&mut self, colour: &Colour) -> Result<(), SceneError> {
        let light = self.pov_colour(colour)?.0;
        if let Some(glow) = self.ambient_glow_at.as_ref()
            && light != self.ambient_light.unwrap_or(Vec3::ONE)
        {
            return Err(SceneError::at(
                &self.here(&colour.span),
                format!(
                    "`ambient_light` comes after a surface that glows by its `ambient` ({glow:?}), \
                     which it would change: POV-Ray's applies to the whole scene, so write \
                     `global_settings` before that surface"
                ),
            ));
        }
        self.ambient_light = Some(light);
        Ok(())
    }

    /// `global_settings { assumed_gamma G }`: POV-Ray 3.7 takes the scene's colours as encoded
    /// with gamma G (it shades in that space and encodes the result for the file), so a colour
    /// c that a surface or light takes is c^G of linear light here, and a flat colour shows as
    /// POV-Ray's does. It is applied where they are made, so a different gamma written after
    /// one is refused, naming it.
    pub(super) fn set_assumed_gamma(&mut self, expr: &Expr) -> Result<(), SceneError> {
        let gamma = self.single(expr)?;
        if !(gamma > 0.0 && gamma.is_finite()) {
            return Err(SceneError::at(
                &self.here(&expr.span),
                format!("`assumed_gamma` {gamma} is not a gamma: it must be positive"),
            ));
        }
        if let Some(first) = self.coloured_at.as_ref()
            && gamma != self.assumed_gamma.unwrap_or(1.0)
        {
            return Err(SceneError::at(
                &self.here(&expr.span),
                format!(
                    "`assumed_gamma` comes after a surface or light that takes a colour \
                     ({first:?}), which it would change: POV-Ray's applies to the whole scene, \
                     so write `global_settings` before that surface or light"
                ),
            ));
        }
        self.assumed_gamma = Some(gamma);
        Ok(())
    }

    /// The `assumed_gamma` G by which the colours c of a surface or light made at `span` are
    /// c^G in linear light (`None` where G is 1).
    pub(super) fn colour_gamma(&mut self, span: &Span) -> Option<f32> {
        if self.coloured_at.is_none() {
            self.coloured_at = Some(self.here(span));
        }
        self.assumed_gamma.filter(|&gamma| gamma != 1.0)
    }

    /// A POV-Ray colour: its red, green and blue, filter and transmit.
    pub(super) fn pov_colour(&mut self, colour: &Colour) -> Result<(Vec3, f32, f32), SceneError> {
        let value = self.value(&colour.value)?;
        let value = self.clamped_colour(value, &colour.span);
        pov_colour(value, &colour.span)
    }

    /// A surface's colour (or finish amount) without negative red, green or blue: POV-Ray's
    /// colour arithmetic may make them, but a surface cannot reflect or emit less than nothing,
    /// so they are clamped to 0, with a warning (once a scene).
    fn clamped_colour(&mut self, value: Value, at: &Span) -> Value {
        let clamped = match &value {
            Value::Float(f) if *f < 0.0 => Value::Float(0.0),
            Value::Vector(v) if v.min_element() < 0.0 => Value::Vector(v.max(DVec3::ZERO)),
            Value::Numbers(n) if n.len() >= 3 && n[..3].iter().any(|c| *c < 0.0) => Value::Numbers(
                n.iter().enumerate().map(|(i, c)| if i < 3 { c.max(0.0) } else { *c }).collect(),
            ),
            _ => return value,
        };
        if !self.warned_negative_colour {
            self.warned_negative_colour = true;
            let here = self.here(at);
            self.warnings.push(format!(
                "{here:?}: warning: a surface's colour with a negative component is clamped to 0 \
                 (a surface cannot reflect or emit less than nothing; said once a scene)"
            ));
        }
        clamped
    }

    /// The material of a look (`docs/povray.md`): the highlights (`phong`, `specular`) are a
    /// glossy dielectric coat over the Lambertian base of their amount and width, or, on a
    /// `metallic` finish, the width of a metal's reflection; `reflection` a mirror; the
    /// pigment's filter and transmit the transmission through the interior's `ior`; how they
    /// share the light is `material::pov_shares`'s, made here for a plain pigment and at each
    /// point of a patterned one. `ambient` is light only where `diffuse` is 0 (the object only
    /// glows), times `global_settings`' `ambient_light`; `emission` always is.
    pub(super) fn look_material(&mut self, look: &Look, span: &Span) -> Arc<MaterialDesc> {
        let Look { pigment, finish, normal, interior, finish_flattened_at } = look;
        if let Some(at) = finish_flattened_at.as_ref().filter(|_| !self.warned_layer_finish) {
            self.warned_layer_finish = true;
            self.warnings.push(format!(
                "{at}: warning: layered `texture`: the layers differ in their finish; the top \
                 one's applies to both (said once a scene)"
            ));
        }
        let colours = match self.colour_gamma(span) {
            Some(gamma) => pigment.colour.gamma_decoded(gamma),
            None => pigment.colour.clone(),
        };
        let colour = colours.max_value();
        let refracts = !pigment.is_opaque();
        let mut reflection = finish.reflection.max(Vec3::ZERO);
        // A metal's highlight is its own reflection's blur; elsewhere it is a coat.
        let (mut coat, mut roughness, mut coat_roughness) =
            (0.0, 0.0, MaterialDesc::DEFAULT_COAT_ROUGHNESS);
        match finish.highlight() {
            Some((amount, alpha)) if finish.metallic && !refracts => {
                if reflection.max_element() <= 0.0 {
                    reflection = Vec3::splat(amount.min(1.0));
                }
                roughness = alpha;
            }
            Some((amount, alpha)) => (coat, coat_roughness) = (amount.min(1.0), alpha),
            None => {}
        }
        let pov_finish =
            PovFinish { diffuse: finish.diffuse, reflection, metallic: finish.metallic, coat };
        let plain = |node: &TextureNode| match node.pattern {
            Pattern::Solid(c) => Some(c),
            _ => None,
        };
        let ambient_glow = if finish.diffuse == 0.0 { finish.ambient } else { Vec3::ZERO };
        if ambient_glow != Vec3::ZERO && self.ambient_glow_at.is_none() {
            self.ambient_glow_at = Some(self.here(span));
        }
        let glow = finish.emission + ambient_glow * self.ambient_light.unwrap_or(Vec3::ONE);
        let emission = match (plain(&colours), plain(&pigment.through)) {
            (Some(c), Some(through)) => pov_glow(glow, c, through.x),
            // Made at each point; its brightest colour, unfaded, bounds it.
            _ => glow * colour,
        };
        let (diffuse, shares, see_through) =
            match (plain(&colours), plain(&pigment.filter), plain(&pigment.through)) {
                (Some(c), Some(filter), Some(through)) => {
                    let shares = pov_shares(&pov_finish, c, filter.x, through.x);
                    (TextureNode::solid(shares.diffuse), shares, None)
                }
                // Made at each point; the description's own shares are those of its most
                // coloured and most transparent point (for the scene's checks of what is used).
                _ => {
                    let shares = pov_shares(&pov_finish, colour, 0.0, pigment.most_through());
                    let see_through = PigmentDesc {
                        filter: pigment.filter.clone(),
                        through: pigment.through.clone(),
                        finish: pov_finish,
                        glow,
                    };
                    (colours, shares, Some(see_through))
                }
            };
        let at = self.here(span);
        Arc::new(MaterialDesc {
            name: None,
            diffuse,
            specular: shares.specular,
            transmission: shares.transmission,
            ior: interior.ior,
            emission,
            // POV-Ray's `emission` and `ambient` glow is seen from both sides (docs/povray.md).
            two_sided: true,
            fresnel: finish.fresnel,
            roughness,
            coat: shares.coat,
            coat_roughness,
            coat_covers: Covers::Everything,
            normal: normal.clone(),
            interior: interior.medium(),
            beam: None,
            pigment: see_through,
            span: at,
        })
    }
}

/// A patterned texture's or pigment's items with the textures or pigments a block pattern takes
/// in place of colours (`checker texture { A } texture { B }`, `checker pigment { A } pigment {
/// B }`) made the texture_map or pigment_map they stand for: the i-th of n at i / (n - 1), where
/// the pattern's colours stand.
fn blocks_as_map(items: &[Item], kind: AppearanceKind) -> Result<Vec<Item>, SceneError> {
    let is_block = |item: &Item| matches!(item, Item::Appearance(a) if a.kind == kind);
    let blocks: Vec<&Item> = items.iter().filter(|item| is_block(item)).collect();
    let mut rest: Vec<Item> = items.iter().filter(|item| !is_block(item)).cloned().collect();
    let Some(first) = blocks.first() else { return Ok(rest) };
    let map_kind = match kind {
        AppearanceKind::Texture => MapKind::Texture,
        AppearanceKind::Pigment => MapKind::Pigment,
        AppearanceKind::Finish | AppearanceKind::Interior | AppearanceKind::Normal => {
            unreachable!("only textures and pigments stand for a block pattern's colours")
        }
    };
    let pattern = items.iter().rev().find_map(|item| match item {
        Item::Pattern { kind, span, .. } => Some((*kind, span)),
        _ => None,
    });
    match pattern {
        Some((pattern, _)) if block_colours(pattern).is_some() => {}
        Some((pattern, span)) => {
            return Err(SceneError::at(
                span,
                format!(
                    "`{}` takes a {}, not {}s (only `checker`, `brick` and `hexagon` take them \
                     in place of colours)",
                    pattern.word(),
                    map_kind.word(),
                    kind.word()
                ),
            ));
        }
        // A texture's textures without a pattern are its layers' place, read as before; a
        // pigment has no such reading.
        None if kind == AppearanceKind::Texture => {}
        None => {
            return Err(SceneError::at(
                first.span(),
                "a pigment stands in a pigment only after `checker`, `brick` or `hexagon`",
            ));
        }
    }
    let last = (blocks.len() - 1).max(1) as f64;
    let entries = blocks
        .iter()
        .enumerate()
        .map(|(i, block)| {
            let span = block.span().clone();
            let position = Expr { kind: ExprKind::Number(i as f64 / last), span: span.clone() };
            // A pigment_map's entry holds a pigment's items; a texture_map's, the texture.
            let items = match block {
                Item::Appearance(a) if kind == AppearanceKind::Pigment => a.items.clone(),
                _ => vec![(*block).clone()],
            };
            Item::MapBlock { position: Some(position), items, span }
        })
        .collect();
    let span = first.span().clone();
    rest.push(Item::PatternMap { kind: map_kind, entries, span });
    Ok(rest)
}

/// A value where POV-Ray takes a colour: a number (grey), `<r, g, b>`, `<r, g, b, f>` or
/// `<r, g, b, f, t>`; red, green and blue must not be negative.
pub(super) fn pov_colour(value: Value, at: &Span) -> Result<(Vec3, f32, f32), SceneError> {
    let (rgb, filter, transmit) = match value {
        Value::Float(f) => (DVec3::splat(f), 0.0, 0.0),
        Value::Vector(v) => (v, 0.0, 0.0),
        Value::Numbers(n) if n.len() == 4 || n.len() == 5 => {
            (DVec3::new(n[0], n[1], n[2]), n[3], n.get(4).copied().unwrap_or(0.0))
        }
        other => {
            return Err(SceneError::at(at, format!("expected a colour, found {}", other.kind())));
        }
    };
    if rgb.min_element() < 0.0 {
        let [r, g, b] = rgb.to_array();
        return Err(SceneError::at(at, format!("colour <{r}, {g}, {b}> has a negative component")));
    }
    let rgb = Vec3::new(single(rgb.x, at)?, single(rgb.y, at)?, single(rgb.z, at)?);
    Ok((rgb, single(filter, at)?.clamp(0.0, 1.0), single(transmit, at)?.clamp(0.0, 1.0)))
}
