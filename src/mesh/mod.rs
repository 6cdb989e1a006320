//! Triangle meshes from files (PLY, ASCII and binary, and Wavefront OBJ), from fonts (`text`) and
//! from height fields' images (PNG, JPEG, PGM, PPM, TGA) and functions (`height_field`).

pub mod bezier_patch;
mod error;
pub mod extrude;
pub mod font;
pub mod height_field;
mod height_images;
pub mod heights;
mod obj;
mod ply;

use std::path::Path;

use glam::Vec3;

use crate::diagnostic::printable;
use crate::input::InputError;

pub use error::{ContentError, Place};

/// An indexed triangle mesh in its own (object) space.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, when the file has them: smooth shading.
    pub normals: Option<Vec<Vec3>>,
    pub triangles: Vec<[u32; 3]>,
}

/// A mesh file that cannot be used, with where in it: `file: line N: ...` or `file: element ...`.
/// The problem may quote the file's bytes (a 20 MB token, escape sequences): it is clipped and
/// escaped.
#[derive(Debug, thiserror::Error)]
#[error("{}: {}", printable(&file.display().to_string()), printable(&problem.to_string()))]
pub struct MeshError {
    pub file: std::path::PathBuf,
    pub problem: MeshProblem,
}

/// Why a mesh file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MeshProblem {
    #[error("unknown mesh format (expected a .ply or .obj file)")]
    UnknownFormat,
    #[error("cannot read: {0}")]
    Unreadable(InputError),
    #[error(
        "cannot read: {source}; this mesh is generated, not shipped: run `{command}` at the top \
         of the repository"
    )]
    NotGenerated { source: InputError, command: &'static str },
    #[error(transparent)]
    Content(#[from] ContentError),
}

/// Reads a `.ply` or `.obj` file by its extension.
pub fn load(path: &Path) -> Result<Mesh, MeshError> {
    read(path).map_err(|problem| MeshError { file: path.to_path_buf(), problem })
}

fn read(path: &Path) -> Result<Mesh, MeshProblem> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let format = match extension.as_deref() {
        Some("ply") => MeshFormat::Ply,
        Some("obj") => MeshFormat::Obj,
        _ => return Err(MeshProblem::UnknownFormat),
    };
    let bytes = crate::input::read(path, crate::input::MAX_MESH_BYTES).map_err(|source| {
        let how = GENERATED.iter().find(|(name, _)| path.ends_with(name));
        match how {
            Some(&(_, command)) if !path.exists() => MeshProblem::NotGenerated { source, command },
            _ => MeshProblem::Unreadable(source),
        }
    })?;
    Ok(parse(&bytes, format)?)
}

/// Meshes of the shipped scenes too large for the repository, and the command that makes each.
const GENERATED: [(&str, &str); 1] =
    [("data/bumpy.ply", "cargo run --release --example bumpy_sphere")];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    Ply,
    Obj,
}

/// Parses and checks a mesh file's contents; the message says where in it the problem is.
pub fn parse(bytes: &[u8], format: MeshFormat) -> Result<Mesh, ContentError> {
    let mesh = match format {
        MeshFormat::Ply => ply::parse(bytes),
        MeshFormat::Obj => obj::parse(bytes),
    }?;
    validate(&mesh)?;
    Ok(mesh)
}

/// Checks what the parsers cannot see locally: indices in range, finite coordinates, a face.
fn validate(mesh: &Mesh) -> Result<(), ContentError> {
    if mesh.triangles.is_empty() {
        return Err(ContentError::NoFaces);
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(ContentError::NotFinite(i));
    }
    let count = mesh.positions.len();
    for (face, triangle) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = triangle.iter().find(|&&i| i as usize >= count) {
            return Err(ContentError::FaceVertexOutOfRange { face, index, count });
        }
    }
    let has_area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a) != Vec3::ZERO
    };
    if !mesh.triangles.iter().any(has_area) {
        return Err(ContentError::AllDegenerate(mesh.triangles.len()));
    }
    Ok(())
}

/// Splits a polygon into a fan of triangles around its first vertex.
/// The most triangles a mesh may have, counted as its faces are read (a face of 255 vertices is
/// 253 triangles: 20 MB of faces would otherwise make 3 GB of triangles before any check).
pub const MAX_TRIANGLES: usize = 1 << 24;

/// Adds the fan of triangles of `polygon`; an error once the mesh has more than `MAX_TRIANGLES`.
fn triangulate(polygon: &[u32], triangles: &mut Vec<[u32; 3]>) -> Result<(), ContentError> {
    let fan = polygon.len().saturating_sub(2);
    if triangles.len() + fan > MAX_TRIANGLES {
        return Err(ContentError::TooManyTriangles);
    }
    for i in 1..=fan {
        triangles.push([polygon[0], polygon[i], polygon[i + 1]]);
    }
    Ok(())
}
