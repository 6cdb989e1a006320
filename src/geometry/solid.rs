//! Solids kept whole: a box and a cone (a cylinder is a cone of equal radii), and what every
//! solid answers besides its closest hit — where a ray crosses its surface, in order, and
//! whether a point is inside. CSG (`csg.rs`) composes these answers.

use arrayvec::ArrayVec;
use glam::{Affine3A, DMat3, DVec3, Vec2, Vec3, Vec3A};

use super::quadratic::quadratic_roots;
use super::shape::{
    Intersection, PlanarKind, QuadricFrame, QuadricKind, Shape, SurfaceSample, planar_coordinates,
    planar_distance, planar_error, planar_unbounded, quadric_coefficients, quadric_distance,
};
use super::{Aabb, Hit, Ray};

/// At most this many crossings of one solid (or CSG subtree) are kept along a ray segment;
/// later ones are dropped (only a mesh or a deep CSG tree can have more).
pub const MAX_CROSSINGS: usize = 32;

/// A planar face of a solid in world space: `origin + s edge1 + t edge2`, facing
/// `edge1 x edge2` (out of the solid).
#[derive(Debug, Clone, Copy)]
pub struct Face {
    pub kind: PlanarKind,
    pub origin: Vec3,
    pub edge1: Vec3,
    pub edge2: Vec3,
    pub normal: Vec3,
}

impl Face {
    pub fn new(kind: PlanarKind, origin: Vec3, edge1: Vec3, edge2: Vec3) -> Self {
        Face { kind, origin, edge1, edge2, normal: edge1.cross(edge2).normalize() }
    }

    #[inline]
    fn distance(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32, f32)> {
        planar_distance(self.kind, self.origin, self.edge1, self.edge2, ray, t_max)
    }

    /// The hit record at coordinates `st`, as `Shape::Planar` makes it.
    fn hit(&self, t: f32, st: Vec2) -> Hit {
        Hit {
            t,
            point: self.origin + st.x * self.edge1 + st.y * self.edge2,
            normal: self.normal,
            shading_normal: self.normal,
            error: planar_error(self.origin, self.edge1, self.edge2),
            primitive: 0,
        }
    }

    fn area(&self) -> f32 {
        let parallelogram = self.edge1.cross(self.edge2).length();
        match self.kind {
            PlanarKind::Triangle => 0.5 * parallelogram,
            PlanarKind::Quad => parallelogram,
            PlanarKind::Disk => std::f32::consts::PI * parallelogram,
        }
    }

    fn sample(&self, u: Vec2) -> SurfaceSample {
        let (s, t) = planar_coordinates(self.kind, u).into();
        SurfaceSample {
            point: self.origin + s * self.edge1 + t * self.edge2,
            normal: self.normal,
            error: planar_error(self.origin, self.edge1, self.edge2),
        }
    }

    fn bounds(&self) -> Aabb {
        Shape::Planar {
            kind: self.kind,
            origin: self.origin,
            edge1: self.edge1,
            edge2: self.edge2,
            normal: self.normal,
        }
        .bounds()
        .unwrap_or(Aabb::EMPTY)
    }

    /// The intersection of a ray known to cross this face's plane at `t`, with its coordinates
    /// (for a solid whose crossings are found another way).
    fn intersection_at(&self, ray: &Ray, t: f32, part: u32) -> Intersection {
        let (s, u) = planar_unbounded(self.origin, self.edge1, self.edge2, ray);
        Intersection { t, st: Vec2::new(s, u), triangle: part, part: 0 }
    }
}

/// A box: six quads (as `scene::build` has always made them, so hits are the same to the last
/// bit) and the map to its unit cube, for crossings and inside tests.
#[derive(Debug, Clone)]
pub struct Cuboid {
    /// Faces at local x = 0, x = 1, y = 0, y = 1, z = 0, z = 1, each facing out.
    pub faces: [Face; 6],
    /// World to the box's own space, where it is the unit cube [0, 1]^3.
    pub to_object: Affine3A,
    pub area: f32,
}

impl Cuboid {
    pub fn new(faces: [Face; 6], to_cube: Affine3A) -> Self {
        let area = faces.iter().map(Face::area).sum();
        Cuboid { faces, to_object: to_cube.inverse(), area }
    }

    #[inline]
    fn intersection(&self, ray: &Ray, mut t_max: f32) -> Option<Intersection> {
        let mut closest = None;
        for (i, face) in self.faces.iter().enumerate() {
            if let Some((t, s, u)) = face.distance(ray, t_max) {
                closest =
                    Some(Intersection { t, st: Vec2::new(s, u), triangle: i as u32, part: 0 });
                t_max = t;
            }
        }
        closest
    }

    fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let o = self.to_object.transform_point3a(ray.origin);
        let d = self.to_object.transform_vector3a(ray.dir);
        let (mut t_in, mut t_out) = (f32::NEG_INFINITY, f32::INFINITY);
        let (mut face_in, mut face_out) = (0, 0);
        for axis in 0..3 {
            let (o, d) = (o[axis], d[axis]);
            if d == 0.0 {
                if !(0.0..=1.0).contains(&o) {
                    return Crossings::outside();
                }
                continue;
            }
            let (t0, t1) = (-o / d, (1.0 - o) / d);
            let (near, far, face_near, face_far) = if t0 < t1 {
                (t0, t1, 2 * axis, 2 * axis + 1)
            } else {
                (t1, t0, 2 * axis + 1, 2 * axis)
            };
            if near > t_in {
                (t_in, face_in) = (near, face_near);
            }
            if far < t_out {
                (t_out, face_out) = (far, face_far);
            }
        }
        if t_in > t_out {
            return Crossings::outside();
        }
        let at = |t: f32, face: usize| self.faces[face].intersection_at(ray, t, face as u32);
        Crossings::convex(t_in, t_out, t_max, || at(t_in, face_in), || at(t_out, face_out))
    }

    fn contains(&self, p: Vec3) -> bool {
        let local = self.to_object.transform_point3(p);
        local.cmpgt(Vec3::ZERO).all() && local.cmplt(Vec3::ONE).all()
    }

    fn sample(&self, u: Vec2) -> SurfaceSample {
        let (face, u) = choose(self.faces.iter().map(Face::area), self.area, u);
        self.faces[face].sample(u)
    }
}

/// A cone or cylinder: in its own space (`frame`) the side is x^2 + y^2 = r(z)^2 for z in
/// [0, 1], r(z) = radii[0] (1 - z) + radii[1] z, closed by the end disks `caps` (world space;
/// none where open or where the radius is 0). A cylinder has radii [1, 1].
#[derive(Debug, Clone)]
pub struct Cone {
    pub frame: QuadricFrame,
    pub radii: [f32; 2],
    pub caps: [Option<Face>; 2],
    pub open: bool,
    /// World area of the side when sampling it by its canonical parameters is uniform by area.
    pub side_area: Option<f32>,
    /// The frame's origin in the world and the inverse of its linear part, in f64: a cone's
    /// side and every crossing and inside test are computed relative to the origin, so that a
    /// cone far from the world's origin loses nothing to cancellation. (A cylinder's closest
    /// hit keeps the f32 arithmetic it has always had.)
    origin: DVec3,
    linear_to_object: DMat3,
}

/// Which part of a cone an intersection is on (`Intersection::triangle`).
const SIDE: u32 = 0;

impl Cone {
    pub fn new(
        frame: QuadricFrame,
        radii: [f32; 2],
        caps: [Option<Face>; 2],
        open: bool,
        side_area: Option<f32>,
    ) -> Self {
        let origin = Vec3::from(frame.to_world.translation).as_dvec3();
        let linear = glam::Mat3::from(frame.to_world.matrix3).as_dmat3().inverse();
        Cone { frame, radii, caps, open, side_area, origin, linear_to_object: linear }
    }

    /// A point and a vector in the cone's own space, in f64.
    fn to_object(&self, p: Vec3, v: Vec3) -> (DVec3, DVec3) {
        let m = &self.linear_to_object;
        (*m * (p.as_dvec3() - self.origin), *m * v.as_dvec3())
    }

    /// The side's intersections along `o + t d` (own space) as (t0, t1) in order: any real
    /// roots of its whole double cone, whether or not they are on the side (`on_side`).
    fn side_roots(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
        let (r0, k) = (f64::from(self.radii[0]), f64::from(self.slope()));
        let r = r0 + k * o.z;
        quadratic_roots(
            d.x * d.x + d.y * d.y - k * k * d.z * d.z,
            o.x * d.x + o.y * d.y - k * d.z * r,
            o.x * o.x + o.y * o.y - r * r,
        )
    }

    /// Whether a side root at `t` is on the cone's side (z in [0, 1], and on the nappe of
    /// non-negative radius).
    fn on_side(&self, o: DVec3, d: DVec3, t: f64) -> bool {
        let z = o.z + t * d.z;
        (0.0..=1.0).contains(&z) && f64::from(self.radii[0]) + f64::from(self.slope()) * z >= 0.0
    }

    /// Area of the whole surface, when it is known in closed form.
    fn area(&self) -> Option<f32> {
        Some(self.side_area? + self.caps.iter().flatten().map(Face::area).sum::<f32>())
    }

    fn slope(&self) -> f32 {
        self.radii[1] - self.radii[0]
    }

    #[inline]
    fn intersection(&self, ray: &Ray, mut t_max: f32) -> Option<Intersection> {
        let mut closest = None;
        let side = if self.slope() == 0.0 {
            // As the cylinder's tube always has.
            let (o, d) = self.frame.ray_to_object(ray);
            quadric_distance(QuadricKind::Tube, o, d, t_max)
        } else {
            let (o, d) = self.to_object(Vec3::from(ray.origin), Vec3::from(ray.dir));
            self.side_roots(o, d).and_then(|(t0, t1)| {
                let accept = |t: f64| {
                    t > 0.0 && (t as f32) < t_max && t as f32 > 0.0 && self.on_side(o, d, t)
                };
                [t0, t1].into_iter().find(|&t| accept(t)).map(|t| t as f32)
            })
        };
        if let Some(t) = side {
            closest = Some(Intersection::at(t));
            t_max = t;
        }
        for (i, cap) in self.caps.iter().enumerate() {
            if let Some((t, s, u)) = cap.as_ref().and_then(|cap| cap.distance(ray, t_max)) {
                let part = i as u32 + 1;
                closest = Some(Intersection { t, st: Vec2::new(s, u), triangle: part, part: 0 });
                t_max = t;
            }
        }
        closest
    }

    fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        if at.triangle != SIDE {
            let cap = self.caps[at.triangle as usize - 1].as_ref();
            return cap.expect("a cap that was hit").hit(at.t, at.st);
        }
        let p = if self.slope() == 0.0 {
            let (o, d) = self.frame.ray_to_object(ray);
            o + at.t * d
        } else {
            let (o, d) = self.to_object(Vec3::from(ray.origin), Vec3::from(ray.dir));
            Vec3A::from((o + f64::from(at.t) * d).as_vec3())
        };
        // (`normalize`, not `normalize_or`: they round differently.)
        let radial = Vec3A::new(p.x, p.y, 0.0);
        let radial = if radial == Vec3A::ZERO { Vec3A::X } else { radial.normalize() };
        let (point, normal) = if self.slope() == 0.0 {
            // As the cylinder's tube always has.
            (radial + Vec3A::new(0.0, 0.0, p.z), radial)
        } else {
            let z = p.z.clamp(0.0, 1.0);
            let r = self.radii[0] + self.slope() * z;
            (radial * r + Vec3A::new(0.0, 0.0, z), radial - Vec3A::new(0.0, 0.0, self.slope()))
        };
        let frame = &self.frame;
        let normal: Vec3 = (frame.normal_to_world * normal).normalize().into();
        Hit {
            t: at.t,
            point: frame.to_world.transform_point3a(point).into(),
            normal,
            shading_normal: normal,
            error: super::shape::REL_ERROR * frame.magnitude,
            primitive: 0,
        }
    }

    /// Crossings of the closed cone: it is convex, so the nearest and farthest of the side's
    /// and the caps' intersections.
    fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let (o, d) = self.to_object(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let mut found = ArrayVec::<(f64, u32), 4>::new();
        if let Some((t0, t1)) = self.side_roots(o, d) {
            let on_side = |&t: &f64| self.on_side(o, d, t);
            found.extend([t0, t1].into_iter().filter(on_side).map(|t| (t, SIDE)));
        }
        if d.z != 0.0 {
            for (i, z) in [0.0, 1.0].into_iter().enumerate() {
                let t = (z - o.z) / d.z;
                let p = o + t * d;
                let r = f64::from(self.radii[i]);
                if r > 0.0 && p.x * p.x + p.y * p.y <= r * r {
                    found.push((t, i as u32 + 1));
                }
            }
        }
        let Some(&first) = found.iter().min_by(|a, b| a.0.total_cmp(&b.0)) else {
            return Crossings::outside();
        };
        let last = *found.iter().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap_or(&first);
        if found.len() < 2 {
            return Crossings::outside();
        }
        let (first, last) = ((first.0 as f32, first.1), (last.0 as f32, last.1));
        let at = |(t, part): (f32, u32)| match part {
            SIDE => Intersection::at(t),
            cap => self.caps[cap as usize - 1]
                .as_ref()
                .map_or(Intersection::at(t), |face| face.intersection_at(ray, t, cap)),
        };
        Crossings::convex(first.0, last.0, t_max, || at(first), || at(last))
    }

    fn contains(&self, p: Vec3) -> bool {
        let (local, _) = self.to_object(p, Vec3::ZERO);
        let r = f64::from(self.radii[0]) + f64::from(self.slope()) * local.z;
        local.z > 0.0 && local.z < 1.0 && local.x * local.x + local.y * local.y < r * r
    }

    fn sample(&self, u: Vec2) -> Option<SurfaceSample> {
        let side = self.side_area?;
        let areas = [side].into_iter().chain(self.caps.iter().map(|c| c.map_or(0.0, |c| c.area())));
        let (part, u) = choose(areas, self.area()?, u);
        if part > 0 {
            return Some(self.caps[part - 1]?.sample(u));
        }
        // z with density proportional to the radius r(z): invert its distribution.
        let (r0, k) = (self.radii[0], self.slope());
        let z = if k.abs() < 1e-6 {
            u.x
        } else {
            let total = r0 + 0.5 * k;
            ((r0 * r0 + 2.0 * k * total * u.x).max(0.0).sqrt() - r0) / k
        };
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let r = r0 + k * z;
        let frame = &self.frame;
        Some(SurfaceSample {
            point: frame.to_world.transform_point3(radial * r + Vec3::new(0.0, 0.0, z)),
            normal: (frame.normal_to_world * Vec3A::from(radial - Vec3::new(0.0, 0.0, k)))
                .normalize()
                .into(),
            error: super::shape::REL_ERROR * frame.magnitude,
        })
    }
}

/// Picks one of several parts in proportion to its area with `u.x`, and reuses what is left of
/// `u.x` for a point on it.
fn choose(areas: impl Iterator<Item = f32>, total: f32, u: Vec2) -> (usize, Vec2) {
    let target = u.x * total;
    let mut below = 0.0;
    let mut last = (0, 0.0, 0.0);
    for (i, area) in areas.enumerate() {
        if area > 0.0 {
            last = (i, below, area);
            if target < below + area {
                break;
            }
        }
        below += area;
    }
    let (i, below, area) = last;
    (i, Vec2::new(((target - below) / area).clamp(0.0, 1.0 - f32::EPSILON / 2.0), u.y))
}

/// Where a ray crosses a solid's surface: the intersection (on the operand that owns the
/// surface), whether the ray goes into the solid there, and whether it goes into that operand
/// (the two differ on a surface of a subtracted operand, whose normal is then turned).
#[derive(Debug, Clone, Copy)]
pub struct Crossing {
    pub at: Intersection,
    pub entering: bool,
    pub entering_operand: bool,
}

/// A solid along a ray segment (0, t_max): whether the segment starts inside, and its
/// crossings in order (each one toggles inside and outside).
#[derive(Debug, Clone)]
pub struct Crossings {
    pub inside_at_start: bool,
    pub list: ArrayVec<Crossing, MAX_CROSSINGS>,
}

impl Crossings {
    pub fn outside() -> Self {
        Crossings { inside_at_start: false, list: ArrayVec::new() }
    }

    /// A convex solid met along the whole line from `t_in` to `t_out`.
    #[inline]
    pub fn convex(
        t_in: f32,
        t_out: f32,
        t_max: f32,
        at_in: impl FnOnce() -> Intersection,
        at_out: impl FnOnce() -> Intersection,
    ) -> Self {
        let mut crossings =
            Crossings { inside_at_start: t_in <= 0.0 && t_out > 0.0, list: ArrayVec::new() };
        if t_in > 0.0 && t_in < t_max {
            crossings.push(at_in(), true);
        }
        if t_out > 0.0 && t_out < t_max {
            crossings.push(at_out(), false);
        }
        crossings
    }

    /// All the roots along the whole line of a bounded solid's surface, in order: the ray is
    /// outside before the first.
    pub fn from_roots(roots: &[f32], t_max: f32, at: impl Fn(f32) -> Intersection) -> Self {
        let before = roots.iter().filter(|&&t| t <= 0.0).count();
        let mut crossings = Crossings { inside_at_start: before % 2 == 1, list: ArrayVec::new() };
        let mut inside = crossings.inside_at_start;
        for &t in roots.iter().filter(|&&t| t > 0.0 && t < t_max) {
            inside = !inside;
            crossings.push(at(t), inside);
        }
        crossings
    }

    #[inline]
    pub fn push(&mut self, at: Intersection, entering: bool) {
        let crossing = Crossing { at, entering, entering_operand: entering };
        let _ = self.list.try_push(crossing);
    }
}

impl Shape {
    /// Where the ray crosses the solid's surface in (0, t_max), and whether it starts inside.
    /// (Not a solid: no crossings, never inside.)
    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        match self {
            Shape::Plane { normal, offset } => {
                // A half-space: inside where n . p + d < 0.
                let (origin, dir) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
                let (side, slope) = (normal.dot(origin) + offset, normal.dot(dir));
                let t = -side / slope;
                let mut crossings =
                    Crossings { inside_at_start: side < 0.0, list: ArrayVec::new() };
                if t > 0.0 && t < t_max {
                    crossings.inside_at_start = slope > 0.0;
                    crossings.push(Intersection::at(t), slope < 0.0);
                }
                crossings
            }
            Shape::Sphere { center, radius } => {
                match super::shape::sphere_roots(*center, *radius, ray) {
                    Some((t0, t1)) => Crossings::convex(
                        t0,
                        t1,
                        t_max,
                        || Intersection::at(t0),
                        || Intersection::at(t1),
                    ),
                    None => Crossings::outside(),
                }
            }
            Shape::Quadric { kind: QuadricKind::Ellipsoid, frame } => {
                let (o, d) = frame.ray_to_object(ray);
                let (a, half_b, c) = quadric_coefficients(QuadricKind::Ellipsoid, o, d);
                match quadratic_roots(a, half_b, c) {
                    Some((t0, t1)) => Crossings::convex(
                        t0,
                        t1,
                        t_max,
                        || Intersection::at(t0),
                        || Intersection::at(t1),
                    ),
                    None => Crossings::outside(),
                }
            }
            Shape::Box(cuboid) => cuboid.crossings(ray, t_max),
            Shape::Cone(cone) if !cone.open => cone.crossings(ray, t_max),
            Shape::Torus(torus) => torus.crossings(ray, t_max),
            Shape::Mesh { mesh, placement } => match placement {
                None => mesh.crossings(ray, t_max),
                Some(placement) => mesh.crossings(&placement.ray_to_object(ray), t_max),
            },
            Shape::Csg(csg) => csg.crossings(ray, t_max),
            Shape::Quadric { .. } | Shape::Cone(_) | Shape::Planar { .. } => Crossings::outside(),
        }
    }

    /// Whether `p` is inside the solid (false for shapes that are not solids).
    pub fn contains(&self, p: Vec3) -> bool {
        match self {
            Shape::Plane { normal, offset } => normal.dot(p) + offset < 0.0,
            Shape::Sphere { center, radius } => p.distance_squared(*center) < radius * radius,
            Shape::Quadric { kind: QuadricKind::Ellipsoid, frame } => {
                frame.to_object.transform_point3(p).length_squared() < 1.0
            }
            Shape::Box(cuboid) => cuboid.contains(p),
            Shape::Cone(cone) => !cone.open && cone.contains(p),
            Shape::Torus(torus) => torus.contains(p),
            Shape::Mesh { mesh, placement } => match placement {
                None => mesh.contains(p),
                Some(placement) => mesh.contains(placement.to_object.transform_point3(p)),
            },
            Shape::Csg(csg) => csg.contains(p),
            Shape::Quadric { .. } | Shape::Planar { .. } => false,
        }
    }

    // The parts of `Shape`'s own queries for the solids of this file.

    #[inline]
    pub(super) fn solid_intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        match self {
            Shape::Box(cuboid) => cuboid.intersection(ray, t_max),
            Shape::Cone(cone) => cone.intersection(ray, t_max),
            _ => None,
        }
    }

    pub(super) fn solid_hit(&self, ray: &Ray, at: &Intersection) -> Option<Hit> {
        match self {
            Shape::Box(cuboid) => Some(cuboid.faces[at.triangle as usize].hit(at.t, at.st)),
            Shape::Cone(cone) => Some(cone.hit(ray, at)),
            _ => None,
        }
    }

    pub(super) fn solid_bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Box(cuboid) => {
                Some(cuboid.faces.iter().fold(Aabb::EMPTY, |b, f| b.union(f.bounds())))
            }
            Shape::Cone(cone) => Some(Aabb::from_points(
                &QuadricFrame::canonical_corners().map(|c| cone.frame.to_world.transform_point3(c)),
            )),
            _ => None,
        }
    }

    pub(super) fn solid_area(&self) -> Option<f32> {
        match self {
            Shape::Box(cuboid) => Some(cuboid.area),
            Shape::Cone(cone) => cone.area(),
            _ => None,
        }
    }

    pub(super) fn solid_sample(&self, u: Vec2) -> Option<SurfaceSample> {
        match self {
            Shape::Box(cuboid) => Some(cuboid.sample(u)),
            Shape::Cone(cone) => cone.sample(u),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choosing_parts_by_area_reuses_u() {
        let areas = [1.0, 0.0, 3.0];
        assert_eq!(choose(areas.into_iter(), 4.0, Vec2::new(0.1, 0.5)), (0, Vec2::new(0.4, 0.5)));
        let (part, u) = choose(areas.into_iter(), 4.0, Vec2::new(0.625, 0.5));
        assert_eq!(part, 2);
        assert!((u.x - 0.5).abs() < 1e-6);
        assert_eq!(choose(areas.into_iter(), 4.0, Vec2::new(0.9999, 0.5)).0, 2);
    }
}
