//! A box kept whole: its six faces for hits, and its unit cube for crossings and inside tests.

use glam::{Affine3A, Vec2, Vec3};

use super::crossings::Crossings;
use super::planar::Planar;
use super::shape::{Intersection, SurfaceSample, choose_part};
use super::{Aabb, Hit, Ray};

/// A box: six quads (as `scene::build` has always made them, so hits are the same to the last
/// bit) and the map to its unit cube, for crossings and inside tests.
#[derive(Debug, Clone)]
pub struct Cuboid {
    /// Faces at local x = 0, x = 1, y = 0, y = 1, z = 0, z = 1, each facing out.
    pub faces: [Planar; 6],
    /// World to the box's own space, where it is the unit cube [0, 1]^3.
    pub to_object: Affine3A,
    pub area: f32,
}

impl Cuboid {
    pub fn new(faces: [Planar; 6], to_cube: Affine3A) -> Self {
        let area = faces.iter().map(Planar::area).sum();
        Cuboid { faces, to_object: to_cube.inverse(), area }
    }

    #[inline]
    pub fn intersection(&self, ray: &Ray, mut t_max: f32) -> Option<Intersection> {
        let mut closest = None;
        for (i, face) in self.faces.iter().enumerate() {
            if let Some(at) = face.intersection(ray, t_max) {
                closest = Some(Intersection { triangle: i as u32, ..at });
                t_max = at.t;
            }
        }
        closest
    }

    /// The hit record of the face the intersection is on.
    pub fn hit(&self, at: &Intersection) -> Hit {
        self.faces[at.triangle as usize].hit(at.t, at.st)
    }

    pub fn bounds(&self) -> Aabb {
        self.faces.iter().fold(Aabb::EMPTY, |b, f| b.union(f.bounds()))
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
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

    pub fn contains(&self, p: Vec3) -> bool {
        let local = self.to_object.transform_point3(p);
        local.cmpgt(Vec3::ZERO).all() && local.cmplt(Vec3::ONE).all()
    }

    pub fn sample(&self, u: Vec2) -> SurfaceSample {
        let (face, u) = choose_part(self.faces.iter().map(Planar::area), self.area, u);
        self.faces[face].sample(u)
    }
}
