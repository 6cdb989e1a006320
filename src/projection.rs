//! POV-Ray's wide projections (`fisheye`, `ultra_wide_angle`, `omnimax`, `panoramic`,
//! `cylinder 1`–`4`, `spherical`): the ray through each image position, as POV-Ray 3.7 traces
//! it (`docs/povray.md`, Geometry and camera).

use glam::{Quat, Vec3};

use crate::geometry::Ray;

/// A projection and its angles in degrees. Which of the camera's vectors it normalises, and
/// which lengths it reads, is POV-Ray's choice for each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Polar: the distance from the image's centre is the angle from `direction`; the image is
    /// the disc of radius 1 in units of |right| across and |up| down.
    Fisheye { angle: f32 },
    /// `angle` across the image, `angle` × |up| / |right| down it.
    UltraWideAngle { angle: f32 },
    /// A 180° fisheye for domes, squeezed by |right| / |up|; nothing below 45° under the axis.
    Omnimax,
    /// 180° across and (almost) down, on the ellipsoid of `right`, `up` and `direction`.
    Panoramic,
    /// A cylinder along `up` (`along_up`) or `right`: `angle` around it, its length along it;
    /// rays leave the location (fixed) or a point moving along the axis (`moving`).
    Cylinder { along_up: bool, moving: bool, angle: f32 },
    /// Latitude and longitude: `horizontal` across, `vertical` down.
    Spherical { horizontal: f32, vertical: f32 },
}

/// POV-Ray's camera vectors, as its `look_at` and transforms leave them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub location: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    pub direction: Vec3,
}

impl Projection {
    /// The ray through image position (x, y) in [0, 1]² (x to the right, y down). Where the
    /// projection leaves the film dark (`sees` is false) it is the projection's formula
    /// continued, which POV-Ray does not trace.
    pub fn ray(&self, frame: &Frame, x: f32, y: f32) -> Ray {
        let (x0, y0) = (x - 0.5, 0.5 - y);
        let (right, up, direction) =
            (frame.right.normalize(), frame.up.normalize(), frame.direction.normalize());
        let (length_right, length_up) = (frame.right.length(), frame.up.length());
        let mut origin = frame.location;
        let dir = match *self {
            Projection::Fisheye { angle } => {
                let (phi, rad) = self.polar(frame, x0, y0);
                towards(phi, rad * angle.to_radians() * 0.5, right, up, direction)
            }
            Projection::Omnimax => {
                let (phi, rad) = self.polar(frame, x0, y0);
                towards(phi, omnimax_theta(rad), right, up, direction)
            }
            Projection::UltraWideAngle { angle } => {
                let a = x0 * angle.to_radians();
                let b = y0 * angle.to_radians() * length_up / length_right;
                a.sin() * right + b.sin() * up + a.cos() * b.cos() * direction
            }
            Projection::Panoramic => {
                // Not normalised: the vectors' lengths are the ellipsoid's axes.
                let a = (1.0 - x) * std::f32::consts::PI;
                let b = y0 * std::f32::consts::PI;
                a.cos() * frame.right + b.tan() * frame.up + a.sin() * frame.direction
            }
            Projection::Cylinder { along_up: true, moving, angle } => {
                let (a, along) = (x0 * angle.to_radians(), y0 * length_up);
                let around = a.sin() * right + a.cos() * direction;
                if moving {
                    origin += along * up;
                    around
                } else {
                    around + along * up
                }
            }
            Projection::Cylinder { along_up: false, moving, angle } => {
                let (b, along) = (y0 * angle.to_radians(), x0 * length_right);
                let around = b.sin() * up + b.cos() * direction;
                if moving {
                    origin += along * right;
                    around
                } else {
                    around + along * right
                }
            }
            Projection::Spherical { horizontal, vertical } => {
                let latitude = Quat::from_axis_angle(right, -y0 * vertical.to_radians());
                let longitude = Quat::from_axis_angle(up, x0 * horizontal.to_radians());
                longitude * (latitude * frame.direction)
            }
        };
        Ray::new(origin, dir.normalize_or(direction))
    }

    /// Whether light reaches image position (x, y): everywhere but outside a fisheye's disc
    /// and an omnimax's ellipse or below its 45°, where POV-Ray traces no ray (the film there is
    /// dark).
    pub fn sees(&self, frame: &Frame, x: f32, y: f32) -> bool {
        let (x0, y0) = (x - 0.5, 0.5 - y);
        match self {
            Projection::Fisheye { .. } => self.polar(frame, x0, y0).1 <= 1.0,
            Projection::Omnimax => {
                let (phi, rad) = self.polar(frame, x0, y0);
                let theta = omnimax_theta(rad);
                rad <= 1.0 && phi.sin() * theta.sin() >= (135f32).to_radians().tan() * theta.cos()
            }
            Projection::UltraWideAngle { .. }
            | Projection::Panoramic
            | Projection::Cylinder { .. }
            | Projection::Spherical { .. } => true,
        }
    }

    /// A fisheye's or omnimax's image position (x0, y0) in [-½, ½]² in polar form: the angle
    /// from `right` towards `up`, and the radius (1 at the disc's edge).
    fn polar(&self, frame: &Frame, x0: f32, y0: f32) -> (f32, f32) {
        let (mut u, mut v) = (2.0 * x0, 2.0 * y0);
        let (length_right, length_up) = (frame.right.length(), frame.up.length());
        if let Projection::Omnimax = self {
            // POV-Ray's dome squeeze, with its constant for the film's aspect.
            const DOME: f32 = 1.283_458;
            let aspect = length_right / length_up;
            if aspect > DOME {
                u *= aspect / DOME;
                v = (v - 1.0) / DOME + 1.0;
            } else if aspect > 1.0 {
                v = (v - 1.0) / aspect + 1.0;
            } else {
                v /= aspect;
            }
        } else {
            (u, v) = (u * length_right, v * length_up);
        }
        (v.atan2(u), u.hypot(v))
    }
}

/// Omnimax's angle from the axis at radius `rad` of its disc (POV-Ray's polynomial).
fn omnimax_theta(rad: f32) -> f32 {
    1.411_269 * rad - 0.094_39 * rad.powi(3) + 0.256_74 * rad.powi(5)
}

/// The unit direction at angle `theta` from `direction`, turned `phi` from `right` towards `up`.
fn towards(phi: f32, theta: f32, right: Vec3, up: Vec3, direction: Vec3) -> Vec3 {
    let (sin_theta, cos_theta) = theta.sin_cos();
    phi.cos() * sin_theta * right + phi.sin() * sin_theta * up + cos_theta * direction
}

#[cfg(test)]
mod tests {
    use super::*;

    const FRAME: Frame =
        Frame { location: Vec3::ZERO, right: Vec3::X, up: Vec3::Y, direction: Vec3::Z };

    fn dir(p: Projection, x: f32, y: f32) -> Vec3 {
        assert!(p.sees(&FRAME, x, y));
        Vec3::from(p.ray(&FRAME, x, y).dir)
    }

    #[test]
    fn every_projection_looks_along_direction_at_the_centre() {
        let all = [
            Projection::Fisheye { angle: 180.0 },
            Projection::UltraWideAngle { angle: 200.0 },
            Projection::Omnimax,
            Projection::Cylinder { along_up: true, moving: false, angle: 90.0 },
            Projection::Cylinder { along_up: false, moving: true, angle: 90.0 },
            Projection::Spherical { horizontal: 360.0, vertical: 180.0 },
        ];
        for p in all {
            assert!(dir(p, 0.5, 0.5).abs_diff_eq(Vec3::Z, 1e-6), "{p:?}");
        }
        // The panoramic's centre column looks along `direction` (sin(π/2) = 1).
        assert!(dir(Projection::Panoramic, 0.5, 0.5).abs_diff_eq(Vec3::Z, 1e-6));
    }

    #[test]
    fn a_fisheye_edge_is_half_its_angle_away_and_outside_its_disc_is_dark() {
        let p = Projection::Fisheye { angle: 180.0 };
        assert!(dir(p, 1.0, 0.5).abs_diff_eq(Vec3::X, 1e-6), "the right edge at 90°");
        assert!(dir(p, 0.5, 0.0).abs_diff_eq(Vec3::Y, 1e-6), "the top edge at 90°");
        assert!(!p.sees(&FRAME, 0.95, 0.05), "a corner is outside the disc");
    }

    #[test]
    fn spherical_and_cylinder_turn_by_their_angles() {
        let sphere = Projection::Spherical { horizontal: 360.0, vertical: 180.0 };
        assert!(dir(sphere, 0.75, 0.5).abs_diff_eq(Vec3::X, 1e-6), "a quarter right: +x");
        assert!(dir(sphere, 0.5, 0.0).abs_diff_eq(Vec3::Y, 1e-6), "the top edge: +y");
        let cylinder = Projection::Cylinder { along_up: true, moving: true, angle: 180.0 };
        let ray = cylinder.ray(&FRAME, 1.0, 0.0);
        assert!(Vec3::from(ray.dir).abs_diff_eq(Vec3::X, 1e-6));
        assert!(Vec3::from(ray.origin).abs_diff_eq(0.5 * Vec3::Y, 1e-6), "moved up the axis");
    }
}
