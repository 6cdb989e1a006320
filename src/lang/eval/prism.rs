//! POV-Ray's prism: its points read and joined into the segments of its curves.

use glam::Vec2;

use super::Evaluator;
use super::expression::single;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{SplineKind, Sweep, spline_segments};
use crate::graph::ShapeNode;
use crate::lang::syntax::Expr;
use crate::lang::value::Value;

impl Evaluator {
    pub(super) fn prism(
        &mut self,
        (spline, sweep): (SplineKind, Sweep),
        heights: &[Expr; 2],
        count: &Expr,
        points: &[Expr],
        open: bool,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let heights = [self.single(&heights[0])?, self.single(&heights[1])?];
        if heights[0] == heights[1] {
            return Err(SceneError::at(span, "the prism's two heights are the same: it is flat"));
        }
        let n = self.number(count, "the prism's number of points")?;
        if n != points.len() as f64 {
            return Err(SceneError::at(
                &count.span,
                format!("the prism says {n} points but {} are given", points.len()),
            ));
        }
        let mut section = Vec::with_capacity(points.len());
        for point in points {
            match self.value(point)? {
                Value::Numbers(v) if v.len() == 2 => {
                    section.push(Vec2::new(single(v[0], &point.span)?, single(v[1], &point.span)?));
                }
                other => {
                    return Err(SceneError::at(
                        &point.span,
                        format!("a prism's point is a 2-vector <x, z>, not {}", other.kind()),
                    ));
                }
            }
        }
        let segments = spline_segments(spline, &section)
            .map_err(|e| SceneError::at(span, format!("the prism's points: {e}")))?;
        Ok(ShapeNode::Prism { segments, sweep, heights, open })
    }
}
