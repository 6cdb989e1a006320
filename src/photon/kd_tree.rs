//! The photon map: stored photons and a k-d tree over their positions (`kiddo`'s immutable tree,
//! leaves of 32 points), with the k-nearest-neighbour query of `photon`'s density estimate.
//! (`kiddo` answered k = 100 queries 2.7 times faster than the tree of one photon per node it
//! replaced, on caustic-point.scn's photons: see the note of issue 21.)

use std::num::NonZero;

use glam::Vec3;
use kiddo::SquaredEuclidean;
use kiddo::immutable::float::kdtree::ImmutableKdTree;

use super::Photon;

/// Points per leaf of the tree.
const BUCKET: usize = 32;

/// The stored photons, in the order given, and the tree of their positions.
pub struct PhotonMap {
    photons: Vec<Photon>,
    tree: ImmutableKdTree<f32, u32, 3, BUCKET>,
}

/// A photon found by `PhotonMap::nearest`: its index and squared distance to the query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Neighbour {
    pub distance_squared: f32,
    pub index: u32,
}

impl PhotonMap {
    /// Builds the tree over `photons` (on the calling thread: the same tree on any thread count).
    pub fn build(photons: Vec<Photon>) -> Self {
        let positions: Vec<[f32; 3]> = photons.iter().map(|p| p.position.to_array()).collect();
        let tree = ImmutableKdTree::new_from_slice(&positions);
        PhotonMap { photons, tree }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    pub fn photon(&self, index: u32) -> &Photon {
        &self.photons[index as usize]
    }

    /// The `k` photons nearest `point` (fewer if the map holds fewer), nearest first.
    pub fn nearest(&self, point: Vec3, k: usize) -> Vec<Neighbour> {
        let Some(k) = NonZero::new(k).filter(|_| !self.is_empty()) else {
            return Vec::new();
        };
        let found = self.tree.nearest_n::<SquaredEuclidean>(&point.to_array(), k);
        found.iter().map(|n| Neighbour { distance_squared: n.distance, index: n.item }).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    fn random_photons(n: u32, seed: u64) -> Vec<Photon> {
        (0..n)
            .map(|i| {
                let mut s = Sampler::new(seed, 7, u64::from(i));
                let (a, b) = (s.next_2d(), s.next_2d());
                // Clustered on a plane and in a cube, with repeated coordinates, as photons are.
                let position = if i % 3 == 0 {
                    Vec3::new(a.x, 0.25, (b.y * 8.0).floor() / 8.0)
                } else {
                    Vec3::new(a.x, a.y, b.x) * 2.0 - 1.0
                };
                Photon::new(position, Vec3::Z, Vec3::splat(i as f32))
            })
            .collect()
    }

    /// The k nearest from the tree are the k nearest by brute force: the same distances, and
    /// the same photons where distances differ.
    #[test]
    fn nearest_photons_equal_brute_force() {
        for (n, k) in [(0, 5), (1, 3), (7, 10), (1000, 1), (5000, 50), (40_000, 100)] {
            let map = PhotonMap::build(random_photons(n, u64::from(n)));
            assert_eq!(map.len(), n as usize);
            for q in 0..50 {
                let mut s = Sampler::new(99, 3, q);
                let point = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.4 - 1.2;
                let found = map.nearest(point, k);
                assert!(found.windows(2).all(|w| w[0].distance_squared <= w[1].distance_squared));
                // The tree's distances, recomputed as brute force computes them.
                let mut tree: Vec<_> = found
                    .iter()
                    .map(|n| (map.photon(n.index).position.distance_squared(point), n.index))
                    .collect();
                tree.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let mut brute: Vec<_> = (0..map.len() as u32)
                    .map(|i| (map.photon(i).position.distance_squared(point), i))
                    .collect();
                brute.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                brute.truncate(k);
                assert_eq!(tree, brute, "n {n}, k {k}, query {point}");
                for n in found.iter() {
                    let exact = map.photon(n.index).position.distance_squared(point);
                    assert!((n.distance_squared - exact).abs() <= 1e-5 * exact.max(1e-6));
                }
            }
        }
    }

    /// The answers are the same when the map is built on one thread as on several.
    #[test]
    fn build_does_not_depend_on_threads() {
        let photons = random_photons(100_000, 5);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let single = one.install(|| PhotonMap::build(photons.clone()));
        let many = PhotonMap::build(photons);
        for q in 0..200 {
            let mut s = Sampler::new(4, 1, q);
            let point = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.0 - 1.0;
            assert_eq!(single.nearest(point, 50), many.nearest(point, 50));
        }
    }
}
