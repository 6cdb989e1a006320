//! The unit sphere, or the open tube x^2 + y^2 = 1, 0 <= z <= 1, under an affine map (a sphere
//! under non-uniform scale, the side of a cylinder).

use glam::{Affine3A, DMat3, DVec3, Mat3A, Vec2, Vec3, Vec3A};

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
    /// Inverse transpose of `to_world`'s linear part: maps normals.
    pub normal_to_world: Mat3A,
    /// The world-space area, when uniform sampling of the canonical parameters (z and angle
    /// for the tube, the sphere's directions) is uniform by area: when the map from the
    /// canonical shape is a similarity up to the tube's own radius and height.
    pub area: Option<f32>,
    /// Magnitude of the world coordinates, for the hit point's error bound.
    pub magnitude: f32,
    /// The canonical space's origin in the world and the inverse of the map's linear part, in
    /// f64: points are taken relative to the origin first, so that a shape far from the
    /// world's origin, or flattened by a strong non-uniform scale, loses nothing to
    /// cancellation.
    origin: DVec3,
    linear_to_object: DMat3,
}

impl QuadricFrame {
    pub fn new(to_world: Affine3A, area: Option<f32>) -> Self {
        let corners = Self::canonical_corners().map(|c| to_world.transform_point3(c).abs());
        QuadricFrame {
            to_world,
            normal_to_world: to_world.matrix3.inverse().transpose(),
            area,
            magnitude: corners.iter().fold(0.0f32, |m, c| m.max(c.max_element())),
            origin: Vec3::from(to_world.translation).as_dvec3(),
            linear_to_object: glam::Mat3::from(to_world.matrix3).as_dmat3().inverse(),
        }
    }

    /// A point and a vector in canonical space, in f64.
    pub(super) fn to_own_space(&self, p: Vec3, v: Vec3) -> (DVec3, DVec3) {
        let m = &self.linear_to_object;
        (*m * (p.as_dvec3() - self.origin), *m * v.as_dvec3())
    }

    /// The hit `at` along `ray` on a surface of the own space whose outward direction at an
    /// own-space point, for the own ray direction, is `outward` (not normalised). Where it
    /// vanishes (a singular point) the ray's reversed direction stands in.
    pub(super) fn hit_along(
        &self,
        ray: &Ray,
        at: &super::shape::Intersection,
        outward: impl FnOnce(DVec3, DVec3) -> DVec3,
    ) -> Hit {
        let (o, d) = self.ray_to_own_space(ray);
        let own = o + f64::from(at.t) * d;
        // Normalised in f64: a steep function's gradient may not fit in f32.
        let outward = outward(own, d).try_normalize().unwrap_or(-d.normalize());
        let normal: Vec3 =
            (self.normal_to_world * Vec3A::from(outward.as_vec3())).normalize().into();
        let point = self.to_world.transform_point3a(Vec3A::from(own.as_vec3()));
        Hit {
            t: at.t,
            point: point.into(),
            normal,
            shading_normal: normal,
            error: REL_ERROR * self.magnitude,
            primitive: 0,
        }
    }

    /// The ray in canonical space, in f64, direction not normalised.
    fn ray_to_own_space(&self, ray: &Ray) -> (DVec3, DVec3) {
        self.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir))
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

/// Where a line meets a canonical quadric: the roots are solved from the line's point nearest
/// the quadric's axis (or centre), where the constant coefficient is of the quadric's own size.
/// From a far origin, |o|^2 - 1 loses that size to cancellation: a sphere scaled by 0.001 along
/// y, seen from above, rendered as a noisy banded square.
struct Roots {
    /// The line's nearest point, and its distance along the line.
    near: DVec3,
    t_near: f64,
    /// The roots from `near`, smaller first.
    from_near: (f64, f64),
}

impl Roots {
    /// The roots as distances along the whole line, in f32.
    fn along(&self) -> (f32, f32) {
        let (t0, t1) = self.from_near;
        ((self.t_near + t0) as f32, (self.t_near + t1) as f32)
    }
}

impl QuadricKind {
    /// The quadratic `a t^2 + 2 half_b t + c` (as `(a, half_b, c)`) that is 0 where `o + t d`
    /// meets the canonical quadric (the tube's whole infinite cylinder).
    fn coefficients(self, o: DVec3, d: DVec3) -> (f64, f64, f64) {
        match self {
            QuadricKind::Ellipsoid => (d.dot(d), o.dot(d), o.dot(o) - 1.0),
            QuadricKind::Tube => {
                (d.x * d.x + d.y * d.y, o.x * d.x + o.y * d.y, o.x * o.x + o.y * o.y - 1.0)
            }
        }
    }

    /// The real roots along `o + t d` (canonical space, `d` not normalised, so t is the world
    /// distance); none where `a = 0` (a line along the tube's axis).
    fn roots(self, o: DVec3, d: DVec3) -> Option<Roots> {
        let (a, half_b, _) = self.coefficients(o, d);
        if a == 0.0 {
            return None;
        }
        let t_near = -half_b / a;
        let near = o + t_near * d;
        let (a, half_b, c) = self.coefficients(near, d);
        let from_near = quadratic_roots(a, half_b, c)?;
        Some(Roots { near, t_near, from_near })
    }

    /// Distance along the ray in (0, t_max) where it meets the quadric (the tube between z = 0
    /// and 1), and the distance from the roots' nearest point.
    fn first(self, roots: &Roots, d: DVec3, t_max: f32) -> Option<(f32, f64)> {
        let (t0, t1) = roots.along();
        let accept = |&(t, from_near): &(f32, f64)| {
            let in_range = t > 0.0 && t < t_max;
            let z = roots.near.z + from_near * d.z;
            in_range && (self == QuadricKind::Ellipsoid || (0.0..=1.0).contains(&z))
        };
        [(t0, roots.from_near.0), (t1, roots.from_near.1)].into_iter().find(accept)
    }

    /// Distance along the ray in (0, t_max) where it meets the quadric.
    #[inline]
    pub(super) fn intersection(self, frame: &QuadricFrame, ray: &Ray, t_max: f32) -> Option<f32> {
        let (o, d) = frame.ray_to_own_space(ray);
        self.first(&self.roots(o, d)?, d, t_max).map(|(t, _)| t)
    }

    pub(super) fn hit(self, frame: &QuadricFrame, ray: &Ray, t: f32) -> Hit {
        let (o, d) = frame.ray_to_own_space(ray);
        // The point from the root `t` was rounded from, nearest the quadric: `o + t d` would
        // scale t's rounding by the map's strongest stretch.
        let p = match self.roots(o, d) {
            Some(roots) => {
                let (t0, t1) = roots.along();
                let (r0, r1) = roots.from_near;
                let from_near = if (t0 - t).abs() <= (t1 - t).abs() { r0 } else { r1 };
                roots.near + from_near * d
            }
            None => o + f64::from(t) * d,
        };
        let p = Vec3A::from(p.as_vec3());
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
                let (o, d) = frame.ray_to_own_space(ray);
                Crossings::between(self.roots(o, d).map(|roots| roots.along()), t_max)
            }
            QuadricKind::Tube => Crossings::outside(),
        }
    }

    /// Whether `p` is inside the ellipsoid (never inside the open tube).
    pub(super) fn contains(self, frame: &QuadricFrame, p: Vec3) -> bool {
        match self {
            QuadricKind::Ellipsoid => frame.to_own_space(p, Vec3::ZERO).0.length_squared() < 1.0,
            QuadricKind::Tube => false,
        }
    }
}
