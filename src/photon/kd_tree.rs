//! The photon map: stored photons in a k-d tree laid out in place (each range's median photon
//! is its node, split on the axis of the range's largest extent), built in parallel, and its
//! k-nearest-neighbour query.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::Vec3;

use super::Photon;

/// Ranges shorter than this are split on the calling thread (a task costs more than the work).
const PARALLEL_MIN: usize = 1 << 14;

/// Photons reordered into a balanced k-d tree: the node of range `lo..hi` is the photon at
/// `lo + (hi - lo) / 2`, split on `axes` of that index; its children are the ranges either side.
#[derive(Debug, Clone, Default)]
pub struct PhotonMap {
    photons: Vec<Photon>,
    axes: Vec<u8>,
}

/// A photon found by `PhotonMap::nearest`: its index and squared distance to the query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Neighbour {
    pub distance_squared: f32,
    pub index: u32,
}

impl Eq for Neighbour {}

impl Ord for Neighbour {
    /// The farther first out of a max-heap; ties by index, so results never depend on chance.
    fn cmp(&self, other: &Self) -> Ordering {
        self.distance_squared.total_cmp(&other.distance_squared).then(self.index.cmp(&other.index))
    }
}

impl PartialOrd for Neighbour {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PhotonMap {
    /// Builds the tree over `photons` (in parallel on rayon; the layout does not depend on the
    /// thread count: every range is split the same way whoever splits it).
    pub fn build(mut photons: Vec<Photon>) -> Self {
        let mut axes = vec![0; photons.len()];
        split(&mut photons, &mut axes);
        PhotonMap { photons, axes }
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

    /// The `k` photons nearest `point` (fewer if the map holds fewer), into `found` as a
    /// max-heap: the farthest at its top.
    pub fn nearest(&self, point: Vec3, k: usize, found: &mut BinaryHeap<Neighbour>) {
        found.clear();
        if k > 0 {
            self.search(0, self.photons.len(), point, k, found);
        }
    }

    fn search(
        &self,
        lo: usize,
        hi: usize,
        point: Vec3,
        k: usize,
        found: &mut BinaryHeap<Neighbour>,
    ) {
        if lo >= hi {
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let axis = usize::from(self.axes[mid]);
        let position = self.photons[mid].position;
        let offset = point[axis] - position[axis];
        let (near, far) =
            if offset < 0.0 { ((lo, mid), (mid + 1, hi)) } else { ((mid + 1, hi), (lo, mid)) };
        self.search(near.0, near.1, point, k, found);
        let candidate =
            Neighbour { distance_squared: point.distance_squared(position), index: mid as u32 };
        if found.len() < k {
            found.push(candidate);
        } else if found.peek().is_some_and(|farthest| candidate < *farthest) {
            found.pop();
            found.push(candidate);
        }
        let reach = found.peek().map_or(f32::INFINITY, |n| n.distance_squared);
        if found.len() < k || offset * offset <= reach {
            self.search(far.0, far.1, point, k, found);
        }
    }
}

/// Makes `photons` a tree: the median on the axis of largest extent at the middle, `axes` there
/// set, each side made a tree in turn (the two sides in parallel when large).
fn split(photons: &mut [Photon], axes: &mut [u8]) {
    if photons.len() <= 1 {
        return;
    }
    let (min, max) = photons.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p.position), hi.max(p.position))
    });
    let axis = (max - min).max_position();
    let mid = photons.len() / 2;
    photons.select_nth_unstable_by(mid, |a, b| a.position[axis].total_cmp(&b.position[axis]));
    axes[mid] = axis as u8;
    let (left, right) = photons.split_at_mut(mid);
    let (left_axes, right_axes) = axes.split_at_mut(mid);
    let (right, right_axes) = (&mut right[1..], &mut right_axes[1..]);
    if left.len() >= PARALLEL_MIN {
        rayon::join(|| split(left, left_axes), || split(right, right_axes));
    } else {
        split(left, left_axes);
        split(right, right_axes);
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
            let mut found = BinaryHeap::new();
            for q in 0..50 {
                let mut s = Sampler::new(99, 3, q);
                let point = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 2.4 - 1.2;
                map.nearest(point, k, &mut found);
                let mut tree: Vec<_> =
                    found.iter().map(|n| (n.distance_squared, n.index)).collect();
                tree.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let mut brute: Vec<_> = (0..map.len() as u32)
                    .map(|i| (map.photon(i).position.distance_squared(point), i))
                    .collect();
                brute.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                brute.truncate(k);
                assert_eq!(tree, brute, "n {n}, k {k}, query {point}");
            }
        }
    }

    /// The layout is the same on one thread as on several.
    #[test]
    fn build_does_not_depend_on_threads() {
        let photons = random_photons(100_000, 5);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let single = one.install(|| PhotonMap::build(photons.clone()));
        let many = PhotonMap::build(photons);
        assert_eq!(single.axes, many.axes);
        assert!(single.photons.iter().zip(&many.photons).all(|(a, b)| a.position == b.position));
    }
}
