//! The unbounded planes, kept outside the BVH and tested four at a time: the normals and
//! offsets of four planes in structure-of-arrays form make one SIMD distance computation.

use glam::{Vec3, Vec4};

use crate::ray::Ray;

/// Four planes `n . p + offset = 0`, one per lane.
#[derive(Debug, Clone, Copy)]
struct Group {
    nx: Vec4,
    ny: Vec4,
    nz: Vec4,
    offset: Vec4,
}

/// A lane that never hits: zero normal, so the distance is -1 / 0 = -inf.
const PADDING: (Vec3, f32) = (Vec3::ZERO, 1.0);

#[derive(Debug, Clone, Default)]
pub struct Planes {
    groups: Vec<Group>,
}

impl Planes {
    /// Planes given as (unit normal, offset).
    pub fn new(planes: &[(Vec3, f32)]) -> Self {
        let groups = planes
            .chunks(4)
            .map(|chunk| {
                let lane = |k: usize| chunk.get(k).copied().unwrap_or(PADDING);
                let lanes = [lane(0), lane(1), lane(2), lane(3)];
                Group {
                    nx: Vec4::from_array(lanes.map(|(n, _)| n.x)),
                    ny: Vec4::from_array(lanes.map(|(n, _)| n.y)),
                    nz: Vec4::from_array(lanes.map(|(n, _)| n.z)),
                    offset: Vec4::from_array(lanes.map(|(_, d)| d)),
                }
            })
            .collect();
        Planes { groups }
    }

    /// The index of the nearest plane the ray meets in (0, t_max), and its distance.
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<(usize, f32)> {
        let mut nearest = None;
        let mut t_nearest = t_max;
        for (g, group) in self.groups.iter().enumerate() {
            let t = group.distances(ray);
            let hits = t.cmpgt(Vec4::ZERO) & t.cmplt(Vec4::splat(t_nearest));
            if hits.any() {
                let t = Vec4::select(hits, t, Vec4::INFINITY);
                t_nearest = t.min_element();
                let lane = t.cmpeq(Vec4::splat(t_nearest)).bitmask().trailing_zeros();
                nearest = Some(4 * g + lane as usize);
            }
        }
        nearest.map(|k| (k, t_nearest))
    }

    /// Whether any plane meets the ray in (0, t_max).
    #[inline]
    pub fn any(&self, ray: &Ray, t_max: f32) -> bool {
        self.groups.iter().any(|group| {
            let t = group.distances(ray);
            (t.cmpgt(Vec4::ZERO) & t.cmplt(Vec4::splat(t_max))).any()
        })
    }
}

impl Group {
    /// Signed distances along the ray to the four planes: -(n . o + offset) / (n . d).
    #[inline]
    fn distances(&self, ray: &Ray) -> Vec4 {
        let (o, d) = (ray.origin, ray.dir);
        let at_origin = self.nx * o.x + self.ny * o.y + self.nz * o.z + self.offset;
        let along_dir = self.nx * d.x + self.ny * d.y + self.nz * d.z;
        -at_origin / along_dir
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_one_plane_at_a_time() {
        // Six faces of a box around the origin, plus one: two groups, the second padded.
        let planes: Vec<(Vec3, f32)> = [
            (Vec3::X, 1.0),
            (-Vec3::X, 2.0),
            (Vec3::Y, 1.5),
            (-Vec3::Y, 1.0),
            (Vec3::Z, 3.0),
            (-Vec3::Z, 1.0),
            (Vec3::new(1.0, 1.0, 0.0).normalize(), 2.5),
        ]
        .into();
        let set = Planes::new(&planes);
        let mut sampler = crate::sampling::Sampler::new(4, 5, 6);
        for _ in 0..500 {
            let origin = Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d()) - 0.5;
            let ray = Ray::new(origin, crate::sampling::uniform_sphere(sampler.next_2d()));
            let t_max = 4.0 * sampler.next_1d();
            let one_by_one = planes
                .iter()
                .enumerate()
                .map(|(k, &(n, d))| (k, -(n.dot(ray.origin.into()) + d) / n.dot(ray.dir.into())))
                .filter(|&(_, t)| t > 0.0 && t < t_max)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            assert_eq!(set.closest(&ray, t_max), one_by_one);
            assert_eq!(set.any(&ray, t_max), one_by_one.is_some());
        }
    }
}
