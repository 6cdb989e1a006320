//! A shape's points and a mesh's triangles, which POV-Ray lets directives run through (`#while`
//! around the points, `#declare` between them): the list runs as a body, and each point or
//! triangle is written out as literal numbers where it is reached (`literal`), so that the shape
//! reads the list as if each had been written one by one. (The mesh's body is
//! `triangles::mesh_item`.)

use super::{Body, Evaluator};
use crate::diagnostic::SceneError;
use crate::lang::syntax::{Expr, ExprKind, Item, Object, Shape};
use crate::lang::value::Value;

impl Evaluator {
    /// The points of `items`, in the order they are reached.
    pub(super) fn listed_points(&mut self, items: &[Item]) -> Result<Vec<Expr>, SceneError> {
        let mut points = Vec::new();
        self.exec(items, &mut Body::Listed(&mut points))?;
        Ok(points)
    }

    pub(super) fn listed_item(
        &mut self,
        item: &Item,
        points: &mut Vec<Expr>,
    ) -> Result<(), SceneError> {
        let Item::Value(point) = item else {
            return Err(Self::misplaced(item, &Body::Listed(points)));
        };
        points.push(self.literal(point)?);
        Ok(())
    }

    /// A mesh's triangle as it is now: its corners, normals and `uv_vectors` written as
    /// literals; its other items as they are (the mesh refuses them).
    pub(super) fn written_triangle(&mut self, triangle: &Object) -> Result<Object, SceneError> {
        let shape = match &triangle.shape {
            Shape::Triangle { a, b, c } => {
                Shape::Triangle { a: self.literal(a)?, b: self.literal(b)?, c: self.literal(c)? }
            }
            Shape::SmoothTriangle { corners, normals } => {
                // In written order: a corner, then its normal.
                let mut six = Vec::with_capacity(6);
                for k in 0..3 {
                    six.push(self.literal(&corners[k])?);
                    six.push(self.literal(&normals[k])?);
                }
                let mut six = six.into_iter();
                let mut next = || six.next().expect("six literals");
                let [p1, n1, p2, n2, p3, n3] = std::array::from_fn(|_| next());
                Shape::SmoothTriangle {
                    corners: Box::new([p1, p2, p3]),
                    normals: Box::new([n1, n2, n3]),
                }
            }
            _ => unreachable!("a mesh's triangle is a `triangle` or a `smooth_triangle`"),
        };
        let mut items = Vec::with_capacity(triangle.items.len());
        for item in &triangle.items {
            items.push(match item {
                Item::UvVectors { corners, span } => {
                    let [a, b, c] = &**corners;
                    let corners = Box::new([self.literal(a)?, self.literal(b)?, self.literal(c)?]);
                    Item::UvVectors { corners, span: span.clone() }
                }
                item => item.clone(),
            });
        }
        Ok(Object { shape, items, span: triangle.span.clone() })
    }

    /// `expr`'s number or vector as it is now, written as a literal at `expr`'s place.
    fn literal(&mut self, expr: &Expr) -> Result<Expr, SceneError> {
        let number = |x: f64| Expr { kind: ExprKind::Number(x), span: expr.span.clone() };
        let kind = match self.value(expr)? {
            Value::Float(x) => ExprKind::Number(x),
            Value::Vector(v) => ExprKind::Vector(v.to_array().map(number).to_vec()),
            Value::Numbers(n) => ExprKind::Vector(n.into_iter().map(number).collect()),
            other => {
                return Err(SceneError::at(
                    &expr.span,
                    format!("a point here is a number or a vector, not {}", other.kind()),
                ));
            }
        };
        Ok(Expr { kind, span: expr.span.clone() })
    }
}
