//! POV-Ray's triangles written in the scene: `smooth_triangle`, `mesh { triangle { }
//! smooth_triangle { } ... }` (its body, `Body::Mesh`) and `mesh2`, each made into a mesh
//! (`ShapeNode::Extrusion`).
//! Smooth triangles carry their corners' normals, interpolated across them; a flat triangle
//! among them gets its face's normal at its corners.

use std::sync::Arc;

use glam::Vec3;

use super::{Body, Evaluator};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{ObjectNode, ShapeNode};
use crate::lang::syntax::{Expr, Item, Mesh2, Object, Shape, VectorList};
use crate::lang::value::Value;
use crate::mesh::Mesh;

/// A triangle's corners, and its corners' normals if it is smooth.
type Corners = ([Vec3; 3], Option<[Vec3; 3]>);

impl Evaluator {
    /// `smooth_triangle { p1, n1, p2, n2, p3, n3 }`.
    pub(super) fn smooth_triangle(
        &mut self,
        corners: &[Expr; 3],
        normals: &[Expr; 3],
    ) -> Result<ShapeNode, SceneError> {
        let triangle = self.smooth_corners(corners, normals)?;
        Ok(made(unwelded(&[triangle])))
    }

    fn smooth_corners(
        &mut self,
        corners: &[Expr; 3],
        normals: &[Expr; 3],
    ) -> Result<Corners, SceneError> {
        let (mut points, mut directions) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
        // In written order: arguments may draw from a random stream.
        for k in 0..3 {
            points[k] = self.vec3(&corners[k])?;
            directions[k] = self.vec3(&normals[k])?;
        }
        Ok((points, Some(directions)))
    }

    /// `mesh { triangle { } smooth_triangle { } ... items }`: `listed`, the triangles among the
    /// directives and macro calls that run through them, and `items`, the mesh's, run as one
    /// body, as POV-Ray reads them: its triangles, then its items, with the directives and macro
    /// calls anywhere (a macro may make triangles or items).
    pub(super) fn mesh_items(
        &mut self,
        listed: &[Item],
        items: &[Item],
        node: &mut ObjectNode,
    ) -> Result<(), SceneError> {
        let mut triangles = Some(Vec::new());
        for part in [listed, items] {
            self.exec(part, &mut Body::Mesh { triangles: &mut triangles, node })?;
        }
        self.close_mesh(&mut triangles, node)
    }

    /// An item in a mesh: a triangle while they are open, else the object's item.
    pub(super) fn mesh_item(
        &mut self,
        item: &Item,
        triangles: &mut Option<Vec<Object>>,
        node: &mut ObjectNode,
    ) -> Result<(), SceneError> {
        if let Item::Object(
            triangle @ Object {
                shape: Shape::Triangle { .. } | Shape::SmoothTriangle { .. }, ..
            },
        ) = item
        {
            let Some(triangles) = triangles else {
                return Err(SceneError::at(
                    &triangle.span,
                    "a triangle after the mesh's items: its triangles come first, then its \
                     texture, transforms and other items (as POV-Ray requires)",
                ));
            };
            triangles.push(self.written_triangle(triangle)?);
            return Ok(());
        }
        self.close_mesh(triangles, node)?;
        self.object_item(item, node)
    }

    /// The mesh of the triangles, if they are still open, made `node`'s shape.
    fn close_mesh(
        &mut self,
        triangles: &mut Option<Vec<Object>>,
        node: &mut ObjectNode,
    ) -> Result<(), SceneError> {
        if let Some(triangles) = triangles.take() {
            node.shape = self.triangle_mesh(&triangles, &node.span)?;
        }
        Ok(())
    }

    /// The mesh of a `mesh`'s triangles: one material for all, so a triangle takes no items of
    /// its own but its corners' `uv_vectors` (read and checked, with a warning).
    fn triangle_mesh(
        &mut self,
        triangles: &[Object],
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        if triangles.is_empty() {
            return Err(SceneError::at(span, "the mesh has no triangles"));
        }
        let mut corners = Vec::with_capacity(triangles.len());
        let mut uv_at = None;
        for triangle in triangles {
            for item in &triangle.items {
                let Item::UvVectors { corners, span } = item else {
                    return Err(SceneError::at(
                        item.span(),
                        "a triangle of a mesh takes no texture or transform of its own here: \
                         the mesh's items apply to all its triangles",
                    ));
                };
                for corner in corners.iter() {
                    self.uv(corner, "triangle's")?;
                }
                uv_at.get_or_insert(span.clone());
            }
            corners.push(match &triangle.shape {
                Shape::Triangle { a, b, c } => {
                    ([self.vec3(a)?, self.vec3(b)?, self.vec3(c)?], None)
                }
                Shape::SmoothTriangle { corners, normals } => {
                    self.smooth_corners(corners, normals)?
                }
                _ => unreachable!("a mesh holds `triangle` and `smooth_triangle` blocks only"),
            });
        }
        if let Some(at) = uv_at {
            self.warn_unused_uv("mesh's triangles'", &at);
        }
        Ok(made(unwelded(&corners)))
    }

    /// `mesh2 { vertex_vectors normal_vectors uv_vectors face_indices normal_indices
    /// uv_indices }`: without normals the faces share their vertices; with them each face has
    /// its own corners, their normals by `normal_indices` (by `face_indices` where it is not
    /// given, as in POV-Ray). The uv lists are read and checked, with a warning: they only
    /// serve `uv_mapping`, which raydiance does not have.
    pub(super) fn mesh2(&mut self, mesh: &Mesh2, span: &Span) -> Result<ShapeNode, SceneError> {
        let (Some(vertex_list), Some(face_list)) = (&mesh.vertices, &mesh.faces) else {
            return Err(SceneError::at(
                span,
                "a mesh2 needs its `vertex_vectors` and its `face_indices`",
            ));
        };
        let positions = self.vectors(vertex_list, "vertex_vectors")?;
        let faces = self.indices(face_list, "face_indices", positions.len())?;
        if faces.is_empty() {
            return Err(SceneError::at(&face_list.count.span, "the mesh2 has no faces"));
        }
        if let Some(uvs) = &mesh.uvs {
            self.check_count(uvs, "uv_vectors")?;
            for entry in &uvs.entries {
                self.uv(entry, "mesh2's")?;
            }
            let count = uvs.entries.len();
            if let Some(uv_indices) = &mesh.uv_indices {
                self.indices(uv_indices, "uv_indices", count)?;
            }
            self.warn_unused_uv("mesh2's", span);
        }
        let Some(normals) = &mesh.normals else {
            return Ok(made(Mesh { positions, normals: None, triangles: faces }));
        };
        let directions = self.vectors(normals, "normal_vectors")?;
        let normal_faces = match &mesh.normal_indices {
            Some(list) => self.indices(list, "normal_indices", directions.len())?,
            None => self.indices(face_list, "face_indices", directions.len())?,
        };
        if normal_faces.len() != faces.len() {
            return Err(SceneError::at(
                span,
                format!(
                    "the mesh2 has {} faces but {} faces of normals",
                    faces.len(),
                    normal_faces.len()
                ),
            ));
        }
        let corners: Vec<Corners> = faces
            .iter()
            .zip(&normal_faces)
            .map(|(face, normal)| {
                (face.map(|i| positions[i as usize]), Some(normal.map(|i| directions[i as usize])))
            })
            .collect();
        Ok(made(unwelded(&corners)))
    }

    /// One of the `whose` uv_vectors: a 2-vector <u, v>.
    fn uv(&mut self, expr: &Expr, whose: &str) -> Result<(), SceneError> {
        match self.value(expr)? {
            Value::Numbers(uv) if uv.len() == 2 => Ok(()),
            other => Err(SceneError::at(
                &expr.span,
                format!(
                    "each of the {whose} uv_vectors is a 2-vector <u, v>, not {}",
                    other.kind()
                ),
            )),
        }
    }

    /// The warning that the `whose` uv_vectors are read, not used.
    pub(super) fn warn_unused_uv(&mut self, whose: &str, at: &Span) {
        let at = self.here(at);
        self.warnings.push(format!(
            "{at:?}: warning: the {whose} uv_vectors are read but not used: they serve \
             `uv_mapping`, which raydiance's textures do not have"
        ));
    }

    /// A list's vectors, as many as it says.
    fn vectors(&mut self, list: &VectorList, word: &str) -> Result<Vec<Vec3>, SceneError> {
        self.check_count(list, word)?;
        list.entries.iter().map(|entry| self.vec3(entry)).collect()
    }

    /// A list's triangles of indices, as many as it says, each below `bound`.
    fn indices(
        &mut self,
        list: &VectorList,
        word: &str,
        bound: usize,
    ) -> Result<Vec<[u32; 3]>, SceneError> {
        self.check_count(list, word)?;
        let mut triangles = Vec::with_capacity(list.entries.len());
        for entry in &list.entries {
            let v = self.vector(entry)?;
            let whole = v.to_array().map(|i| i.fract() == 0.0 && i >= 0.0 && i < bound as f64);
            if whole.contains(&false) {
                return Err(SceneError::at(
                    &entry.span,
                    format!(
                        "each of the mesh2's {word} is three whole numbers from 0 to {}, not \
                         <{}, {}, {}>",
                        bound as i64 - 1,
                        v.x,
                        v.y,
                        v.z
                    ),
                ));
            }
            triangles.push(v.to_array().map(|i| i as u32));
        }
        Ok(triangles)
    }

    fn check_count(&mut self, list: &VectorList, word: &str) -> Result<(), SceneError> {
        let count = self.number(&list.count, &format!("the mesh2's {word} count"))?;
        if count != list.entries.len() as f64 {
            return Err(SceneError::at(
                &list.count.span,
                format!("the mesh2's {word} says {count} but {} are given", list.entries.len()),
            ));
        }
        Ok(())
    }
}

fn made(mesh: Mesh) -> ShapeNode {
    ShapeNode::Extrusion(Arc::new(mesh))
}

/// Triangles each with corners of its own; normals for all if any is smooth (a flat
/// triangle's face normal at its corners).
fn unwelded(triangles: &[Corners]) -> Mesh {
    let positions: Vec<Vec3> = triangles.iter().flat_map(|(corners, _)| *corners).collect();
    let smooth = triangles.iter().any(|(_, normals)| normals.is_some());
    let normals = smooth.then(|| {
        triangles
            .iter()
            .flat_map(|([a, b, c], normals)| {
                normals.unwrap_or([(*b - *a).cross(*c - *a).normalize_or_zero(); 3])
            })
            .collect()
    });
    let triangles = (0..triangles.len() as u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    Mesh { positions, normals, triangles }
}
