//! Values: what expressions produce and names are bound to (f64 throughout; the scene graph
//! takes f32).

use std::sync::Arc;

use glam::DVec3;

use super::eval::{Finish, Look, Pigment, Stop};
use super::syntax::MacroDef;
use crate::graph::{MaterialDesc, ObjectNode, SkyDesc, TextureNode};

#[derive(Debug, Clone)]
pub enum Value {
    Float(f64),
    Vector(DVec3),
    /// A vector literal with other than three components (`matrix` takes twelve).
    Numbers(Vec<f64>),
    /// Shared between copies; `#declare S = concat(S, ...)` appends in place when nothing else
    /// holds it.
    String(Arc<String>),
    Array(Arc<Array>),
    /// A stream of pseudo-random numbers made by `seed(n)`: an index into the evaluator's
    /// streams, so that copies of it draw from the same stream (as in POV-Ray).
    Stream(usize),
    Macro(Arc<MacroDef>),
    Material(Arc<MaterialDesc>),
    Object(Arc<ObjectNode>),
    Texture(Arc<TextureNode>),
    /// POV-Ray's declared `pigment`, `finish`, `texture`, `interior` (its ior) and `normal`
    /// (`.pov`).
    Pigment(Arc<Pigment>),
    Finish(Arc<Finish>),
    Look(Arc<Look>),
    Interior(std::sync::Arc<super::eval::Interior>),
    /// `None`: a normal raydiance reads without rendering (`bump_map`).
    Normal(Option<Arc<crate::graph::NormalNode>>),
    /// A declared `media` (`.pov`).
    Media(Arc<crate::graph::MediumDesc>),
    /// A declared `color_map` (`.pov`): its stops.
    ColorMap(Arc<Vec<Stop>>),
    /// A declared camera's parameters (`.pov`).
    Camera(Arc<super::eval::CameraParams>),
    /// A declared `sky_sphere` (`.pov`).
    Sky(Arc<SkyDesc>),
    /// A declared `light_source` (`.pov`), as read where it is declared.
    Light(Arc<super::eval::LightState>),
    /// A declared float function (`.pov`), compiled.
    Function(Arc<crate::function::FloatFunction>),
    /// A file's handle made by `#fopen` (`.pov`): an index into the evaluator's files.
    File(usize),
    /// A declared colour function (`function { pigment { } }`, `.pov`), compiled.
    ColourFunction(Arc<crate::function::ColourFunction>),
    /// POV-Ray's declared `transform { }` (`.pov`): the composed map from object to world.
    Transform(Arc<glam::Affine3A>),
    /// POV-Ray's transform function (`function { transform { } }`, `.pov`): called with a
    /// point, its image.
    TransformFunction(Arc<glam::Affine3A>),
}

impl Value {
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Float(_) => "a number",
            Value::Vector(_) => "a vector",
            Value::Numbers(n) if n.len() == 2 => "a 2-vector",
            Value::Numbers(_) => "a list of numbers",
            Value::String(_) => "a string",
            Value::Array(_) => "an array",
            Value::Stream(_) => "a random stream",
            Value::Macro(_) => "a macro",
            Value::Material(_) => "a material",
            Value::Object(_) => "an object",
            Value::Texture(_) => "a texture",
            Value::Pigment(_) => "a pigment",
            Value::Finish(_) => "a finish",
            Value::Look(_) => "a POV-Ray texture",
            Value::Interior(_) => "an interior",
            Value::Normal(_) => "a normal",
            Value::Media(_) => "a media",
            Value::Camera(_) => "a camera",
            Value::Sky(_) => "a sky_sphere",
            Value::Light(_) => "a light_source",
            Value::ColorMap(_) => "a color_map",
            Value::Function(_) => "a function",
            Value::File(_) => "a file's handle",
            Value::ColourFunction(_) => "a colour function",
            Value::Transform(_) => "a transform",
            Value::TransformFunction(_) => "a transform function",
        }
    }
}

/// `array[d0][d1]...`: elements in row-major order; an element is `None` until set. They are
/// held in chunks shared between copies of the array: writing an element of a copy copies its
/// chunk, not the whole array, and an array declared without elements holds one chunk of `None`s.
#[derive(Debug, Clone)]
pub struct Array {
    pub dimensions: Vec<usize>,
    chunks: Vec<Arc<Vec<Option<Value>>>>,
}

/// Elements in a chunk of an array.
pub const ARRAY_CHUNK: usize = 1024;

impl Array {
    /// An array of `dimensions` with no element set.
    pub fn unset(dimensions: Vec<usize>) -> Array {
        let total: usize = dimensions.iter().product();
        let empty = Arc::new(vec![None; total.min(ARRAY_CHUNK)]);
        Array { chunks: vec![empty; total.div_ceil(ARRAY_CHUNK)], dimensions }
    }

    /// An array of `dimensions` holding `elements`, in row-major order.
    pub fn of(dimensions: Vec<usize>, elements: &[Option<Value>]) -> Array {
        let chunks = elements.chunks(ARRAY_CHUNK).map(|c| Arc::new(c.to_vec())).collect();
        Array { dimensions, chunks }
    }

    /// How many chunks hold the elements (each an `Arc` that a copy of the array copies).
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// The element at flat position `flat` (below the product of the dimensions), if set.
    pub fn get(&self, flat: usize) -> Option<&Value> {
        self.chunks[flat / ARRAY_CHUNK][flat % ARRAY_CHUNK].as_ref()
    }

    /// Sets the element at flat position `flat`; returns how many elements were copied to do so
    /// (its chunk, where another array shares it).
    pub fn set(&mut self, flat: usize, value: Value) -> usize {
        let chunk = &mut self.chunks[flat / ARRAY_CHUNK];
        let copied = if Arc::get_mut(chunk).is_some() { 0 } else { chunk.len() };
        Arc::make_mut(chunk)[flat % ARRAY_CHUNK] = Some(value);
        copied
    }
}

/// The largest number of elements an array may have (as many as the loop turns of a scene).
pub const MAX_ARRAY_ELEMENTS: usize = 10_000_000;

/// The longest string, in bytes, that `concat` may make.
pub const MAX_STRING_BYTES: usize = 1 << 20;
