//! POV-Ray's `bicubic_patch`: its settings checked and its control points read, the patch made
//! into smooth triangles (`mesh::bezier_patch`).

use std::sync::Arc;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::graph::ShapeNode;
use crate::lang::syntax::{BicubicPatch, Expr};
use crate::mesh::bezier_patch::{MAX_PATCH_STEPS, tessellate};

impl Evaluator {
    pub(super) fn bicubic_patch(
        &mut self,
        patch: &BicubicPatch,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        // Type 0 keeps only the control points and type 1 the pieces: the same surface.
        let Some(patch_type) = &patch.patch_type else {
            return Err(SceneError::at(span, "a bicubic_patch needs its `type` (0 or 1)"));
        };
        let kind = self.number(patch_type, "the bicubic_patch's type")?;
        if kind != 0.0 && kind != 1.0 {
            return Err(SceneError::at(
                &patch_type.span,
                format!("a bicubic_patch's type is 0 or 1, not {kind}"),
            ));
        }
        // A flatness above 0 lets POV-Ray stop cutting a piece that is flat enough; cut to
        // its steps, the patch is as close to the surface as POV-Ray's or closer.
        if let Some(flatness) = &patch.flatness {
            let value = self.number(flatness, "the bicubic_patch's flatness")?;
            if value < 0.0 {
                return Err(SceneError::at(
                    &flatness.span,
                    format!("a bicubic_patch's flatness is 0 or more, not {value}"),
                ));
            }
        }
        let steps =
            [self.steps(&patch.u_steps, "u_steps")?, self.steps(&patch.v_steps, "v_steps")?];
        let mut points = [glam::Vec3::ZERO; 16];
        for (point, expr) in points.iter_mut().zip(&patch.points) {
            *point = self.vec3(expr)?;
        }
        if let Some(first) = patch.uv_vectors.first() {
            for corner in &patch.uv_vectors {
                self.value(corner)?;
            }
            self.warn_unused_uv("bicubic_patch's", &first.span);
        }
        let mesh = tessellate(&points, steps);
        if mesh.triangles.is_empty() {
            return Err(SceneError::at(
                span,
                "the bicubic_patch's control points lie on one line: it has no surface",
            ));
        }
        Ok(ShapeNode::Extrusion(Arc::new(mesh)))
    }

    /// `u_steps` or `v_steps`: a whole number from 0 (the default) to `MAX_PATCH_STEPS`.
    fn steps(&mut self, steps: &Option<Expr>, word: &str) -> Result<u32, SceneError> {
        let Some(expr) = steps else { return Ok(0) };
        let value = self.number(expr, &format!("the bicubic_patch's {word}"))?;
        if value.fract() != 0.0 || !(0.0..=f64::from(MAX_PATCH_STEPS)).contains(&value) {
            return Err(SceneError::at(
                &expr.span,
                format!(
                    "a bicubic_patch's {word} is a whole number from 0 to {MAX_PATCH_STEPS} (2^{word} \
                     pieces), not {value}"
                ),
            ));
        }
        Ok(value as u32)
    }
}
