//! A triangle mesh ready for intersection: triangles as (vertex, edge, edge) in BVH order under
//! their own BVH, four to a leaf's group, in the mesh's object space. Instances share one, each with its own transform
//! (a two-level hierarchy), so a mesh used a hundred times is stored once.

use std::ops::Range;

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, BVec4A, Mat3A, Vec2, Vec3, Vec3A, Vec4};

use super::crossings::Crossings;
use super::shape::Intersection;
use super::{Aabb, Hit, Ray};
use crate::accel::{Bvh, HugeArray, prefetch};
use crate::lanes::Vec3x4;
use crate::mesh::Mesh;

/// Four triangles side by side, coordinate by coordinate: a vertex and the two edges from it.
/// A ray is tested against all four at once in SIMD lanes; a leaf's triangles fill its groups,
/// its last one padded with zeros (no edges: never hit). Up to four triangles in a leaf then
/// cost one test (measured in callgrind on S5 and S6; see the commit).
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
#[repr(C)]
struct Triangles4 {
    origin: [Vec4; 3],
    edge1: [Vec4; 3],
    edge2: [Vec4; 3],
}

/// The indices of a padding slot, which holds no triangle.
const NO_TRIANGLE: [u32; 3] = [u32::MAX; 3];

#[derive(Debug)]
pub struct TriangleMesh {
    /// In BVH order, four triangles to a group.
    triangles: HugeArray<Triangles4>,
    /// Per slot (group * 4 + lane): the triangle's vertex indices, for interpolating normals,
    /// or `NO_TRIANGLE`.
    indices: Vec<[u32; 3]>,
    count: usize,
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
        let (bvh, order) = Bvh::build(&bounds, 4);
        let indices: Vec<[u32; 3]> =
            order.iter().map(|i| i.map_or(NO_TRIANGLE, |i| mesh.triangles[i as usize])).collect();
        let triangles = indices
            .chunks_exact(4)
            .map(|group| {
                let mut four = Triangles4::zeroed();
                for (lane, t) in group.iter().enumerate().filter(|(_, t)| **t != NO_TRIANGLE) {
                    let [a, b, c] = corners(t);
                    for (field, v) in
                        [(&mut four.origin, a), (&mut four.edge1, b - a), (&mut four.edge2, c - a)]
                    {
                        for axis in 0..3 {
                            field[axis][lane] = v[axis];
                        }
                    }
                }
                four
            })
            .collect();
        let triangles = HugeArray::new(triangles);
        let magnitude = bvh.bounds().min.abs().max(bvh.bounds().max.abs()).max_element();
        let count = mesh.triangles.len();
        TriangleMesh { triangles, indices, count, normals: mesh.normals, bvh, magnitude }
    }

    /// The triangle in a slot: a vertex and the two edges from it.
    fn triangle(&self, slot: usize) -> [Vec3; 3] {
        let four = &self.triangles[slot / 4];
        let lane = slot % 4;
        [four.origin, four.edge1, four.edge2].map(|v| Vec3::new(v[0][lane], v[1][lane], v[2][lane]))
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    pub fn triangle_count(&self) -> usize {
        self.count
    }

    /// The closest triangle the ray meets, in object space.
    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let (triangles, mut closest) = (&*self.triangles, None);
        let lanes = RaySplat::new(ray);
        let test = |i: usize, t_max| {
            let (hits, t, s, u) = lanes.intersect(&triangles[i], t_max);
            if !hits.any() {
                return None;
            }
            // The nearest, the first of equals: what testing one by one would keep.
            let t = Vec4::select(hits, t, Vec4::INFINITY);
            let nearest = t.min_element();
            let lane = (t.cmpeq(Vec4::splat(nearest)) & hits).bitmask().trailing_zeros() as usize;
            let (st, triangle) = (Vec2::new(s[lane], u[lane]), (4 * i + lane) as u32);
            closest = Some(Intersection { t: nearest, st, triangle, part: 0 });
            Some(nearest)
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
        let [origin, edge1, edge2] = self.triangle(i);
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
        for t in self.indices.iter().filter(|&&t| t != NO_TRIANGLE) {
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
        let lanes = RaySplat::new(ray);
        let mut all = Vec::new();
        let mut visit = |i: usize| {
            let (hits, t, s, u) = lanes.intersect(&triangles[i], f32::INFINITY);
            for lane in (0..4).filter(|&lane| hits.test(lane)) {
                let (t, st) = (t[lane], Vec2::new(s[lane], u[lane]));
                all.push(Intersection { t, st, triangle: (4 * i + lane) as u32, part: 0 });
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
        let lanes = RaySplat::new(&ray);
        let mut count = 0;
        let mut visit = |i: usize| {
            count += lanes.intersect(&triangles[i], f32::INFINITY).0.bitmask().count_ones();
            false
        };
        self.bvh.any(&ray, f32::INFINITY, &mut visit, |leaf| preload(triangles, leaf));
        count % 2 == 1
    }

    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let triangles = &*self.triangles;
        let lanes = RaySplat::new(ray);
        let occludes = |i: usize| lanes.intersect(&triangles[i], t_max).0.any();
        self.bvh.any(ray, t_max, occludes, |leaf| preload(triangles, leaf))
    }
}

/// Starts loading a leaf's groups, first and last (see `Bvh::closest`).
#[inline]
fn preload(triangles: &[Triangles4], leaf: Range<usize>) {
    prefetch(&triangles[leaf.start]);
    prefetch(&triangles[leaf.end - 1].edge2[2]);
}

/// A ray's origin and direction in each of four lanes.
struct RaySplat {
    origin: Vec3x4,
    dir: Vec3x4,
}

impl RaySplat {
    fn new(ray: &Ray) -> Self {
        RaySplat { origin: Vec3x4::splat(ray.origin.into()), dir: Vec3x4::splat(ray.dir.into()) }
    }

    /// Möller–Trumbore against four triangles: per lane whether the ray meets the triangle in
    /// (0, t_max), the distance and the barycentric coordinates along the two edges. Each lane
    /// computes what `Vec3` operations compute for its triangle alone, in their order (see
    /// `Vec3x4`), and rejects as the one-triangle test does, NaN included.
    #[inline]
    fn intersect(&self, four: &Triangles4, t_max: f32) -> (BVec4A, Vec4, Vec4, Vec4) {
        let coordinates = |[x, y, z]: [Vec4; 3]| Vec3x4 { x, y, z };
        let (origin, edge1, edge2) =
            (coordinates(four.origin), coordinates(four.edge1), coordinates(four.edge2));
        let zero = Vec4::ZERO;
        let pvec = self.dir.cross(edge2);
        let det = edge1.dot(pvec);
        let inv_det = Vec4::ONE / det;
        let tvec = self.origin - origin;
        let s = tvec.dot(pvec) * inv_det;
        let qvec = tvec.cross(edge1);
        let u = self.dir.dot(qvec) * inv_det;
        let t = edge2.dot(qvec) * inv_det;
        let hits = det.cmpne(zero)
            & s.cmpge(zero)
            & s.cmple(Vec4::ONE)
            & !(u.cmplt(zero) | (s + u).cmpgt(Vec4::ONE))
            & t.cmpgt(zero)
            & t.cmplt(Vec4::splat(t_max));
        (hits, t, s, u)
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Sampler, uniform_sphere};

    /// The plain test of one triangle (Möller–Trumbore), as meshes did it one at a time.
    fn intersect_triangle(
        [origin, edge1, edge2]: [Vec3; 3],
        ray: &Ray,
        t_max: f32,
    ) -> Option<(f32, f32, f32)> {
        let (ray_origin, ray_dir) = (Vec3::from(ray.origin), Vec3::from(ray.dir));
        let pvec = ray_dir.cross(edge2);
        let det = edge1.dot(pvec);
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let tvec = ray_origin - origin;
        let s = tvec.dot(pvec) * inv_det;
        if !(0.0..=1.0).contains(&s) {
            return None;
        }
        let qvec = tvec.cross(edge1);
        let u = ray_dir.dot(qvec) * inv_det;
        if u < 0.0 || s + u > 1.0 {
            return None;
        }
        let t = edge2.dot(qvec) * inv_det;
        (t > 0.0 && t < t_max).then_some((t, s, u))
    }

    /// Four triangles at a time under the BVH find, bit for bit, the hit that testing every
    /// triangle one at a time finds, on the bunny from inside and outside its bounds.
    #[test]
    fn batched_tests_agree_with_one_triangle_at_a_time() {
        let mesh = crate::mesh::load(std::path::Path::new("scenes/data/bunny.ply")).unwrap();
        let triangles: Vec<[u32; 3]> = mesh.triangles.clone();
        let corners = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            [a, b - a, c - a]
        };
        let reference: Vec<[Vec3; 3]> = triangles.iter().map(corners).collect();
        let bunny = TriangleMesh::new(mesh.clone());
        assert_eq!(bunny.triangle_count(), triangles.len());
        let (center, size) = (bunny.bounds().centroid(), bunny.bounds().extent().max_element());
        let mut sampler = Sampler::new(3, 1, 4);
        let mut hits = 0;
        for _ in 0..4000 {
            let origin = center + uniform_sphere(sampler.next_2d()) * size * sampler.next_1d();
            let ray = Ray::new(origin, uniform_sphere(sampler.next_2d()));
            let t_max = if sampler.next_1d() < 0.5 { f32::INFINITY } else { size };
            let mut one_by_one: Option<(f32, f32, f32, usize)> = None;
            for (j, triangle) in reference.iter().enumerate() {
                let t_max = one_by_one.map_or(t_max, |(t, ..)| t);
                if let Some((t, s, u)) = intersect_triangle(*triangle, &ray, t_max) {
                    one_by_one = Some((t, s, u, j));
                }
            }
            let batched = bunny.intersection(&ray, t_max).map(|at| {
                let slot = at.triangle as usize;
                let j = triangles.iter().position(|t| *t == bunny.indices[slot]).unwrap();
                assert_eq!(bunny.triangle(slot), reference[j]);
                (at.t, at.st.x, at.st.y, j)
            });
            assert_eq!(batched, one_by_one);
            assert_eq!(bunny.occluded(&ray, t_max), one_by_one.is_some());
            let all = reference
                .iter()
                .filter(|&&t| intersect_triangle(t, &ray, f32::INFINITY).is_some())
                .count();
            assert_eq!(bunny.contains(ray.origin.into()), {
                let dir = Vec3::new(0.5773, 0.5774, 0.5775).normalize();
                let from = Ray::new(ray.origin.into(), dir);
                reference
                    .iter()
                    .filter(|&&t| intersect_triangle(t, &from, f32::INFINITY).is_some())
                    .count()
                    % 2
                    == 1
            });
            assert_eq!(bunny.crossings(&ray, f32::INFINITY).inside_at_start, all % 2 == 1);
            hits += usize::from(one_by_one.is_some());
        }
        assert!(hits > 1000, "the test rays hit the bunny ({hits})");
    }
}
