//! A shape's points and a mesh's triangles, which POV-Ray lets directives run through (`#while`
//! around the points, `#declare` between them): the list runs as a body, and each point or
//! triangle is written out as literal numbers where it is reached, so that the shape reads the
//! list as if each had been written one by one.

use super::{Body, Evaluator};
use crate::diagnostic::SceneError;
use crate::lang::syntax::{Expr, ExprKind, Item, Object, Shape};
use crate::lang::value::Value;

impl Evaluator {
    /// The points of `items`, in the order they are reached.
    pub(super) fn listed_points(&mut self, items: &[Item]) -> Result<Vec<Expr>, SceneError> {
        self.listed(items, |item| match item {
            Item::Value(point) => point,
            _ => unreachable!("a list of points holds values only"),
        })
    }

    /// The triangles of `items`, in the order they are reached.
    pub(super) fn listed_triangles(&mut self, items: &[Item]) -> Result<Vec<Object>, SceneError> {
        self.listed(items, |item| match item {
            Item::Object(triangle) => triangle,
            _ => unreachable!("a mesh's list holds triangles only"),
        })
    }

    /// The members of `items` as they are reached, each taken by `member`.
    fn listed<T>(&mut self, items: &[Item], member: fn(Item) -> T) -> Result<Vec<T>, SceneError> {
        let mut listed = Vec::new();
        self.exec(items, &mut Body::Listed(&mut listed))?;
        Ok(listed.into_iter().map(member).collect())
    }

    pub(super) fn listed_item(
        &mut self,
        item: &Item,
        listed: &mut Vec<Item>,
    ) -> Result<(), SceneError> {
        let written = match item {
            Item::Value(point) => Item::Value(self.literal(point)?),
            Item::Object(Object { shape: Shape::Triangle { a, b, c }, items, span }) => {
                let shape = Shape::Triangle {
                    a: self.literal(a)?,
                    b: self.literal(b)?,
                    c: self.literal(c)?,
                };
                Item::Object(Object { shape, items: items.clone(), span: span.clone() })
            }
            Item::Object(Object {
                shape: Shape::SmoothTriangle { corners, normals },
                items,
                span,
            }) => {
                // In written order: a corner, then its normal.
                let mut six = Vec::with_capacity(6);
                for k in 0..3 {
                    six.push(self.literal(&corners[k])?);
                    six.push(self.literal(&normals[k])?);
                }
                let mut six = six.into_iter();
                let mut next = || six.next().expect("six literals");
                let [p1, n1, p2, n2, p3, n3] = std::array::from_fn(|_| next());
                let shape = Shape::SmoothTriangle {
                    corners: Box::new([p1, p2, p3]),
                    normals: Box::new([n1, n2, n3]),
                };
                Item::Object(Object { shape, items: items.clone(), span: span.clone() })
            }
            _ => return Err(Self::misplaced(item, &Body::Listed(listed))),
        };
        listed.push(written);
        Ok(())
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
