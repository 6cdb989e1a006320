//! POV-Ray's blob: its components, each with its own transforms, and its threshold.

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{BlobComponent, ComponentShape};
use crate::graph::{ShapeNode, compose};
use crate::lang::syntax::{Expr, Object, Shape};

impl Evaluator {
    /// A component of the blob being read: its shape, radius and strength, and its items (its
    /// transforms; a texture of its own is read without effect, with a warning).
    pub(super) fn blob_component(&mut self, object: &Object) -> Result<BlobComponent, SceneError> {
        let (shape, radius, strength) = match &object.shape {
            Shape::BlobSphere { center, radius, strength } => {
                (ComponentShape::Sphere { center: self.vec3(center)? }, radius, strength)
            }
            Shape::BlobCylinder { a, b, radius, strength } => {
                let (a_at, a, b) = (&a.span, self.vec3(a)?, self.vec3(b)?);
                if a == b {
                    return Err(SceneError::at(
                        a_at,
                        "the blob cylinder's ends are the same point",
                    ));
                }
                (ComponentShape::Capsule { a, b }, radius, strength)
            }
            _ => unreachable!("the grammar gives only components in a blob"),
        };
        let radius = self.positive(radius, "a blob component's radius")?;
        let strength = self.component_strength(strength)?;
        // The items, read as an object's are, for the transforms among them.
        let items =
            Object { shape: Shape::Union, items: object.items.clone(), span: object.span.clone() };
        let placed = self.object(&items)?;
        if placed.material.is_some() {
            let at = self.here(&object.span);
            self.warnings.push(format!(
                "{at:?}: warning: a blob component's own texture is not used: the blob's is"
            ));
        }
        Ok(BlobComponent { shape, radius, strength, to_blob: compose(&placed.transforms) })
    }

    fn component_strength(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        let strength = self.number(expr, "a blob component's strength")?;
        if strength == 0.0 {
            return Err(SceneError::at(&expr.span, "a blob component's strength is 0"));
        }
        super::expression::single(strength, &expr.span)
    }

    /// A blob read whole: a threshold above 0 and some component of positive strength, or
    /// it has no surface.
    pub(super) fn check_blob(&self, shape: &ShapeNode, span: &Span) -> Result<(), SceneError> {
        let ShapeNode::Blob { threshold, components } = shape else { return Ok(()) };
        let problem = if *threshold <= 0.0 || threshold.is_nan() {
            Some(format!("a blob's threshold {threshold} must be above 0"))
        } else if !components.iter().any(|c| c.strength > 0.0) {
            Some("a blob without a component of positive strength has no surface".to_string())
        } else {
            None
        };
        problem.map_or(Ok(()), |message| Err(SceneError::at(span, message)))
    }
}
