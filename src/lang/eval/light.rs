//! `light_source`: a point light, a `spotlight` or a `parallel` light (both dialects), and in
//! `.pov` POV-Ray's light colour, `area_light`, `fade_distance`/`fade_power`, `shadowless` and
//! `looks_like` and transforms (`docs/povray.md`, Lights).

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{Affine3A, Vec3};

use super::expression::single_vector;
use super::{Body, Evaluator, as_vector};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{BeamDesc, LightDesc, LightForm, MaterialDesc, ObjectNode, ShapeNode, SpotCone};
use crate::lang::dialect::Dialect;
use crate::lang::syntax::{Expr, Item};
use crate::lang::value::Value;

/// POV-Ray's spotlight defaults: `radius 30 falloff 45 tightness 0`, `point_at <0, 0, 1>`.
const SPOT_RADIUS: f32 = 30.0;
const SPOT_FALLOFF: f32 = 45.0;
const SPOT_POINT_AT: Vec3 = Vec3::Z;

/// A light's items as they are read.
#[derive(Clone, Debug)]
pub struct LightState {
    /// Where the light is, moved by the transforms read so far.
    position: Vec3,
    /// `.pov`: every transform read so far, which moves the default `point_at` too.
    moved: Affine3A,
    power: Option<Vec3>,
    /// `.pov`: `fade_distance` and `fade_power`.
    fade_distance: f32,
    fade_power: f32,
    spotlight: Option<Span>,
    parallel: Option<Span>,
    radius: Option<(f32, Span)>,
    falloff: Option<(f32, Span)>,
    tightness: Option<(f32, Span)>,
    point_at: Option<(Vec3, Span)>,
    area: Option<AreaAxes>,
    circular: bool,
    orient: bool,
    shadowless: bool,
    looks_like: Option<Arc<ObjectNode>>,
    /// `.pov`: where a colour with a negative component was given (POV-Ray's light that
    /// takes light away); such a light is left out.
    negative: Option<Span>,
}

/// `area_light <axis1>, <axis2>, n1, n2`: the grid's sides (its counts only say how POV-Ray
/// samples it).
#[derive(Clone, Debug)]
struct AreaAxes {
    axis1: Vec3,
    axis2: Vec3,
    span: Span,
}

/// A `.pov` light whose power waits for the camera: matched at the distance d from the light
/// to where the camera looks (`docs/povray.md`).
pub struct PovLight {
    target: PovTarget,
    /// `fade_distance` and `fade_power`, when both are positive.
    fade: Option<(f32, f32)>,
}

enum PovTarget {
    /// A light of `Evaluator::lights`, given POV-Ray's colour as its power.
    Light(usize),
    /// An `area_light`, made an emitter once its power is known.
    Area(AreaLight),
}

/// An `area_light`'s items: where it is, its colour, its grid's sides, the emitter's shape and,
/// for an area spotlight, its beam.
struct AreaLight {
    position: Vec3,
    colour: Vec3,
    axis1: Vec3,
    axis2: Vec3,
    shape: AreaShape,
    beam: Option<BeamDesc>,
    span: Span,
}

/// The emitter an `area_light` becomes.
#[derive(Clone, Copy)]
enum AreaShape {
    Quad,
    /// `circular`: a disk of the grid's area.
    Disk,
    /// `circular orient`: POV-Ray's disk turned to face every point it lights, a sphere.
    Sphere,
}

impl Evaluator {
    /// `light_source { position items }`.
    pub(super) fn light(
        &mut self,
        position: &Expr,
        items: &[Item],
        span: &Span,
    ) -> Result<(), SceneError> {
        let state = self.light_state(position, items)?;
        self.place_light(state, span)
    }

    /// A light's items read where it stands; it is placed in the scene by `place_light`.
    pub(super) fn light_state(
        &mut self,
        position: &Expr,
        items: &[Item],
    ) -> Result<LightState, SceneError> {
        let at = position.span.clone();
        let mut state = match self.value(position)? {
            // `light_source { Declared transforms }` (`.pov`): the declared light, moved on.
            Value::Light(declared) => (*declared).clone(),
            value => LightState::at(single_vector(as_vector(&value, &at, "this value")?, &at)?),
        };
        self.exec(items, &mut Body::Light(&mut state))?;
        Ok(state)
    }

    /// Adds the light read into `state` to the scene.
    pub(super) fn place_light(&mut self, state: LightState, span: &Span) -> Result<(), SceneError> {
        let Some(power) = state.power else {
            let message = match self.dialect {
                Dialect::Pov => "the light_source needs a colour",
                Dialect::Scn => "the light_source needs `power rgb <r, g, b>`",
            };
            return Err(SceneError::at(span, message));
        };
        if let Some(at) = &state.negative {
            // Light is never negative: a light that darkens what it reaches has no physical
            // reading, so it is left out (the scene is lit by its other lights only).
            let at = self.here(at);
            self.warnings.push(format!(
                "{at:?}: warning: this light_source's colour has a negative component, which \
                 POV-Ray subtracts from the light others give: light is never negative, so \
                 this light is left out"
            ));
            return Ok(());
        }
        // `assumed_gamma`: the light's colour in linear light.
        let power = self.colour_gamma(span).map_or(power, |gamma| power.powf(gamma));
        let position = state.position;
        let form = light_form(&state)?;
        let fade = (state.fade_distance > 0.0 && state.fade_power > 0.0)
            .then_some((state.fade_distance, state.fade_power));
        if let Some(area) = &state.area {
            let (beam, emits) = match &form {
                LightForm::Point => (None, true),
                &LightForm::Spot { point_at, cone } => {
                    (Some(BeamDesc { axis: (point_at - position).normalize(), cone }), true)
                }
                LightForm::Parallel { .. } => (None, false),
            };
            let plain = emits && !state.shadowless && state.looks_like.is_none();
            let spans_area = area.axis1.cross(area.axis2).length() > 0.0;
            if plain && spans_area {
                let shape = match (state.circular, state.orient) {
                    (false, _) => AreaShape::Quad,
                    (true, false) => AreaShape::Disk,
                    (true, true) => AreaShape::Sphere,
                };
                let target = PovTarget::Area(AreaLight {
                    position,
                    colour: power,
                    axis1: area.axis1,
                    axis2: area.axis2,
                    shape,
                    beam,
                    span: self.here(span),
                });
                self.pov_lights.push(PovLight { target, fade });
                return Ok(());
            }
            let at = self.here(&area.span);
            let kind = if form == LightForm::Point { "a point light" } else { "a spotlight" };
            self.warnings.push(format!(
                "{at:?}: warning: this `area_light` is read as {kind}: {}",
                if spans_area {
                    "a parallel, shadowless or looks_like light has no area here"
                } else {
                    "its sides span no area"
                }
            ));
        }
        if self.dialect == Dialect::Pov {
            self.pov_lights.push(PovLight { target: PovTarget::Light(self.lights.len()), fade });
        }
        self.lights.push(LightDesc {
            position,
            power,
            form,
            shadowless: state.shadowless,
            looks_like: state.looks_like,
            span: self.here(span),
        });
        Ok(())
    }

    /// As POV-Ray does: a transform moves the light's position, `point_at` and area as they
    /// stand when it is read (items after it are not moved).
    fn move_light(
        &mut self,
        t: &crate::lang::syntax::Transform,
        state: &mut LightState,
    ) -> Result<(), SceneError> {
        let moving = self.transform(t)?.to_affine();
        state.moved_by(moving);
        Ok(())
    }

    pub(super) fn light_item(
        &mut self,
        item: &Item,
        state: &mut LightState,
    ) -> Result<(), SceneError> {
        match item {
            Item::LightPower { key, colour } => {
                if state.power.is_some() {
                    return Err(SceneError::at(key, "the light's power is given twice"));
                }
                let power = match self.dialect {
                    Dialect::Scn => self.colour(colour)?,
                    Dialect::Pov => self.signed_colour(colour)?,
                };
                if power.min_element() < 0.0 {
                    state.negative = Some(colour.span.clone());
                }
                state.power = Some(power.max(Vec3::ZERO));
            }
            Item::PovParam { key, value, items } => {
                let value = value.as_ref().map(|v| &v.value);
                let span = key.span.clone();
                let word = key.name.as_str();
                let what = format!("`{word}`");
                match word {
                    "fade_distance" => {
                        state.fade_distance = self.non_negative(given(value), &what)?
                    }
                    "fade_power" => state.fade_power = self.non_negative(given(value), &what)?,
                    "radius" => state.radius = Some((self.angle(given(value), word)?, span)),
                    "falloff" => state.falloff = Some((self.angle(given(value), word)?, span)),
                    "tightness" => {
                        state.tightness = Some((self.non_negative(given(value), &what)?, span));
                    }
                    "point_at" => state.point_at = Some((self.vec3(given(value))?, span)),
                    "spotlight" => state.spotlight = Some(span),
                    "parallel" => state.parallel = Some(span),
                    "shadowless" => state.shadowless = true,
                    "circular" => state.circular = true,
                    "orient" => state.orient = true,
                    // How POV-Ray samples an area light; raydiance samples it continuously.
                    "jitter" => {}
                    // Light always scatters in media and is dimmed by them here (physics).
                    "media_interaction" | "media_attenuation" => {
                        let on = match value {
                            Some(v) => self.number(v, &what)? != 0.0,
                            None => true,
                        };
                        if !on && word == "media_interaction" {
                            let at = self.here(&span);
                            self.warnings.push(format!(
                                "{at:?}: warning: `media_interaction off` is not honoured: \
                                 light scatters in every medium"
                            ));
                        }
                    }
                    "adaptive" => {
                        self.non_negative(given(value), &what)?;
                    }
                    "area_light" => {
                        let [Item::Value(axis2), Item::Value(n1), Item::Value(n2)] = &items[..]
                        else {
                            unreachable!("the grammar gives area_light's four values")
                        };
                        let axis1 = self.vec3(given(value))?;
                        let axis2 = self.vec3(axis2)?;
                        self.integer(n1, 1, 1 << 16)?;
                        self.integer(n2, 1, 1 << 16)?;
                        state.area = Some(AreaAxes { axis1, axis2, span });
                    }
                    "looks_like" => {
                        let [Item::Object(object)] = &items[..] else {
                            unreachable!("the grammar gives looks_like's object")
                        };
                        let mut node = self.object(object)?;
                        if node.material.is_none() {
                            let look = self.default_look.clone();
                            node.material = Some(self.look_material(&look, &object.span));
                        }
                        state.looks_like = Some(Arc::new(node));
                    }
                    other => unreachable!("no light item `{other}`"),
                }
            }
            Item::Transform(t) if self.dialect == Dialect::Pov => self.move_light(t, state)?,
            _ => return Err(Self::misplaced(item, &Body::Light(state))),
        }
        Ok(())
    }

    /// A spotlight's angle in degrees from its axis. The manual asks for less than 90, but
    /// POV-Ray takes more (laser.pov's `radius 50 falloff 100`) and uses the cosine as it
    /// comes: a `radius` past 90 lights the whole front half at full strength, a `falloff` past
    /// 90 only widens the fade, and no light goes behind the spotlight. So does raydiance, with
    /// a warning (laser.pov has `falloff 250`: its cosine is cos 110°).
    fn angle(&mut self, expr: &Expr, word: &str) -> Result<f32, SceneError> {
        let degrees = match self.dialect {
            Dialect::Scn => self.non_negative(expr, &format!("`{word}`"))?,
            // POV-Ray keeps the angle's cosine, the same for -a as for a (`radius -90` in
            // radiosity/cornell.pov).
            Dialect::Pov => self.single(expr)?.abs(),
        };
        if degrees > 90.0 {
            let at = self.here(&expr.span);
            self.warnings.push(format!(
                "{at:?}: warning: `{word}` {degrees} is more than 90 degrees from the spotlight's \
                 axis: read as POV-Ray reads it (no light goes behind the spotlight)"
            ));
        }
        Ok(degrees)
    }

    /// POV-Ray's light colours as power (`docs/povray.md`): a POV-Ray light gives a surface
    /// facing it `colour` × cos θ at every distance; a point light of intensity π·C·d² gives a
    /// Lambertian surface at distance d the same radiance, so d is taken as the distance from the
    /// light to where the camera looks (a parallel light's irradiance is π·C at any distance).
    /// A fading light (`fade_distance` f, `fade_power` p) is POV-Ray's colour × 2 / (1 + (d/f)^p)
    /// there. An area light becomes an emitter of the point light's power.
    pub(super) fn light_powers_from_colours(&mut self) {
        let look_at = self.pov_look_at.unwrap_or(Vec3::Z);
        for PovLight { target, fade } in std::mem::take(&mut self.pov_lights) {
            let position = match &target {
                PovTarget::Light(i) => self.lights[*i].position,
                PovTarget::Area(area) => area.position,
            };
            let d = position.distance(look_at);
            let faded = fade.map_or(1.0, |(f, p)| 2.0 / (1.0 + (d / f).powf(p)));
            match target {
                PovTarget::Light(i) => {
                    let light = &mut self.lights[i];
                    let reach = match light.form {
                        LightForm::Point | LightForm::Spot { .. } => d * d,
                        LightForm::Parallel { .. } => 1.0,
                    };
                    light.power *= PI * reach * faded;
                }
                PovTarget::Area(area) => {
                    let intensity = PI * d * d * faded * area.colour;
                    self.objects.push(area_emitter(area, intensity, look_at));
                }
            }
        }
    }
}

/// The value the grammar gives with this word.
fn given(value: Option<&Expr>) -> &Expr {
    value.expect("the grammar gives the value")
}

impl LightState {
    fn at(position: Vec3) -> LightState {
        LightState {
            position,
            moved: Affine3A::IDENTITY,
            power: None,
            fade_distance: 0.0,
            fade_power: 0.0,
            spotlight: None,
            parallel: None,
            radius: None,
            falloff: None,
            tightness: None,
            point_at: None,
            area: None,
            circular: false,
            orient: false,
            shadowless: false,
            looks_like: None,
            negative: None,
        }
    }

    /// Moves the light, its `point_at` and its area as they stand now (items read after are
    /// not moved), as POV-Ray's transforms of a light do.
    pub(super) fn moved_by(&mut self, moving: Affine3A) {
        self.position = moving.transform_point3(self.position);
        if let Some((point_at, _)) = &mut self.point_at {
            *point_at = moving.transform_point3(*point_at);
        }
        if let Some(area) = &mut self.area {
            area.axis1 = moving.transform_vector3(area.axis1);
            area.axis2 = moving.transform_vector3(area.axis2);
        }
        self.moved = moving * self.moved;
    }
}

/// The light's form from its items: a spotlight's or parallel light's numbers without the word
/// that needs them are errors, where they are written.
fn light_form(state: &LightState) -> Result<LightForm, SceneError> {
    if let (Some(_), Some(parallel)) = (&state.spotlight, &state.parallel) {
        return Err(SceneError::at(parallel, "a parallel spotlight is not supported"));
    }
    if state.spotlight.is_none() {
        for (word, given) in [
            ("radius", &state.radius),
            ("falloff", &state.falloff),
            ("tightness", &state.tightness),
        ] {
            if let Some((_, span)) = given {
                return Err(SceneError::at(
                    span,
                    format!("`{word}` shapes a spotlight: add `spotlight` to the light"),
                ));
            }
        }
    }
    let point_at = |default: Vec3| -> Result<Vec3, SceneError> {
        let Some((point_at, span)) = &state.point_at else {
            return Ok(state.moved.transform_point3(default));
        };
        if *point_at == state.position {
            return Err(SceneError::at(span, "`point_at` is the light's position: no direction"));
        }
        Ok(*point_at)
    };
    Ok(match (&state.spotlight, &state.parallel) {
        (Some(_), _) => {
            let radius = state.radius.as_ref().map_or(SPOT_RADIUS, |r| r.0);
            let falloff = state.falloff.as_ref().map_or(SPOT_FALLOFF, |f| f.0);
            let tightness = state.tightness.as_ref().map_or(0.0, |t| t.0);
            let cone = SpotCone { radius, falloff, tightness };
            LightForm::Spot { point_at: point_at(SPOT_POINT_AT)?, cone }
        }
        (None, Some(_)) => LightForm::Parallel { point_at: point_at(Vec3::ZERO)? },
        (None, None) => {
            if let Some((_, span)) = &state.point_at {
                return Err(SceneError::at(
                    span,
                    "`point_at` aims a spotlight or a parallel light: add `spotlight` or \
                     `parallel` to the light",
                ));
            }
            LightForm::Point
        }
    })
}

/// An `area_light` as an emitter of the same power as a point light of `intensity` (4π times
/// it), centred on the light and facing `look_at`; an area spotlight's, of the same intensity
/// as the point spotlight in every direction (`docs/povray.md`, Lights).
fn area_emitter(light: AreaLight, intensity: Vec3, look_at: Vec3) -> ObjectNode {
    let AreaLight { position, axis1, axis2, shape, beam, span, .. } = light;
    let area = axis1.cross(axis2).length();
    let mut normal = axis1.cross(axis2) / area;
    if normal.dot(look_at - position) < 0.0 {
        normal = -normal;
    }
    // A circular light as a disk or sphere of the grid's area; an oriented one sending a beam
    // as a disk facing along it, where the points it lights lie.
    let radius = (area / PI).sqrt();
    let (shape, emitting_area) = match (shape, beam) {
        (AreaShape::Quad, _) => {
            let (edge1, edge2) =
                if axis1.cross(axis2).dot(normal) > 0.0 { (axis1, axis2) } else { (axis2, axis1) };
            (ShapeNode::Quad { corner: position - 0.5 * (axis1 + axis2), edge1, edge2 }, area)
        }
        (AreaShape::Disk, _) => {
            (ShapeNode::Disk { center: position, normal, radius, hole: 0.0 }, area)
        }
        (AreaShape::Sphere, Some(beam)) => {
            (ShapeNode::Disk { center: position, normal: beam.axis, radius, hole: 0.0 }, area)
        }
        (AreaShape::Sphere, None) => {
            (ShapeNode::Sphere { center: position, radius }, 4.0 * PI * radius * radius)
        }
    };
    let emission = match beam {
        // Each bit of area a point spotlight, their intensities adding up to `intensity`.
        Some(_) => intensity / emitting_area,
        // A one-sided diffuse emitter of radiance Le and area A emits π A Le.
        None => 4.0 * PI * intensity / (PI * emitting_area),
    };
    let material = MaterialDesc {
        emission,
        diffuse: crate::graph::TextureNode::solid(Vec3::ZERO),
        beam,
        ..MaterialDesc::new(span.clone())
    };
    ObjectNode { shape, material: Some(Arc::new(material)), transforms: Vec::new(), depth: 1, span }
}
