//! A spatial hash grid of spheres (progressive photon mapping's visible points with their
//! radii), for finding the spheres that hold a point: cells as wide as the largest diameter,
//! each sphere listed in the buckets of the cells its bounding box overlaps (at most 8), the
//! cells hashed into a table twice the spheres' number (Teschner et al. 2003's hash).

use glam::{IVec3, Vec3};
use rayon::prelude::*;

#[derive(Debug, Clone)]
pub struct HashGrid {
    origin: Vec3,
    cell_size: f32,
    /// Bucket `b` lists `entries[starts[b]..starts[b + 1]]`, in the spheres' order.
    starts: Vec<u32>,
    /// Each sphere where its buckets list it, whole: a lookup reads one run of memory.
    entries: Vec<Entry>,
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    id: u32,
    centre: Vec3,
    radius_squared: f32,
}

impl HashGrid {
    /// The most memory `build` takes per sphere: a sphere overlaps at most 8 cells, each
    /// listed as a (bucket, sphere) pair and then as an entry, and the table has at most 4
    /// buckets a sphere (twice the spheres, rounded up to a power of two), plus one.
    pub const BYTES_PER_SPHERE: usize =
        8 * (size_of::<(u32, u32)>() + size_of::<Entry>()) + 4 * size_of::<u32>();

    /// The grid of spheres `(id, centre, radius)`; ids are what `candidates` returns.
    pub fn build(spheres: &[(u32, Vec3, f32)]) -> Self {
        let (min, max_radius) = spheres.iter().fold((Vec3::INFINITY, 0.0f32), |(lo, r), s| {
            (lo.min(s.1 - Vec3::splat(s.2)), r.max(s.2))
        });
        let origin = if spheres.is_empty() { Vec3::ZERO } else { min };
        let cell_size = (2.0 * max_radius).max(f32::MIN_POSITIVE);
        let buckets = (2 * spheres.len()).next_power_of_two();
        let mut grid = HashGrid { origin, cell_size, starts: Vec::new(), entries: Vec::new() };
        // (bucket, sphere) of every overlapped cell, in the spheres' order whatever the threads.
        let mut pairs: Vec<(u32, u32)> = spheres
            .par_iter()
            .enumerate()
            .flat_map_iter(|(sphere, &(_, centre, radius))| {
                let (lo, hi) = (grid.cell(centre - radius), grid.cell(centre + radius));
                let grid = &grid;
                (lo.z..=hi.z).flat_map(move |z| {
                    (lo.y..=hi.y).flat_map(move |y| {
                        (lo.x..=hi.x).map(move |x| {
                            (grid.bucket(IVec3::new(x, y, z), buckets), sphere as u32)
                        })
                    })
                })
            })
            .collect();
        // Two cells of a sphere may share a bucket: it is listed once.
        pairs.par_sort_unstable();
        pairs.dedup();
        let mut starts = vec![0u32; buckets + 1];
        for &(bucket, _) in &pairs {
            starts[bucket as usize + 1] += 1;
        }
        for b in 0..buckets {
            starts[b + 1] += starts[b];
        }
        grid.starts = starts;
        grid.entries = pairs
            .into_iter()
            .map(|(_, sphere)| {
                let (id, centre, radius) = spheres[sphere as usize];
                Entry { id, centre, radius_squared: radius * radius }
            })
            .collect();
        grid
    }

    /// The ids of the spheres that hold `point` (strictly within their radius).
    pub fn holding(&self, point: Vec3) -> impl Iterator<Item = u32> + '_ {
        let buckets = self.starts.len() - 1;
        let listed = if buckets == 0 || !(point - self.origin).cmpge(Vec3::ZERO).all() {
            &[][..]
        } else {
            let b = self.bucket(self.cell(point), buckets) as usize;
            &self.entries[self.starts[b] as usize..self.starts[b + 1] as usize]
        };
        listed
            .iter()
            .filter(move |e| e.centre.distance_squared(point) < e.radius_squared)
            .map(|e| e.id)
    }

    /// The integer coordinates of the cell holding `point` (clamped to what i32 holds).
    fn cell(&self, point: Vec3) -> IVec3 {
        let c = ((point - self.origin) / self.cell_size).floor();
        c.clamp(Vec3::splat(-1e9), Vec3::splat(1e9)).as_ivec3()
    }

    fn bucket(&self, cell: IVec3, buckets: usize) -> u32 {
        let hash = (cell.x as u32).wrapping_mul(73_856_093)
            ^ (cell.y as u32).wrapping_mul(19_349_663)
            ^ (cell.z as u32).wrapping_mul(83_492_791);
        hash & (buckets as u32 - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    /// The spheres that hold each query point, found through the grid, are those found by
    /// testing every sphere.
    #[test]
    fn spheres_holding_a_point_equal_brute_force() {
        for (n, max_radius) in [(0, 0.1), (1, 0.3), (50, 0.2), (3000, 0.05), (20_000, 0.02)] {
            let spheres: Vec<(u32, Vec3, f32)> = (0..n)
                .map(|i| {
                    let mut s = Sampler::new(4, 1, u64::from(i));
                    let centre = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.0 - 1.0;
                    (i * 3 + 1, centre, max_radius * (0.1 + 0.9 * s.next_1d()))
                })
                .collect();
            let grid = HashGrid::build(&spheres);
            let mut hits = 0;
            for q in 0..20_000 {
                let mut s = Sampler::new(8, 2, q);
                let point = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.2 - 1.1;
                let holds = |&(_, c, r): &(u32, Vec3, f32)| c.distance_squared(point) < r * r;
                let brute: Vec<u32> = spheres.iter().filter(|s| holds(s)).map(|s| s.0).collect();
                let mut found: Vec<u32> = grid.holding(point).collect();
                found.sort();
                assert_eq!(found, brute, "{n} spheres, point {point}");
                hits += brute.len();
            }
            assert!(n < 50 || hits > 100, "the test must find spheres: {hits}");
        }
    }
}
