//! POV-Ray's `isosurface { }` read into its description: the function, the container and the
//! settings with POV-Ray's defaults, and a warning where the function is seen to be steeper
//! than `max_gradient` allows.

use glam::DVec3;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::geometry::{Container, IsosurfaceDesc};
use crate::lang::syntax::{self, Expr, Ident, Shape};

/// Grid points per axis over the container where the gradient is measured for the warning.
const GRADIENT_GRID: usize = 16;

impl Evaluator {
    pub(super) fn isosurface(
        &mut self,
        isosurface: &syntax::Isosurface,
        at: &Span,
    ) -> Result<IsosurfaceDesc, SceneError> {
        let Some(def) = &isosurface.function else {
            return Err(SceneError::at(at, "an isosurface needs its `function { }`"));
        };
        let function = self.float_function(def)?;
        if function.parameters() != 3 {
            return Err(SceneError::at(
                &def.span,
                format!(
                    "an isosurface's function takes x, y and z: this one takes {} parameters",
                    function.parameters()
                ),
            ));
        }
        let container = match &isosurface.container {
            // POV-Ray's default container.
            None => Container::Box { min: DVec3::splat(-1.0), max: DVec3::ONE },
            Some(object) => self.container(object)?,
        };
        let mut desc = IsosurfaceDesc {
            function,
            container,
            threshold: 0.0,
            accuracy: 0.001,
            max_gradient: 1.1,
            open: false,
        };
        for (key, values) in &isosurface.settings {
            match key.name.as_str() {
                "threshold" => desc.threshold = self.setting_number(key, values)?,
                "accuracy" => desc.accuracy = self.setting_positive(key, values)?,
                "max_gradient" => desc.max_gradient = self.setting_positive(key, values)?,
                // Every crossing is found: `max_trace` only bounds POV-Ray's work.
                "max_trace" => {
                    self.setting_number(key, values)?;
                }
                "all_intersections" => {}
                "evaluate" => {
                    if values.len() != 3 {
                        return Err(SceneError::at(&key.span, "`evaluate` takes three numbers"));
                    }
                    self.warnings.push(format!(
                        "{:?}: warning: `evaluate` has no effect here: `max_gradient` bounds the \
                         steps along a ray",
                        self.here(&key.span)
                    ));
                }
                "open" => desc.open = true,
                other => unreachable!("the grammar has no isosurface setting `{other}`"),
            }
        }
        let found = desc.largest_gradient(GRADIENT_GRID);
        if found > desc.max_gradient {
            self.warnings.push(format!(
                "{:?}: warning: the isosurface's function has a gradient of at least {found:.4} \
                 but its max_gradient is {}: parts of the surface may be missed (raise \
                 max_gradient)",
                self.here(at),
                desc.max_gradient
            ));
        }
        Ok(desc)
    }

    /// `contained_by`'s box or sphere.
    pub(super) fn container(&mut self, object: &syntax::Object) -> Result<Container, SceneError> {
        if let Some(item) = object.items.first() {
            return Err(SceneError::at(
                item.span(),
                "`contained_by`'s box or sphere takes only its own arguments",
            ));
        }
        Ok(match &object.shape {
            Shape::Box { corner_a, corner_b } => {
                let (a, b) = (self.vector(corner_a)?, self.vector(corner_b)?);
                Container::Box { min: a.min(b), max: a.max(b) }
            }
            Shape::Sphere { center, radius } => Container::Sphere {
                center: self.vector(center)?,
                radius: f64::from(self.positive(radius, "the container's radius")?),
            },
            _ => unreachable!("the grammar's container is a box or a sphere"),
        })
    }

    pub(super) fn setting_number(
        &mut self,
        key: &Ident,
        values: &[Expr],
    ) -> Result<f64, SceneError> {
        match values {
            [value] => self.number(value, &format!("`{}`", key.name)),
            _ => Err(SceneError::at(&key.span, format!("`{}` takes one number", key.name))),
        }
    }

    pub(super) fn setting_positive(
        &mut self,
        key: &Ident,
        values: &[Expr],
    ) -> Result<f64, SceneError> {
        let value = self.setting_number(key, values)?;
        if value <= 0.0 {
            return Err(SceneError::at(
                &key.span,
                format!("`{}` {value} must be positive", key.name),
            ));
        }
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::graph::{SceneGraph, ShapeNode};

    fn pov(text: &str) -> Result<SceneGraph, String> {
        crate::lang::parse_scene(Path::new("isosurface.pov"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn settings_take_povray_s_defaults_and_are_read() {
        let graph = pov("isosurface { function { x } }\n\
             isosurface { function { y } contained_by { sphere { <1, 2, 3>, 4 } } threshold 0.5 \
             accuracy 0.01 max_gradient 2 open max_trace all_intersections }")
        .unwrap();
        let desc = |i: usize| match &graph.objects[i].shape {
            ShapeNode::Isosurface(desc) => desc.clone(),
            other => panic!("{other:?}"),
        };
        let (first, second) = (desc(0), desc(1));
        assert_eq!((first.threshold, first.accuracy, first.max_gradient), (0.0, 0.001, 1.1));
        assert!(!first.open);
        assert_eq!((second.threshold, second.accuracy, second.max_gradient), (0.5, 0.01, 2.0));
        assert!(second.open);
        assert!(matches!(second.container, crate::geometry::Container::Sphere { radius: 4.0, .. }));
    }

    #[test]
    fn a_steeper_function_than_max_gradient_is_warned_of() {
        let steep = pov("isosurface { function { 10 * x } max_gradient 2 }").unwrap();
        assert!(steep.warnings.iter().any(|w| w.contains("max_gradient")), "{:?}", steep.warnings);
        let gentle = pov("isosurface { function { 10 * x } max_gradient 11 }").unwrap();
        assert!(gentle.warnings.is_empty(), "{:?}", gentle.warnings);
    }

    #[test]
    fn bad_settings_are_refused() {
        let cases = [
            ("isosurface { contained_by { box { -1, 1 } } }", "needs its `function { }`"),
            (
                "#declare F = function(a) { a }\nisosurface { function { F(x) } accuracy 0 }",
                "must be positive",
            ),
            ("isosurface { function { x } threshold 1, 2 }", "takes one number"),
            (
                "isosurface { function { x } contained_by { box { -1, 1 scale 2 } } }",
                "only its own",
            ),
        ];
        for (text, expected) in cases {
            let message = pov(text).err().unwrap_or_else(|| panic!("{text} is refused"));
            assert!(message.contains(expected), "{text}: {message}");
        }
    }
}
