//! Values: what expressions produce and names are bound to (f64 throughout; the scene graph
//! takes f32).

use std::sync::Arc;

use glam::DVec3;

use super::syntax::MacroDef;
use crate::graph::{MaterialDesc, ObjectNode, TextureNode};

#[derive(Debug, Clone)]
pub enum Value {
    Float(f64),
    Vector(DVec3),
    /// A vector literal with other than three components (`matrix` takes twelve).
    Numbers(Vec<f64>),
    String(Arc<str>),
    Array(Arc<Array>),
    /// A stream of pseudo-random numbers made by `seed(n)`: an index into the evaluator's
    /// streams, so that copies of it draw from the same stream (as in POV-Ray).
    Stream(usize),
    Macro(Arc<MacroDef>),
    Material(Arc<MaterialDesc>),
    Object(Arc<ObjectNode>),
    Texture(Arc<TextureNode>),
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
        }
    }
}

/// `array[d0][d1]...`: elements in row-major order; an element is `None` until set.
#[derive(Debug, Clone)]
pub struct Array {
    pub dimensions: Vec<usize>,
    pub elements: Vec<Option<Value>>,
}

/// The largest number of elements an array may have (as many as the loop turns of a scene).
pub const MAX_ARRAY_ELEMENTS: usize = 10_000_000;
