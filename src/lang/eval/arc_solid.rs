//! POV-Ray's ovus and lemon: their radii read and checked as POV-Ray checks them.

use glam::Vec3;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::lemon_min_inner_radius;
use crate::graph::ShapeNode;
use crate::lang::syntax::Expr;

impl Evaluator {
    /// `ovus { bottom, top }`. A top radius of twice the bottom one or more swallows the bottom
    /// sphere: POV-Ray draws the top sphere alone, with a warning, and so does raydiance.
    pub(super) fn ovus(&mut self, bottom: &Expr, top: &Expr) -> Result<ShapeNode, SceneError> {
        let bottom_radius = self.positive(bottom, "the ovus' bottom radius")?;
        let top_radius = self.positive(top, "the ovus' top radius")?;
        if top_radius >= 2.0 * bottom_radius {
            self.warnings.push(format!(
                "{:?}: warning: the ovus' top radius {top_radius} is twice its bottom radius \
                 {bottom_radius} or more: it is the top sphere alone, as in POV-Ray",
                self.here(&top.span)
            ));
            let center = Vec3::new(0.0, bottom_radius, 0.0);
            return Ok(ShapeNode::Sphere { center, radius: top_radius });
        }
        Ok(ShapeNode::Ovus { bottom: bottom_radius, top: top_radius })
    }

    /// `lemon { base, base_radius, cap, cap_radius, inner_radius [open] }`. An inner radius too
    /// small to reach both rims from the axis' far side is raised to the least that does, with
    /// a warning, as POV-Ray 3.8 does.
    pub(super) fn lemon(
        &mut self,
        [base, base_radius, cap, cap_radius, inner_radius]: [&Expr; 5],
        open: bool,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let ends = [self.vec3(base)?, self.vec3(cap)?];
        let base_radius = self.non_negative(base_radius, "the lemon's base radius")?;
        let cap_radius = self.non_negative(cap_radius, "the lemon's cap radius")?;
        let mut inner = self.positive(inner_radius, "the lemon's inner radius")?;
        let length = ends[0].distance(ends[1]);
        if length == 0.0 {
            return Err(SceneError::at(span, "the lemon's base and cap are the same point"));
        }
        let least =
            lemon_min_inner_radius(f64::from(base_radius / length), f64::from(cap_radius / length))
                as f32
                * length;
        if inner < least {
            self.warnings.push(format!(
                "{:?}: warning: the lemon's inner radius {inner} is too small; the least is \
                 {least}, which is taken, as in POV-Ray",
                self.here(&inner_radius.span)
            ));
            inner = least;
        }
        Ok(ShapeNode::Lemon { ends, radii: [base_radius, cap_radius], inner_radius: inner, open })
    }
}
