//! POV-Ray's torus: the points at distance `minor` from the circle of radius `major` about the
//! y axis in the x-z plane, under an affine map. Its intersections are the real roots of a
//! quartic, found robustly: in the torus' own space scaled to major radius 1, from a ray
//! origin moved to the torus' bounding sphere first (so a torus far from the origin or seen
//! from far away is as precise as one nearby), by isolating each root between the roots of the
//! derivatives and refining it with safeguarded Newton steps in f64 (`polynomial`).

use std::f64::consts::PI as PI64;

use arrayvec::ArrayVec;
use glam::{Affine3A, Vec2, Vec3, Vec3A};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::{Intersection, REL_ERROR, SurfaceSample};
use super::{Aabb, Hit, Ray};

#[derive(Debug, Clone)]
pub struct Torus {
    /// Maps the torus of major radius 1 and minor radius `minor` (its own space) to the world.
    pub frame: QuadricFrame,
    /// The minor radius over the major radius.
    pub minor: f32,
    /// World area, when the map is a similarity (then uniform sampling of the torus' own
    /// space is uniform by area).
    pub area: Option<f32>,
}

impl Torus {
    /// The torus `torus { major, minor }` placed in the world by `to_world`.
    pub fn new(major: f32, minor: f32, to_world: Affine3A) -> Self {
        let frame_map = to_world * Affine3A::from_scale(Vec3::splat(major));
        let area = super::similarity_scale(&to_world)
            .map(|s| 4.0 * std::f32::consts::PI.powi(2) * major * minor * s * s);
        let mut frame = QuadricFrame::new(frame_map, area);
        let ratio = minor / major;
        let reach = 1.0 + ratio;
        frame.magnitude = Torus::local_corners(ratio, reach)
            .iter()
            .fold(0.0f32, |m, c| m.max(frame_map.transform_point3(*c).abs().max_element()));
        Torus { frame, minor: ratio, area }
    }

    fn local_corners(minor: f32, reach: f32) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { -reach } else { reach },
                if i & 2 == 0 { -minor } else { minor },
                if i & 4 == 0 { -reach } else { reach },
            )
        })
    }

    pub fn bounds(&self) -> Aabb {
        let corners = Torus::local_corners(self.minor, 1.0 + self.minor);
        Aabb::from_points(&corners.map(|c| self.frame.to_world.transform_point3(c)))
    }

    pub fn area(&self) -> Option<f32> {
        self.area
    }

    /// Every intersection of the ray's whole line with the torus, in order (world distances).
    pub fn roots(&self, ray: &Ray) -> ArrayVec<f32, 4> {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let speed = d.length();
        let mut roots = ArrayVec::new();
        if speed == 0.0 || !speed.is_finite() {
            return roots;
        }
        let d = d / speed;
        let minor = f64::from(self.minor);
        // The bounding sphere of radius 1 + minor: no root outside it. Move the origin to the
        // line's point nearest the centre, so that the quartic's coefficients are of the
        // torus' size however far away the ray starts.
        let reach = 1.0 + minor;
        let shift = -o.dot(d);
        let near = o + shift * d;
        let half_chord_squared = reach * reach - near.length_squared();
        if half_chord_squared < 0.0 {
            return roots;
        }
        let half_chord = half_chord_squared.sqrt();
        // (|p|^2 + 1 - r^2)^2 - 4 (x^2 + z^2) for p = near + s d, |d| = 1.
        let a = near.dot(d);
        let b = near.length_squared() + 1.0 - minor * minor;
        let horizontal = d.x * d.x + d.z * d.z;
        let cross = near.x * d.x + near.z * d.z;
        let quartic = [
            b * b - 4.0 * (near.x * near.x + near.z * near.z),
            4.0 * a * b - 8.0 * cross,
            4.0 * a * a + 2.0 * b - 4.0 * horizontal,
            4.0 * a,
            1.0,
        ];
        let margin = 1e-9 * reach;
        let found = polynomial_roots(&quartic, -half_chord - margin, half_chord + margin);
        // A quartic has four roots at most (rounding never makes more of them).
        roots.extend(found.into_iter().take(4).map(|s| ((shift + s) / speed) as f32));
        roots
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.roots(ray).into_iter().find(|&t| t > 0.0 && t < t_max).map(Intersection::at)
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        Crossings::from_roots(&self.roots(ray), t_max, Intersection::at)
    }

    /// The point on the torus nearest `p` (own space) and the outward normal there.
    fn project(&self, p: Vec3A) -> (Vec3A, Vec3A) {
        let ring = Vec3A::new(p.x, 0.0, p.z).normalize_or(Vec3A::X);
        let normal = (p - ring).normalize_or(ring);
        (ring + normal * self.minor, normal)
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let (point, normal) = self.project(Vec3A::from((o + f64::from(at.t) * d).as_vec3()));
        let normal: Vec3 = (self.frame.normal_to_world * normal).normalize().into();
        Hit {
            t: at.t,
            point: self.frame.to_world.transform_point3a(point).into(),
            normal,
            shading_normal: normal,
            error: REL_ERROR * self.frame.magnitude,
            primitive: 0,
        }
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        let ring = (p.x * p.x + p.z * p.z).sqrt() - 1.0;
        let minor = f64::from(self.minor);
        ring * ring + p.y * p.y < minor * minor
    }

    /// A point uniform by area: the angle about the y axis uniform, the angle about the tube
    /// with density proportional to 1 + r cos(theta), by Newton's method on its distribution.
    /// `None` unless the area is known and the torus is a ring (minor < major).
    pub fn sample(&self, u: Vec2) -> Option<SurfaceSample> {
        self.area?;
        let r = f64::from(self.minor);
        if r >= 1.0 {
            return None;
        }
        // theta + r sin(theta) = 2 pi u, increasing in theta.
        let target = 2.0 * PI64 * f64::from(u.x);
        let mut theta = target;
        for _ in 0..20 {
            let step = (theta + r * theta.sin() - target) / (1.0 + r * theta.cos());
            theta = (theta - step).clamp(0.0, 2.0 * PI64);
            if step.abs() < 1e-12 {
                break;
            }
        }
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let ring = Vec3::new(phi.cos(), 0.0, phi.sin());
        let theta = theta as f32;
        let normal = ring * theta.cos() + Vec3::Y * theta.sin();
        let frame = &self.frame;
        Some(SurfaceSample {
            point: frame.to_world.transform_point3(ring + normal * self.minor),
            normal: (frame.normal_to_world * Vec3A::from(normal)).normalize().into(),
            error: REL_ERROR * frame.magnitude,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn torus_seen_along_an_axis_and_from_far() {
        let torus = Torus::new(2.0, 0.5, Affine3A::IDENTITY);
        let ray = Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X);
        let roots = torus.roots(&ray);
        let expected = [7.5, 8.5, 11.5, 12.5];
        assert_eq!(roots.len(), 4);
        for (r, e) in roots.iter().zip(expected) {
            assert!((r - e).abs() < 1e-5, "{roots:?}");
        }
        let hit = torus.hit(&ray, &Intersection::at(roots[0]));
        assert!((hit.normal + Vec3::X).length() < 1e-5 && (hit.point.x + 2.5).abs() < 1e-5);
        // Down the hole: no hit.
        assert!(torus.roots(&Ray::new(Vec3::new(0.0, 10.0, 0.0), -Vec3::Y)).is_empty());
        // 1000 units away, moved there.
        let far = Torus::new(2.0, 0.5, Affine3A::from_translation(Vec3::splat(1000.0)));
        let ray = Ray::new(Vec3::new(990.0, 1000.0, 1000.0), Vec3::X);
        let roots = far.roots(&ray);
        assert_eq!(roots.len(), 4);
        assert!((roots[0] - 7.5).abs() < 1e-3, "{roots:?}");
        assert!(far.contains(Vec3::new(1002.0, 1000.2, 1000.0)));
        assert!(!far.contains(Vec3::new(1000.0, 1000.0, 1000.0)));
    }
}
