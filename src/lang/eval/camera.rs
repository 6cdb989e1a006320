//! `camera { ... }`: either form, checked where it is written.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};

use super::expression::{single, single_vector};
use super::{Body, Evaluator, as_float, as_vector};
use crate::diagnostic::{SceneError, Span};
use crate::graph::{CameraDesc, CameraForm};
use crate::lang::dialect::Dialect;
use crate::lang::syntax::{AppearanceKind, Item, ProjectionWord};
use crate::lang::value::Value;
use crate::projection::{Frame, Projection};

/// Where the projection's word is kept among the parameters (`cylinder` with its type: `cylinder
/// 2`): not a word of the language, so no parameter has its name.
const PROJECTION: &str = "#projection";

/// POV-Ray's default `angle` of a fisheye, ultra-wide-angle or cylinder camera, in degrees, and
/// a spherical camera's (horizontal, vertical).
const POV_WIDE_ANGLE: f32 = 90.0;
const POV_SPHERICAL_ANGLES: (f32, f32) = (360.0, 180.0);

/// Where a `.pov` camera's transforms are kept among the parameters, composed in written order,
/// as the twelve numbers of POV-Ray's `matrix`.
const TRANSFORMS: &str = "#transforms";

/// POV-Ray's camera defaults (`.pov`): at the origin, looking along +z, `up` y, `right` 1.33 x.
const POV_LOCATION: Vec3 = Vec3::ZERO;
const POV_DIRECTION: Vec3 = Vec3::Z;
const POV_UP: Vec3 = Vec3::Y;
const POV_RIGHT: Vec3 = Vec3::new(1.33, 0.0, 0.0);

/// Where a `.pov` camera's `normal { }` is kept among the parameters.
const NORMAL: &str = "#normal";

/// The camera's parameters as given: value and where its key is written.
pub type CameraParams = HashMap<String, (Value, Span)>;

impl Evaluator {
    pub(super) fn camera_item(
        &mut self,
        item: &Item,
        given: &mut CameraParams,
    ) -> Result<(), SceneError> {
        if let Item::CameraProjection { projection, span } = item {
            let word = match projection {
                ProjectionWord::Perspective => "perspective".to_string(),
                ProjectionWord::Orthographic => "orthographic".to_string(),
                ProjectionWord::Fisheye => "fisheye".to_string(),
                ProjectionWord::UltraWideAngle => "ultra_wide_angle".to_string(),
                ProjectionWord::Omnimax => "omnimax".to_string(),
                ProjectionWord::Panoramic => "panoramic".to_string(),
                ProjectionWord::Spherical => "spherical".to_string(),
                ProjectionWord::Cylinder(written) => {
                    // POV-Ray reads the type as an integer.
                    let kind = self.single(written)?.trunc();
                    if !(1.0..=4.0).contains(&kind) {
                        return Err(SceneError::at(
                            &written.span,
                            format!("the cylinder camera's type is 1, 2, 3 or 4, not {kind}"),
                        ));
                    }
                    format!("cylinder {kind}")
                }
            };
            let projection = Value::String(Arc::new(word));
            if given.insert(PROJECTION.to_string(), (projection, span.clone())).is_some() {
                return Err(SceneError::at(span, "the camera's projection is given twice"));
            }
            return Ok(());
        }
        if let (Item::Value(expr), Dialect::Pov) = (item, self.dialect) {
            // A declared camera's name: its parameters, which later items may change.
            return match self.value(expr)? {
                Value::Camera(declared) => {
                    given.extend(declared.iter().map(|(k, v)| (k.clone(), v.clone())));
                    Ok(())
                }
                other => Err(SceneError::at(
                    &expr.span,
                    format!("a camera names a declared camera, not {}", other.kind()),
                )),
            };
        }
        if let (Item::Transform(t), Dialect::Pov) = (item, self.dialect) {
            let moved = self.transform(t)?.to_affine() * camera_transforms(given);
            let numbers = [moved.matrix3.to_cols_array().as_slice(), &moved.translation.to_array()]
                .concat()
                .into_iter()
                .map(f64::from)
                .collect();
            given.insert(TRANSFORMS.to_string(), (Value::Numbers(numbers), t.span.clone()));
            return Ok(());
        }
        if let (Item::Appearance(a), Dialect::Pov) = (item, self.dialect)
            && a.kind == AppearanceKind::Normal
        {
            let normal = self.normal(a, None)?.map(Arc::new);
            if given.insert(NORMAL.to_string(), (Value::Normal(normal), a.span.clone())).is_some() {
                return Err(SceneError::at(&a.span, "the camera's `normal` is given twice"));
            }
            return Ok(());
        }
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
        if self.dialect == Dialect::Pov {
            let camera = self.pov_camera(&given, span)?;
            self.camera = Some(camera);
            return Ok(());
        }
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
        let span = self.here(span);
        self.camera = Some(CameraDesc { form, aperture, focal_distance, normal: None, span });
        Ok(())
    }
}

impl Evaluator {
    /// POV-Ray's camera (`.pov`), as POV-Ray 3.7 builds it: the vectors default to POV-Ray's, then
    /// `angle` sets the length of `direction` (perspective) or scales `right` and `up`
    /// (orthographic), then `look_at` turns them about `sky` keeping their lengths and the
    /// handedness of `right`. A ray leaves through `location + direction + (u - 1/2) right +
    /// (1/2 - v) up`, u, v in [0, 1] from the image's top left.
    pub(super) fn pov_camera(
        &mut self,
        given: &CameraParams,
        span: &Span,
    ) -> Result<CameraDesc, SceneError> {
        for key in ["origin", "left", "forward", "focal_distance"] {
            if let Some((_, at)) = given.get(key) {
                return Err(SceneError::at(at, format!("`{key}` is not a POV-Ray camera word")));
            }
        }
        let vector = |key: &str, default: Vec3| -> Result<Vec3, SceneError> {
            given.get(key).map_or(Ok(default), |(v, at)| {
                single_vector(as_vector(v, at, &format!("`{key}`"))?, at)
            })
        };
        let location = vector("location", POV_LOCATION)?;
        let mut direction = vector("direction", POV_DIRECTION)?;
        let mut up = vector("up", POV_UP)?;
        let mut right = vector("right", POV_RIGHT)?;
        let sky = vector("sky", POV_UP)?;
        // Focal blur: read, and warned about (the camera stays a pinhole).
        let blur = ["aperture", "focal_point", "blur_samples", "confidence", "variance"]
            .iter()
            .find_map(|k| given.get(*k));
        if let Some((_, at)) = blur {
            let at = self.here(at);
            self.warnings.push(format!(
                "{at:?}: warning: POV-Ray's focal blur (`aperture`, `focal_point`, \
                 `blur_samples`, `confidence`, `variance`) is not rendered: the camera is a \
                 pinhole"
            ));
        }
        let word = match given.get(PROJECTION) {
            Some((Value::String(word), _)) => word.as_str(),
            _ => "perspective",
        };
        let orthographic = word == "orthographic";
        let wide = !matches!(word, "perspective" | "orthographic");
        for (key, v) in [("direction", direction), ("up", up), ("right", right), ("sky", sky)] {
            if v.length() == 0.0 {
                let at = given.get(key).map_or(span, |g| &g.1);
                return Err(SceneError::at(at, format!("`{key}` is a zero vector")));
            }
        }
        let projection = if wide { Some(wide_projection(word, given, span)?) } else { None };
        if let Some((value, at)) = given.get("angle").filter(|_| !wide) {
            let angle = single(as_float(value, at, "`angle`")?, at)?;
            if !(angle > 0.0 && angle < 180.0) {
                return Err(SceneError::at(
                    at,
                    format!("angle {angle} must be between 0 and 180 degrees"),
                ));
            }
            let half = (angle.to_radians() * 0.5).tan();
            if orthographic {
                // The image plane is as wide as a perspective camera's at the direction's length.
                let scale = 2.0 * half * direction.length() / right.length();
                right *= scale;
                up *= scale;
            } else {
                direction = direction.normalize() * (0.5 * right.length() / half);
            }
        }
        let look_at = match given.get("look_at") {
            Some((value, at)) => {
                let look_at = single_vector(as_vector(value, at, "`look_at`")?, at)?;
                let view = look_at - location;
                if view.length() == 0.0 {
                    return Err(SceneError::at(at, "`look_at` is the camera's `location`"));
                }
                let handedness = up.cross(direction).dot(right);
                let new_direction = view.normalize();
                let mut new_right = sky.cross(new_direction);
                if new_right.length() <= 1e-6 * sky.length() {
                    // As POV-Ray does: the camera keeps its `right`, and `up` follows from it.
                    let at = self.here(at);
                    self.warnings.push(format!(
                        "{at:?}: warning: `sky` is parallel to the view direction: the camera \
                         keeps its `right` (as POV-Ray does)"
                    ));
                    new_right = right;
                }
                let new_right = new_right.normalize();
                let new_up = new_direction.cross(new_right).normalize();
                direction = new_direction * direction.length();
                right = new_right * right.length() * if handedness < 0.0 { -1.0 } else { 1.0 };
                up = new_up * up.length();
                look_at
            }
            None => location + direction,
        };
        if right.cross(up).length() <= 1e-6 * right.length() * up.length() {
            return Err(SceneError::at(span, "`right` and `up` are parallel: no image plane"));
        }
        // POV-Ray moves the camera it has built, wherever the transforms stand among its items.
        let moved = camera_transforms(given);
        let (location, look_at) =
            (moved.transform_point3(location), moved.transform_point3(look_at));
        let [direction, right, up] = [direction, right, up].map(|v| moved.transform_vector3(v));
        self.pov_look_at = Some(look_at);
        let (left, half_up) = (-0.5 * right, 0.5 * up);
        let form = match projection {
            Some(projection) => {
                let frame = Frame { location, right, up, direction };
                CameraForm::Wide { projection, frame }
            }
            None if orthographic => {
                CameraForm::Orthographic { origin: location, left, up: half_up, forward: direction }
            }
            None => CameraForm::Lab { origin: location, left, up: half_up, forward: direction },
        };
        let normal = match given.get(NORMAL) {
            Some((Value::Normal(normal), _)) => normal.as_deref().cloned(),
            _ => None,
        };
        Ok(CameraDesc { form, aperture: 0.0, focal_distance: None, normal, span: self.here(span) })
    }
}

/// POV-Ray's wide projection `word` (as `camera_item` keeps it) with its angles: `angle`
/// (POV-Ray's default 90°; ignored by `omnimax` and `panoramic`, as in POV-Ray), and a spherical
/// camera's `angle H, V` (V defaults to H / 2; both to 360, 180).
fn wide_projection(
    word: &str,
    given: &CameraParams,
    span: &Span,
) -> Result<Projection, SceneError> {
    let angles = match given.get("angle") {
        None => None,
        Some((Value::Numbers(n), at)) if n.len() == 2 && word == "spherical" => {
            Some((single(n[0], at)?, Some(single(n[1], at)?), at))
        }
        Some((value, at)) => Some((single(as_float(value, at, "`angle`")?, at)?, None, at)),
    };
    if let Some((h, v, at)) = angles
        && (h < 0.0 || v.is_some_and(|v| v < 0.0))
    {
        return Err(SceneError::at(at, "a negative viewing angle"));
    }
    let angle = angles.map_or(POV_WIDE_ANGLE, |(h, _, _)| h);
    Ok(match word {
        "fisheye" => Projection::Fisheye { angle },
        "ultra_wide_angle" => Projection::UltraWideAngle { angle },
        "omnimax" => Projection::Omnimax,
        "panoramic" => Projection::Panoramic,
        "spherical" => {
            let (horizontal, vertical) =
                angles.map_or(POV_SPHERICAL_ANGLES, |(h, v, _)| (h, v.unwrap_or(0.5 * h)));
            Projection::Spherical { horizontal, vertical }
        }
        "cylinder 1" => Projection::Cylinder { along_up: true, moving: false, angle },
        "cylinder 2" => Projection::Cylinder { along_up: false, moving: false, angle },
        "cylinder 3" => Projection::Cylinder { along_up: true, moving: true, angle },
        "cylinder 4" => Projection::Cylinder { along_up: false, moving: true, angle },
        other => {
            let at = given.get(PROJECTION).map_or(span, |(_, at)| at);
            return Err(SceneError::at(at, format!("`{other}` is not a wide projection")));
        }
    })
}

/// The camera's transforms so far, composed (the identity when there are none).
fn camera_transforms(given: &CameraParams) -> Affine3A {
    let Some((Value::Numbers(n), _)) = given.get(TRANSFORMS) else {
        return Affine3A::IDENTITY;
    };
    let n: Vec<f32> = n.iter().map(|&x| x as f32).collect();
    Affine3A::from_mat3_translation(Mat3::from_cols_slice(&n[..9]), Vec3::from_slice(&n[9..]))
}
