//! POV-Ray's `ovus` and `lemon`: solids of revolution about their own y axis whose profile, in
//! the (r, y) half-plane, is circular arcs, each over a band of heights, and flat end caps.
//! An arc centred on the axis turns into a sphere; one centred at r < 0 into the inner (lemon)
//! part of a spindle torus, whose quartic also holds the outer (apple) part, told apart at each
//! root by which of the two circles the point lies on (POV-Ray 3.7's ovus.cpp, 3.8's lemon.cpp).
//! Roots are found as the torus' are: in f64, from the line's point nearest the solid's centre,
//! by `polynomial_roots`.

use arrayvec::ArrayVec;
use glam::{Affine3A, DVec2, DVec3, Quat, Vec3, Vec3A};

use super::crossings::Crossings;
use super::polynomial::polynomial_roots;
use super::quadric::QuadricFrame;
use super::shape::{Intersection, REL_ERROR};
use super::{Aabb, Hit, Ray};

/// How near the axis (relative to the solid's size) an arc's centre is taken to be on it, a
/// sphere: the spindle torus' quartic has near-double roots there, which rounding loses (POV-Ray
/// 3.8's lemon also turns to a sphere within a tolerance).
const ON_AXIS: f64 = 1e-5;

/// An arc of the profile: the circle of `radius` about `center` (r, y), over heights `band`
/// (from below, up to above; infinite for a sphere's cap, which ends where the sphere does).
#[derive(Debug, Clone, Copy)]
struct Arc {
    center: DVec2,
    radius: f64,
    band: (f64, f64),
}

/// A flat end: the disc of `radius` about the axis at `height`, facing up or down.
#[derive(Debug, Clone, Copy)]
struct Cap {
    height: f64,
    radius: f64,
    up: bool,
}

#[derive(Debug, Clone)]
pub struct ArcSolid {
    /// Maps the solid's own space to the world.
    frame: QuadricFrame,
    arcs: ArrayVec<Arc, 3>,
    caps: ArrayVec<Cap, 2>,
    /// An open lemon (no caps) is a surface, not a solid.
    open: bool,
    /// Own-space bounds: the largest radius, the lowest and highest heights.
    reach: f64,
    heights: (f64, f64),
}

/// The smallest inner radius POV-Ray takes for a lemon of axis length 1 with these end radii:
/// the arc's centre is then on the axis (a sphere); a smaller radius would put it at r > 0.
pub fn lemon_min_inner_radius(base_radius: f64, cap_radius: f64) -> f64 {
    let (a, b) = (base_radius, cap_radius);
    // r^2 >= L^2 (1 + (a + b)^2) / 4, L^2 = (b - a)^2 + 1 the squared chord (lemon.cpp).
    (((b - a).powi(2) + 1.0) * ((a + b).powi(2) + 1.0)).sqrt() / 2.0
}

/// An arc centre's r (at most 0), or 0 within `ON_AXIS` of a solid of this size.
fn on_axis(r: f64, size: f64) -> f64 {
    if r > -ON_AXIS * size { 0.0 } else { r }
}

impl ArcSolid {
    /// POV-Ray 3.7's `ovus { bottom, top }` (0 < top < 2 bottom) under `to_world`: the sphere of
    /// radius `bottom` at the origin and of radius `top` at (0, bottom, 0), joined by the arc of
    /// radius 2 max(bottom, top) tangent to both inside (POV-Ray's parser).
    pub fn ovus(bottom: f64, top: f64, to_world: Affine3A) -> Self {
        let (b, t) = (bottom, top);
        let (connecting, center, low, high) = if b > t {
            let c = 2.0 * b;
            let v = 2.0 * t - b - t * t / (2.0 * b);
            let h = (b * b - v * v).max(0.0).sqrt();
            (c, DVec2::new(on_axis(-h, b), v), -v, (b - v) * t / (c - t) + b)
        } else {
            let c = 2.0 * t;
            let v = -2.0 * t + b + 1.5 * t * t / b;
            let h = (t * t - (v - b) * (v - b)).max(0.0).sqrt();
            (c, DVec2::new(on_axis(-h, t), v), -v * b / (c - b), 2.0 * b - v)
        };
        let arcs = [
            Arc { center: DVec2::ZERO, radius: b, band: (f64::NEG_INFINITY, low) },
            Arc { center, radius: connecting, band: (low, high) },
            Arc { center: DVec2::new(0.0, b), radius: t, band: (high, f64::INFINITY) },
        ];
        ArcSolid::new(arcs.into_iter().collect(), ArrayVec::new(), false, to_world)
    }

    /// POV-Ray 3.8's `lemon { base, base_radius, cap, cap_radius, inner_radius [open] }` under
    /// `to_world`: the arc of `inner_radius` from the base's rim to the cap's, centred on the
    /// axis' far side (at r <= 0), turned about the axis, closed by the two discs unless open.
    /// `inner_radius` is at least `lemon_min_inner_radius` of the radii over the axis' length.
    pub fn lemon(
        ends: [Vec3; 2],
        radii: [f64; 2],
        inner_radius: f64,
        open: bool,
        to_world: Affine3A,
    ) -> Self {
        let axis = ends[1] - ends[0];
        let length = axis.length();
        let own = Affine3A::from_scale_rotation_translation(
            Vec3::splat(length),
            Quat::from_rotation_arc(Vec3::Y, axis / length),
            ends[0],
        );
        let [a, b] = radii.map(|r| r / f64::from(length));
        let r = inner_radius / f64::from(length);
        // The circle through (a, 0) and (b, 1), its centre at the smaller r (lemon.cpp).
        let chord_squared = (b - a).powi(2) + 1.0;
        let f = (4.0 * r * r / chord_squared - 1.0).max(0.0).sqrt();
        let center = DVec2::new(on_axis((a + b - f) / 2.0, 1.0), ((b - a) * f + 1.0) / 2.0);
        let arc = Arc { center, radius: r, band: (0.0, 1.0) };
        let caps =
            [Cap { height: 0.0, radius: a, up: false }, Cap { height: 1.0, radius: b, up: true }];
        let caps = if open { ArrayVec::new() } else { caps.into_iter().collect() };
        ArcSolid::new([arc].into_iter().collect(), caps, open, to_world * own)
    }

    fn new(arcs: ArrayVec<Arc, 3>, caps: ArrayVec<Cap, 2>, open: bool, to_world: Affine3A) -> Self {
        let (mut reach, mut heights) = (0.0f64, (f64::INFINITY, f64::NEG_INFINITY));
        for arc in &arcs {
            let (c, r) = (arc.center, arc.radius);
            let (low, high) = (arc.band.0.max(c.y - r), arc.band.1.min(c.y + r));
            let nearest = c.y.clamp(low, high);
            reach = reach.max(c.x + (r * r - (nearest - c.y).powi(2)).max(0.0).sqrt());
            heights = (heights.0.min(low), heights.1.max(high));
        }
        let mut frame = QuadricFrame::new(to_world, None);
        let mut solid = ArcSolid { frame: frame.clone(), arcs, caps, open, reach, heights };
        frame.magnitude = solid
            .own_corners()
            .iter()
            .fold(0.0f32, |m, c| m.max(to_world.transform_point3(*c).abs().max_element()));
        solid.frame = frame;
        solid
    }

    fn own_corners(&self) -> [Vec3; 8] {
        let (r, (low, high)) = (self.reach as f32, self.heights);
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { -r } else { r },
                if i & 2 == 0 { low as f32 } else { high as f32 },
                if i & 4 == 0 { -r } else { r },
            )
        })
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.own_corners().map(|c| self.frame.to_world.transform_point3(c)))
    }

    /// Every crossing of the ray's whole line with the surface, in order: its world distance
    /// and its part (an arc's index, or the arcs' count plus a cap's).
    fn roots(&self, ray: &Ray) -> ArrayVec<(f32, u32), 14> {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let speed = d.length();
        let mut roots = ArrayVec::new();
        if speed == 0.0 || !speed.is_finite() {
            return roots;
        }
        let d = d / speed;
        // The bounding sphere about the middle of the heights: no root outside it. From the
        // line's point nearest its centre the coefficients are of the solid's size.
        let middle = DVec3::new(0.0, 0.5 * (self.heights.0 + self.heights.1), 0.0);
        let bound_squared = self.reach.powi(2) + (0.5 * (self.heights.1 - self.heights.0)).powi(2);
        let shift = -(o - middle).dot(d);
        let near = o + shift * d;
        let half_chord_squared = bound_squared - (near - middle).length_squared();
        if half_chord_squared < 0.0 {
            return roots;
        }
        let half_chord = half_chord_squared.sqrt();
        let mut found: ArrayVec<(f64, u32), 14> = ArrayVec::new();
        for (part, arc) in self.arcs.iter().enumerate() {
            let n = near - DVec3::new(0.0, arc.center.y, 0.0);
            let on_arc = |s: f64| {
                let q = n + s * d;
                let rho = (q.x * q.x + q.z * q.z).sqrt();
                let y = q.y + arc.center.y;
                let miss = |c: f64| ((rho - c).powi(2) + q.y * q.y - arc.radius.powi(2)).abs();
                arc.band.0 <= y && y < arc.band.1 && miss(arc.center.x) <= miss(-arc.center.x)
            };
            let r2 = arc.radius * arc.radius;
            if arc.center.x == 0.0 {
                // A sphere: r^2 - |n - (n.d) d|^2 without cancellation (as `Shape::Sphere`).
                let a = n.dot(d);
                let discriminant = r2 - (n - a * d).length_squared();
                if discriminant >= 0.0 {
                    let root = discriminant.sqrt();
                    found.extend(
                        [-a - root, -a + root]
                            .into_iter()
                            .filter(|&s| on_arc(s))
                            .map(|s| (s, part as u32)),
                    );
                }
                continue;
            }
            // (|q|^2 + c^2 - r^2)^2 - 4 c^2 (x^2 + z^2) for q = n + s d, |d| = 1: both the
            // circle about (c, y) and its mirror about (-c, y), turned about the axis.
            let c2 = arc.center.x * arc.center.x;
            let a = n.dot(d);
            let b = n.length_squared() + c2 - r2;
            let horizontal = d.x * d.x + d.z * d.z;
            let cross = n.x * d.x + n.z * d.z;
            let quartic = [
                b * b - 4.0 * c2 * (n.x * n.x + n.z * n.z),
                4.0 * a * b - 8.0 * c2 * cross,
                4.0 * a * a + 2.0 * b - 4.0 * c2 * horizontal,
                4.0 * a,
                1.0,
            ];
            let margin = 1e-9 * bound_squared.sqrt();
            let all = polynomial_roots(&quartic, -half_chord - margin, half_chord + margin);
            let ours = all.into_iter().take(4).filter(|&s| on_arc(s));
            found.extend(ours.map(|s| (s, part as u32)));
        }
        for (i, cap) in self.caps.iter().enumerate() {
            let s = (cap.height - near.y) / d.y;
            let q = near + s * d;
            if s.is_finite() && q.x * q.x + q.z * q.z <= cap.radius * cap.radius {
                found.push((s, (self.arcs.len() + i) as u32));
            }
        }
        found.sort_by(|x, y| x.0.total_cmp(&y.0));
        roots.extend(found.into_iter().map(|(s, part)| (((shift + s) / speed) as f32, part)));
        roots
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let (t, part) = self.roots(ray).into_iter().find(|&(t, _)| t > 0.0 && t < t_max)?;
        Some(Intersection { triangle: part, ..Intersection::at(t) })
    }

    /// An open lemon is no solid: no crossings.
    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        if self.open {
            return Crossings::outside();
        }
        let roots = self.roots(ray);
        let ts: ArrayVec<f32, 14> = roots.iter().map(|&(t, _)| t).collect();
        let part = |t: f32| roots.iter().find(|r| r.0 == t).map_or(0, |r| r.1);
        Crossings::from_roots(&ts, t_max, |t| Intersection {
            triangle: part(t),
            ..Intersection::at(t)
        })
    }

    /// The point of part `part` nearest `q` (own space) and the outward normal there.
    fn project(&self, part: usize, q: DVec3) -> (DVec3, DVec3) {
        let Some(arc) = self.arcs.get(part) else {
            let cap = self.caps[part - self.arcs.len()];
            let normal = if cap.up { DVec3::Y } else { DVec3::NEG_Y };
            return (DVec3::new(q.x, cap.height, q.z), normal);
        };
        let rho = (q.x * q.x + q.z * q.z).sqrt();
        // Along the profile's radius from the arc's centre, turned back about the axis.
        let out = DVec2::new(rho - arc.center.x, q.y - arc.center.y).normalize_or(DVec2::Y);
        let on = arc.center + arc.radius * out;
        let around = if rho > 0.0 { DVec2::new(q.x, q.z) / rho } else { DVec2::X };
        let point = DVec3::new(around.x * on.x, on.y, around.y * on.x);
        (point, DVec3::new(around.x * out.x, out.y, around.y * out.x))
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let (point, normal) = self.project(at.triangle as usize, o + f64::from(at.t) * d);
        let normal: Vec3 =
            (self.frame.normal_to_world * Vec3A::from(normal.as_vec3())).normalize().into();
        Hit {
            t: at.t,
            point: self.frame.to_world.transform_point3(point.as_vec3()),
            normal,
            shading_normal: normal,
            error: REL_ERROR * self.frame.magnitude,
            primitive: 0,
        }
    }

    /// Inside the profile at the point's height (never inside an open lemon).
    pub fn contains(&self, p: Vec3) -> bool {
        if self.open {
            return false;
        }
        let (q, _) = self.frame.to_own_space(p, Vec3::ZERO);
        let rho = (q.x * q.x + q.z * q.z).sqrt();
        self.arcs.iter().any(|arc| {
            arc.band.0 <= q.y
                && q.y <= arc.band.1
                && (rho - arc.center.x).powi(2) + (q.y - arc.center.y).powi(2) < arc.radius.powi(2)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ovus_is_its_two_spheres_joined_smoothly() {
        let ovus = ArcSolid::ovus(1.0, 0.65, Affine3A::IDENTITY);
        // Up the axis: the bottom sphere's pole, then the top sphere's.
        let up = Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y);
        let roots = ovus.roots(&up);
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!((roots[0].0 - 4.0).abs() < 1e-5 && (roots[1].0 - 6.65).abs() < 1e-5, "{roots:?}");
        // Across at the height of the joining arc's middle: its widest, inside the arc.
        let arc = ovus.arcs[1];
        let widest = arc.center.x + arc.radius;
        let across = Ray::new(Vec3::new(-5.0, arc.center.y as f32, 0.0), Vec3::X);
        let hit = ovus.intersect_for_test(&across);
        assert!((hit.point.x + widest as f32).abs() < 1e-5, "{hit:?} {widest}");
        assert!((hit.normal + Vec3::X).length() < 1e-5);
        assert!(widest > 1.0, "wider than the bottom sphere");
        // The profile is smooth where the arcs meet: both tangent points are on both circles.
        for (sphere, y) in [(ovus.arcs[0], arc.band.0), (ovus.arcs[2], arc.band.1)] {
            let r = (sphere.radius.powi(2) - (y - sphere.center.y).powi(2)).sqrt();
            let on_arc = (r - arc.center.x).powi(2) + (y - arc.center.y).powi(2);
            assert!((on_arc - arc.radius.powi(2)).abs() < 1e-9, "{y} {r}");
        }
        assert!(
            ovus.contains(Vec3::new(0.0, 1.5, 0.0)) && !ovus.contains(Vec3::new(0.0, 1.7, 0.0))
        );
    }

    #[test]
    fn a_lemon_runs_between_its_end_discs() {
        let lemon = ArcSolid::lemon(
            [Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0)],
            [0.5, 0.3],
            1.5,
            false,
            Affine3A::IDENTITY,
        );
        let arc = lemon.arcs[0];
        // Through the base's and the cap's rims (own space: heights 0 and 1, radii over 2).
        for (y, r) in [(0.0, 0.25), (1.0, 0.15)] {
            let on = (r - arc.center.x).powi(2) + (y - arc.center.y).powi(2);
            assert!((on - arc.radius.powi(2)).abs() < 1e-9);
        }
        assert!(arc.center.x <= 0.0);
        let up = Ray::new(Vec3::new(0.1, -1.0, 0.0), Vec3::Y);
        let roots = lemon.roots(&up);
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!((roots[0].0 - 1.0).abs() < 1e-5 && (roots[1].0 - 3.0).abs() < 1e-5, "{roots:?}");
        assert!(
            lemon.contains(Vec3::new(0.0, 1.0, 0.4)) && !lemon.contains(Vec3::new(0.0, 2.1, 0.0))
        );
        assert!((lemon_min_inner_radius(0.0, 0.0) - 0.5).abs() < 1e-12, "the sphere on the axis");
    }

    impl ArcSolid {
        fn intersect_for_test(&self, ray: &Ray) -> Hit {
            self.hit(ray, &self.intersection(ray, f32::INFINITY).expect("a hit"))
        }
    }
}
