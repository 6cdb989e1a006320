//! POV-Ray's `parametric { }` read into its description: the three functions of u and v, the
//! (u, v) rectangle, the container and the settings with POV-Ray's defaults, and a warning where
//! a function is seen to be steeper than `max_gradient` allows.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{Container, ParametricDesc, ScalarField};
use crate::lang::syntax::{self, Expr};
use crate::lang::value::Value;

/// Grid points per side of the (u, v) rectangle where the slopes are measured for the warning.
const GRADIENT_GRID: usize = 32;

impl Evaluator {
    pub(super) fn parametric(
        &mut self,
        surface: &syntax::Parametric,
        at: &Span,
    ) -> Result<ParametricDesc, SceneError> {
        let mut functions: Vec<Arc<dyn ScalarField>> = Vec::with_capacity(3);
        for def in surface.functions.iter() {
            let function = self.float_function(def)?;
            if function.parameters() != 3 {
                return Err(SceneError::at(
                    &def.span,
                    "a parametric surface's functions are of u and v (x and y): this one names \
                     its own parameters",
                ));
            }
            functions.push(function);
        }
        let [first, second] = [&surface.uv[0], &surface.uv[1]].map(|e| self.uv_corner(e));
        let (first, second) = (first?, second?);
        let uv = [first.min(second), first.max(second)];
        if uv[0].x == uv[1].x || uv[0].y == uv[1].y {
            return Err(SceneError::at(
                &surface.uv[1].span,
                format!("the (u, v) rectangle from {} to {} is empty", uv[0], uv[1]),
            ));
        }
        let container = match &surface.container {
            // POV-Ray's default container.
            None => Container::Box { min: DVec3::splat(-1.0), max: DVec3::ONE },
            Some(object) => self.container(object)?,
        };
        let functions: [Arc<dyn ScalarField>; 3] =
            functions.try_into().expect("the grammar gives three functions");
        let mut desc =
            ParametricDesc { functions, uv, container, max_gradient: 1.0, accuracy: 0.001 };
        for (key, values) in &surface.settings {
            match key.name.as_str() {
                "max_gradient" => desc.max_gradient = self.setting_positive(key, values)?,
                "accuracy" => desc.accuracy = self.setting_positive(key, values)?,
                // POV-Ray's precomputed bounds of the first pieces are the bounds every piece
                // gets here as it is met: the same surface.
                "precompute" => {
                    let depth = self.number(&values[0], "`precompute`'s depth")?;
                    if !(1.0..=20.0).contains(&depth) || depth.fract() != 0.0 {
                        return Err(SceneError::at(
                            &values[0].span,
                            format!("`precompute`'s depth is a whole number 1 to 20, not {depth}"),
                        ));
                    }
                }
                other => unreachable!("the grammar has no parametric setting `{other}`"),
            }
        }
        let found = desc.largest_gradient(GRADIENT_GRID);
        if found > desc.max_gradient {
            self.warnings.push(format!(
                "{:?}: warning: the parametric surface's functions have a slope of at least \
                 {found:.4} but its max_gradient is {}: parts of the surface may be missed \
                 (raise max_gradient)",
                self.here(at),
                desc.max_gradient
            ));
        }
        Ok(desc)
    }

    /// A corner of the (u, v) rectangle: a 2-vector (or a number for both).
    fn uv_corner(&mut self, expr: &Expr) -> Result<DVec2, SceneError> {
        match self.value(expr)? {
            Value::Numbers(v) if v.len() == 2 => Ok(DVec2::new(v[0], v[1])),
            Value::Float(f) => Ok(DVec2::splat(f)),
            other => Err(SceneError::at(
                &expr.span,
                format!(
                    "a corner of the (u, v) rectangle is a 2-vector <u, v>, not {}",
                    other.kind()
                ),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::DVec2;

    use crate::graph::{SceneGraph, ShapeNode};

    fn pov(text: &str) -> Result<SceneGraph, String> {
        crate::lang::parse_scene(Path::new("parametric.pov"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn settings_take_povray_s_defaults_and_functions_take_u_and_v() {
        let graph = pov("parametric { function { u } function { v * 2 } function { 0 } <0, -1>, \
             <1, 1> }\nparametric { function { cos(u) } function { sin(u) } function { v } \
             <0, 0>, <2 * pi, 1> contained_by { sphere { 0, 2 } } accuracy 0.01 max_gradient 2 \
             precompute 10 x, y, z }")
        .unwrap();
        let desc = |i: usize| match &graph.objects[i].shape {
            ShapeNode::Parametric(desc) => desc.clone(),
            other => panic!("{other:?}"),
        };
        let (first, second) = (desc(0), desc(1));
        assert_eq!((first.max_gradient, first.accuracy), (1.0, 0.001));
        assert_eq!(first.uv, [DVec2::new(0.0, -1.0), DVec2::ONE]);
        let p = first.point(DVec2::new(0.25, 0.5));
        assert_eq!((p.x, p.y, p.z), (0.25, 1.0, 0.0), "u is x, v is y");
        assert_eq!((second.max_gradient, second.accuracy), (2.0, 0.01));
        assert!(graph.warnings.iter().any(|w| w.contains("1:1: warning: the parametric surface")));
        assert_eq!(graph.warnings.len(), 1, "{:?}", graph.warnings);
    }

    #[test]
    fn bad_parametric_surfaces_are_refused() {
        let cases = [
            ("parametric { function { u } function { v } function { 0 } <0, 0>, <1, 0> }", "empty"),
            (
                "parametric { function(a) { a } function { v } function { 0 } <0, 0>, <1, 1> }",
                "names its own parameters",
            ),
            (
                "parametric { function { u } function { v } function { 0 } <0, 0>, <1, 1> \
                 precompute 30 x }",
                "1 to 20",
            ),
            (
                "parametric { function { u } function { v } function { 0 } <0, 0>, <1, 1> \
                 accuracy 0 }",
                "must be positive",
            ),
            (
                "parametric { function { u } function { v } function { 0 } <0, 0>, \"s\" }",
                "2-vector",
            ),
        ];
        for (text, expected) in cases {
            let message = pov(text).err().unwrap_or_else(|| panic!("{text} is refused"));
            assert!(message.contains(expected), "{text}: {message}");
        }
    }
}
