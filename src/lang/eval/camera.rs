//! `camera { ... }`: either form, checked where it is written.

use std::collections::HashMap;

use glam::Vec3;

use super::expression::{single, single_vector};
use super::{Body, Evaluator, as_float, as_vector};
use crate::diagnostic::{SceneError, Span};
use crate::lang::syntax::Item;
use crate::lang::value::Value;
use crate::scene::graph::{CameraDesc, CameraForm};

/// The camera's parameters as given: value and where its key is written.
pub type CameraParams = HashMap<String, (Value, Span)>;

impl Evaluator {
    pub(super) fn camera_item(
        &mut self,
        item: &Item,
        given: &mut CameraParams,
    ) -> Result<(), SceneError> {
        let Item::CameraParam { key, value } = item else {
            return Err(Self::misplaced(item, &Body::Camera(given)));
        };
        if given.contains_key(&key.name) {
            return Err(SceneError::at(&key.span, format!("`{}` is given twice", key.name)));
        }
        let value = self.value(value)?;
        given.insert(key.name.clone(), (value, key.span.clone()));
        Ok(())
    }

    pub(super) fn camera(&mut self, items: &[Item], span: &Span) -> Result<(), SceneError> {
        if self.camera.is_some() {
            return Err(SceneError::at(span, "a second camera (a scene has exactly one)"));
        }
        let mut given = CameraParams::new();
        self.exec(items, &mut Body::Camera(&mut given))?;
        let vector = |key: &str| -> Result<Option<Vec3>, SceneError> {
            given
                .get(key)
                .map(|(v, at)| single_vector(as_vector(v, at, &format!("`{key}`"))?, at))
                .transpose()
        };
        let float = |key: &str| -> Result<Option<f32>, SceneError> {
            given
                .get(key)
                .map(|(v, at)| single(as_float(v, at, &format!("`{key}`"))?, at))
                .transpose()
        };
        let require = |key: &str, v: Option<Vec3>| {
            v.ok_or_else(|| SceneError::at(span, format!("the camera needs `{key}`")))
        };
        let pov = ["location", "look_at", "angle"].iter().find(|k| given.contains_key(**k));
        let lab = ["origin", "left", "forward"].iter().find(|k| given.contains_key(**k));
        let form = match (pov, lab) {
            (Some(p), Some(l)) => {
                return Err(SceneError::at(
                    &given[*l].1,
                    format!("`{l}` (the lab camera) and `{p}` (POV-Ray's camera) do not mix"),
                ));
            }
            (Some(_), None) => {
                let location = require("location", vector("location")?)?;
                let look_at = require("look_at", vector("look_at")?)?;
                let up = vector("up")?.unwrap_or(Vec3::Y);
                // POV-Ray's default: a horizontal field of view of 2 atan(0.5 * 4/3) degrees.
                let angle = float("angle")?.unwrap_or(67.380_13);
                if !(angle > 0.0 && angle < 180.0) {
                    return Err(SceneError::at(
                        &given["angle"].1,
                        format!("angle {angle} must be between 0 and 180 degrees"),
                    ));
                }
                let view = look_at - location;
                if view.length() == 0.0 {
                    return Err(SceneError::at(
                        span,
                        "`look_at` is the camera's `location`: no view direction",
                    ));
                }
                if up.cross(view).length() <= 1e-6 * up.length() * view.length() {
                    return Err(SceneError::at(
                        span,
                        "`up` is zero or parallel to the view direction",
                    ));
                }
                CameraForm::LookAt { location, look_at, up, angle }
            }
            (None, _) => {
                let origin = require("origin", vector("origin")?)?;
                let left = require("left", vector("left")?)?;
                let up = require("up", vector("up")?)?;
                let forward = require("forward", vector("forward")?)?;
                for (key, v) in [("left", left), ("up", up), ("forward", forward)] {
                    if v.length() == 0.0 {
                        return Err(SceneError::at(
                            &given[key].1,
                            format!("`{key}` is a zero vector"),
                        ));
                    }
                }
                if left.cross(up).length() <= 1e-6 * left.length() * up.length() {
                    return Err(SceneError::at(
                        &given["up"].1,
                        "`left` and `up` are parallel: no image plane",
                    ));
                }
                if forward.dot(left.cross(up)).abs()
                    <= 1e-6 * forward.length() * left.length() * up.length()
                {
                    return Err(SceneError::at(
                        &given["forward"].1,
                        "`forward` lies in the image plane of `left` and `up`",
                    ));
                }
                CameraForm::Lab { origin, left, up, forward }
            }
        };
        let aperture = float("aperture")?.unwrap_or(0.0);
        if aperture < 0.0 {
            return Err(SceneError::at(
                &given["aperture"].1,
                format!("aperture {aperture} is negative"),
            ));
        }
        let focal_distance = float("focal_distance")?;
        if let Some(d) = focal_distance.filter(|d| *d <= 0.0) {
            return Err(SceneError::at(
                &given["focal_distance"].1,
                format!("focal_distance {d} must be positive"),
            ));
        }
        self.camera = Some(CameraDesc { form, aperture, focal_distance, span: self.here(span) });
        Ok(())
    }
}
