//! The unit sphere, or the open tube x^2 + y^2 = 1, 0 <= z <= 1, under an affine map (a sphere
//! under non-uniform scale, the side of a cylinder).

use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};

use super::crossings::Crossings;
use super::quadratic::quadratic_roots;
use super::shape::{REL_ERROR, SurfaceSample};
use super::{Aabb, Hit, Ray};
use crate::sampling::uniform_sphere;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuadricKind {
    Ellipsoid,
    Tube,
}

/// The maps between a quadric's canonical space and the world.
#[derive(Debug, Clone)]
pub struct QuadricFrame {
    pub to_world: Affine3A,
    pub to_object: Affine3A,
    /// Inverse transpose of `to_world`'s linear part: maps normals.
    pub normal_to_world: Mat3A,
    /// The world-space area, when uniform sampling of the canonical parameters (z and angle
    /// for the tube, the sphere's directions) is uniform by area: when the map from the
    /// canonical shape is a similarity up to the tube's own radius and height.
    pub area: Option<f32>,
    /// Magnitude of the world coordinates, for the hit point's error bound.
    pub magnitude: f32,
}

impl QuadricFrame {
    pub fn new(to_world: Affine3A, area: Option<f32>) -> Self {
        let corners = Self::canonical_corners().map(|c| to_world.transform_point3(c).abs());
        QuadricFrame {
            to_world,
            to_object: to_world.inverse(),
            normal_to_world: to_world.matrix3.inverse().transpose(),
            area,
            magnitude: corners.iter().fold(0.0f32, |m, c| m.max(c.max_element())),
        }
    }

    /// The ray in canonical space, direction not normalised (so distances are the world's).
    pub(super) fn ray_to_object(&self, ray: &Ray) -> (Vec3A, Vec3A) {
        (self.to_object.transform_point3a(ray.origin), self.to_object.transform_vector3a(ray.dir))
    }

    /// Corners of a box holding both canonical quadrics.
    pub(super) fn canonical_corners() -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
    }

    /// World bounds of what the canonical box holds.
    pub(super) fn bounds(&self) -> Aabb {
        Aabb::from_points(&Self::canonical_corners().map(|c| self.to_world.transform_point3(c)))
    }
}

impl QuadricKind {
    /// The quadratic `a t^2 + 2 half_b t + c` (as `(a, half_b, c)`) that is 0 where `o + t d`
    /// meets the canonical quadric (the tube's whole infinite cylinder).
    fn coefficients(self, o: Vec3A, d: Vec3A) -> (f32, f32, f32) {
        match self {
            QuadricKind::Ellipsoid => (d.dot(d), o.dot(d), o.dot(o) - 1.0),
            QuadricKind::Tube => {
                (d.x * d.x + d.y * d.y, o.x * d.x + o.y * d.y, o.x * o.x + o.y * o.y - 1.0)
            }
        }
    }

    /// Distance along `o + t d` (canonical space, `d` not normalised, so t is the world
    /// distance) in (0, t_max).
    #[inline]
    pub(super) fn distance(self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<f32> {
        let (a, half_b, c) = self.coefficients(o, d);
        let (t0, t1) = quadratic_roots(a, half_b, c)?;
        let accept = |t: f32| {
            let in_range = t > 0.0 && t < t_max;
            in_range && (self == QuadricKind::Ellipsoid || (0.0..=1.0).contains(&(o.z + t * d.z)))
        };
        [t0, t1].into_iter().find(|&t| accept(t))
    }

    pub(super) fn intersection(self, frame: &QuadricFrame, ray: &Ray, t_max: f32) -> Option<f32> {
        let (o, d) = frame.ray_to_object(ray);
        self.distance(o, d, t_max)
    }

    pub(super) fn hit(self, frame: &QuadricFrame, ray: &Ray, t: f32) -> Hit {
        let (o, d) = frame.ray_to_object(ray);
        let p = o + t * d;
        // Back onto the surface, then to the world.
        let (p, n) = match self {
            QuadricKind::Ellipsoid => {
                let n = p.normalize();
                (n, n)
            }
            QuadricKind::Tube => {
                let radial = Vec3A::new(p.x, p.y, 0.0).normalize();
                (radial + Vec3A::new(0.0, 0.0, p.z), radial)
            }
        };
        let normal = (frame.normal_to_world * n).normalize().into();
        Hit {
            t,
            point: frame.to_world.transform_point3a(p).into(),
            normal,
            shading_normal: normal,
            error: REL_ERROR * frame.magnitude,
            primitive: 0,
        }
    }

    /// A point uniform by area, where the frame's area is known.
    pub(super) fn sample(self, frame: &QuadricFrame, u: Vec2) -> Option<SurfaceSample> {
        frame.area?;
        let (p, n) = match self {
            QuadricKind::Ellipsoid => {
                let n = uniform_sphere(u);
                (n, n)
            }
            QuadricKind::Tube => {
                let phi = 2.0 * std::f32::consts::PI * u.y;
                let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
                (n + Vec3::new(0.0, 0.0, u.x), n)
            }
        };
        Some(SurfaceSample {
            point: frame.to_world.transform_point3(p),
            normal: (frame.normal_to_world * Vec3A::from(n)).normalize().into(),
            error: REL_ERROR * frame.magnitude,
        })
    }

    /// The ellipsoid's crossings; the open tube is no solid: none.
    pub(super) fn crossings(self, frame: &QuadricFrame, ray: &Ray, t_max: f32) -> Crossings {
        match self {
            QuadricKind::Ellipsoid => {
                let (o, d) = frame.ray_to_object(ray);
                let (a, half_b, c) = self.coefficients(o, d);
                Crossings::between(quadratic_roots(a, half_b, c), t_max)
            }
            QuadricKind::Tube => Crossings::outside(),
        }
    }

    /// Whether `p` is inside the ellipsoid (never inside the open tube).
    pub(super) fn contains(self, frame: &QuadricFrame, p: Vec3) -> bool {
        match self {
            QuadricKind::Ellipsoid => frame.to_object.transform_point3(p).length_squared() < 1.0,
            QuadricKind::Tube => false,
        }
    }
}
