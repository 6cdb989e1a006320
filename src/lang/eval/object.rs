//! Objects: shapes checked where they are written, modifiers, groups and instances.

use glam::{Mat3, Vec3};

use super::{Body, Evaluator, MAX_OBJECT_DEPTH, as_vector, resolve};
use crate::diagnostic::SceneError;
use crate::lang::syntax::{self, Item, Shape, TransformKind};
use crate::lang::value::Value;
use crate::scene::graph::{ObjectNode, ShapeNode, Transform};

impl Evaluator {
    pub(super) fn object(&mut self, object: &syntax::Object) -> Result<ObjectNode, SceneError> {
        let span = self.here(&object.span);
        let shape = match &object.shape {
            Shape::Plane { normal, offset } => {
                let normal = self.nonzero(normal, "the plane's normal")?;
                ShapeNode::Plane { normal, offset: self.float(offset)? as f32 }
            }
            Shape::Sphere { center, radius } => ShapeNode::Sphere {
                center: self.vec3(center)?,
                radius: self.positive(radius, "radius")?,
            },
            Shape::Box { corner_a, corner_b } => {
                let at = corner_b.span.clone();
                let (corner_a, corner_b) = (self.vec3(corner_a)?, self.vec3(corner_b)?);
                if (corner_a - corner_b).abs().min_element() == 0.0 {
                    return Err(SceneError::at(
                        &at,
                        "the box's corners are equal in one coordinate: it has no volume",
                    ));
                }
                ShapeNode::Box { corner_a, corner_b }
            }
            Shape::Triangle { a, b, c } => {
                let at = c.span.clone();
                let (a, b, c) = (self.vec3(a)?, self.vec3(b)?, self.vec3(c)?);
                if (b - a).cross(c - a).length() <= 1e-12 * (b - a).length() * (c - a).length() {
                    return Err(SceneError::at(
                        &at,
                        "the triangle's corners are collinear: it has no area",
                    ));
                }
                ShapeNode::Triangle { a, b, c }
            }
            Shape::Quad { corner, edge1, edge2 } => {
                let at = edge2.span.clone();
                let (corner, edge1, edge2) =
                    (self.vec3(corner)?, self.vec3(edge1)?, self.vec3(edge2)?);
                if edge1.cross(edge2).length() <= 1e-12 * edge1.length() * edge2.length() {
                    return Err(SceneError::at(
                        &at,
                        "the quad's edges are zero or parallel: it has no area",
                    ));
                }
                ShapeNode::Quad { corner, edge1, edge2 }
            }
            Shape::Disk { center, normal, radius } => {
                let center = self.vec3(center)?;
                let normal = self.nonzero(normal, "the disk's normal")?;
                ShapeNode::Disk { center, normal, radius: self.positive(radius, "radius")? }
            }
            Shape::Cylinder { base, cap, radius } => {
                let at = cap.span.clone();
                let (base, cap) = (self.vec3(base)?, self.vec3(cap)?);
                if base == cap {
                    return Err(SceneError::at(
                        &at,
                        "the cylinder's base and cap centres are the same point",
                    ));
                }
                ShapeNode::Cylinder { base, cap, radius: self.positive(radius, "radius")? }
            }
            Shape::Mesh { file } => {
                let name = self.string(file, "`mesh`")?;
                ShapeNode::Mesh { path: resolve(&file.span.file.path, &name) }
            }
            Shape::Instance { of } => match self.value(of)? {
                Value::Object(object) => ShapeNode::Instance(object),
                other => {
                    let what = match &of.kind {
                        syntax::ExprKind::Ident(name) => format!("`{name}`"),
                        _ => "this".to_string(),
                    };
                    return Err(SceneError::at(
                        &of.span,
                        format!("{what} is {}, not an object", other.kind()),
                    ));
                }
            },
            Shape::Union => ShapeNode::Union(Vec::new()),
        };
        let depth = match &shape {
            ShapeNode::Instance(target) => target.depth + 1,
            _ => 1,
        };
        let mut node = ObjectNode { shape, material: None, transforms: Vec::new(), depth, span };
        self.exec(&object.items, &mut Body::Object(&mut node))?;
        if node.depth > MAX_OBJECT_DEPTH {
            return Err(SceneError::at(
                &object.span,
                format!("objects nested more than {MAX_OBJECT_DEPTH} levels deep"),
            ));
        }
        Ok(node)
    }

    /// A modifier of an object, or (in a union) a child.
    pub(super) fn object_item(
        &mut self,
        item: &Item,
        node: &mut ObjectNode,
    ) -> Result<(), SceneError> {
        match item {
            Item::Material(m) => node.material = Some(self.material(m, None)?),
            Item::MaterialName(name) => node.material = Some(self.material_named(name)?),
            Item::Transform(t) => node.transforms.push(self.transform(t)?),
            Item::Object(object) if matches!(node.shape, ShapeNode::Union(_)) => {
                let child = self.object(object)?;
                add_child(node, child);
            }
            Item::Value(expr) => match self.value(expr)? {
                // What a macro gives among an object's items: a material, or a union's child.
                Value::Material(m) => node.material = Some(m),
                Value::Object(child) if matches!(node.shape, ShapeNode::Union(_)) => {
                    let child = super::instance(child, self.here(&expr.span));
                    add_child(node, child);
                }
                _ => return Err(Self::misplaced(item, &Body::Object(node))),
            },
            _ => return Err(Self::misplaced(item, &Body::Object(node))),
        }
        Ok(())
    }

    pub(super) fn transform(&mut self, t: &syntax::Transform) -> Result<Transform, SceneError> {
        let at = &t.value.span;
        let value = self.value(&t.value)?;
        Ok(match t.kind {
            TransformKind::Translate => {
                Transform::Translate(as_vector(&value, at, "`translate`")?.as_vec3())
            }
            TransformKind::Rotate => {
                Transform::Rotate(as_vector(&value, at, "`rotate`")?.as_vec3())
            }
            TransformKind::Scale => {
                let s = as_vector(&value, at, "`scale`")?.as_vec3();
                if s.cmpeq(Vec3::ZERO).any() {
                    let (x, y, z) = (s.x, s.y, s.z);
                    return Err(SceneError::at(
                        at,
                        format!(
                            "scale <{x}, {y}, {z}> has a zero component: it flattens the object"
                        ),
                    ));
                }
                Transform::Scale(s)
            }
            TransformKind::Matrix => {
                let numbers = match value {
                    Value::Numbers(n) if n.len() == 12 => n,
                    other => {
                        return Err(SceneError::at(
                            at,
                            format!("`matrix` takes 12 numbers, not {}", other.kind()),
                        ));
                    }
                };
                let m: Vec<f32> = numbers.iter().map(|&f| f as f32).collect();
                let linear = Mat3::from_cols_slice(&m[..9]);
                if linear.determinant().abs() < 1e-12 {
                    return Err(SceneError::at(
                        at,
                        "the matrix is singular: it flattens the object",
                    ));
                }
                Transform::Matrix { linear, translation: Vec3::new(m[9], m[10], m[11]) }
            }
        })
    }
}

fn add_child(node: &mut ObjectNode, child: ObjectNode) {
    node.depth = node.depth.max(child.depth + 1);
    if let ShapeNode::Union(children) = &mut node.shape {
        children.push(child);
    }
}
