//! POV-Ray's transforms as values (`.pov`): `transform { items }` composes its transforms,
//! declared transforms and `inverse` into one affine map, which `#declare T = transform { }`
//! binds, `transform T` applies, and `function { transform { } }` maps points with.

use glam::{Affine3A, DVec3, Mat3, Vec3};

use super::{Body, Evaluator};
use crate::diagnostic::{SceneError, Span};
use crate::graph::Transform;
use crate::lang::syntax::{Call, Expr, Item};
use crate::lang::value::Value;

/// A `transform { }` block being read: what its items compose to so far, and whether an
/// `inverse` stands among them.
pub struct TransformState {
    affine: Affine3A,
    inverse: bool,
}

impl Evaluator {
    /// `transform { items }`: the items composed first written, first applied; with `inverse`
    /// anywhere among them, the inverse of the whole (as POV-Ray reads the block).
    pub(super) fn transform_block(
        &mut self,
        items: &[Item],
        span: &Span,
    ) -> Result<Affine3A, SceneError> {
        let mut state = TransformState { affine: Affine3A::IDENTITY, inverse: false };
        self.exec(items, &mut Body::Transform(&mut state))?;
        if !state.inverse {
            return Ok(state.affine);
        }
        // A composition of POV-Ray's transforms, each invertible, is singular only where their
        // scales underflow single precision.
        if state.affine.matrix3.determinant().abs() < 1e-30 {
            return Err(SceneError::at(span, "this transform is singular: it has no inverse"));
        }
        Ok(state.affine.inverse())
    }

    /// The item of a `transform { }` block.
    pub(super) fn transform_item(
        &mut self,
        item: &Item,
        state: &mut TransformState,
    ) -> Result<(), SceneError> {
        let next = match item {
            Item::Transform(t) => self.transform(t)?.to_affine(),
            Item::PovParam { key, value: None, items }
                if key.name == "inverse" && items.is_empty() =>
            {
                state.inverse = true;
                return Ok(());
            }
            Item::Value(expr) => self.transform_value(expr)?,
            _ => return Err(Self::misplaced(item, &Body::Transform(state))),
        };
        state.affine = next * state.affine;
        Ok(())
    }

    /// The transform `expr` stands for (a declared transform, or a macro's).
    pub(super) fn transform_value(&mut self, expr: &Expr) -> Result<Affine3A, SceneError> {
        match self.value(expr)? {
            Value::Transform(affine) => Ok(*affine),
            other => Err(SceneError::at(
                &expr.span,
                format!("`transform` takes a transform, not {}", other.kind()),
            )),
        }
    }

    /// A transform function called from the scene: `F(x, y, z)`, the image of the point.
    pub(super) fn call_transform_function(
        &mut self,
        affine: &Affine3A,
        call: &Call,
    ) -> Result<Value, SceneError> {
        if call.arguments.len() != 3 {
            return Err(SceneError::at(
                &call.span,
                format!(
                    "transform function `{}` takes 3 arguments (x, y, z), not {}",
                    call.name.name,
                    call.arguments.len()
                ),
            ));
        }
        let mut p = [0.0; 3];
        for (coordinate, arg) in p.iter_mut().zip(&call.arguments) {
            *coordinate = self.number(arg, &format!("`{}`", call.name.name))? as f32;
        }
        Ok(Value::Vector(DVec3::from(affine.transform_point3(Vec3::from(p)))))
    }
}

/// A composed transform as the scene graph's `matrix`.
pub(super) fn matrix_of(affine: Affine3A) -> Transform {
    Transform::Matrix { linear: Mat3::from(affine.matrix3), translation: affine.translation.into() }
}
