//! POV-Ray's julia_fractal: the points of a 3-D slice of 4-D space whose orbit under
//! h <- f(h) + c stays within POV-Ray's escape radius for `max_iteration` steps (f squares or
//! cubes, in the quaternions or the hypercomplex numbers), under an affine map. Along a ray
//! the solid is sampled every 1 / precision (POV-Ray's step) within the sphere of that radius,
//! and each change between outside and inside is bisected; the normal is the gradient of
//! |h|^2 at the step where the orbit leaves the sphere, carried through the iteration exactly.

use glam::{Affine3A, DVec3, DVec4, Vec3};

use super::crossings::Crossings;
use super::quadric::QuadricFrame;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};

/// The most steps of an orbit, and the finest step along a ray (1 / precision).
pub const MAX_JULIA_ITERATIONS: u32 = 1000;
pub const MAX_JULIA_PRECISION: f64 = 10_000.0;

/// The 4-D algebra the orbit is computed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algebra {
    /// ij = k, ji = -k, ii = jj = kk = -1.
    Quaternion,
    /// Commutative: ij = ji = k, ii = jj = -1, kk = 1.
    Hypercomplex,
}

/// The function f of h <- f(h) + c.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JuliaFunction {
    Square,
    Cube,
}

/// `julia_fractal { c  algebra  function  max_iteration n  precision p  slice <n>, d }`.
#[derive(Debug, Clone, PartialEq)]
pub struct JuliaDesc {
    pub parameter: DVec4,
    pub algebra: Algebra,
    pub function: JuliaFunction,
    /// From 1 to `MAX_JULIA_ITERATIONS`.
    pub max_iteration: u32,
    /// From 1 to `MAX_JULIA_PRECISION`.
    pub precision: f64,
    /// The slice's normal (its w not 0) and its distance from the origin: a point (x, y, z) is
    /// the 4-D point whose w puts it in the slice.
    pub slice: (DVec4, f64),
}

#[derive(Debug, Clone)]
pub struct Julia {
    /// The own space is the fractal's scaled by 1 / `radius`: the escape sphere is the unit
    /// sphere.
    frame: QuadricFrame,
    desc: JuliaDesc,
    /// POV-Ray's escape radius: 1 + |c| up to 2 in the quaternions, 4 in the hypercomplex
    /// numbers. An orbit is out once |h| exceeds it.
    radius: f64,
    /// w = w_at_origin + w_slope . (x, y, z) in the slice.
    w_at_origin: f64,
    w_slope: DVec3,
}

impl Algebra {
    fn multiply(self, a: DVec4, b: DVec4) -> DVec4 {
        match self {
            Algebra::Quaternion => DVec4::new(
                a.x * b.x - a.y * b.y - a.z * b.z - a.w * b.w,
                a.x * b.y + a.y * b.x + a.z * b.w - a.w * b.z,
                a.x * b.z - a.y * b.w + a.z * b.x + a.w * b.y,
                a.x * b.w + a.y * b.z - a.z * b.y + a.w * b.x,
            ),
            Algebra::Hypercomplex => DVec4::new(
                a.x * b.x - a.y * b.y - a.z * b.z + a.w * b.w,
                a.x * b.y + a.y * b.x - a.z * b.w - a.w * b.z,
                a.x * b.z - a.y * b.w + a.z * b.x - a.w * b.y,
                a.x * b.w + a.y * b.z + a.z * b.y + a.w * b.x,
            ),
        }
    }
}

impl Julia {
    pub fn new(desc: JuliaDesc, to_world: Affine3A) -> Self {
        let (normal, distance) = (desc.slice.0.normalize(), desc.slice.1);
        let radius = match desc.algebra {
            Algebra::Quaternion => (1.0 + desc.parameter.length()).min(2.0),
            Algebra::Hypercomplex => 4.0,
        };
        let scale = Affine3A::from_scale(Vec3::splat(radius as f32));
        Julia {
            frame: QuadricFrame::new(to_world * scale, None),
            radius,
            w_at_origin: distance / normal.w,
            w_slope: -normal.truncate() / normal.w,
            desc,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.frame.bounds()
    }

    /// The 4-D point of the slice at the own space's point `own`.
    fn slice_point(&self, own: DVec3) -> DVec4 {
        let p = self.radius * own;
        p.extend(self.w_at_origin + self.w_slope.dot(p))
    }

    fn step(&self, h: DVec4) -> DVec4 {
        let a = self.desc.algebra;
        let f = match self.desc.function {
            JuliaFunction::Square => a.multiply(h, h),
            JuliaFunction::Cube => a.multiply(a.multiply(h, h), h),
        };
        f + self.desc.parameter
    }

    /// |h|^2 past which an orbit is out.
    fn exit_value(&self) -> f64 {
        self.radius * self.radius
    }

    /// Whether the orbit from the own space's point `own` stays within the sphere.
    fn inside(&self, own: DVec3) -> bool {
        let mut h = self.slice_point(own);
        if h.length_squared() > self.exit_value() {
            return false;
        }
        for _ in 0..self.desc.max_iteration {
            h = self.step(h);
            if h.length_squared() > self.exit_value() {
                return false;
            }
        }
        true
    }

    /// The direction out of the solid at a point of its surface: the gradient of |h_k|^2 at
    /// the step k whose |h_k|^2 is nearest the escape value, with the derivatives of the orbit
    /// along x, y and z carried through each step (the product rule, in either algebra).
    fn outward(&self, own: DVec3) -> DVec3 {
        let a = self.desc.algebra;
        let mut h = self.slice_point(own);
        let mut tangents = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| e.extend(self.w_slope.dot(e)));
        let gradient = |h: DVec4, tangents: &[DVec4; 3]| {
            DVec3::new(h.dot(tangents[0]), h.dot(tangents[1]), h.dot(tangents[2]))
        };
        let exit = self.exit_value();
        let mut best = ((h.length_squared() - exit).abs(), gradient(h, &tangents));
        for _ in 0..self.desc.max_iteration {
            if h.length_squared() > exit {
                break;
            }
            tangents = tangents.map(|v| match self.desc.function {
                JuliaFunction::Square => a.multiply(h, v) + a.multiply(v, h),
                JuliaFunction::Cube => {
                    let hh = a.multiply(h, h);
                    a.multiply(hh, v) + a.multiply(a.multiply(h, v), h) + a.multiply(v, hh)
                }
            });
            h = self.step(h);
            let miss = (h.length_squared() - exit).abs();
            if miss < best.0 {
                best = (miss, gradient(h, &tangents));
            }
        }
        best.1
    }

    /// Every change between outside and inside along the ray at distances in (0, t_max), in
    /// order (own space and world distances agree: the direction is mapped, not normalised).
    fn roots(&self, ray: &Ray, t_max: f32) -> Vec<f32> {
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let mut roots = Vec::new();
        // The stretch within the unit sphere.
        let (a, half_b, c) = (d.length_squared(), o.dot(d), o.length_squared() - 1.0);
        let discriminant = half_b * half_b - a * c;
        if discriminant <= 0.0 {
            return roots;
        }
        let root = discriminant.sqrt();
        let near = ((-half_b - root) / a).max(0.0);
        let far = ((-half_b + root) / a).min(f64::from(t_max));
        if near >= far {
            return roots;
        }
        // 1 / precision in the fractal's space.
        let step = 1.0 / (self.desc.precision * self.radius * d.length());
        let count = ((far - near) / step).ceil().max(1.0) as usize;
        let inside = |t: f64| self.inside(o + t * d);
        let (mut previous, mut was_inside) = (near, inside(near));
        if was_inside && near > 0.0 {
            roots.push(near as f32);
        }
        for k in 1..=count {
            let t = if k == count { far } else { near + k as f64 * step };
            let now = inside(t);
            if now != was_inside {
                let (mut lo, mut hi) = (previous, t);
                for _ in 0..60 {
                    let middle = 0.5 * (lo + hi);
                    if middle <= lo || middle >= hi {
                        break;
                    }
                    if inside(middle) == was_inside { lo = middle } else { hi = middle }
                }
                roots.push((0.5 * (lo + hi)) as f32);
                was_inside = now;
            }
            previous = t;
        }
        roots
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let t = *self.roots(ray, t_max).first()?;
        (t > 0.0 && t < t_max).then(|| Intersection::at(t))
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (o, _) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::ZERO);
        let ahead = self.roots(ray, t_max).into_iter().filter(|&t| t > 0.0 && t < t_max);
        Crossings::alternating(self.inside(o), ahead.map(Intersection::at))
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        self.frame.hit_along(ray, at, |own, _| self.outward(own))
    }

    pub fn contains(&self, p: Vec3) -> bool {
        let (p, _) = self.frame.to_own_space(p, Vec3::ZERO);
        self.inside(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc(algebra: Algebra, function: JuliaFunction) -> JuliaDesc {
        JuliaDesc {
            parameter: DVec4::new(-0.083, 0.0, -0.83, -0.025),
            algebra,
            function,
            max_iteration: 8,
            precision: 20.0,
            slice: (DVec4::W, 0.0),
        }
    }

    #[test]
    fn the_algebras_multiply_their_units_as_povray_s_manual_says() {
        let [one, i, j, k] = [DVec4::X, DVec4::Y, DVec4::Z, DVec4::W];
        let q = |a, b| Algebra::Quaternion.multiply(a, b);
        let h = |a, b| Algebra::Hypercomplex.multiply(a, b);
        for (got, want) in [
            (q(i, j), k),
            (q(j, k), i),
            (q(k, i), j),
            (q(j, i), -k),
            (q(k, k), -one),
            (h(i, j), k),
            (h(j, k), -i),
            (h(k, i), -j),
            (h(j, i), k),
            (h(j, j), -one),
            (h(k, k), one),
        ] {
            assert_eq!(got, want);
        }
    }

    #[test]
    fn the_outward_direction_is_the_gradient_of_the_escaping_step() {
        for (algebra, function) in [
            (Algebra::Quaternion, JuliaFunction::Square),
            (Algebra::Hypercomplex, JuliaFunction::Cube),
        ] {
            let julia = Julia::new(desc(algebra, function), Affine3A::IDENTITY);
            // The surface along +x from the centre, found by bisection.
            let (mut lo, mut hi) = (0.0, 1.0);
            assert!(julia.inside(DVec3::ZERO) && !julia.inside(DVec3::X));
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if julia.inside(DVec3::new(m, 0.0, 0.0)) { lo = m } else { hi = m }
            }
            let at = DVec3::new(lo, 0.0, 0.0);
            let outward = julia.outward(at).normalize();
            // Just outside along the outward direction the orbit escapes; just inside, not.
            assert!(!julia.inside(at + 1e-4 * outward), "{algebra:?}");
            assert!(julia.inside(at - 1e-4 * outward), "{algebra:?}");
        }
    }
}
