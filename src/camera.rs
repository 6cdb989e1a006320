//! The camera: the lab's image-plane form, to which POV-Ray's `look_at` form is converted.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::diagnostic::SceneError;
use crate::geometry::Ray;
use crate::graph::{CameraDesc, CameraForm};
use crate::projection::{Frame, Projection};
use crate::sampling::concentric_disk;
use crate::texture::{Bump, ImageMap, tilt};

/// Rays leave `origin` through `origin + forward + a * left + b * up`, a, b in [-1, 1]:
/// a = 1 is the image's left edge (column 0), b = 1 its top edge (row 0).
#[derive(Debug, Clone)]
pub struct Camera {
    pub origin: Vec3,
    pub left: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    /// Thin-lens radius (0: pinhole) and the distance along `forward` that is in focus.
    pub aperture: f32,
    pub focal_distance: f32,
    pub kind: CameraKind,
    /// POV-Ray's camera `normal { }`: the rays' directions tilted by it.
    pub bump: Option<Bump>,
}

/// How rays leave the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraKind {
    /// Through the image plane `origin + forward + a * left + b * up` (and the lens).
    Perspective,
    /// Parallel rays (POV-Ray's `orthographic`): each leaves `origin + a * left + b * up` along
    /// `forward`.
    Orthographic,
    /// One of POV-Ray's wide projections, from POV-Ray's vectors.
    Wide(Projection, Frame),
}

impl Camera {
    /// The camera of a description, for an image of `width` x `height` pixels, with warnings
    /// (the lab form's plane not of the image's aspect ratio, a focal distance without a lens).
    pub fn new(
        desc: &CameraDesc,
        width: u32,
        height: u32,
    ) -> Result<(Camera, Vec<String>), SceneError> {
        let aspect = width as f32 / height as f32;
        let (origin, left, up, forward, warning) = match desc.form {
            CameraForm::Lab { origin, left, up, forward } => {
                let plane_aspect = left.length() / up.length();
                // POV-Ray's customary `right 1.33*x` for 4:3 images is 0.25 % off: not worth
                // a warning; a plane 1 % off or more is a mistake worth telling.
                let warning = ((plane_aspect / aspect - 1.0).abs() > 1e-2).then(|| {
                    format!(
                        "{:?}: warning: the camera's image plane has aspect {plane_aspect} \
                         (|left| / |up|) but the image is {width}x{height} (aspect {aspect}); \
                         pixels will not be square",
                        desc.span
                    )
                });
                (origin, left, up, forward, warning)
            }
            // POV-Ray's image plane is what `right` and `up` say, whatever the resolution.
            CameraForm::Orthographic { origin, left, up, forward } => {
                (origin, left, up, forward, None)
            }
            CameraForm::Wide { projection: _, frame } => {
                let (left, up) = (-0.5 * frame.right, 0.5 * frame.up);
                (frame.location, left, up, frame.direction, None)
            }
            CameraForm::LookAt { location, look_at, up, angle } => {
                // Left-handed like POV-Ray: with forward +z and up +y, right is up x forward = +x.
                let forward = (look_at - location).normalize();
                let right = up.cross(forward).normalize();
                let true_up = forward.cross(right);
                let half_width = (angle.to_radians() * 0.5).tan();
                let half_height = half_width / aspect;
                (location, -right * half_width, true_up * half_height, forward, None)
            }
        };
        let degenerate = [left, up, forward].iter().any(|v| !v.is_finite() || v.length() == 0.0)
            || left.cross(up).length() <= 1e-6 * left.length() * up.length();
        if degenerate {
            return Err(SceneError::at(
                &desc.span,
                "the camera's vectors are zero or parallel: no image plane",
            ));
        }
        let mut warnings: Vec<String> = warning.into_iter().collect();
        // Given but unused parameters are reported (as warnings: the language allows them).
        if desc.focal_distance.is_some() && desc.aperture <= 0.0 {
            warnings.push(format!(
                "{:?}: warning: `focal_distance` has no effect without an `aperture`",
                desc.span
            ));
        }
        let focal_distance = desc.focal_distance.unwrap_or(forward.length());
        let kind = match desc.form {
            CameraForm::Orthographic { .. } => CameraKind::Orthographic,
            CameraForm::Wide { projection, frame } => CameraKind::Wide(projection, frame),
            CameraForm::Lab { .. } | CameraForm::LookAt { .. } => CameraKind::Perspective,
        };
        let aperture = desc.aperture;
        let bump = match &desc.normal {
            Some(normal) => Some(
                Bump::new(normal, &mut |path| ImageMap::load(path).map(Arc::new)).map_err(|e| {
                    SceneError::at(&desc.span, format!("cannot read the camera's bump_map: {e}"))
                })?,
            ),
            None => None,
        };
        let camera = Camera { origin, left, up, forward, aperture, focal_distance, kind, bump };
        Ok((camera, warnings))
    }

    /// The ray through image position (x, y) in [0, 1]^2 (x to the right, y down), through the
    /// lens position `lens` in [0, 1]^2 when the camera has an aperture. (Where the camera does
    /// not `see`, the projection's formula continued.) Always inlined, but for a `normal`'s
    /// tilt: out of line, the ray came back through memory, and the copy of it into a task's
    /// camera samples waited on the narrower stores that had written it (perf of S1).
    #[inline(always)]
    pub fn ray(&self, x: f32, y: f32, lens: Vec2) -> Ray {
        let ray = self.straight_ray(x, y, lens);
        match &self.bump {
            None => ray,
            Some(bump) => Self::bumped(bump, ray, x, y),
        }
    }

    /// `ray`, through image position (x, y), tilted by the camera's `normal` `bump`: as
    /// POV-Ray's camera normal, the unit direction perturbed as a surface normal is, by the
    /// pattern at the image position with x to the right and y up, centred.
    #[cold]
    fn bumped(bump: &Bump, ray: Ray, x: f32, y: f32) -> Ray {
        let dir = Vec3::from(ray.dir);
        let by = bump.perturbation(Vec3::new(x - 0.5, 0.5 - y, 0.0), dir);
        Ray::new(ray.origin.into(), tilt(dir, by, dir, dir))
    }

    /// `ray` before the camera's `normal`.
    #[inline(always)]
    fn straight_ray(&self, x: f32, y: f32, lens: Vec2) -> Ray {
        match &self.kind {
            CameraKind::Perspective => {}
            CameraKind::Orthographic => {
                let origin = self.origin + (1.0 - 2.0 * x) * self.left + (1.0 - 2.0 * y) * self.up;
                return Ray::new(origin, self.forward.normalize());
            }
            CameraKind::Wide(projection, frame) => return projection.ray(frame, x, y),
        }
        let dir = self.forward + (1.0 - 2.0 * x) * self.left + (1.0 - 2.0 * y) * self.up;
        if self.aperture <= 0.0 {
            return Ray::new(self.origin, dir.normalize());
        }
        // Thin lens: all rays through the lens meet where the pinhole ray meets the focal plane
        // (the plane at `focal_distance` along forward).
        let forward_unit = self.forward.normalize();
        let focus = self.origin + dir * (self.focal_distance / dir.dot(forward_unit));
        let disk = self.aperture * concentric_disk(lens);
        let origin = self.origin + disk.x * self.left.normalize() + disk.y * self.up.normalize();
        Ray::new(origin, (focus - origin).normalize())
    }

    /// Whether light reaches image position (x, y) in [0, 1]^2: everywhere but where a wide
    /// projection leaves the film dark (outside a fisheye's disc).
    #[inline]
    pub fn sees(&self, x: f32, y: f32) -> bool {
        match &self.kind {
            CameraKind::Perspective | CameraKind::Orthographic => true,
            CameraKind::Wide(projection, frame) => projection.sees(frame, x, y),
        }
    }
}
