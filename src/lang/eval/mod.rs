//! The interpreter: runs the syntax tree (`lang::syntax`) to a scene graph. Directives run over
//! the tree with a stack of scopes (the global one, one per included file, one per macro call);
//! every other item goes to the body it stands in (the scene, an object, a material, ...), which
//! says what it accepts. Every error points at the text.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec3};

mod appearance;
mod arc_solid;
mod array;
mod blob;
mod camera;
mod expression;
mod file_io;
mod function;
mod height_field;
mod image_pigment;
mod isosurface;
mod julia;
mod light;
mod listed;
mod material;
mod medium;
mod normal;
mod object;
mod outline;
mod parametric;
mod patch;
mod pattern;
mod pigment;
mod polynomial;
mod prism;
mod probe;
mod scope;
mod sky;
mod sphere_sweep;
mod text;
mod texture_space;
mod transform;
mod triangles;

use super::syntax::{
    self, Call, CaseTest, Condition, Declare, Declared, ExprKind, Ident, Item, MapKind,
    MessageKind, SettingKind, Transform, TransformKind,
};
use super::value::Value;
use super::{parser, tree};
use crate::animation::Frame;
use crate::diagnostic::{Context, Note, SceneError, SourceFile, Span};
use crate::digest::Digest;
use crate::graph::{
    CameraDesc, CsgOp, IntegratorKind, LightDesc, ObjectNode, SceneGraph, Settings, ShapeNode,
    SkyDesc,
};
use crate::lang::dialect::Dialect;
use crate::region::MAX_RESOLUTION;

use appearance::PigmentState;
pub use appearance::{Finish, Look};
use array::element_index;
pub use camera::CameraParams;
pub use file_io::{MAX_FILES_OPENED, MAX_WRITTEN_BYTES};
pub use light::LightState;
use light::PovLight;
pub use material::TextureState;
pub use medium::Interior;
use normal::NormalState;
use pattern::MapState;
pub use pigment::{Pigment, Stop};
use scope::{Scope, Slot};

/// Includes may nest this deep.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Files read by `#include` in one scene (the same file included twice counts twice), and
/// their text together: a chain of files that each include the next twice would otherwise read
/// 2^depth files.
pub const MAX_INCLUDES: u32 = 10_000;
pub const MAX_INCLUDED_BYTES: u64 = 256 << 20;

/// Groups and instances may nest this deep (instances of instances need no brackets).
pub const MAX_OBJECT_DEPTH: u32 = 256;

/// Intersections, differences and merges may nest this deep, counting the unions among their
/// operands (each a merge): tracing a CSG object keeps the crossings of every level on the render
/// thread's stack (about 3 KiB a level).
pub const MAX_CSG_DEPTH: u32 = 64;

/// Operands of one intersection, difference or merge: a ray that meets the object is tested
/// against each of them (a difference of 10^5 spheres traced 3000 times slower than their union).
pub const MAX_CSG_OPERANDS: usize = 1024;

/// Macro calls may nest this deep (a macro calling itself counts each call).
pub const MAX_MACRO_DEPTH: usize = 256;

/// Macro calls of one scene together: the language's work budget beside the loop turns (a
/// macro calling itself twice would otherwise run for 2^depth calls). A call nested 40 deep
/// takes nearly a microsecond (each name is looked up through every caller's scope): a
/// million such calls took 0.8 s on a release build, so the budget ends them in a fifth of that.
pub const MAX_MACRO_CALLS: u64 = if cfg!(fuzzing) { FUZZING_BUDGET } else { 250_000 };

/// Objects the interpreter makes in one scene (each object written, every time it is evaluated;
/// a mesh is one): a loop making unions of objects is stopped at about half a gigabyte, before
/// the build counts primitives. `object { Name }` counts one, however much `Name` holds.
pub const MAX_OBJECTS_MADE: u64 = if cfg!(fuzzing) { FUZZING_BUDGET } else { 1 << 22 };

/// Array elements made or copied in one scene (chunk pointers count one each): some half a
/// gigabyte. An array declared without elements makes one chunk however large it is.
pub const MAX_ARRAY_ELEMENTS_MADE: u64 = if cfg!(fuzzing) { FUZZING_BUDGET } else { 1 << 24 };

/// Turns of all `#while` and `#for` loops of one scene together.
pub const MAX_LOOP_TURNS: u64 = if cfg!(fuzzing) { FUZZING_BUDGET } else { 10_000_000 };

/// The fuzz targets run each input under a sanitizer, many times slower: there the budgets of
/// loops, macro calls and objects are smaller, so that a loop that never ends is refused in a fraction of a
/// second rather than read as a hang. The checks themselves are the same.
const FUZZING_BUDGET: u64 = 100_000;

/// POV-Ray's tolerance for `=`, `!=`, `<=`, `>=`.
pub const EPSILON: f64 = 1e-10;

/// The most photons `photon_k` may gather in one density estimate.
pub const MAX_PHOTON_K: u64 = 10_000;

/// Stack kept free before evaluating deeper, and the size of each extra segment: deep macro
/// recursion grows the stack on the heap instead of overflowing a small thread stack.
const RED_ZONE: usize = 128 * 1024;
const STACK_SEGMENT: usize = 4 * 1024 * 1024;

#[derive(Default)]
pub struct Evaluator {
    /// Scopes, outermost first: the global one, then one per included file or macro call.
    scopes: Vec<Scope>,
    settings: Option<Settings>,
    camera: Option<CameraDesc>,
    lights: Vec<LightDesc>,
    objects: Vec<ObjectNode>,
    /// The files being read, outermost first: their identity (canonical path) and their path
    /// as named.
    open_files: Vec<(PathBuf, PathBuf)>,
    /// How many macro calls are being evaluated.
    calls: usize,
    /// The macro calls and includes being evaluated, innermost first: nodes made here carry it
    /// in their spans, so that errors found while building the scene name them.
    context: Option<Arc<Context>>,
    loop_turns: u64,
    macro_calls: u64,
    array_elements: u64,
    includes: u32,
    included_bytes: u64,
    /// Texture nodes made or copied so far.
    texture_nodes: u64,
    /// Objects made so far.
    objects_made: u64,
    /// Warnings given while evaluating (`#warning` prints its own at once).
    warnings: Vec<String>,
    /// The state of each `seed(n)` stream.
    streams: Vec<u32>,
    /// Levels of CSG operations of the declared objects that CSG operands have instanced, by
    /// address (the `Arc` kept so that the address stays theirs): shared objects are counted once.
    csg_levels: std::collections::HashMap<usize, (Arc<ObjectNode>, u32)>,
    /// The animation frame the scene is evaluated at: `clock` and `frame_number`.
    frame: Frame,
    /// Digest of the text of every file read, in the order read.
    sources: Digest,
    /// The scene's language: the main file's, for every file it includes.
    dialect: Dialect,
    /// `.pov`: the image's size in pixels (`image_width`, `image_height`).
    image: (u32, u32),
    /// `.pov`: the point the camera looks at, where POV-Ray's lights are matched.
    pov_look_at: Option<Vec3>,
    /// `.pov`: the lights given a POV-Ray colour, whose power is set once the camera is known.
    pov_lights: Vec<PovLight>,
    /// `.pov`: the lights written in the objects being evaluated (POV-Ray lets a light be part
    /// of an object): moved by each object's transforms, placed when the outermost is done.
    held_lights: Vec<(LightState, Span)>,
    /// `.pov`: what `#default` has made POV-Ray's default texture.
    default_look: Look,
    /// `.pov`: the look of each object being evaluated, innermost last (`None` until one of its
    /// items gives it one).
    looks: Vec<Option<Look>>,
    /// `.pov`: the material and look of the object last made, for `unlit_object` to keep.
    made_look: Option<(Arc<crate::graph::MaterialDesc>, Look)>,
    /// `.pov`: the looks declared objects wear, by their material's address (the `Arc` kept so
    /// that the address stays theirs): what a wrapper's texture, pigment, normal or finish
    /// modifies.
    worn_looks: std::collections::HashMap<usize, (Arc<crate::graph::MaterialDesc>, Look)>,
    /// `.pov`: the declared objects laid under each material they were placed with.
    laid: texture_space::Laid,
    /// `.pov`: `sky_sphere`, the environment light.
    sky: Option<SkyDesc>,
    /// `.pov`: `background`, seen and not lighting.
    backdrop: Vec3,
    /// `atmosphere { }` (POV-Ray's `fog` and scene-wide `media`): the medium filling the scene.
    atmosphere: Option<crate::graph::MediumDesc>,
    /// `.pov`: the finish's words warned about as not rendered (once each).
    warned_finish: BTreeSet<String>,
    /// `.pov`: the `inverse` and `clipped_by` of each object being evaluated, innermost last.
    shapings: Vec<object::Shaping>,
    /// Folders searched for included files after the including file's (`--include-path`).
    include_path: Vec<PathBuf>,
    /// `.pov`: whether the warning that a pattern's textures share one finish has been given.
    warned_map_finish: bool,
    /// `.pov`: whether the warning that layered textures share the top one's finish has been
    /// given (the standard includes' stones layer many).
    warned_layer_finish: bool,
    /// `.pov`: whether the warning that a surface's negative colour is clamped has been given.
    warned_negative_colour: bool,
    /// `.pov`: `global_settings { ambient_light }`, by which a glow's `ambient` is multiplied
    /// (`None`: POV-Ray's default, white).
    ambient_light: Option<Vec3>,
    /// `.pov`: where the first surface that glows by its `ambient` was made (an `ambient_light`
    /// after it would change what it already is).
    ambient_glow_at: Option<Span>,
    /// `.pov`: `global_settings { assumed_gamma G }`, the gamma the scene's colours are
    /// encoded with (`None`: 1, linear).
    assumed_gamma: Option<f32>,
    /// `.pov`: where the first surface or light took its colour (an `assumed_gamma` after it
    /// would change what it already is).
    coloured_at: Option<Span>,
    /// `.pov`: the files opened by `#fopen`.
    files: file_io::Files,
    /// `.pov`: the objects `min_extent`, `max_extent`, `trace` and `inside` have asked about.
    probes: probe::Probes,
}

/// POV-Ray's image size when none is given (its `+W320 +H240`).
pub const POV_IMAGE: (u32, u32) = (320, 240);

/// Where items stand, which decides what they may be.
pub enum Body<'a> {
    Scene,
    Settings(&'a mut Settings),
    Camera(&'a mut CameraParams),
    Light(&'a mut LightState),
    Object(&'a mut ObjectNode),
    Material(&'a mut crate::graph::MaterialDesc),
    Texture(&'a mut TextureState),
    ColorMap(&'a mut Vec<Stop>),
    /// POV-Ray's pigment, finish, texture (with `#default`) and interior's ior (`.pov`).
    Pigment(&'a mut PigmentState),
    /// POV-Ray's `normal { }` (both dialects).
    Normal(&'a mut NormalState),
    /// A pigment, normal, texture or slope map's entries.
    PatternMap(&'a mut MapState),
    Finish(&'a mut Finish),
    Look(&'a mut Look),
    Interior(&'a mut medium::Interior),
    /// POV-Ray's `sky_sphere` (`.pov`).
    Sky(&'a mut SkyDesc),
    /// A macro called as a value: its body gives one.
    Value(&'a mut Option<Value>),
    /// POV-Ray's `transform { }` (`.pov`).
    Transform(&'a mut transform::TransformState),
    /// A shape's points, with the directives that run through them: each as it stands when it
    /// is reached, its values written out (`listed`).
    Listed(&'a mut Vec<syntax::Expr>),
    /// POV-Ray's mesh of triangles (`.pov`): its triangles as they are reached, written out as
    /// the points are, while `triangles` is open; its first other item makes the mesh of them
    /// into `node`'s shape and closes them, and that item and those after it are the object's
    /// (`triangles::mesh_item`).
    Mesh {
        triangles: &'a mut Option<Vec<syntax::Object>>,
        node: &'a mut ObjectNode,
    },
}

impl Body<'_> {
    fn place(&self) -> &'static str {
        match self {
            Body::Scene => "at the top level of a scene",
            Body::Settings(_) => "in `settings`",
            Body::Camera(_) => "in a camera",
            Body::Light(_) => "in a light_source",
            Body::Object(node) => match node.shape {
                ShapeNode::Union(_) => "in a union",
                ShapeNode::Csg { op: CsgOp::Intersection, .. } => "in an intersection",
                ShapeNode::Csg { op: CsgOp::Difference, .. } => "in a difference",
                ShapeNode::Csg { op: CsgOp::Merge, .. } => "in a merge",
                ShapeNode::Csg { op: CsgOp::Inverse | CsgOp::Clip, .. } => "in this object",
                ShapeNode::Plane { .. }
                | ShapeNode::Sphere { .. }
                | ShapeNode::Box { .. }
                | ShapeNode::Triangle { .. }
                | ShapeNode::Quad { .. }
                | ShapeNode::Disk { .. }
                | ShapeNode::Cylinder { .. }
                | ShapeNode::Cone { .. }
                | ShapeNode::Torus { .. }
                | ShapeNode::Isosurface(_)
                | ShapeNode::Parametric(_)
                | ShapeNode::Algebraic { .. }
                | ShapeNode::Prism { .. }
                | ShapeNode::Lathe { .. }
                | ShapeNode::Sor { .. }
                | ShapeNode::Ovus { .. }
                | ShapeNode::Lemon { .. }
                | ShapeNode::Polygon { .. }
                | ShapeNode::Superellipsoid { .. }
                | ShapeNode::JuliaFractal(_)
                | ShapeNode::Mesh { .. }
                | ShapeNode::Extrusion(_)
                | ShapeNode::HeightField { .. }
                | ShapeNode::Instance(_) => "in this object",
                ShapeNode::Blob { .. } => "in this blob",
            },
            Body::Material(_) => "in a material",
            Body::Texture(_) => "in a texture",
            Body::ColorMap(_) => "in a color_map",
            Body::Pigment(_) => "in a pigment",
            Body::Normal(_) => "in a normal",
            Body::PatternMap(map) => match map.kind {
                MapKind::Pigment => "in a pigment_map",
                MapKind::Normal => "in a normal_map",
                MapKind::Texture => "in a texture_map",
                MapKind::Slope => "in a slope_map",
            },
            Body::Finish(_) => "in a finish",
            Body::Look(_) => "in a texture",
            Body::Interior(_) => "in an interior",
            Body::Sky(_) => "in a sky_sphere",
            Body::Value(_) => "where a value is expected",
            Body::Transform(_) => "in a transform",
            Body::Listed(_) => "among a shape's points",
            Body::Mesh { .. } => "in a mesh",
        }
    }
}

impl Evaluator {
    /// An evaluator for a scene in `dialect` whose image is `image` pixels (POV-Ray's
    /// `image_width` and `image_height`; `None`: the scene's own or POV-Ray's default).
    pub fn for_image(frame: Frame, dialect: Dialect, image: Option<(u32, u32)>) -> Self {
        Evaluator { frame, dialect, image: image.unwrap_or(POV_IMAGE), ..Evaluator::default() }
    }

    /// The evaluator, searching `include_path`'s folders for included files after the
    /// including file's own.
    pub fn searching(self, include_path: Vec<PathBuf>) -> Self {
        Evaluator { include_path, ..self }
    }

    /// Evaluates the main file and returns the scene it describes.
    pub fn scene(self, file: Arc<SourceFile>) -> Result<SceneGraph, SceneError> {
        self.scene_and_sources(file).map(|(graph, _)| graph)
    }

    /// Evaluates the main file; returns the scene and a digest of the text of every file read.
    pub fn scene_and_sources(
        mut self,
        file: Arc<SourceFile>,
    ) -> Result<(SceneGraph, Digest), SceneError> {
        self.sources.add(file.text.as_bytes());
        self.scopes.push(Scope::default());
        if self.dialect == Dialect::Pov {
            let (width, height) = self.image;
            // The version POV-Ray's scenes test for: raydiance reads POV-Ray 3.7's language.
            let names =
                [("image_width", width.into()), ("image_height", height.into()), ("version", 3.7)];
            for (name, value) in names {
                self.scopes[0].names.insert(name.into(), Slot::Value(Value::Float(value)));
            }
        }
        self.open_files.push((identity(&file.path), file.path.clone()));
        let items = tree::parse_file(&file, self.dialect)?;
        self.exec(&items, &mut Body::Scene)?;
        let at_end = parser::span_at(&file, file.text.trim_end().len());
        let camera = match (self.camera.take(), self.dialect) {
            (Some(camera), _) => camera,
            // POV-Ray's default camera.
            (None, Dialect::Pov) => self.pov_camera(&CameraParams::new(), &at_end)?,
            (None, Dialect::Scn) => {
                let message = match items.is_empty() {
                    true => "the scene is empty: a scene needs one `camera { ... }` and objects",
                    false => "missing camera: a scene needs one `camera { ... }`",
                };
                return Err(SceneError::at(&at_end, message));
            }
        };
        self.light_powers_from_colours();
        let settings = match self.dialect {
            Dialect::Scn => self.settings.unwrap_or_default(),
            Dialect::Pov => {
                let (width, height) = self.image;
                Settings { width, height, ..self.settings.unwrap_or_default() }
            }
        };
        let graph = SceneGraph {
            settings,
            camera,
            lights: self.lights,
            objects: self.objects,
            sky: self.sky,
            backdrop: self.backdrop,
            atmosphere: self.atmosphere,
            warnings: self.warnings,
        };
        Ok((graph, self.sources))
    }

    /// Runs the items of a body.
    pub(super) fn exec(&mut self, items: &[Item], body: &mut Body) -> Result<(), SceneError> {
        stacker::maybe_grow(RED_ZONE, STACK_SEGMENT, || {
            for item in items {
                self.exec_item(item, body)?;
            }
            Ok(())
        })
    }

    fn exec_item(&mut self, item: &Item, body: &mut Body) -> Result<(), SceneError> {
        match item {
            Item::Declare(declare) => self.declare(declare),
            Item::Undef(name) => {
                self.undef(&name.name);
                Ok(())
            }
            Item::Include { file, span } => self.include(file, span, body),
            Item::If { branches, otherwise, .. } => {
                for (condition, items) in branches {
                    if self.condition(condition)? {
                        return self.exec(items, body);
                    }
                }
                match otherwise {
                    Some(items) => self.exec(items, body),
                    None => Ok(()),
                }
            }
            Item::Switch { value, clauses, otherwise, .. } => {
                let value = self.number(value, "`#switch`'s value")?;
                let mut first = None;
                for (i, clause) in clauses.iter().enumerate() {
                    if self.case_holds(&clause.test, value)? {
                        first = Some(i);
                        break;
                    }
                }
                let Some(first) = first else {
                    return otherwise.as_ref().map_or(Ok(()), |items| self.exec(items, body));
                };
                // Clauses without `#break` fall through to the next, as in POV-Ray.
                for clause in &clauses[first..] {
                    self.exec(&clause.items, body)?;
                    if clause.breaks {
                        break;
                    }
                }
                Ok(())
            }
            Item::While { condition, body: items, span } => loop {
                let go = self.number(condition, "`#while`'s condition")?;
                if go == 0.0 {
                    return Ok(());
                }
                self.count_turn(span)?;
                self.exec(items, body)?;
            },
            Item::For { variable, from, to, step, body: items, span } => {
                self.for_loop(variable, from, to, step.as_ref(), items, span, body)
            }
            Item::Macro(definition) => {
                // Macros are global, as in POV-Ray.
                let name = definition.name.name.clone();
                self.scopes[0].names.insert(name, Slot::Value(Value::Macro(definition.clone())));
                Ok(())
            }
            Item::Message { kind, text, span } => {
                let text = match self.value(text)? {
                    Value::String(s) => s,
                    other => {
                        return Err(SceneError::at(
                            &text.span,
                            format!("a message is a string, not {}", other.kind()),
                        ));
                    }
                };
                match kind {
                    MessageKind::Debug => eprint!("{text}"),
                    // Clipped and escaped as an error's text is.
                    MessageKind::Warning => {
                        eprintln!("{span:?}: warning: {}", crate::diagnostic::printable(&text))
                    }
                    MessageKind::Error => return Err(SceneError::at(span, text.to_string())),
                }
                Ok(())
            }
            Item::File(directive) => self.file_directive(directive),
            Item::GlobalSettings { ambient_light, assumed_gamma, others, span } => {
                if let Some(colour) = ambient_light {
                    self.set_ambient_light(colour)?;
                }
                // `.scn`'s colours are linear light: its `assumed_gamma` is one of the others.
                let pov = self.dialect == Dialect::Pov;
                if let Some(gamma) = assumed_gamma.as_ref().filter(|_| pov) {
                    self.set_assumed_gamma(gamma)?;
                }
                if *others || (assumed_gamma.is_some() && !pov) {
                    self.warnings.push(format!(
                        "{:?}: warning: POV-Ray's `global_settings` has no effect here apart from \
                         its `ambient_light` (and in `.pov` its `assumed_gamma`): raydiance's \
                         settings are `settings {{ resolution ..., samples ..., integrator ..., \
                         max_depth ..., seed ..., background ... }}`",
                        self.here(span)
                    ));
                }
                Ok(())
            }
            Item::Ignored { what, span } => {
                self.warnings.push(format!("{:?}: warning: {}", self.here(span), what.warning()));
                Ok(())
            }
            Item::Call(call) => self.call_macro(call, body),
            Item::Settings { .. }
            | Item::Setting(_)
            | Item::Camera { .. }
            | Item::CameraParam { .. }
            | Item::CameraProjection { .. }
            | Item::Light { .. }
            | Item::LightPower { .. }
            | Item::Object(_)
            | Item::Material(_)
            | Item::MaterialName(_)
            | Item::Transform(_)
            | Item::MaterialParam(_)
            | Item::Texture(_)
            | Item::TextureParam(_)
            | Item::PatternMap { .. }
            | Item::MapBlock { .. }
            | Item::ColorMap { .. }
            | Item::MapEntry { .. }
            | Item::Default { .. }
            | Item::SkySphere { .. }
            | Item::Appearance(_)
            | Item::Pattern { .. }
            | Item::PovParam { .. }
            | Item::ClippedBy { .. }
            | Item::ImageMap { .. }
            | Item::UvVectors { .. }
            | Item::Value(_) => match body {
                Body::Scene => self.scene_item(item),
                Body::Settings(settings) => self.setting_item(item, settings),
                Body::Camera(params) => self.camera_item(item, params),
                Body::Light(power) => self.light_item(item, power),
                Body::Object(node) => self.object_item(item, node),
                Body::Material(material) => self.material_item(item, material),
                Body::Texture(state) => self.texture_item(item, state),
                Body::ColorMap(entries) => self.map_entry(item, entries),
                Body::Value(slot) => self.value_item(item, slot),
                Body::Pigment(state) => self.pigment_item(item, state),
                Body::Normal(state) => self.normal_item(item, state),
                Body::PatternMap(state) => self.map_block(item, state),
                Body::Finish(finish) => self.finish_item(item, finish),
                Body::Look(look) => self.look_item(item, look),
                Body::Interior(interior) => self.interior_item(item, interior),
                Body::Sky(sky) => self.sky_item(item, sky),
                Body::Transform(state) => self.transform_item(item, state),
                Body::Listed(listed) => self.listed_item(item, listed),
                Body::Mesh { triangles, node } => self.mesh_item(item, triangles, node),
            },
        }
    }

    /// `span` as the span of a node made here: with the macro calls and includes around it.
    pub(super) fn here(&self, span: &Span) -> Span {
        Span { context: self.context.clone(), ..span.clone() }
    }

    /// An item that cannot stand in `body`.
    fn misplaced(item: &Item, body: &Body) -> SceneError {
        SceneError::at(item.span(), format!("{} cannot stand {}", item.describe(), body.place()))
    }

    fn scene_item(&mut self, item: &Item) -> Result<(), SceneError> {
        match item {
            Item::Settings { items, span } => {
                if self.settings.is_some() {
                    return Err(SceneError::at(
                        span,
                        "a second `settings` block (a scene has at most one)",
                    ));
                }
                let mut settings = Settings::default();
                self.exec(items, &mut Body::Settings(&mut settings))?;
                self.settings = Some(settings);
                Ok(())
            }
            Item::Camera { items, span } => self.camera(items, span),
            // POV-Ray's `background { C }` (only `.pov` gives a setting outside `settings`): seen,
            // not lighting, as in POV-Ray.
            Item::Setting(setting) => {
                let SettingKind::Background(colour) = &setting.kind else {
                    return Err(Self::misplaced(item, &Body::Scene));
                };
                self.backdrop = self.colour(colour)?;
                Ok(())
            }
            Item::Light { position, items, span } => self.light(position, items, span),
            Item::Object(object) => {
                let mut node = self.object(object)?;
                for (light, span) in std::mem::take(&mut self.held_lights) {
                    self.place_light(light, &span)?;
                }
                if self.dialect == Dialect::Pov {
                    if node.material.is_none() {
                        // POV-Ray's default texture, where nothing gives the object one.
                        let look = self.default_look_of(&node);
                        node.material = Some(self.look_material(&look, &object.span));
                    }
                    self.lay_textures(&mut node)?;
                }
                self.objects.push(node);
                Ok(())
            }
            Item::SkySphere { items, span } => self.sky_sphere(items, span),
            Item::PovParam { key, items, .. } if key.name == "atmosphere" => {
                let medium = self.medium(items, &key.span)?;
                self.add_atmosphere(medium)
            }
            Item::PovParam { key, items, .. } if key.name == "media" => {
                let medium = self.pov_media(items, &key.span)?;
                self.add_atmosphere(medium)
            }
            Item::PovParam { key, items, .. } if key.name == "fog" => {
                self.pov_fog(items, &key.span)
            }
            Item::Default { items, .. } => {
                let mut look = self.default_look.clone();
                self.exec(items, &mut Body::Look(&mut look))?;
                self.default_look = look;
                Ok(())
            }
            Item::Value(expr) => match self.value(expr)? {
                // A macro or array element that holds an object, standing as a statement.
                Value::Object(node) => {
                    let mut node = instance(node, self.here(&expr.span));
                    if self.dialect == Dialect::Pov {
                        self.lay_textures(&mut node)?;
                    }
                    self.objects.push(node);
                    Ok(())
                }
                _ => Err(Self::misplaced(item, &Body::Scene)),
            },
            _ => Err(Self::misplaced(item, &Body::Scene)),
        }
    }

    fn setting_item(&mut self, item: &Item, settings: &mut Settings) -> Result<(), SceneError> {
        let Item::Setting(setting) = item else {
            return Err(Self::misplaced(item, &Body::Settings(settings)));
        };
        match &setting.kind {
            SettingKind::Resolution(w, h) => {
                let most = MAX_RESOLUTION.into();
                settings.width = self.integer(w, 1, most)? as u32;
                settings.height = self.integer(h, 1, most)? as u32;
            }
            // (`pipeline::MAX_SAMPLES` and `MAX_DEPTH`, which this layer does not import.)
            SettingKind::Samples(e) => settings.samples = self.integer(e, 1, 1_000_000)? as u32,
            SettingKind::MaxDepth(e) => settings.max_depth = self.integer(e, 0, 1024)? as u32,
            SettingKind::Seed(e) => settings.seed = self.integer(e, 0, u32::MAX.into())?,
            SettingKind::Background(c) => settings.background = self.colour(c)?,
            SettingKind::Integrator(name) => {
                let Some(kind) = IntegratorKind::named(&name.name) else {
                    let mut message = format!(
                        "unknown integrator `{}` (expected `direct`, `path`, `photon`, `final_gather` or `sppm`)",
                        name.name
                    );
                    let names = IntegratorKind::ALL.map(IntegratorKind::name);
                    if let Some(g) = parser::closest(&name.name, names.into_iter()) {
                        message.push_str(&format!("; did you mean `{g}`?"));
                    }
                    return Err(SceneError::at(&name.span, message));
                };
                settings.integrator = kind;
            }
            SettingKind::Photons(e) => {
                let limit = u64::from(crate::photon::MAX_PHOTONS);
                settings.photons = Some(self.setting_integer(e, "photons", 1, limit)? as u32);
            }
            SettingKind::PhotonK(e) => {
                settings.photon_k = self.setting_integer(e, "photon_k", 1, MAX_PHOTON_K)? as u32;
            }
            SettingKind::PhotonRadius(e) => {
                settings.photon_radius = self.positive(e, "`photon_radius`")?;
            }
        }
        Ok(())
    }

    /// An item of a macro's body called where a value is expected.
    fn value_item(&mut self, item: &Item, slot: &mut Option<Value>) -> Result<(), SceneError> {
        let value = match item {
            Item::Value(expr) => self.value(expr)?,
            Item::Object(object) => Value::Object(Arc::new(self.unlit_object(object)?)),
            Item::Material(material) => self.material_value(material, None)?,
            Item::Texture(texture) => Value::Texture(Arc::new(self.texture(texture)?)),
            // POV-Ray's pigment, finish, texture or interior, as if declared.
            Item::Appearance(appearance) => self.declared_appearance(appearance)?,
            // POV-Ray's `transform { }` (a macro of `transforms.inc`), as if declared.
            Item::Transform(
                t @ Transform { kind: TransformKind::Block(_) | TransformKind::Value(_), .. },
            ) => Value::Transform(Arc::new(self.transform(t)?.to_affine())),
            _ => return Err(Self::misplaced(item, &Body::Value(slot))),
        };
        if slot.is_some() {
            return Err(SceneError::at(
                item.span(),
                "a second value in a macro called where one value is expected",
            ));
        }
        *slot = Some(value);
        Ok(())
    }

    fn declare(&mut self, declare: &Declare) -> Result<(), SceneError> {
        if self.append_in_place(declare)? {
            return Ok(());
        }
        let Declare { local, name, indices, value, .. } = declare;
        let value = self.declared(value, Some(&name.name))?;
        if indices.is_empty() {
            self.bind(&name.name, value, *local);
            return Ok(());
        }
        let mut at = Vec::new();
        for index in indices {
            at.push((self.number(index, "an index")?, index.span.clone()));
        }
        self.set_element(name, *local, &at, value)
    }

    /// A `#declare`d value; `name` (the declared name) names a material in messages.
    fn declared(&mut self, value: &Declared, name: Option<&str>) -> Result<Value, SceneError> {
        Ok(match value {
            Declared::Material(m) => self.material_value(m, name)?,
            Declared::Object(o) => Value::Object(Arc::new(self.unlit_object(o)?)),
            Declared::Texture(t) => Value::Texture(Arc::new(self.texture(t)?)),
            Declared::Array(a) => self.array(a)?,
            Declared::Value(e) => self.value(e)?,
            Declared::Appearance(a) => self.declared_appearance(a)?,
            Declared::LayeredTexture { layers, .. } => {
                let mut look = self.default_look.clone();
                for (n, layer) in layers.iter().enumerate() {
                    let under = look.clone();
                    self.apply_appearance(layer, &mut look)?;
                    if n > 0 {
                        self.layer(&under, &mut look, &layer.span);
                    }
                }
                Value::Look(Arc::new(look))
            }
            Declared::ColorMap { entries, .. } => {
                let mut map = Vec::new();
                self.exec(entries, &mut Body::ColorMap(&mut map))?;
                Value::ColorMap(Arc::new(map))
            }
            Declared::Media { items, span } => Value::Media(Arc::new(self.pov_media(items, span)?)),
            Declared::Camera { items, .. } => {
                let mut given = CameraParams::new();
                self.exec(items, &mut Body::Camera(&mut given))?;
                Value::Camera(Arc::new(given))
            }
            Declared::Sky { items, span } => Value::Sky(Arc::new(self.sky_desc(items, span)?)),
            Declared::Light { position, items, .. } => {
                Value::Light(Arc::new(self.light_state(position, items)?))
            }
            Declared::Function(def) => self.function_value(def)?,
            Declared::Transform(t) => Value::Transform(Arc::new(self.transform(t)?.to_affine())),
            Declared::If { branches, otherwise, span } => {
                for (condition, value) in branches {
                    if self.condition(condition)? {
                        return self.declared(value, name);
                    }
                }
                match otherwise {
                    Some(value) => self.declared(value, name)?,
                    None => {
                        return Err(SceneError::at(
                            span,
                            "no branch of this `#if` gives the value (add an `#else`)",
                        ));
                    }
                }
            }
        })
    }

    fn condition(&mut self, condition: &Condition) -> Result<bool, SceneError> {
        match condition {
            Condition::Expr(e) => Ok(self.number(e, "`#if`'s condition")? != 0.0),
            Condition::Defined { name, indices, defined } => {
                Ok(self.is_set(name, indices)? == *defined)
            }
        }
    }

    /// Whether a `#switch`'s `value` meets a `#case` (equal within POV-Ray's tolerance) or a
    /// `#range` (between its ends, inclusive).
    fn case_holds(&mut self, test: &CaseTest, value: f64) -> Result<bool, SceneError> {
        Ok(match test {
            CaseTest::Case(expr) => (self.number(expr, "`#case`")? - value).abs() <= EPSILON,
            CaseTest::Range(low, high) => {
                let low = self.number(low, "`#range`")?;
                let high = self.number(high, "`#range`")?;
                low - value <= EPSILON && value - high <= EPSILON
            }
        })
    }

    fn count_turn(&mut self, span: &Span) -> Result<(), SceneError> {
        self.loop_turns += 1;
        if self.loop_turns > MAX_LOOP_TURNS {
            return Err(SceneError::at(
                span,
                format!("more than {MAX_LOOP_TURNS} loop turns in this scene (does the loop end?)"),
            ));
        }
        Ok(())
    }

    /// `#for (I, A, B, S)`: as `#local I = A; #while (I <= B) ... #local I = I + S; #end`
    /// (`>=` for a negative step), with POV-Ray's tolerance on the comparison.
    #[allow(clippy::too_many_arguments)]
    fn for_loop(
        &mut self,
        variable: &Ident,
        from: &super::syntax::Expr,
        to: &super::syntax::Expr,
        step: Option<&super::syntax::Expr>,
        items: &[Item],
        span: &Span,
        body: &mut Body,
    ) -> Result<(), SceneError> {
        let start = self.number(from, "`#for`'s start")?;
        let end = self.number(to, "`#for`'s end")?;
        let step_value = match step {
            Some(s) => {
                let v = self.number(s, "`#for`'s step")?;
                if v == 0.0 {
                    return Err(SceneError::at(
                        &s.span,
                        "`#for`'s step is 0: the loop would not end",
                    ));
                }
                v
            }
            None => 1.0,
        };
        self.bind(&variable.name, Value::Float(start), true);
        loop {
            let current = match self.lookup(&variable.name) {
                Some(Value::Float(f)) => *f,
                Some(other) => {
                    return Err(SceneError::at(
                        &variable.span,
                        format!("the loop's `{}` became {}", variable.name, other.kind()),
                    ));
                }
                None => return Err(self.unknown(variable)),
            };
            let go =
                if step_value > 0.0 { current - end <= EPSILON } else { end - current <= EPSILON };
            if !go {
                return Ok(());
            }
            self.count_turn(span)?;
            self.exec(items, body)?;
            let current = match self.lookup(&variable.name) {
                Some(Value::Float(f)) => *f,
                _ => return Err(self.unknown(variable)),
            };
            self.bind(&variable.name, Value::Float(current + step_value), true);
        }
    }

    fn call_macro(&mut self, call: &Call, body: &mut Body) -> Result<(), SceneError> {
        let definition = match self.lookup(&call.name.name) {
            Some(Value::Macro(m)) => m.clone(),
            // A function called where a macro's value is expected (`F(x, y, z)` as the last
            // item of a macro's body): its value.
            Some(Value::Function(_) | Value::ColourFunction(_) | Value::TransformFunction(_))
                if matches!(body, Body::Value(_)) =>
            {
                let call =
                    syntax::Expr { kind: ExprKind::Call(call.clone()), span: call.span.clone() };
                return self.exec_item(&Item::Value(call), body);
            }
            Some(other) => {
                return Err(SceneError::at(
                    &call.name.span,
                    format!("`{}` is {}, not a macro", call.name.name, other.kind()),
                ));
            }
            None => return Err(self.unknown_as(&call.name, "macro")),
        };
        let parameters = &definition.parameters;
        if call.arguments.len() != parameters.len() {
            let names: Vec<&str> = parameters.iter().map(|p| p.name.as_str()).collect();
            let plural = if names.len() == 1 { "" } else { "s" };
            return Err(SceneError::at(
                &call.span,
                format!(
                    "macro `{}` takes {} argument{plural} ({}), not {}",
                    definition.name.name,
                    names.len(),
                    names.join(", "),
                    call.arguments.len()
                ),
            )
            .with_note(format!("`{}` is defined at {:?}", definition.name.name, definition.span)));
        }
        if self.calls >= MAX_MACRO_DEPTH {
            return Err(SceneError::at(
                &call.span,
                format!("macro calls nested more than {MAX_MACRO_DEPTH} deep"),
            ));
        }
        self.macro_calls += 1;
        if self.macro_calls > MAX_MACRO_CALLS {
            return Err(SceneError::at(
                &call.span,
                format!(
                    "more than {MAX_MACRO_CALLS} macro calls in this scene (does a macro call \
                     itself without end?)"
                ),
            ));
        }
        let mut scope = Scope::default();
        for (parameter, argument) in parameters.iter().zip(&call.arguments) {
            let slot = match argument.lone_ident().map(|name| self.resolve(name)) {
                Some((scope, name)) => Slot::Alias { scope, name },
                None => Slot::Value(self.value(argument)?),
            };
            scope.names.insert(parameter.name.clone(), slot);
        }
        self.scopes.push(scope);
        self.calls += 1;
        let note = Note::MacroCall { name: definition.name.name.clone(), at: call.span.clone() };
        let context = Arc::new(Context { note, outer: self.context.clone() });
        let outer = self.context.replace(context.clone());
        let result = self.exec(&definition.body, body);
        self.context = outer;
        self.calls -= 1;
        self.scopes.pop();
        result.map_err(|e| e.noted(context.note.to_string()))
    }

    fn include(
        &mut self,
        file: &super::syntax::Expr,
        at: &Span,
        body: &mut Body,
    ) -> Result<(), SceneError> {
        let name = self.string(file, "`#include`")?;
        let (path, built_in) = self.find_include(&file.span.file.path, &name);
        let id = identity(&path);
        if self.open_files.len() > MAX_INCLUDE_DEPTH {
            return Err(SceneError::at(
                at,
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH}"),
            ));
        }
        if self.open_files.iter().any(|(open, _)| *open == id) {
            let chain: Vec<String> =
                self.open_files.iter().map(|(_, p)| p.display().to_string()).collect();
            return Err(SceneError::at(
                at,
                format!("include cycle: {} includes `{name}` again", chain.join(" includes ")),
            ));
        }
        self.includes += 1;
        if self.includes > MAX_INCLUDES {
            return Err(SceneError::at(
                at,
                format!("more than {MAX_INCLUDES} files included in one scene"),
            ));
        }
        let text = match built_in {
            Some(text) => text.to_string(),
            None => self.dialect.read(&path).map_err(|e| match path.exists() {
                true => SceneError::at(at, format!("cannot read `{}`: {e}", path.display())),
                false => SceneError::at(at, not_found(&name, &path)),
            })?,
        };
        self.included_bytes += text.len() as u64;
        if self.included_bytes > MAX_INCLUDED_BYTES {
            return Err(SceneError::at(
                at,
                format!("more than {} MiB of text included in one scene", MAX_INCLUDED_BYTES >> 20),
            ));
        }
        self.sources.add(text.as_bytes());
        let file = Arc::new(SourceFile::new(path, text));
        self.open_files.push((id, file.path.clone()));
        // The file's `#local`s end with it.
        self.scopes.push(Scope::default());
        let note = Note::Included { at: at.clone() };
        let context = Arc::new(Context { note, outer: self.context.clone() });
        let outer = self.context.replace(context.clone());
        let result =
            tree::parse_file(&file, self.dialect).and_then(|items| self.exec(&items, body));
        self.context = outer;
        self.scopes.pop();
        self.open_files.pop();
        result.map_err(|e| e.noted(context.note.to_string()))
    }
}

impl Evaluator {
    /// Where `#include "name"` in `from` reads: `from`'s folder, then each `--include-path`
    /// folder, then each folder of `RAYDIANCE_INCLUDE_PATH`, then (`.pov`) raydiance's built-in
    /// library, whose text is returned. An absolute name, or one found nowhere, is read where
    /// `from` names it.
    fn find_include(&self, from: &Path, name: &str) -> (PathBuf, Option<&'static str>) {
        let local = resolve(from, name);
        if local.is_file() || Path::new(name).is_absolute() {
            return (local, None);
        }
        let mut folders = self.include_folders().into_iter();
        if let Some(found) = folders.find_map(|f| Some(f.join(name)).filter(|p| p.is_file())) {
            return (found, None);
        }
        match (self.dialect, crate::lang::library::file(name)) {
            (Dialect::Pov, Some(text)) => (PathBuf::from(format!("<built-in>/{name}")), Some(text)),
            _ => (local, None),
        }
    }
}

impl Evaluator {
    /// The folders searched after the including file's own: each `--include-path` folder, then
    /// each of `RAYDIANCE_INCLUDE_PATH`.
    fn include_folders(&self) -> Vec<PathBuf> {
        let variable = std::env::var_os(INCLUDE_PATH_VARIABLE)
            .map(|v| std::env::split_paths(&v).collect::<Vec<_>>())
            .unwrap_or_default();
        self.include_path.iter().cloned().chain(variable).collect()
    }
}

/// Where an included file was looked for, when it is nowhere: `local` (what a relative name
/// means beside the including file), and the folders of `RAYDIANCE_INCLUDE_PATH`.
fn not_found(name: &str, local: &Path) -> String {
    let folders = std::env::var_os(INCLUDE_PATH_VARIABLE).unwrap_or_default();
    let searched = match (Path::new(name).is_absolute(), folders.is_empty()) {
        (true, _) => String::new(),
        (false, true) => {
            format!(" ({INCLUDE_PATH_VARIABLE}, which names more folders to search, is not set)")
        }
        (false, false) => format!(
            " nor in the folders of {INCLUDE_PATH_VARIABLE} ({})",
            folders.to_string_lossy()
        ),
    };
    format!("cannot read `{name}`: there is no file `{}`{searched}", local.display())
}

/// The environment variable naming folders searched for included files (as `PATH` is written).
pub const INCLUDE_PATH_VARIABLE: &str = "RAYDIANCE_INCLUDE_PATH";

/// An object value standing where an object goes: an instance of it, located here.
fn instance(node: Arc<ObjectNode>, span: Span) -> ObjectNode {
    let depth = node.depth + 1;
    ObjectNode {
        shape: ShapeNode::Instance(node),
        material: None,
        transforms: Vec::new(),
        depth,
        span,
    }
}

pub(super) fn as_float(value: &Value, at: &Span, what: &str) -> Result<f64, SceneError> {
    match value {
        Value::Float(f) => Ok(*f),
        other => Err(SceneError::at(at, format!("{what} needs a number, not {}", other.kind()))),
    }
}

/// A vector, or a number promoted to `<f, f, f>`.
pub(super) fn as_vector(value: &Value, at: &Span, what: &str) -> Result<DVec3, SceneError> {
    match value {
        Value::Float(f) => Ok(DVec3::splat(*f)),
        Value::Vector(v) => Ok(*v),
        other => Err(SceneError::at(at, format!("{what} needs a vector, not {}", other.kind()))),
    }
}

/// A path named in `from`, relative to `from`'s folder unless absolute.
pub(super) fn resolve(from: &Path, name: &str) -> PathBuf {
    from.parent().unwrap_or(Path::new("")).join(name)
}

/// A path's identity for cycle detection: canonical where the file exists.
fn identity(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| path.to_path_buf())
}
