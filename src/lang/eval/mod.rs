//! Statements to scene graph: `#declare`, `#include`, settings, camera, lights, objects and
//! materials, each checked where it is written so that every error points at its text.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Mat3, Vec3};
use pest::iterators::Pair;

mod camera;
mod material;

use super::parser::{self, Rule};
use super::value::{self, Env, Value};
use crate::diagnostic::{SceneError, SourceFile, Span};
use crate::scene::graph::{
    CameraDesc, IntegratorKind, ObjectNode, PointLightDesc, SceneGraph, Settings, ShapeNode,
    Transform,
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
