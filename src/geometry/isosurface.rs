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

/// The most steps one ray takes through the container: the least step is at least its
/// length over this, so a tiny `accuracy` in a large container cannot hang a render.
const MAX_STEPS: f64 = 100_000.0;

/// `Intersection::triangle` of a hit on the container's wall (as a cone's parts).
const WALL: u32 = 1;

/// A function of a point of an isosurface's own space. The language's compiled functions
/// (`function::FloatFunction`) are one; geometry sits below the layers that compile them.
pub trait ScalarField: std::fmt::Debug + Send + Sync + std::panic::RefUnwindSafe {
    fn value(&self, p: DVec3) -> f64;
}

/// What `isosurface { }` says, in the function's own space.
#[derive(Debug, Clone)]
pub struct IsosurfaceDesc {
    pub function: Arc<dyn ScalarField>,
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
    pub(super) fn span(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
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
    pub(super) fn corners(&self) -> [DVec3; 8] {
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

/// Equal descriptions share their function (a function is compared by what it is, not by
/// what it computes).
impl PartialEq for IsosurfaceDesc {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.function, &other.function)
            && self.container == other.container
            && self.threshold == other.threshold
            && self.accuracy == other.accuracy
            && self.max_gradient == other.max_gradient
            && self.open == other.open
    }
}

impl IsosurfaceDesc {
    /// The function less the threshold at `p`: negative inside.
    fn level(&self, p: DVec3) -> f64 {
        self.function.value(p) - self.threshold
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
        let at = |t: f64, part: u32| Intersection { triangle: part, ..Intersection::at(t as f32) };
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
        let hit = self.frame.hit_along(ray, at, |p, _| {
            if at.triangle == WALL { self.desc.container.normal(p) } else { self.gradient(p) }
        });
        Hit { error: self.error, ..hit }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::function::{Binary, Builder, FloatFunction, Op, Unary};
    use crate::geometry::{Csg, CsgNode, CsgOp, Shape};

    fn program(parameters: usize, ops: Vec<Op>) -> Arc<FloatFunction> {
        let mut builder = Builder::new(parameters);
        ops.into_iter().for_each(|op| builder.push(op).unwrap());
        Arc::new(builder.finish())
    }

    fn squared_length() -> Vec<Op> {
        let mut ops = Vec::new();
        for i in 0..3 {
            ops.extend([Op::Parameter(i), Op::Unary(Unary::Sqr)]);
            if i > 0 {
                ops.push(Op::Binary(Binary::Add));
            }
        }
        ops
    }

    /// The unit sphere's signed distance, sqrt(x² + y² + z²) - 1 (gradient length 1).
    fn unit_sphere() -> Arc<FloatFunction> {
        let mut ops = squared_length();
        ops.extend([Op::Unary(Unary::Sqrt), Op::Number(1.0), Op::Binary(Binary::Subtract)]);
        program(3, ops)
    }

    /// x² + y² + z² - 1 + 0.3 sin(4x) sin(3y): a wavy ball. In the box |p| ≤ 1.5 its gradient
    /// is at most 2 |p| + 0.3 (4 + 3) < 7.3.
    fn wavy_ball() -> Arc<FloatFunction> {
        let mut ops = squared_length();
        ops.extend([Op::Number(1.0), Op::Binary(Binary::Subtract), Op::Number(0.3)]);
        for (axis, frequency) in [(0, 4.0), (1, 3.0)] {
            ops.extend([
                Op::Number(frequency),
                Op::Parameter(axis),
                Op::Binary(Binary::Multiply),
                Op::Unary(Unary::Sin),
                Op::Binary(Binary::Multiply),
            ]);
        }
        ops.push(Op::Binary(Binary::Add));
        program(3, ops)
    }

    fn isosurface(
        function: Arc<FloatFunction>,
        max_gradient: f64,
        to_world: Affine3A,
    ) -> Isosurface {
        let desc = IsosurfaceDesc {
            function,
            container: Container::Box { min: DVec3::splat(-1.5), max: DVec3::splat(1.5) },
            threshold: 0.0,
            accuracy: 1e-4,
            max_gradient,
            open: false,
        };
        Isosurface::new(Arc::new(desc), to_world)
    }

    /// Reproducible numbers in [0, 1).
    fn numbers(seed: u64) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Rays from around `center` at distance `reach` towards points near it, some grazing a
    /// sphere of `radius` about it.
    fn rays(center: Vec3, radius: f32, reach: f32, count: usize) -> Vec<Ray> {
        let mut u = numbers(7);
        let mut direction =
            || Vec3::new(2.0 * u() - 1.0, 2.0 * u() - 1.0, 2.0 * u() - 1.0).normalize_or(Vec3::X);
        (0..count)
            .map(|i| {
                let origin = center + reach * direction();
                let towards = center - origin;
                let aside = towards.cross(direction()).normalize_or(Vec3::Y);
                // Every fourth ray aims at the sphere's rim: grazing within 0.1 % either side.
                let offset = if i % 4 == 0 {
                    radius * (1.0 + 0.002 * (i % 8) as f32 / 4.0 - 0.001)
                } else {
                    1.2 * radius * (i % 11) as f32 / 10.0
                };
                Ray::new(origin, (towards + aside * offset).normalize())
            })
            .collect()
    }

    #[test]
    fn a_sphere_function_renders_the_analytic_sphere_under_a_similarity() {
        let to_world = Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0))
            * Affine3A::from_rotation_z(0.4)
            * Affine3A::from_scale(Vec3::splat(2.0));
        let surface = isosurface(unit_sphere(), 1.0, to_world);
        let sphere = Shape::Sphere { center: Vec3::new(1.0, 2.0, 3.0), radius: 2.0 };
        let mut hits = 0;
        for ray in rays(Vec3::new(1.0, 2.0, 3.0), 2.0, 8.0, 400) {
            let expected = sphere.intersect(&ray, f32::INFINITY);
            let found = surface.intersection(&ray, f32::INFINITY).map(|at| surface.hit(&ray, &at));
            match (expected, found) {
                (Some(e), Some(f)) => {
                    hits += 1;
                    assert!((e.t - f.t).abs() <= f.error + 1e-5, "{ray:?}: {} {}", e.t, f.t);
                    // Grazing hits are where the normal's error grows (the root moves along the
                    // ray by accuracy / cos): loose there, tight elsewhere.
                    let grazing = e.normal.dot(Vec3::from(ray.dir)).abs() < 0.1;
                    let tolerance = if grazing { 0.05 } else { 1e-3 };
                    assert!((e.normal - f.normal).length() < tolerance, "{ray:?}");
                }
                (None, None) => {}
                // A ray within the accuracy of grazing may go either way.
                (e, f) => {
                    let hit = e.or(f).unwrap();
                    assert!(hit.normal.dot(Vec3::from(ray.dir)).abs() < 0.05, "{ray:?}");
                }
            }
        }
        assert!(hits > 200, "{hits}");
    }

    /// The first t in (0, t_far) where `contains` changes along the ray, by steps of `h`.
    fn marched(contains: impl Fn(Vec3) -> bool, ray: &Ray, t_far: f32, h: f32) -> Option<f32> {
        let start = contains(ray.at(0.0));
        (1..(t_far / h) as usize).map(|i| i as f32 * h).find(|&t| contains(ray.at(t)) != start)
    }

    /// Under a map that stretches, rotates and mirrors: the first hit is where a fine march
    /// first changes side, and the crossings alternate as `contains` says between them.
    fn agrees_with_a_march(shape: &Shape, center: Vec3, reach: f32) {
        let h = 2e-3;
        let mut hits = 0;
        for ray in rays(center, 1.5, reach, 160) {
            let found = shape.intersection(&ray, f32::INFINITY).map(|at| at.t);
            hits += usize::from(found.is_some());
            let march = marched(|p| shape.contains(p), &ray, 2.0 * reach, h);
            match (found, march) {
                (Some(t), Some(m)) => {
                    assert!(t <= m + 1e-3 && t > m - h - 1e-3, "{ray:?}: {t} {m}")
                }
                (None, None) => {}
                // Only a sliver thinner than the march's step, or than accuracy, may differ.
                (Some(t), None) => {
                    let near = marched(
                        |p| shape.contains(p),
                        &Ray::new(ray.at(t - h), Vec3::from(ray.dir)),
                        2.0 * h,
                        h / 50.0,
                    );
                    assert!(near.is_some(), "{ray:?}: a hit at {t} where nothing changes");
                }
                (None, Some(m)) => {
                    let back = marched(
                        |p| shape.contains(p),
                        &Ray::new(ray.at(m), Vec3::from(ray.dir)),
                        4.0 * h,
                        h / 50.0,
                    );
                    assert!(
                        back.is_some(),
                        "{ray:?}: the march enters at {m}, the surface is missed"
                    );
                }
            }
            let crossings = shape.crossings(&ray, 2.0 * reach);
            let mut inside = crossings.inside_at_start;
            let mut before = 0.0;
            for c in crossings.list.iter().chain([&crate::geometry::Crossing {
                at: Intersection::at(2.0 * reach),
                entering: !inside,
                entering_operand: false,
            }]) {
                if c.at.t - before > 2e-3 {
                    let middle = ray.at(0.5 * (before + c.at.t));
                    assert_eq!(
                        shape.contains(middle),
                        inside,
                        "{ray:?} between {before} and {}",
                        c.at.t
                    );
                }
                inside = c.entering;
                before = c.at.t;
            }
        }
        assert!(hits > 60, "{hits} of 160 rays hit");
    }

    #[test]
    fn a_wavy_isosurface_agrees_with_a_fine_march_under_a_stretching_mirror() {
        let to_world = Affine3A::from_translation(Vec3::new(0.5, -1.0, 2.0))
            * Affine3A::from_rotation_y(0.7)
            * Affine3A::from_scale(Vec3::new(-1.0, 2.0, 0.5));
        let surface = Shape::Isosurface(Box::new(isosurface(wavy_ball(), 7.3, to_world)));
        agrees_with_a_march(&surface, Vec3::new(0.5, -1.0, 2.0), 6.0);
    }

    #[test]
    fn an_isosurface_minus_a_sphere_agrees_with_a_fine_march() {
        let surface = Shape::Isosurface(Box::new(isosurface(wavy_ball(), 7.3, Affine3A::IDENTITY)));
        let bite = Shape::Sphere { center: Vec3::new(0.6, 0.3, 0.0), radius: 0.7 };
        let root = CsgNode::Operation {
            op: CsgOp::Difference,
            children: vec![CsgNode::Operand(0), CsgNode::Operand(1)],
        };
        let csg = Shape::Csg(Box::new(Csg::new(root, vec![surface, bite])));
        agrees_with_a_march(&csg, Vec3::ZERO, 5.0);
    }

    #[test]
    fn the_wall_closes_the_solid_where_the_function_is_inside() {
        // The unit sphere's function in a box of half size 0.5: the box itself.
        let mut desc = IsosurfaceDesc {
            function: unit_sphere(),
            container: Container::Box { min: DVec3::splat(-0.5), max: DVec3::splat(0.5) },
            threshold: 0.0,
            accuracy: 1e-4,
            max_gradient: 1.0,
            open: false,
        };
        let ray = Ray::new(Vec3::new(-3.0, 0.1, 0.2), Vec3::X);
        let closed = Isosurface::new(Arc::new(desc.clone()), Affine3A::IDENTITY);
        let at = closed.intersection(&ray, f32::INFINITY).unwrap();
        let hit = closed.hit(&ray, &at);
        assert!((hit.t - 2.5).abs() < 1e-5 && hit.normal == -Vec3::X, "{hit:?}");
        desc.open = true;
        let open = Isosurface::new(Arc::new(desc), Affine3A::IDENTITY);
        assert!(
            open.intersection(&ray, f32::INFINITY).is_none(),
            "an open container shows nothing"
        );
    }

    #[test]
    fn the_largest_gradient_is_seen_on_the_grid() {
        let surface = isosurface(wavy_ball(), 7.3, Affine3A::IDENTITY);
        let found = surface.desc.largest_gradient(16);
        assert!(found > 3.0 && found < 7.3, "{found}");
    }
}
