//! POV-Ray's `julia_fractal`: its parameter and settings read and checked.

use glam::DVec4;

use super::Evaluator;
use crate::diagnostic::SceneError;
use crate::geometry::{
    Algebra, JuliaDesc, JuliaFunction, MAX_JULIA_ITERATIONS, MAX_JULIA_PRECISION,
};
use crate::graph::ShapeNode;
use crate::lang::syntax::{Expr, JuliaFractal};
use crate::lang::value::Value;

impl Evaluator {
    pub(super) fn julia_fractal(
        &mut self,
        fractal: &JuliaFractal,
    ) -> Result<ShapeNode, SceneError> {
        let parameter = self.vector4(&fractal.parameter, "the julia_fractal's parameter")?;
        let function = match &fractal.function {
            None => JuliaFunction::Square,
            Some(word) => match word.name.as_str() {
                "sqr" => JuliaFunction::Square,
                // POV-Ray 3.7's hypercomplex cube is not h·h·h (the shapes differ visibly), and
                // its formula is not in the manual: refused rather than drawn unlike POV-Ray.
                "cube" if fractal.algebra == Algebra::Hypercomplex => {
                    return Err(SceneError::at(
                        &word.span,
                        "the julia_fractal's function `cube` is not supported in the hypercomplex \
                         numbers: raydiance's would not be POV-Ray's shape (`quaternion cube` and \
                         `hypercomplex sqr` are)",
                    ));
                }
                "cube" => JuliaFunction::Cube,
                other => {
                    let why = match fractal.algebra {
                        Algebra::Quaternion => {
                            "POV-Ray's quaternion fractals have only sqr and cube"
                        }
                        Algebra::Hypercomplex => "raydiance has sqr and cube",
                    };
                    return Err(SceneError::at(
                        &word.span,
                        format!("the julia_fractal's function `{other}` is not supported: {why}"),
                    ));
                }
            },
        };
        let max_iteration = match &fractal.max_iteration {
            None => 20,
            Some(expr) => {
                let n = self.number(expr, "the julia_fractal's max_iteration")?;
                if n.fract() != 0.0 || !(1.0..=f64::from(MAX_JULIA_ITERATIONS)).contains(&n) {
                    return Err(SceneError::at(
                        &expr.span,
                        format!(
                            "a julia_fractal's max_iteration is a whole number from 1 to \
                             {MAX_JULIA_ITERATIONS}, not {n}"
                        ),
                    ));
                }
                n as u32
            }
        };
        // As in POV-Ray, a precision below 1 is 1.
        let precision = match &fractal.precision {
            None => 20.0,
            Some(expr) => {
                let p = self.number(expr, "the julia_fractal's precision")?;
                if p > MAX_JULIA_PRECISION {
                    return Err(SceneError::at(
                        &expr.span,
                        format!(
                            "a julia_fractal's precision is at most {MAX_JULIA_PRECISION} (its \
                             step along a ray is 1 / precision), not {p}"
                        ),
                    ));
                }
                p.max(1.0)
            }
        };
        let slice = match &fractal.slice {
            None => (DVec4::W, 0.0),
            Some((normal, distance)) => {
                let n = self.vector4(normal, "the julia_fractal's slice")?;
                if n.w == 0.0 {
                    return Err(SceneError::at(
                        &normal.span,
                        format!(
                            "a julia_fractal's slice normal needs a fourth component other than \
                             0, not <{}, {}, {}, {}>",
                            n.x, n.y, n.z, n.w
                        ),
                    ));
                }
                (n, self.number(distance, "the julia_fractal's slice distance")?)
            }
        };
        let algebra = fractal.algebra;
        Ok(ShapeNode::JuliaFractal(Box::new(JuliaDesc {
            parameter,
            algebra,
            function,
            max_iteration,
            precision,
            slice,
        })))
    }

    /// A 4-vector `<a, b, c, d>`.
    fn vector4(&mut self, expr: &Expr, what: &str) -> Result<DVec4, SceneError> {
        match self.value(expr)? {
            Value::Numbers(v) if v.len() == 4 => Ok(DVec4::new(v[0], v[1], v[2], v[3])),
            other => Err(SceneError::at(
                &expr.span,
                format!("{what} is a 4-vector <a, b, c, d>, not {}", other.kind()),
            )),
        }
    }
}
