//! POV-Ray's parametric surface: the points (x(u, v), y(u, v), z(u, v)) for (u, v) in a
//! rectangle, inside a container, under an affine map; an open surface (no inside). A ray is met
//! as POV-Ray 3.7 meets it (parametric.cpp): the rectangle is cut in halves across its longer
//! side, and a piece is kept only while the ray passes through the box that bounds its points,
//! each coordinate bounded from its values at the piece's corners and `max_gradient` (POV-Ray's
//! `Interval`: along an edge of length l whose ends differ by |a - b| a function whose slope is
//! at most g stays within (g l - |a - b|) / 2 of them); a piece smaller than `accuracy` (in
//! (u, v) or along the ray) is a hit where the ray enters its box. The nearest is kept. The
//! normal is POV-Ray's: the cross product of the steps `accuracy` along u and along v.

use std::sync::Arc;

use glam::{Affine3A, DVec2, DVec3, Vec3};

use super::isosurface::{Container, ScalarField};
use super::quadric::QuadricFrame;
use super::shape::{Intersection, REL_ERROR};
use super::{Aabb, Hit, Ray};

/// The most pieces one ray examines: a surface too steep for its `max_gradient` or a tiny
/// `accuracy` cannot hang a render (the nearest hit found by then is kept).
const MAX_PIECES: usize = 1 << 18;

/// What `parametric { }` says, in the surface's own space. Each function is evaluated at
/// (u, v, 0).
#[derive(Debug, Clone)]
pub struct ParametricDesc {
    pub functions: [Arc<dyn ScalarField>; 3],
    /// The (u, v) rectangle's corners, the first the lower in both.
    pub uv: [DVec2; 2],
    pub container: Container,
    pub max_gradient: f64,
    pub accuracy: f64,
}

/// Equal descriptions share their functions (compared by what they are).
impl PartialEq for ParametricDesc {
    fn eq(&self, other: &Self) -> bool {
        self.functions.iter().zip(&other.functions).all(|(a, b)| Arc::ptr_eq(a, b))
            && self.uv == other.uv
            && self.container == other.container
            && self.max_gradient == other.max_gradient
            && self.accuracy == other.accuracy
    }
}

impl ParametricDesc {
    /// The surface's point at (u, v).
    pub fn point(&self, uv: DVec2) -> DVec3 {
        let p = DVec3::new(uv.x, uv.y, 0.0);
        DVec3::new(
            self.functions[0].value(p),
            self.functions[1].value(p),
            self.functions[2].value(p),
        )
    }

    /// The largest slope of a coordinate between neighbours of an n × n grid over the (u, v)
    /// rectangle: a lower bound of the functions' gradients, for the warning that
    /// `max_gradient` is too small.
    pub fn largest_gradient(&self, n: usize) -> f64 {
        let [low, high] = self.uv;
        let step = (high - low) / (n as f64 - 1.0);
        let at = |i: usize, j: usize| self.point(low + step * DVec2::new(i as f64, j as f64));
        let mut largest = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let here = at(i, j);
                if i + 1 < n && step.x > 0.0 {
                    largest = largest.max(((at(i + 1, j) - here) / step.x).abs().max_element());
                }
                if j + 1 < n && step.y > 0.0 {
                    largest = largest.max(((at(i, j + 1) - here) / step.y).abs().max_element());
                }
            }
        }
        largest
    }

    /// Bounds of each coordinate over the piece [low, high] (POV-Ray's
    /// `Evaluate_Function_Interval_UV`).
    fn piece_bounds(&self, low: DVec2, high: DVec2) -> (DVec3, DVec3) {
        let g = self.max_gradient;
        // Within an edge of length l from a to b (POV-Ray's `Interval`).
        let interval = |l: f64, a: f64, b: f64| {
            let reach = ((g * l - (a - b).abs()) / 2.0).max(0.0);
            (a.min(b) - reach, a.max(b) + reach)
        };
        let corners = [
            self.point(low),
            self.point(DVec2::new(low.x, high.y)),
            self.point(DVec2::new(high.x, low.y)),
            self.point(high),
        ];
        let (du, dv) = (high.x - low.x, high.y - low.y);
        let mut min = DVec3::ZERO;
        let mut max = DVec3::ZERO;
        for axis in 0..3 {
            let [f00, f01, f10, f11] = corners.map(|c| c[axis]);
            let (left_min, left_max) = interval(dv, f00, f01);
            let (right_min, right_max) = interval(dv, f10, f11);
            min[axis] = interval(du, left_min, right_min).0;
            max[axis] = interval(du, left_max, right_max).1;
        }
        (min, max)
    }
}

/// A parametric surface placed in the world.
#[derive(Debug, Clone)]
pub struct Parametric {
    desc: Arc<ParametricDesc>,
    frame: QuadricFrame,
    /// Error bound of a hit point: a piece's size in the world, and rounding.
    error: f32,
}

impl Parametric {
    pub fn new(desc: Arc<ParametricDesc>, to_world: Affine3A) -> Self {
        let frame = QuadricFrame::new(to_world, None);
        let bounds = desc.container.corners();
        let magnitude = bounds
            .iter()
            .fold(0.0f32, |m, c| m.max(to_world.transform_point3(c.as_vec3()).abs().max_element()));
        let stretch = [to_world.matrix3.x_axis, to_world.matrix3.y_axis, to_world.matrix3.z_axis]
            .iter()
            .fold(0.0f32, |m, axis| m.max(axis.length()));
        let error = 4.0 * desc.accuracy as f32 * stretch + REL_ERROR * magnitude;
        Parametric { desc, frame, error }
    }

    pub fn bounds(&self) -> Aabb {
        let corners = self.desc.container.corners();
        Aabb::from_points(&corners.map(|c| self.frame.to_world.transform_point3(c.as_vec3())))
    }

    /// The nearest hit in (0, t_max) and its (u, v).
    fn nearest(&self, ray: &Ray, t_max: f32) -> Option<(f64, DVec2)> {
        let desc = &*self.desc;
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let speed = d.length();
        if speed == 0.0 || !speed.is_finite() {
            return None;
        }
        let (c0, c1) = desc.container.span(o, d)?;
        // As POV-Ray, nothing nearer than 4 accuracy (in own space) to the ray's origin: a
        // piece's box reaches that far off the surface, and a ray leaving it must not meet it.
        let near = c0.max(0.0) + 4.0 * desc.accuracy / speed;
        let mut far = c1.min(f64::from(t_max));
        if near >= far {
            return None;
        }
        let inverse = d.recip();
        // Where the ray is in the box [min, max]: the slabs' overlap.
        let through = |min: DVec3, max: DVec3| -> Option<(f64, f64, f64)> {
            let (a, b) = ((min - o) * inverse, (max - o) * inverse);
            let (enter, exit) = (a.min(b), a.max(b));
            // An axis the ray runs along (the slab's bounds NaN or infinite): inside or not.
            let mut t0 = f64::NEG_INFINITY;
            let mut t1 = f64::INFINITY;
            let mut longest = 0.0f64;
            for axis in 0..3 {
                if d[axis].abs() < 1e-12 * speed {
                    if o[axis] < min[axis] || o[axis] > max[axis] {
                        return None;
                    }
                    continue;
                }
                t0 = t0.max(enter[axis]);
                t1 = t1.min(exit[axis]);
                longest = longest.max((exit[axis] - enter[axis]) * speed);
            }
            (t0 <= t1).then_some((t0, t1, longest))
        };
        let [low, high] = desc.uv;
        let mut stack = vec![(low, high)];
        let mut best = None;
        let mut pieces = 0;
        while let Some((low, high)) = stack.pop() {
            pieces += 1;
            if pieces > MAX_PIECES {
                break;
            }
            let (min, max) = desc.piece_bounds(low, high);
            let Some((t0, t1, longest)) = through(min, max) else {
                continue;
            };
            if t1 < near || t0 > far {
                continue;
            }
            let size = high - low;
            if size.max_element().min(longest) < desc.accuracy {
                // POV-Ray takes the hit where the ray enters the piece's box.
                let t = t0.max(near);
                if t < far {
                    far = t;
                    best = Some((t, low));
                }
                continue;
            }
            let (a, b) = if size.x >= size.y {
                let middle = 0.5 * (low.x + high.x);
                ((low, DVec2::new(middle, high.y)), (DVec2::new(middle, low.y), high))
            } else {
                let middle = 0.5 * (low.y + high.y);
                ((low, DVec2::new(high.x, middle)), (DVec2::new(low.x, middle), high))
            };
            // The second half is popped first: both are examined, the nearest hit kept.
            stack.push(b);
            stack.push(a);
        }
        best
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let (t, uv) = self.nearest(ray, t_max)?;
        let t = t as f32;
        // The (u, v) of the hit rides in the coordinates a planar shape keeps there.
        (t > 0.0 && t < t_max).then(|| Intersection { st: uv.as_vec2(), ..Intersection::at(t) })
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let desc = &*self.desc;
        let uv = at.st.as_dvec2();
        let h = desc.accuracy;
        let here = desc.point(uv);
        let along_u = desc.point(uv + DVec2::new(h, 0.0)) - here;
        let along_v = desc.point(uv + DVec2::new(0.0, h)) - here;
        let hit = self.frame.hit_along(ray, at, |_, _| along_u.cross(along_v));
        Hit { error: self.error, ..hit }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, TAU};

    /// A function of (u, v) written in Rust.
    #[derive(Debug)]
    struct Of(fn(f64, f64) -> f64);

    impl ScalarField for Of {
        fn value(&self, p: DVec3) -> f64 {
            (self.0)(p.x, p.y)
        }
    }

    fn sphere(accuracy: f64) -> Parametric {
        // Longitude u, latitude v: the unit sphere.
        let functions: [Arc<dyn ScalarField>; 3] = [
            Arc::new(Of(|u, v| u.cos() * v.cos())),
            Arc::new(Of(|_, v| v.sin())),
            Arc::new(Of(|u, v| u.sin() * v.cos())),
        ];
        let desc = ParametricDesc {
            functions,
            uv: [DVec2::new(0.0, -FRAC_PI_2), DVec2::new(TAU, FRAC_PI_2)],
            container: Container::Box { min: DVec3::splat(-1.1), max: DVec3::splat(1.1) },
            max_gradient: 1.0,
            accuracy,
        };
        Parametric::new(Arc::new(desc), Affine3A::IDENTITY)
    }

    #[test]
    fn a_parametric_sphere_is_met_where_the_sphere_is() {
        let sphere = sphere(0.001);
        let ray = Ray::new(Vec3::new(0.3, 0.2, -3.0), Vec3::Z);
        let at = sphere.intersection(&ray, f32::INFINITY).expect("a hit");
        let expected = 3.0 - (1.0f32 - 0.13).sqrt();
        assert!((at.t - expected).abs() < 0.005, "{} {expected}", at.t);
        let hit = sphere.hit(&ray, &at);
        let outward = hit.point.normalize();
        assert!(hit.normal.dot(outward).abs() > 0.99, "{hit:?}");
        assert!(sphere.intersection(&Ray::new(Vec3::new(1.2, 0.0, -3.0), Vec3::Z), 9.0).is_none());
        assert!(sphere.intersection(&ray, expected - 0.1).is_none(), "t_max respected");
        assert!(sphere.desc.largest_gradient(16) <= 1.0 + 1e-9);
    }
}
