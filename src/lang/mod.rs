//! Text to scene graph: the pest grammar (`grammar/scn.pest`), expression evaluation,
//! `#declare` and `#include`. Knows nothing of rendering.

mod eval;
mod parser;
mod value;

pub use eval::MAX_INCLUDE_DEPTH;
pub use parser::MAX_NESTING;

use std::path::Path;
use std::sync::Arc;

use crate::diagnostic::{SceneError, SourceFile};
use crate::scene::graph::SceneGraph;

/// Reads and evaluates a scene file.
pub fn load_scene(path: &Path) -> Result<SceneGraph, SceneError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::unlocated(format!("cannot read `{}`: {e}", path.display())))?;
    parse_scene(path, &text)
}

/// Evaluates scene text as if read from `path` (which locates errors and relative paths).
pub fn parse_scene(path: &Path, text: &str) -> Result<SceneGraph, SceneError> {
    let file = Arc::new(SourceFile { path: path.to_path_buf(), text: text.to_string() });
    eval::Evaluator::default().scene(file)
}
