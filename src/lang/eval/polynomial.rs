//! POV-Ray's algebraic surfaces (`quadric`, `cubic`, `quartic`, `poly`): their coefficients
//! read into the terms of one polynomial.

use super::Evaluator;
use crate::diagnostic::SceneError;
use crate::geometry::{MAX_DEGREE, Term, pov_ray_term_count, pov_ray_terms};
use crate::graph::ShapeNode;
use crate::lang::syntax::{Expr, PolyOrder};
use crate::lang::value::Value;

impl Evaluator {
    /// `quadric { <A,B,C>, <D,E,F>, <G,H,I>, J }`.
    pub(super) fn quadric(
        &mut self,
        squares: &Expr,
        products: &Expr,
        linear: &Expr,
        constant: &Expr,
    ) -> Result<ShapeNode, SceneError> {
        let [a, b, c] = self.vector(squares)?.to_array();
        let [d, e, f] = self.vector(products)?.to_array();
        let [g, h, i] = self.vector(linear)?.to_array();
        let j = self.number(constant, "the quadric's constant")?;
        let terms = [
            (a, [2, 0, 0]),
            (b, [0, 2, 0]),
            (c, [0, 0, 2]),
            (d, [1, 1, 0]),
            (e, [1, 0, 1]),
            (f, [0, 1, 1]),
            (g, [1, 0, 0]),
            (h, [0, 1, 0]),
            (i, [0, 0, 1]),
            (j, [0, 0, 0]),
        ];
        let terms = terms.map(|(coefficient, powers)| Term { coefficient, powers });
        Ok(ShapeNode::Algebraic { terms: terms.to_vec() })
    }

    /// `cubic { <20 numbers> }`, `quartic { <35 numbers> }`, `poly { order, <...> }`.
    pub(super) fn poly(
        &mut self,
        order: &PolyOrder,
        coefficients: &Expr,
    ) -> Result<ShapeNode, SceneError> {
        let (order, what) = match order {
            PolyOrder::Cubic => (3, "`cubic`"),
            PolyOrder::Quartic => (4, "`quartic`"),
            PolyOrder::Written(order) => {
                let n = self.number(order, "the poly's order")?;
                if n.fract() != 0.0 || !(2.0..=MAX_DEGREE as f64).contains(&n) {
                    return Err(SceneError::at(
                        &order.span,
                        format!("a poly's order is a whole number from 2 to {MAX_DEGREE}, not {n}"),
                    ));
                }
                (n as usize, "this `poly`")
            }
        };
        let count = pov_ray_term_count(order);
        let numbers = match self.value(coefficients)? {
            Value::Numbers(n) if n.len() == count => n,
            Value::Vector(v) if count == 3 => v.to_array().to_vec(),
            other => {
                let given = match &other {
                    Value::Numbers(n) => format!("{} numbers", n.len()),
                    Value::Vector(_) => "3 numbers".to_string(),
                    other => other.kind().to_string(),
                };
                return Err(SceneError::at(
                    &coefficients.span,
                    format!("{what} takes a vector of {count} coefficients, not {given}"),
                ));
            }
        };
        let terms = pov_ray_terms(order, &numbers);
        if terms.iter().all(|t| t.coefficient == 0.0 || t.degree() == 0) {
            return Err(SceneError::at(
                &coefficients.span,
                format!("{what}'s coefficients are all 0 but the constant: it has no surface"),
            ));
        }
        Ok(ShapeNode::Algebraic { terms })
    }
}
