//! A cone or cylinder kept whole (a cylinder is a cone of equal radii): its side and end
//! disks, and its inside.

use arrayvec::ArrayVec;
use glam::{DVec3, Vec2, Vec3, Vec3A};

use super::crossings::Crossings;
use super::planar::Planar;
use super::quadratic::quadratic_roots;
use super::quadric::{QuadricFrame, QuadricKind};
use super::shape::{Intersection, REL_ERROR, SurfaceSample, choose_part};
use super::{Aabb, Hit, Ray};

/// A cone or cylinder: in its own space (`frame`) the side is x^2 + y^2 = r(z)^2 for z in
/// [0, 1], r(z) = radii[0] (1 - z) + radii[1] z, closed by the end disks `caps` (world space;
/// none where open or where the radius is 0). A cylinder has radii [1, 1].
#[derive(Debug, Clone)]
pub struct Cone {
    pub frame: QuadricFrame,
    pub radii: [f32; 2],
    pub caps: [Option<Planar>; 2],
    pub open: bool,
    /// World area of the side when sampling it by its canonical parameters is uniform by area.
    pub side_area: Option<f32>,
}

/// Which part of a cone an intersection is on (`Intersection::triangle`).
const SIDE: u32 = 0;

impl Cone {
    pub fn new(
        frame: QuadricFrame,
        radii: [f32; 2],
        caps: [Option<Planar>; 2],
        open: bool,
        side_area: Option<f32>,
    ) -> Self {
        Cone { frame, radii, caps, open, side_area }
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
    pub fn area(&self) -> Option<f32> {
        Some(self.side_area? + self.caps.iter().flatten().map(Planar::area).sum::<f32>())
    }

    fn slope(&self) -> f32 {
        self.radii[1] - self.radii[0]
    }

    #[inline]
    pub fn intersection(&self, ray: &Ray, mut t_max: f32) -> Option<Intersection> {
        let mut closest = None;
        let side = if self.slope() == 0.0 {
            // As the cylinder's tube always has.
            QuadricKind::Tube.intersection(&self.frame, ray, t_max)
        } else {
            let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
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
            if let Some(at) = cap.as_ref().and_then(|cap| cap.intersection(ray, t_max)) {
                closest = Some(Intersection { triangle: i as u32 + 1, ..at });
                t_max = at.t;
            }
        }
        closest
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        if let Some(cap) = self.cap(at.triangle) {
            return cap.hit(at.t, at.st);
        }
        if self.slope() == 0.0 {
            return QuadricKind::Tube.hit(&self.frame, ray, at.t);
        }
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
        let p = Vec3A::from((o + f64::from(at.t) * d).as_vec3());
        // (`normalize`, not `normalize_or`: they round differently.)
        let radial = Vec3A::new(p.x, p.y, 0.0);
        let radial = if radial == Vec3A::ZERO { Vec3A::X } else { radial.normalize() };
        let z = p.z.clamp(0.0, 1.0);
        let r = self.radii[0] + self.slope() * z;
        let (point, normal) =
            (radial * r + Vec3A::new(0.0, 0.0, z), radial - Vec3A::new(0.0, 0.0, self.slope()));
        let frame = &self.frame;
        let normal: Vec3 = (frame.normal_to_world * normal).normalize().into();
        Hit {
            t: at.t,
            point: frame.to_world.transform_point3a(point).into(),
            normal,
            shading_normal: normal,
            error: REL_ERROR * frame.magnitude,
            primitive: 0,
        }
    }

    /// The end disk a part number names (1 the base, 2 the cap); `None` for the side.
    fn cap(&self, part: u32) -> Option<&Planar> {
        self.caps.get(part.checked_sub(1)? as usize)?.as_ref()
    }

    /// Crossings of the closed cone: it is convex, so the nearest and farthest of the side's
    /// and the caps' intersections. An open one is no solid: none.
    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        if self.open {
            return Crossings::outside();
        }
        let (o, d) = self.frame.to_own_space(Vec3::from(ray.origin), Vec3::from(ray.dir));
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
        let at = |(t, part): (f32, u32)| {
            self.cap(part).map_or(Intersection::at(t), |cap| cap.intersection_at(ray, t, part))
        };
        Crossings::convex(first.0, last.0, t_max, || at(first), || at(last))
    }

    /// Whether `p` is inside the closed cone (never inside an open one).
    pub fn contains(&self, p: Vec3) -> bool {
        if self.open {
            return false;
        }
        let (local, _) = self.frame.to_own_space(p, Vec3::ZERO);
        let r = f64::from(self.radii[0]) + f64::from(self.slope()) * local.z;
        local.z > 0.0 && local.z < 1.0 && local.x * local.x + local.y * local.y < r * r
    }

    pub fn sample(&self, u: Vec2) -> Option<SurfaceSample> {
        let side = self.side_area?;
        let areas = [side].into_iter().chain(self.caps.iter().map(|c| c.map_or(0.0, |c| c.area())));
        let (part, u) = choose_part(areas, self.area()?, u);
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
            error: REL_ERROR * frame.magnitude,
        })
    }
    pub fn bounds(&self) -> Aabb {
        self.frame.bounds()
    }
}
