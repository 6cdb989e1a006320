//! POV-Ray's questions about an object's geometry while the scene is read (`.pov`):
//! `min_extent` and `max_extent` (its bounding box), `trace` (the first point of its surface along
//! a ray, and the normal there) and `inside` (whether a point is in its solid). The object is
//! built alone into a scene (`scene::build`), once however often it is asked, and the scene is
//! asked.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{DVec3, Vec3};

use super::Evaluator;
use super::expression::single_vector;
use crate::diagnostic::SceneError;
use crate::geometry::Ray;
use crate::graph::{CameraDesc, CameraForm, ObjectNode, SceneGraph, Settings};
use crate::lang::syntax::Expr;
use crate::lang::value::Value;
use crate::scene::Scene;

/// What `min_extent` and `max_extent` give for an unbounded object (a plane): POV-Ray's.
pub const UNBOUNDED_EXTENT: f64 = 1e10;

/// The objects asked about so far, each built once: by the address of the declared object
/// (the `Arc` kept so that the address stays its own).
#[derive(Default)]
pub struct Probes {
    built: HashMap<usize, (Arc<ObjectNode>, Arc<Scene>)>,
}

impl Evaluator {
    /// The object `expr` names, built alone into a scene.
    fn probe(&mut self, expr: &Expr, what: &str) -> Result<Arc<Scene>, SceneError> {
        let object = match self.value(expr)? {
            Value::Object(object) => object,
            other => {
                return Err(SceneError::at(
                    &expr.span,
                    format!("{what} takes an object, not {}", other.kind()),
                ));
            }
        };
        let key = Arc::as_ptr(&object) as usize;
        if let Some((_, scene)) = self.probes.built.get(&key) {
            return Ok(scene.clone());
        }
        let span = self.here(&expr.span);
        let graph = SceneGraph {
            settings: Settings::default(),
            camera: CameraDesc {
                form: CameraForm::LookAt {
                    location: Vec3::ZERO,
                    look_at: Vec3::Z,
                    up: Vec3::Y,
                    angle: 60.0,
                },
                aperture: 0.0,
                focal_distance: None,
                normal: None,
                span: span.clone(),
            },
            lights: Vec::new(),
            objects: vec![super::instance(object.clone(), span)],
            sky: None,
            backdrop: Vec3::ZERO,
            atmosphere: None,
            warnings: Vec::new(),
        };
        let scene = Arc::new(crate::scene::build(&graph)?);
        self.probes.built.insert(key, (object, scene.clone()));
        Ok(scene)
    }

    /// `min_extent(Object)` (`max` false) or `max_extent(Object)` (`max` true): a corner of the
    /// box raydiance bounds the object by; ±10^10 on every axis for an unbounded object, as in
    /// POV-Ray.
    pub(super) fn extent(&mut self, object: &Expr, max: bool) -> Result<Value, SceneError> {
        let word = if max { "`max_extent`" } else { "`min_extent`" };
        let bounds = self.probe(object, word)?.bounds();
        let corner = match (bounds, max) {
            (Some(b), false) => b.min.as_dvec3(),
            (Some(b), true) => b.max.as_dvec3(),
            (None, false) => DVec3::splat(-UNBOUNDED_EXTENT),
            (None, true) => DVec3::splat(UNBOUNDED_EXTENT),
        };
        Ok(Value::Vector(corner))
    }

    /// `trace(Object, Start, Direction [, Normal])`: the first point of the object's surface
    /// along the ray, and its unit normal (outwards for a solid) bound to `Normal`; where the ray
    /// meets nothing, both are <0, 0, 0>, as in POV-Ray.
    pub(super) fn trace(&mut self, args: &[Expr]) -> Result<Value, SceneError> {
        let scene = self.probe(&args[0], "`trace`")?;
        let start = self.probe_vector(&args[1], "`trace`'s start")?;
        let direction = self.probe_vector(&args[2], "`trace`'s direction")?;
        if direction == Vec3::ZERO || !direction.is_finite() {
            return Err(SceneError::at(&args[2].span, "`trace`'s direction is zero"));
        }
        let hit = scene.intersect(&Ray::new(start, direction.normalize()));
        let (point, normal) = hit.map_or((DVec3::ZERO, DVec3::ZERO), |hit| {
            (hit.point.as_dvec3(), hit.shading_normal.as_dvec3())
        });
        if let Some(name) = args.get(3) {
            let Some(name) = name.lone_ident() else {
                return Err(SceneError::at(
                    &name.span,
                    "`trace`'s fourth argument is the name that receives the normal",
                ));
            };
            self.bind(name, Value::Vector(normal), false);
        }
        Ok(Value::Vector(point))
    }

    /// `inside(Object, Point)`: 1 if the point is inside the object's solid, else 0 (always 0
    /// for a surface without an inside).
    pub(super) fn inside(&mut self, args: &[Expr]) -> Result<Value, SceneError> {
        let scene = self.probe(&args[0], "`inside`")?;
        let point = self.probe_vector(&args[1], "`inside`'s point")?;
        Ok(Value::Float(if scene.contains(point) { 1.0 } else { 0.0 }))
    }

    fn probe_vector(&mut self, expr: &Expr, what: &str) -> Result<Vec3, SceneError> {
        let value = self.value(expr)?;
        single_vector(super::as_vector(&value, &expr.span, what)?, &expr.span)
    }
}
