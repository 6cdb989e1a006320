//! A triangle mesh ready for intersection: triangles as (vertex, edge, edge) in BVH order under
//! their own BVH, in the mesh's object space. Instances share one, each with its own transform
//! (a two-level hierarchy), so a mesh used a hundred times is stored once.

use std::ops::Range;

use glam::{Affine3A, Mat3A, Vec2, Vec3, Vec3A};

use super::shape::Intersection;
use super::solid::Crossings;
use super::{Aabb, Hit, Ray};
use crate::accel::{Bvh, HugeArray, prefetch};
use crate::mesh::Mesh;

#[derive(Debug)]
pub struct TriangleMesh {
    /// Per triangle, in BVH order: a vertex and the two edges from it.
    triangles: HugeArray<[Vec3; 3]>,
    /// Per triangle, in BVH order: its vertex indices, for interpolating normals.
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<Vec3>>,
    bvh: Bvh,
    /// Magnitude of the coordinates, for error bounds of hit points.
    magnitude: f32,
}

impl TriangleMesh {
    pub fn new(mesh: Mesh) -> Self {
        let corners = |t: &[u32; 3]| t.map(|i| mesh.positions[i as usize]);
        let bounds: Vec<Aabb> =
            mesh.triangles.iter().map(|t| Aabb::from_points(&corners(t))).collect();
        let (bvh, order) = Bvh::build(&bounds);
        let indices: Vec<[u32; 3]> = order.iter().map(|&i| mesh.triangles[i as usize]).collect();
        let triangles = indices
            .iter()
            .map(|t| {
                let [a, b, c] = corners(t);
                [a, b - a, c - a]
            })
            .collect();
        let triangles = HugeArray::new(triangles);
        let magnitude = bvh.bounds().min.abs().max(bvh.bounds().max.abs()).max_element();
        TriangleMesh { triangles, indices, normals: mesh.normals, bvh, magnitude }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The closest triangle the ray meets, in object space.
    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let (triangles, mut closest) = (&*self.triangles, None);
        let test = |i: usize, t_max| {
            let (t, s, u) = intersect_triangle(&triangles[i], ray, t_max)?;
            closest = Some(Intersection { t, st: Vec2::new(s, u), triangle: i as u32, part: 0 });
            Some(t)
        };
        self.bvh.closest(ray, t_max, test, |leaf| preload(triangles, leaf));
        closest
    }

    /// The hit record of an intersection, in object space. The normal is the face's
    /// `(b - a) x (c - a)`; with vertex normals the shading normal is interpolated from them,
    /// turned to the normal's side.
    pub fn hit(&self, at: &Intersection) -> Hit {
        let i = at.triangle as usize;
        let (s, u) = at.st.into();
        let [origin, edge1, edge2] = self.triangles[i];
        let normal = edge1.cross(edge2).normalize();
        let shading_normal = match &self.normals {
            None => normal,
            Some(normals) => {
                let [a, b, c] = self.indices[i].map(|v| normals[v as usize]);
                let n = ((1.0 - s - u) * a + s * b + u * c).normalize_or_zero();
                if n == Vec3::ZERO { normal } else { n * n.dot(normal).signum() }
            }
        };
        Hit {
            t: at.t,
            point: origin + s * edge1 + u * edge2,
            normal,
            shading_normal,
            error: 256.0 * f32::EPSILON * self.magnitude,
            primitive: 0,
        }
    }

    /// Whether every edge is shared by exactly two triangles: the mesh bounds a solid.
    pub fn is_closed(&self) -> bool {
        let mut edges = std::collections::HashMap::<(u32, u32), u32>::new();
        for t in &self.indices {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        !edges.is_empty() && edges.values().all(|&n| n == 2)
    }

    /// Where the ray (object space) crosses the closed mesh in (0, t_max), and whether it
    /// starts inside: by the parity of all its crossings beyond the origin.
    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let triangles = &*self.triangles;
        let mut all = Vec::new();
        let mut visit = |i: usize| {
            if let Some((t, s, u)) = intersect_triangle(&triangles[i], ray, f32::INFINITY) {
                all.push(Intersection { t, st: Vec2::new(s, u), triangle: i as u32, part: 0 });
            }
            false
        };
        self.bvh.any(ray, f32::INFINITY, &mut visit, |leaf| preload(triangles, leaf));
        all.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
        let mut crossings = Crossings::outside();
        crossings.inside_at_start = all.len() % 2 == 1;
        let mut inside = crossings.inside_at_start;
        for at in all.into_iter().take_while(|at| at.t < t_max) {
            inside = !inside;
            crossings.push(at, inside);
        }
        crossings
    }

    /// Whether `p` (object space) is inside the closed mesh: the parity of the crossings of a
    /// ray from it.
    pub fn contains(&self, p: Vec3) -> bool {
        let dir = Vec3::new(0.5773, 0.5774, 0.5775).normalize();
        let ray = Ray::new(p, dir);
        let triangles = &*self.triangles;
        let mut count = 0;
        let mut visit = |i: usize| {
            count += usize::from(intersect_triangle(&triangles[i], &ray, f32::INFINITY).is_some());
            false
        };
        self.bvh.any(&ray, f32::INFINITY, &mut visit, |leaf| preload(triangles, leaf));
        count % 2 == 1
    }

    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let triangles = &*self.triangles;
        let occludes = |i: usize| intersect_triangle(&triangles[i], ray, t_max).is_some();
        self.bvh.any(ray, t_max, occludes, |leaf| preload(triangles, leaf))
    }
}

/// Starts loading a leaf's triangles, first and last (see `Bvh::closest`).
#[inline]
fn preload(triangles: &[[Vec3; 3]], leaf: Range<usize>) {
    prefetch(&triangles[leaf.start]);
    prefetch(&triangles[leaf.end - 1][2]);
}

/// Möller–Trumbore: distance and barycentric coordinates along the two edges.
#[inline]
fn intersect_triangle(
    [origin, edge1, edge2]: &[Vec3; 3],
    ray: &Ray,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    let (ray_origin, ray_dir) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
    let pvec = ray_dir.cross(*edge2);
    let det = edge1.dot(pvec);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = ray_origin - *origin;
    let s = tvec.dot(pvec) * inv_det;
    if !(0.0..=1.0).contains(&s) {
        return None;
    }
    let qvec = tvec.cross(*edge1);
    let u = ray_dir.dot(qvec) * inv_det;
    if u < 0.0 || s + u > 1.0 {
        return None;
    }
    let t = edge2.dot(qvec) * inv_det;
    (t > 0.0 && t < t_max).then_some((t, s, u))
}

/// Where an instance puts its mesh in the world.
#[derive(Debug, Clone)]
pub struct Placement {
    pub to_world: Affine3A,
    pub to_object: Affine3A,
    pub normal_to_world: Mat3A,
}

impl Placement {
    pub fn new(to_world: Affine3A) -> Self {
        Placement {
            to_world,
            to_object: to_world.inverse(),
            normal_to_world: to_world.matrix3.inverse().transpose(),
        }
    }

    /// The ray in object space. Its direction is not renormalised, so distances are the same.
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.to_object.transform_point3a(ray.origin),
            dir: self.to_object.transform_vector3a(ray.dir),
        }
    }

    pub fn hit_to_world(&self, hit: Hit) -> Hit {
        let to_world = |n: Vec3| Vec3::from((self.normal_to_world * Vec3A::from(n)).normalize());
        let point = self.to_world.transform_point3(hit.point);
        let scale =
            self.to_world.matrix3.abs().to_cols_array().iter().fold(0.0f32, |m, e| m.max(*e));
        Hit {
            point,
            normal: to_world(hit.normal),
            shading_normal: to_world(hit.shading_normal),
            error: hit.error * 3.0 * scale + 256.0 * f32::EPSILON * point.abs().max_element(),
            ..hit
        }
    }
}
