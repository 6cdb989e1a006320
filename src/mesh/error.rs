//! What is wrong in a mesh file's contents, and where in it: the messages of the PLY and OBJ
//! readers and of the checks of the mesh they read.

use std::fmt;

/// A problem in a mesh file's contents, or one at a place in it (`At`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContentError {
    #[error("{place}: {problem}")]
    At { place: Place, problem: Box<ContentError> },

    // Both formats.
    #[error("`{0}` is not a number")]
    NotANumber(String),
    #[error("the mesh has more than {max} triangles", max = super::MAX_TRIANGLES)]
    TooManyTriangles,

    // PLY.
    #[error("not a PLY file (it does not start with `ply`)")]
    NotPly,
    #[error("the header has no `end_header`")]
    NoEndHeader,
    #[error("the header is not text")]
    HeaderNotText,
    #[error("the header has no `format` line")]
    NoFormat,
    #[error("unknown format `{0}`")]
    UnknownFormat(String),
    #[error("`{0}` is not an element count")]
    NotACount(String),
    #[error("a property before any element")]
    PropertyBeforeElement,
    #[error("unknown type `{0}`")]
    UnknownType(String),
    #[error("cannot read `{0}`")]
    UnreadableLine(String),
    #[error("the ASCII body is not text")]
    BodyNotText,
    #[error("element vertex: needs properties x, y and z")]
    NoCoordinates,
    #[error("element face: needs a list property vertex_indices")]
    NoVertexIndices,
    #[error("the file ends too early")]
    EndsEarly,
    #[error("the file ends too early (at byte {0} of the data)")]
    EndsEarlyAtByte(usize),
    #[error("a list of {0} items")]
    LongList(f64),
    #[error("a face needs 3 or more vertices, this one has {0}")]
    PlyFaceTooSmall(f64),
    #[error("{0} is not a vertex index")]
    NotAVertexIndex(f64),

    // OBJ.
    #[error("not UTF-8 text: {0}")]
    NotUtf8(#[from] std::str::Utf8Error),
    #[error("expected three numbers")]
    NotThreeNumbers,
    #[error("missing {0} index")]
    MissingIndex(&'static str),
    #[error("`{word}` is not a {what} index")]
    NotAnIndex { word: String, what: &'static str },
    #[error("{what} index {index} is out of range (there are {count} so far)")]
    IndexOutOfRange { what: &'static str, index: i64, count: usize },
    #[error("a face needs 3 vertices, this one has {0}")]
    ObjFaceTooSmall(usize),

    // The mesh read.
    #[error("the mesh has no faces")]
    NoFaces,
    #[error("vertex {0} has a coordinate that is not a finite number")]
    NotFinite(usize),
    #[error("face {face} uses vertex {index}, but there are only {count} vertices")]
    FaceVertexOutOfRange { face: usize, index: u32, count: usize },
    #[error("{} degenerate (of no area): it would be invisible", degenerate(*.0))]
    AllDegenerate(usize),
}

impl ContentError {
    /// This problem at `place`.
    pub fn at(self, place: Place) -> ContentError {
        ContentError::At { place, problem: Box::new(self) }
    }
}

/// The triangles that are all degenerate, in words.
fn degenerate(triangles: usize) -> String {
    match triangles {
        1 => "its one triangle is".to_string(),
        n => format!("all {n} triangles of the mesh are"),
    }
}

/// Where in a mesh file: a line of an OBJ file or of a PLY header (from 1), or an item of a
/// PLY element (from 0).
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    Line(usize),
    HeaderLine(usize),
    Item { element: String, index: usize },
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Place::Line(line) => write!(f, "line {line}"),
            Place::HeaderLine(line) => write!(f, "header line {line}"),
            Place::Item { element, index } => write!(f, "{element} {index}"),
        }
    }
}
