//! POV-Ray's isosurface: the points of a container (box or sphere) where a function is below
//! its threshold, under an affine map. Along a ray the function is stepped no further than its
//! distance from the threshold allows under the gradient bound `max_gradient` (a Lipschitz
//! bound: the level cannot be reached sooner), and each crossing so bracketed is bisected to
//! `accuracy`. Normals are the function's gradient by central differences; where the function
//! is below the threshold on the container's wall, the wall closes the solid (unless `open`).

use std::sync::Arc;

use glam::{Affine3A, DVec3, Vec3};

use super::crossings::Crossings;
use super::quadric::QuadricFrame;
use super::shape::{Intersection, REL_ERROR};
use super::{Aabb, Hit, Ray};
use crate::function::FloatFunction;

/// The most steps one ray takes through the container: the least step is at least its
/// length over this, so a tiny `accuracy` in a large container cannot hang a render.
const MAX_STEPS: f64 = 100_000.0;

/// `Intersection::part` of a hit on the container's wall.
const WALL: u32 = 1;

/// What `isosurface { }` says, in the function's own space.
#[derive(Debug, Clone, PartialEq)]
pub struct IsosurfaceDesc {
    /// Of three parameters: x, y and z.
    pub function: Arc<FloatFunction>,
    pub container: Container,
    pub threshold: f64,
    /// How near its true place a crossing is found (a distance in the function's space).
    pub accuracy: f64,
    /// A bound on the length of the function's gradient.
    pub max_gradient: f64,
    /// The container's walls are not part of the surface.
    pub open: bool,
}

/// `contained_by { box { } }` or `contained_by { sphere { } }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Container {
    Box { min: DVec3, max: DVec3 },
    Sphere { center: DVec3, radius: f64 },
}

impl Container {
    /// Where the line `o + t d` is inside, if it meets the container.
    fn span(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
        match *self {
            Container::Box { min, max } => {
                let inverse = d.recip();
                let (a, b) = ((min - o) * inverse, (max - o) * inverse);
                let near = a.min(b).max_element();
                let far = a.max(b).min_element();
                (near <= far).then_some((near, far))
            }
            Container::Sphere { center, radius } => {
                let oc = o - center;
                let a = d.length_squared();
                let b = oc.dot(d);
                // r^2 - |oc - (b/a) d|^2 times a: no cancellation for a distant origin.
                let perp = oc - d * (b / a);
                let discriminant = a * (radius * radius - perp.length_squared());
                if discriminant < 0.0 {
                    return None;
                }
                let root = discriminant.sqrt();
                Some(((-b - root) / a, (-b + root) / a))
            }
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        match *self {
            Container::Box { min, max } => p.cmpgt(min).all() && p.cmplt(max).all(),
            Container::Sphere { center, radius } => p.distance_squared(center) < radius * radius,
        }
    }

    /// The outward normal of the wall nearest `p`.
    fn normal(&self, p: DVec3) -> DVec3 {
        match *self {
            Container::Box { min, max } => {
                let distances =
                    [p.x - min.x, p.y - min.y, p.z - min.z, max.x - p.x, max.y - p.y, max.z - p.z];
                let nearest = (0..6).min_by(|&i, &j| distances[i].total_cmp(&distances[j]));
                let i = nearest.unwrap_or(0);
                let axis = [DVec3::X, DVec3::Y, DVec3::Z][i % 3];
                if i < 3 { -axis } else { axis }
            }
            Container::Sphere { center, .. } => (p - center).normalize_or(DVec3::Y),
        }
    }

    /// The corners of a box holding the container.
    fn corners(&self) -> [DVec3; 8] {
        let (min, max) = match *self {
            Container::Box { min, max } => (min, max),
            Container::Sphere { center, radius } => {
                (center - DVec3::splat(radius), center + DVec3::splat(radius))
            }
        };
        std::array::from_fn(|i| {
            DVec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
    }
}

impl IsosurfaceDesc {
    /// The function less the threshold at `p`: negative inside.
    fn level(&self, p: DVec3) -> f64 {
        self.function.eval(&[p.x, p.y, p.z]) - self.threshold
    }

    /// The largest slope of the function between neighbours of an `n`³ grid over the
    /// container: a lower bound of its gradient's length, for the warning that `max_gradient`
    /// is too small.
    pub fn largest_gradient(&self, n: usize) -> f64 {
        let corners = self.container.corners();
        let (min, max) = (corners[0], corners[7]);
        let cell = (max - min) / n as f64;
        let at =
            |i: usize, j: usize, k: usize| min + cell * DVec3::new(i as f64, j as f64, k as f64);
        let mut largest = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let p = at(i, j, k);
                    let v = self.level(p);
                    for (q, step) in [
                        (at(i + 1, j, k), cell.x),
                        (at(i, j + 1, k), cell.y),
                        (at(i, j, k + 1), cell.z),
                    ] {
                        let slope = (self.level(q) - v).abs() / step;
                        if slope.is_finite() {
                            largest = largest.max(slope);
                        }
                    }
                }
            }
        }
        largest
    }
}

/// An isosurface placed in the world.
#[derive(Debug, Clone)]
pub struct Isosurface {
    desc: Arc<IsosurfaceDesc>,
    frame: QuadricFrame,
    /// Error bound of a hit point: the crossing's accuracy in the world, and rounding.
    error: f32,
}

impl Isosurface {
    pub fn new(desc: Arc<IsosurfaceDesc>, to_world: Affine3A) -> Self {
        let frame = QuadricFrame::new(to_world, None);
        let world_corners =
            desc.container.corners().map(|c| to_world.transform_point3(c.as_vec3()));
        let magnitude = world_corners.iter().fold(0.0f32, |m, c| m.max(c.abs().max_element()));
        let stretch = [to_world.matrix3.x_axis, to_world.matrix3.y_axis, to_world.matrix3.z_axis]
            .iter()
            .fold(0.0f32, |m, axis| m.max(axis.length()));
        let error = 2.0 * desc.accuracy as f32 * stretch + REL_ERROR * magnitude;
        Isosurface { desc, frame, error }
    }

    pub fn bounds(&self) -> Aabb {
        let corners = self.desc.container.corners();
        Aabb::from_points(&corners.map(|c| self.frame.to_world.transform_point3(c.as_vec3())))
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        self.walk(ray, t_max, true).list.first().map(|c| c.at)
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        self.walk(ray, t_max, false)
    }

    /// The ray's crossings of the surface in (0, t_max), in order; only the first if `first`.
    fn walk(&self, ray: &Ray, t_max: f32, first: bool) -> Crossings {
        let desc = &*self.desc;
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let speed = d.length();
        let mut crossings = Crossings::outside();
        if speed == 0.0 || !speed.is_finite() {
            return crossings;
        }
        let Some((c0, c1)) = desc.container.span(o, d) else {
            return crossings;
        };
        crossings.inside_at_start = c0 <= 0.0 && c1 > 0.0 && desc.level(o) < 0.0;
        let (lo, hi) = (c0.max(0.0), c1.min(f64::from(t_max)));
        if lo >= hi {
            return crossings;
        }
        let at = |t: f64, part: u32| Intersection { part, ..Intersection::at(t as f32) };
        let mut t = lo;
        let mut v = desc.level(o + t * d);
        let mut inside = v < 0.0;
        if c0 > 0.0 && inside && !desc.open {
            crossings.push(at(c0, WALL), true);
            if first {
                return crossings;
            }
        }
        // |df/dt| <= max_gradient * |d| along the ray.
        let lipschitz = desc.max_gradient * speed;
        let least_step = (desc.accuracy / speed).max((c1 - c0) / MAX_STEPS);
        while t < hi {
            // `max` takes the least step where the level is NaN.
            let next = (t + (v.abs() / lipschitz).max(least_step)).min(hi);
            let w = desc.level(o + next * d);
            if (w < 0.0) != inside {
                let root = self.bisect(o, d, t, next, inside);
                inside = !inside;
                crossings.push(at(root, 0), inside);
                if first {
                    return crossings;
                }
            }
            (t, v) = (next, w);
        }
        if c1 < f64::from(t_max) && inside && !desc.open {
            crossings.push(at(c1, WALL), false);
        }
        crossings
    }

    /// The crossing between `a` (where the point is inside if `inside`) and `b` (where it is
    /// not), to within `accuracy`.
    fn bisect(&self, o: DVec3, d: DVec3, mut a: f64, mut b: f64, inside: bool) -> f64 {
        let speed = d.length();
        for _ in 0..64 {
            if (b - a) * speed <= self.desc.accuracy {
                break;
            }
            let middle = 0.5 * (a + b);
            if (self.desc.level(o + middle * d) < 0.0) == inside {
                a = middle;
            } else {
                b = middle;
            }
        }
        0.5 * (a + b)
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let p = o + f64::from(at.t) * d;
        let own_normal = if at.part == WALL {
            self.desc.container.normal(p)
        } else {
            self.gradient(p).try_normalize().unwrap_or(-d.normalize())
        };
        let normal = self.frame.normal_to_world * glam::Vec3A::from(own_normal.as_vec3());
        let normal = Vec3::from(normal.normalize());
        Hit {
            t: at.t,
            point: self.frame.to_world.transform_point3(p.as_vec3()),
            normal,
            shading_normal: normal,
            error: self.error,
            primitive: 0,
        }
    }

    /// The function's gradient at `p` by central differences a step of `accuracy` apart.
    fn gradient(&self, p: DVec3) -> DVec3 {
        let h = self.desc.accuracy.max(1e-9);
        let slope = |axis: DVec3| {
            (self.desc.level(p + axis * h) - self.desc.level(p - axis * h)) / (2.0 * h)
        };
        DVec3::new(slope(DVec3::X), slope(DVec3::Y), slope(DVec3::Z))
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.desc.container.contains(p) && self.desc.level(p) < 0.0
    }
}
