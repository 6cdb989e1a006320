//! Statements to scene graph: `#declare`, `#include`, settings, camera, lights, objects and
//! materials, each checked where it is written so that every error points at its text.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Mat3, Vec3};
use pest::iterators::Pair;

use super::parser::{self, Rule};
use super::value::{self, Env, Value};
use crate::diagnostic::{SceneError, SourceFile, Span};
use crate::scene::graph::{
    CameraDesc, CameraForm, IntegratorKind, MaterialDesc, ObjectNode, Pattern, PointLightDesc,
    SceneGraph, Settings, ShapeNode, TextureNode, Transform,
};

/// Includes may nest this deep.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Groups and instances may nest this deep (instances of instances need no brackets).
pub const MAX_OBJECT_DEPTH: u32 = 256;

#[derive(Default)]
pub struct Evaluator {
    env: Env,
    settings: Option<Settings>,
    settings_seen: bool,
    camera: Option<CameraDesc>,
    lights: Vec<PointLightDesc>,
    objects: Vec<ObjectNode>,
    /// The files being read, outermost first: their identity (canonical path) and their path
    /// as named.
    open_files: Vec<(PathBuf, PathBuf)>,
}

/// One file's text, for locating its pairs.
struct Source<'f> {
    file: &'f Arc<SourceFile>,
}

impl Source<'_> {
    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        let (line, col) = pair.line_col();
        Span { file: self.file.clone(), line: line as u32, col: col as u32 }
    }

    fn error(&self, pair: &Pair<'_, Rule>, message: impl Into<String>) -> SceneError {
        SceneError::at(&self.span(pair), message)
    }
}

impl Evaluator {
    /// Evaluates the main file and returns the scene it describes.
    pub fn scene(mut self, file: Arc<SourceFile>) -> Result<SceneGraph, SceneError> {
        self.open_files.push((identity(&file.path), file.path.clone()));
        self.run(&file)?;
        let camera = self.camera.ok_or_else(|| {
            SceneError::at(
                &parser::span_at(&file, file.text.trim_end().len()),
                "missing camera: a scene needs one `camera { ... }`",
            )
        })?;
        Ok(SceneGraph {
            settings: self.settings.unwrap_or_default(),
            camera,
            lights: self.lights,
            objects: self.objects,
        })
    }

    fn run(&mut self, file: &Arc<SourceFile>) -> Result<(), SceneError> {
        let src = Source { file };
        for statement in parser::parse(file)? {
            match statement.as_rule() {
                Rule::declare => self.declare(&src, statement)?,
                Rule::include => self.include(&src, statement)?,
                Rule::settings => self.settings(&src, statement)?,
                Rule::camera => self.camera(&src, statement)?,
                Rule::light_source => self.light(&src, statement)?,
                Rule::EOI => {}
                _ => {
                    let object = self.object(&src, statement)?;
                    self.objects.push(object);
                }
            }
        }
        Ok(())
    }

    fn declare(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<(), SceneError> {
        let mut inner = pair.into_inner();
        let (Some(name), Some(value)) = (inner.next(), inner.next()) else {
            unreachable!("the grammar gives #declare a name and a value")
        };
        let name = name.as_str().to_string();
        let value = match value.as_rule() {
            Rule::material => Value::Material(self.material(src, value, Some(&name))?),
            Rule::rgb_colour => Value::Vector(self.colour(src, value)?.as_dvec3()),
            Rule::texture => Value::Texture(Arc::new(self.texture_arg(src, value)?)),
            Rule::expr => self.value(src, value)?,
            _ => Value::Object(Arc::new(self.object(src, value)?)),
        };
        self.env.insert(name, value);
        Ok(())
    }

    fn include(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<(), SceneError> {
        let at = src.span(&pair);
        let name = string(&pair);
        let path = resolve(&src.file.path, &name);
        let id = identity(&path);
        if self.open_files.len() > MAX_INCLUDE_DEPTH {
            return Err(SceneError::at(
                &at,
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        if self.open_files.iter().any(|(open, _)| *open == id) {
            let chain: Vec<String> =
                self.open_files.iter().map(|(_, p)| p.display().to_string()).collect();
            return Err(SceneError::at(
                &at,
                format!("include cycle: {} includes `{name}` again", chain.join(" includes ")),
            ));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| SceneError::at(&at, format!("cannot read `{}`: {e}", path.display())))?;
        let file = Arc::new(SourceFile { path, text });
        self.open_files.push((id, file.path.clone()));
        let result = self.run(&file);
        self.open_files.pop();
        // The whole include chain, but not a wall of notes for a runaway one.
        result.map_err(|e| match e.notes.len() {
            0..4 => e.with_note(format!("included from {at:?}")),
            4 => e.with_note("(and more)"),
            _ => e,
        })
    }

    fn settings(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<(), SceneError> {
        if self.settings_seen {
            return Err(src.error(&pair, "a second `settings` block (a scene has at most one)"));
        }
        self.settings_seen = true;
        let mut settings = Settings::default();
        for item in pair.into_inner().filter(|p| p.as_rule() != Rule::kw_settings) {
            let rule = item.as_rule();
            let mut args = item.into_inner().skip(1);
            let mut next = || args.next().expect("the grammar gives every setting its value");
            match rule {
                Rule::resolution => {
                    settings.width = self.integer(src, next(), 1, 65536)? as u32;
                    settings.height = self.integer(src, next(), 1, 65536)? as u32;
                }
                Rule::samples => settings.samples = self.integer(src, next(), 1, 1_000_000)? as u32,
                Rule::max_depth => settings.max_depth = self.integer(src, next(), 0, 1024)? as u32,
                Rule::seed => settings.seed = self.integer(src, next(), 0, u32::MAX.into())?,
                Rule::background => settings.background = self.colour(src, next())?,
                _ => {
                    let name = next();
                    settings.integrator = match name.as_str() {
                        "direct" => IntegratorKind::Direct,
                        "path" => IntegratorKind::Path,
                        other => {
                            let mut message = format!(
                                "unknown integrator `{other}` (expected `direct` or `path`)"
                            );
                            if let Some(g) = parser::closest(other, ["direct", "path"].into_iter())
                            {
                                message.push_str(&format!("; did you mean `{g}`?"));
                            }
                            return Err(src.error(&name, message));
                        }
                    }
                }
            }
        }
        self.settings = Some(settings);
        Ok(())
    }

    fn camera(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<(), SceneError> {
        let span = src.span(&pair);
        if self.camera.is_some() {
            return Err(SceneError::at(&span, "a second camera (a scene has exactly one)"));
        }
        let mut given: HashMap<&str, (Value, Span)> = HashMap::new();
        for item in pair.into_inner().filter(|p| p.as_rule() == Rule::camera_item) {
            let mut inner = item.into_inner();
            let (key, expr) = (inner.next().expect("key"), inner.next().expect("value"));
            let key_span = src.span(&key);
            let key = key.as_str();
            if given.contains_key(key) {
                return Err(SceneError::at(&key_span, format!("`{key}` is given twice")));
            }
            given.insert(key, (self.value(src, expr)?, key_span));
        }
        let vector = |key: &str| -> Result<Option<Vec3>, SceneError> {
            given
                .get(key)
                .map(|(v, at)| as_vector(v, at, &format!("`{key}`")).map(|v| v.as_vec3()))
                .transpose()
        };
        let float = |key: &str| -> Result<Option<f32>, SceneError> {
            given
                .get(key)
                .map(|(v, at)| as_float(v, at, &format!("`{key}`")).map(|f| f as f32))
                .transpose()
        };
        let require = |key: &str, v: Option<Vec3>| {
            v.ok_or_else(|| SceneError::at(&span, format!("the camera needs `{key}`")))
        };
        let pov = ["location", "look_at", "angle"].iter().find(|k| given.contains_key(*k));
        let lab = ["origin", "left", "forward"].iter().find(|k| given.contains_key(*k));
        let form = match (pov, lab) {
            (Some(p), Some(l)) => {
                return Err(SceneError::at(
                    &given[*l].1,
                    format!("`{l}` (the lab camera) and `{p}` (POV-Ray's camera) do not mix"),
                ));
            }
            (Some(_), None) => {
                let location = require("location", vector("location")?)?;
                let look_at = require("look_at", vector("look_at")?)?;
                let up = vector("up")?.unwrap_or(Vec3::Y);
                // POV-Ray's default: a horizontal field of view of 2 atan(0.5 * 4/3) degrees.
                let angle = float("angle")?.unwrap_or(67.380_13);
                if !(angle > 0.0 && angle < 180.0) {
                    return Err(SceneError::at(
                        &given["angle"].1,
                        format!("angle {angle} must be between 0 and 180 degrees"),
                    ));
                }
                let view = look_at - location;
                if view.length() == 0.0 {
                    return Err(SceneError::at(
                        &span,
                        "`look_at` is the camera's `location`: no view direction",
                    ));
                }
                if up.cross(view).length() <= 1e-6 * up.length() * view.length() {
                    return Err(SceneError::at(
                        &span,
                        "`up` is zero or parallel to the view direction",
                    ));
                }
                CameraForm::LookAt { location, look_at, up, angle }
            }
            _ => {
                let origin = require("origin", vector("origin")?)?;
                let left = require("left", vector("left")?)?;
                let up = require("up", vector("up")?)?;
                let forward = require("forward", vector("forward")?)?;
                for (key, v) in [("left", left), ("up", up), ("forward", forward)] {
                    if v.length() == 0.0 {
                        return Err(SceneError::at(
                            &given[key].1,
                            format!("`{key}` is a zero vector"),
                        ));
                    }
                }
                if left.cross(up).length() <= 1e-6 * left.length() * up.length() {
                    return Err(SceneError::at(
                        &given["up"].1,
                        "`left` and `up` are parallel: no image plane",
                    ));
                }
                if forward.dot(left.cross(up)).abs()
                    <= 1e-6 * forward.length() * left.length() * up.length()
                {
                    return Err(SceneError::at(
                        &given["forward"].1,
                        "`forward` lies in the image plane of `left` and `up`",
                    ));
                }
                CameraForm::Lab { origin, left, up, forward }
            }
        };
        let aperture = float("aperture")?.unwrap_or(0.0);
        if aperture < 0.0 {
            return Err(SceneError::at(
                &given["aperture"].1,
                format!("aperture {aperture} is negative"),
            ));
        }
        let focal_distance = float("focal_distance")?;
        if let Some(d) = focal_distance.filter(|d| *d <= 0.0) {
            return Err(SceneError::at(
                &given["focal_distance"].1,
                format!("focal_distance {d} must be positive"),
            ));
        }
        self.camera = Some(CameraDesc { form, aperture, focal_distance, span });
        Ok(())
    }

    fn light(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<(), SceneError> {
        let span = src.span(&pair);
        let mut inner = pair.into_inner().skip(1);
        let position = self.vector(src, inner.next().expect("the grammar gives a position"))?;
        let mut power = None;
        while let Some(key) = inner.next() {
            let colour = inner.next().expect("the grammar gives the colour");
            if power.is_some() {
                return Err(src.error(&key, "the light's power is given twice"));
            }
            power = Some(self.colour(src, colour)?);
        }
        let power = power
            .ok_or_else(|| SceneError::at(&span, "the light_source needs `power rgb <r, g, b>`"))?;
        self.lights.push(PointLightDesc { position: position.as_vec3(), power, span });
        Ok(())
    }

    fn object(&mut self, src: &Source, pair: Pair<'_, Rule>) -> Result<ObjectNode, SceneError> {
        let span = src.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner().skip(1).peekable();
        let mut take =
            |n: usize| -> Vec<Pair<'_, Rule>> { (0..n).filter_map(|_| inner.next()).collect() };
        let shape = match rule {
            Rule::plane => {
                let [n, d] = take(2).try_into().expect("two arguments");
                let normal = self.nonzero(src, n, "the plane's normal")?;
                ShapeNode::Plane { normal, offset: self.float(src, d)? as f32 }
            }
            Rule::sphere => {
                let [c, r] = take(2).try_into().expect("two arguments");
                ShapeNode::Sphere {
                    center: self.vec3(src, c)?,
                    radius: self.positive(src, r, "radius")?,
                }
            }
            Rule::box_shape => {
                let [a, b] = take(2).try_into().expect("two arguments");
                let at = src.span(&b);
                let (corner_a, corner_b) = (self.vec3(src, a)?, self.vec3(src, b)?);
                if (corner_a - corner_b).abs().min_element() == 0.0 {
                    return Err(SceneError::at(
                        &at,
                        "the box's corners are equal in one coordinate: it has no volume",
                    ));
                }
                ShapeNode::Box { corner_a, corner_b }
            }
            Rule::triangle => {
                let [a, b, c] = take(3).try_into().expect("three arguments");
                let at = src.span(&c);
                let (a, b, c) = (self.vec3(src, a)?, self.vec3(src, b)?, self.vec3(src, c)?);
                if (b - a).cross(c - a).length() <= 1e-12 * (b - a).length() * (c - a).length() {
                    return Err(SceneError::at(
                        &at,
                        "the triangle's corners are collinear: it has no area",
                    ));
                }
                ShapeNode::Triangle { a, b, c }
            }
            Rule::quad => {
                let [p, e1, e2] = take(3).try_into().expect("three arguments");
                let at = src.span(&e2);
                let (corner, edge1, edge2) =
                    (self.vec3(src, p)?, self.vec3(src, e1)?, self.vec3(src, e2)?);
                if edge1.cross(edge2).length() <= 1e-12 * edge1.length() * edge2.length() {
                    return Err(SceneError::at(
                        &at,
                        "the quad's edges are zero or parallel: it has no area",
                    ));
                }
                ShapeNode::Quad { corner, edge1, edge2 }
            }
            Rule::disk => {
                let [c, n, r] = take(3).try_into().expect("three arguments");
                let center = self.vec3(src, c)?;
                let normal = self.nonzero(src, n, "the disk's normal")?;
                ShapeNode::Disk { center, normal, radius: self.positive(src, r, "radius")? }
            }
            Rule::cylinder => {
                let [b, c, r] = take(3).try_into().expect("three arguments");
                let at = src.span(&c);
                let (base, cap) = (self.vec3(src, b)?, self.vec3(src, c)?);
                if base == cap {
                    return Err(SceneError::at(
                        &at,
                        "the cylinder's base and cap centres are the same point",
                    ));
                }
                ShapeNode::Cylinder { base, cap, radius: self.positive(src, r, "radius")? }
            }
            Rule::mesh => {
                let [name] = take(1).try_into().expect("a file name");
                ShapeNode::Mesh { path: resolve(&src.file.path, &string(&name)) }
            }
            Rule::instance => {
                let [name] = take(1).try_into().expect("a name");
                match self.lookup(src, &name)? {
                    Value::Object(object) => ShapeNode::Instance(object),
                    other => {
                        return Err(src.error(
                            &name,
                            format!("`{}` is {}, not an object", name.as_str(), other.kind()),
                        ));
                    }
                }
            }
            _ => ShapeNode::Union(Vec::new()),
        };
        let depth = match &shape {
            ShapeNode::Instance(target) => target.depth + 1,
            _ => 1,
        };
        let mut node = ObjectNode { shape, material: None, transforms: Vec::new(), depth, span };
        for modifier in inner {
            match modifier.as_rule() {
                Rule::material => node.material = Some(self.material(src, modifier, None)?),
                Rule::material_name => node.material = Some(self.material_named(src, &modifier)?),
                Rule::transform => node.transforms.push(self.transform(src, modifier)?),
                _ => {
                    let child = self.object(src, modifier)?;
                    node.depth = node.depth.max(child.depth + 1);
                    if let ShapeNode::Union(children) = &mut node.shape {
                        children.push(child);
                    }
                }
            }
        }
        if node.depth > MAX_OBJECT_DEPTH {
            return Err(SceneError::at(
                &node.span,
                format!("objects nested more than {MAX_OBJECT_DEPTH} levels deep"),
            ));
        }
        Ok(node)
    }

    fn transform(&self, src: &Source, pair: Pair<'_, Rule>) -> Result<Transform, SceneError> {
        let mut inner = pair.into_inner();
        let (key, expr) = (inner.next().expect("key"), inner.next().expect("value"));
        let at = src.span(&expr);
        let value = self.value(src, expr)?;
        let key = key.into_inner().next().map_or("", |k| k.as_str());
        Ok(match key {
            "translate" => Transform::Translate(as_vector(&value, &at, "`translate`")?.as_vec3()),
            "rotate" => Transform::Rotate(as_vector(&value, &at, "`rotate`")?.as_vec3()),
            "scale" => {
                let s = as_vector(&value, &at, "`scale`")?.as_vec3();
                if s.cmpeq(Vec3::ZERO).any() {
                    let (x, y, z) = (s.x, s.y, s.z);
                    return Err(SceneError::at(
                        &at,
                        format!(
                            "scale <{x}, {y}, {z}> has a zero component: it flattens the object"
                        ),
                    ));
                }
                Transform::Scale(s)
            }
            _ => {
                let numbers = match value {
                    Value::Numbers(n) if n.len() == 12 => n,
                    other => {
                        return Err(SceneError::at(
                            &at,
                            format!("`matrix` takes 12 numbers, not {}", other.kind()),
                        ));
                    }
                };
                let m: Vec<f32> = numbers.iter().map(|&f| f as f32).collect();
                let linear = Mat3::from_cols_slice(&m[..9]);
                if linear.determinant().abs() < 1e-12 {
                    return Err(SceneError::at(
                        &at,
                        "the matrix is singular: it flattens the object",
                    ));
                }
                Transform::Matrix { linear, translation: Vec3::new(m[9], m[10], m[11]) }
            }
        })
    }

    fn material(
        &self,
        src: &Source,
        pair: Pair<'_, Rule>,
        name: Option<&str>,
    ) -> Result<Arc<MaterialDesc>, SceneError> {
        let span = src.span(&pair);
        let mut items = pair.into_inner().skip(1).peekable();
        let base = match items.peek() {
            Some(p) if p.as_rule() == Rule::base_material => {
                let named = items.next().expect("peeked");
                Some(self.material_named(src, &named)?)
            }
            _ => None,
        };
        let mut items = items.peekable();
        if items.peek().is_none() && name.is_none() {
            if let Some(base) = base {
                return Ok(base); // `material { White }`: the declared material itself, shared
            }
        }
        let mut material = match base {
            Some(base) => MaterialDesc { name: None, span: span.clone(), ..(*base).clone() },
            None => MaterialDesc::new(span.clone()),
        };
        material.name = name.map(str::to_string);
        for item in items {
            let mut inner = item.into_inner();
            let key = inner.next().expect("key");
            let key_name = key.clone().into_inner().next().map_or(key.as_str(), |k| k.as_str());
            match key_name {
                "fresnel" => material.fresnel = true,
                "ior" => {
                    let expr = inner.next().expect("value");
                    material.ior = self.positive(src, expr, "ior")?;
                }
                "diffuse" => {
                    material.diffuse = self.texture_arg(src, inner.next().expect("value"))?;
                }
                _ => {
                    let colour = self.colour(src, inner.next().expect("value"))?;
                    match key_name {
                        "specular" => material.specular = colour,
                        "transmission" => material.transmission = colour,
                        _ => material.emission = colour,
                    }
                }
            }
        }
        let total = material.diffuse.max_value() + material.specular + material.transmission;
        if let Some(channel) = (0..3).find(|&c| total[c] > 1.0 + 1e-6) {
            let who = material
                .name
                .as_ref()
                .map_or("this material".to_string(), |n| format!("material `{n}`"));
            return Err(SceneError::at(
                &span,
                format!(
                    "{who} reflects more light than it receives: diffuse + specular + transmission = {} in the {} channel (at most 1)",
                    total[channel],
                    ["red", "green", "blue"][channel]
                ),
            ));
        }
        Ok(Arc::new(material))
    }

    /// A colour or a texture node, where `diffuse` takes one.
    fn texture_arg(&self, src: &Source, pair: Pair<'_, Rule>) -> Result<TextureNode, SceneError> {
        let pair = match pair.as_rule() {
            Rule::texture_arg => pair.into_inner().next().expect("a texture or a colour"),
            _ => pair,
        };
        if pair.as_rule() == Rule::colour {
            // A declared texture's name reads as a colour expression.
            let value = pair.clone().into_inner().find(|p| p.as_rule() == Rule::expr);
            if let Some(Value::Texture(texture)) = value.map(|e| self.value(src, e)).transpose()? {
                return Ok((*texture).clone());
            }
            return Ok(TextureNode::solid(self.colour(src, pair)?));
        }
        let node = pair.into_inner().next().expect("one kind of texture");
        let kind = node.as_rule();
        let mut inner = node.into_inner().skip(1);
        let mut args = Vec::new();
        let mut transforms = Vec::new();
        let mut map = None;
        let (mut axis, mut octaves, mut turbulence) = (None, None, None);
        let mut path = None;
        for item in inner.by_ref() {
            match item.as_rule() {
                Rule::texture_arg => args.push(self.texture_arg(src, item)?),
                Rule::string => path = Some(resolve(&src.file.path, &string(&item))),
                Rule::transform => transforms.push(self.transform(src, item)?),
                Rule::color_map => {
                    let at = src.span(&item);
                    let takes_map =
                        matches!(kind, Rule::gradient | Rule::noise | Rule::marble | Rule::wood);
                    if !takes_map {
                        return Err(SceneError::at(
                            &at,
                            "`color_map` has no effect on this texture",
                        ));
                    }
                    let mut entries: Vec<(f32, Vec3)> = Vec::new();
                    for entry in item.into_inner().filter(|e| e.as_rule() == Rule::map_entry) {
                        let mut parts = entry.into_inner();
                        let position_pair = parts.next().expect("position");
                        let position_at = src.span(&position_pair);
                        let position = self.float(src, position_pair)? as f32;
                        let colour = self.colour(src, parts.next().expect("colour"))?;
                        let previous = entries.last().map_or(0.0, |e| e.0);
                        if !(previous..=1.0).contains(&position) {
                            return Err(SceneError::at(
                                &position_at,
                                format!(
                                    "color_map position {position} must be in [0, 1] and not below the one before"
                                ),
                            ));
                        }
                        entries.push((position, colour));
                    }
                    if map.replace(entries).is_some() {
                        return Err(SceneError::at(&at, "a second color_map"));
                    }
                }
                _ => {
                    let mut parts = item.into_inner();
                    let key = parts.next().expect("key");
                    let key_at = src.span(&key);
                    let value = parts.next().expect("value");
                    let applies = match key.as_str() {
                        "axis" => matches!(kind, Rule::stripes | Rule::gradient),
                        "octaves" => matches!(kind, Rule::noise | Rule::marble | Rule::wood),
                        _ => matches!(kind, Rule::marble | Rule::wood),
                    };
                    if !applies {
                        return Err(SceneError::at(
                            &key_at,
                            format!("`{}` has no effect on this texture", key.as_str()),
                        ));
                    }
                    match key.as_str() {
                        "axis" => axis = Some(self.nonzero(src, value, "the axis")?),
                        "octaves" => octaves = Some(self.integer(src, value, 1, 16)? as u32),
                        _ => {
                            let at = src.span(&value);
                            let t = self.float(src, value)? as f32;
                            if t < 0.0 {
                                return Err(SceneError::at(
                                    &at,
                                    format!("turbulence {t} is negative"),
                                ));
                            }
                            turbulence = Some(t);
                        }
                    }
                }
            }
        }
        // Black to white when no map is given.
        let map = map
            .filter(|m| !m.is_empty())
            .unwrap_or_else(|| vec![(0.0, Vec3::ZERO), (1.0, Vec3::ONE)]);
        let mut args = args.into_iter().map(Box::new);
        let mut arg = || args.next().expect("the grammar gives the arguments");
        let octaves = octaves.unwrap_or(4);
        let turbulence = turbulence.unwrap_or(0.0);
        let pattern = match kind {
            Rule::checker => Pattern::Checker(arg(), arg()),
            Rule::stripes => Pattern::Stripes { a: arg(), b: arg(), axis: axis.unwrap_or(Vec3::X) },
            Rule::gradient => Pattern::Gradient { axis: axis.unwrap_or(Vec3::Y), map },
            Rule::noise => Pattern::Noise { octaves, map },
            Rule::marble => Pattern::Marble { turbulence, octaves, map },
            Rule::wood => Pattern::Wood { turbulence, octaves, map },
            Rule::image_map => Pattern::Image { path: path.expect("the grammar gives a file") },
            _ => Pattern::Mix { a: arg(), b: arg(), t: arg() },
        };
        Ok(TextureNode { pattern, transforms })
    }

    fn material_named(
        &self,
        src: &Source,
        pair: &Pair<'_, Rule>,
    ) -> Result<Arc<MaterialDesc>, SceneError> {
        let ident = pair.clone().into_inner().next().unwrap_or_else(|| pair.clone());
        match self.lookup(src, &ident)? {
            Value::Material(m) => Ok(m),
            other => Err(src.error(
                &ident,
                format!("`{}` is {}, not a material", ident.as_str(), other.kind()),
            )),
        }
    }

    fn lookup(&self, src: &Source, ident: &Pair<'_, Rule>) -> Result<Value, SceneError> {
        self.env.get(ident.as_str()).cloned().ok_or_else(|| {
            let mut message = format!("unknown identifier `{}`", ident.as_str());
            if let Some(guess) =
                parser::closest(ident.as_str(), self.env.keys().map(String::as_str))
            {
                message.push_str(&format!("; did you mean `{guess}`?"));
            }
            src.error(ident, message)
        })
    }

    fn value(&self, src: &Source, expr: Pair<'_, Rule>) -> Result<Value, SceneError> {
        value::eval(expr, &self.env, &|p, m| src.error(p, m))
    }

    fn float(&self, src: &Source, expr: Pair<'_, Rule>) -> Result<f64, SceneError> {
        let at = src.span(&expr);
        as_float(&self.value(src, expr)?, &at, "this value")
    }

    fn vector(&self, src: &Source, expr: Pair<'_, Rule>) -> Result<DVec3, SceneError> {
        let at = src.span(&expr);
        as_vector(&self.value(src, expr)?, &at, "this value")
    }

    fn vec3(&self, src: &Source, expr: Pair<'_, Rule>) -> Result<Vec3, SceneError> {
        self.vector(src, expr).map(|v| v.as_vec3())
    }

    fn nonzero(&self, src: &Source, expr: Pair<'_, Rule>, what: &str) -> Result<Vec3, SceneError> {
        let at = src.span(&expr);
        let v = self.vec3(src, expr)?;
        if v.length() == 0.0 {
            return Err(SceneError::at(&at, format!("{what} is a zero vector")));
        }
        Ok(v)
    }

    fn positive(&self, src: &Source, expr: Pair<'_, Rule>, what: &str) -> Result<f32, SceneError> {
        let at = src.span(&expr);
        let f = self.float(src, expr)?;
        if f <= 0.0 {
            let sign = if f < 0.0 { "negative" } else { "zero" };
            return Err(SceneError::at(&at, format!("{what} {f} is {sign}: it must be positive")));
        }
        Ok(f as f32)
    }

    fn integer(
        &self,
        src: &Source,
        expr: Pair<'_, Rule>,
        min: u64,
        max: u64,
    ) -> Result<u64, SceneError> {
        let at = src.span(&expr);
        let f = self.float(src, expr)?;
        if f.fract() != 0.0 || f < min as f64 || f > max as f64 {
            return Err(SceneError::at(
                &at,
                format!("{f} is not a whole number from {min} to {max}"),
            ));
        }
        Ok(f as u64)
    }

    /// A `colour` pair: `rgb <r, g, b>`, `rgb s`, or an expression; components must not be negative.
    fn colour(&self, src: &Source, pair: Pair<'_, Rule>) -> Result<Vec3, SceneError> {
        let at = src.span(&pair);
        let expr =
            pair.into_inner().find(|p| p.as_rule() == Rule::expr).expect("a colour has a value");
        let colour = match self.value(src, expr)? {
            Value::Float(f) => DVec3::splat(f),
            Value::Vector(v) => v,
            other => {
                return Err(SceneError::at(
                    &at,
                    format!("expected a colour, found {}", other.kind()),
                ));
            }
        };
        if colour.min_element() < 0.0 {
            let [r, g, b] = colour.to_array();
            return Err(SceneError::at(
                &at,
                format!("colour <{r}, {g}, {b}> has a negative component"),
            ));
        }
        Ok(colour.as_vec3())
    }
}

fn as_float(value: &Value, at: &Span, what: &str) -> Result<f64, SceneError> {
    match value {
        Value::Float(f) => Ok(*f),
        other => Err(SceneError::at(at, format!("{what} needs a number, not {}", other.kind()))),
    }
}

/// A vector, or a number promoted to `<f, f, f>`.
fn as_vector(value: &Value, at: &Span, what: &str) -> Result<DVec3, SceneError> {
    match value {
        Value::Float(f) => Ok(DVec3::splat(*f)),
        Value::Vector(v) => Ok(*v),
        other => Err(SceneError::at(at, format!("{what} needs a vector, not {}", other.kind()))),
    }
}

/// The text of a `string` pair (or of the string inside `pair`).
fn string(pair: &Pair<'_, Rule>) -> String {
    pair.clone()
        .into_inner()
        .flatten()
        .find(|p| p.as_rule() == Rule::string_text)
        .map_or(String::new(), |p| p.as_str().to_string())
}

/// A path named in `from`, relative to `from`'s folder unless absolute.
fn resolve(from: &Path, name: &str) -> PathBuf {
    from.parent().unwrap_or(Path::new("")).join(name)
}

/// A path's identity for cycle detection: canonical where the file exists.
fn identity(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| path.to_path_buf())
}
