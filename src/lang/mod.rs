//! Text to scene graph: the pest grammar (`grammar/scn.pest`) parsed once into an owned syntax
//! tree (`syntax`, built by `tree`), which the interpreter (`eval`) runs with its directives,
//! scopes and macros. Knows nothing of rendering.

pub mod dialect;
mod eval;
mod hints;
pub mod keywords;
mod library;
mod parser;
mod povray;
pub mod syntax;
mod tree;
mod value;

pub use eval::{
    MAX_ARRAY_ELEMENTS_MADE, MAX_CSG_OPERANDS, MAX_INCLUDE_DEPTH, MAX_INCLUDED_BYTES, MAX_INCLUDES,
    MAX_LOOP_TURNS, MAX_MACRO_CALLS, MAX_MACRO_DEPTH, MAX_OBJECTS_MADE,
};
pub use eval::{MAX_FILES_OPENED, MAX_WRITTEN_BYTES};
pub use parser::MAX_NESTING;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::animation::Frame;
use crate::diagnostic::{SceneError, SourceFile};
use crate::digest::Digest;
use crate::graph::SceneGraph;
use dialect::Dialect;

/// Reads and evaluates a scene file.
pub fn load_scene(path: &Path) -> Result<SceneGraph, SceneError> {
    load_scene_at(path, Frame::default()).map(|(graph, _)| graph)
}

/// Reads and evaluates a scene file at an animation frame (its `clock` and `frame_number`);
/// returns the scene and a digest of the text of every file read (the scene and its includes).
pub fn load_scene_at(path: &Path, frame: Frame) -> Result<(SceneGraph, Digest), SceneError> {
    load_scene_for_image(path, frame, None)
}

/// As `load_scene_at`, for an image of `image` pixels when the command line gives its size: a
/// `.pov` scene reads it as `image_width` and `image_height`.
pub fn load_scene_for_image(
    path: &Path,
    frame: Frame,
    image: Option<(u32, u32)>,
) -> Result<(SceneGraph, Digest), SceneError> {
    load_scene_with(path, frame, image, &[])
}

/// As `load_scene_for_image`, searching `include_path`'s folders for included files after the
/// including file's own (before `RAYDIANCE_INCLUDE_PATH` and the built-in library).
pub fn load_scene_with(
    path: &Path,
    frame: Frame,
    image: Option<(u32, u32)>,
    include_path: &[PathBuf],
) -> Result<(SceneGraph, Digest), SceneError> {
    let dialect = Dialect::of(path);
    let text = read_scene_text(path, dialect)?;
    let file = Arc::new(SourceFile::new(path.to_path_buf(), text));
    let evaluator = eval::Evaluator::for_image(frame, dialect, image);
    evaluator.searching(include_path.to_vec()).scene_and_sources(file)
}

/// Whether the scene file can be read: checked before work that only the scene can make worth
/// doing (planning thousands of frames).
pub fn check_readable(path: &Path) -> Result<(), SceneError> {
    read_scene_text(path, Dialect::of(path)).map(drop)
}

fn read_scene_text(path: &Path, dialect: Dialect) -> Result<String, SceneError> {
    dialect
        .read(path)
        .map_err(|e| SceneError::unlocated(format!("cannot read `{}`: {e}", path.display())))
}

/// Evaluates scene text as if read from `path` (which locates errors and relative paths).
pub fn parse_scene(path: &Path, text: &str) -> Result<SceneGraph, SceneError> {
    let file = Arc::new(SourceFile::new(path.to_path_buf(), text.to_string()));
    eval::Evaluator::for_image(Frame::default(), Dialect::of(path), None).scene(file)
}

/// Parses scene text into its syntax tree, without evaluating it.
pub fn parse_tree(path: &Path, text: &str) -> Result<Vec<syntax::Item>, SceneError> {
    let file = Arc::new(SourceFile::new(path.to_path_buf(), text.to_string()));
    tree::parse_file(&file, Dialect::of(path))
}
