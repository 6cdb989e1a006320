//! POV-Ray's lathe, sor and polygon: their points read, checked and made into the curves,
//! pieces and outlines of the shapes.

use glam::{Vec2, Vec3};

use super::Evaluator;
use super::expression::single;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{
    SplineKind, close_outlines, open_spline_segments, outline_normal, sor_pieces,
};
use crate::graph::ShapeNode;
use crate::lang::syntax::Expr;
use crate::lang::value::Value;

impl Evaluator {
    pub(super) fn lathe(
        &mut self,
        spline: SplineKind,
        count: &Expr,
        points: &[Expr],
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let points = self.points::<2>("lathe", count, points)?;
        let points: Vec<Vec2> = points.iter().map(|p| Vec2::from_array(*p)).collect();
        if let Some(i) = points.iter().position(|p| p.x < 0.0) {
            return Err(SceneError::at(
                span,
                format!("the lathe's point {} has a negative radius {}", i + 1, points[i].x),
            ));
        }
        let segments = open_spline_segments(spline, &points)
            .map_err(|e| SceneError::at(span, format!("the lathe's points: {e}")))?;
        Ok(ShapeNode::Lathe { segments })
    }

    pub(super) fn sor(
        &mut self,
        count: &Expr,
        points: &[Expr],
        open: bool,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let points = self.points::<2>("sor", count, points)?;
        let points: Vec<Vec2> = points.iter().map(|p| Vec2::from_array(*p)).collect();
        let pieces = sor_pieces(&points)
            .map_err(|e| SceneError::at(span, format!("the sor's points: {e}")))?;
        Ok(ShapeNode::Sor { pieces, open })
    }

    pub(super) fn polygon(
        &mut self,
        count: &Expr,
        points: &[Expr],
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let points = self.points::<3>("polygon", count, points)?;
        let mut points: Vec<Vec3> = points.iter().map(|p| Vec3::from_array(*p)).collect();
        if points.len() < 3 {
            return Err(SceneError::at(span, "a polygon needs 3 points or more"));
        }
        if close_outlines(&mut points) {
            let at = self.here(span);
            self.warnings.push(format!(
                "{at:?}: warning: the polygon's last outline is not closed: it is closed from its \
                 last point back to its first, as POV-Ray does"
            ));
        }
        if outline_normal(&points).is_none() {
            return Err(SceneError::at(span, "the polygon's points enclose no area"));
        }
        Ok(ShapeNode::Polygon { points })
    }

    /// The `count` points of a lathe, sor or polygon (`what`), each a vector of `N` numbers (a
    /// polygon's 2-vectors are in the plane z = 0).
    fn points<const N: usize>(
        &mut self,
        what: &str,
        count: &Expr,
        points: &[Expr],
    ) -> Result<Vec<[f32; N]>, SceneError> {
        let n = self.number(count, &format!("the {what}'s number of points"))?;
        if n != points.len() as f64 {
            return Err(SceneError::at(
                &count.span,
                format!("the {what} says {n} points but {} are given", points.len()),
            ));
        }
        let mut read = Vec::with_capacity(points.len());
        for point in points {
            match self.value(point)? {
                Value::Numbers(v) if v.len() == N || N == 3 && v.len() == 2 => {
                    let mut p = [0.0; N];
                    for (k, &x) in v.iter().enumerate() {
                        p[k] = single(x, &point.span)?;
                    }
                    read.push(p);
                }
                // A 3-vector is a `Vector`, not `Numbers`.
                Value::Vector(v) if N == 3 => {
                    let mut p = [0.0; N];
                    for (k, x) in v.to_array().into_iter().enumerate() {
                        p[k] = single(x, &point.span)?;
                    }
                    read.push(p);
                }
                other => {
                    return Err(SceneError::at(
                        &point.span,
                        format!("a {what}'s point is a {N}-vector, not {}", other.kind()),
                    ));
                }
            }
        }
        Ok(read)
    }
}
