//! A bounding volume hierarchy: binned SAH build (in parallel), flattened depth-first nodes,
//! front-to-back traversal.

use std::ops::Range;

use arrayvec::ArrayVec;
use glam::{Vec3, Vec3A, Vec4};

use crate::geometry::{Aabb, Ray};

const BINS: usize = 16;
const MAX_LEAF: usize = 4;
/// Cost of visiting a node relative to one primitive test (SAH): a visit tests both children's
/// boxes, each about as costly as a primitive. (Measured: 2 renders S3 and S4 4% faster than 1,
/// S5 and S6 no slower; 3 is slower on S3 and S5.)
const TRAVERSAL_COST: f32 = 2.0;
/// Below this many primitives a subtree is built on the current thread.
const PARALLEL_MIN: usize = 4096;
/// Past this depth splits are by median, which bounds the depth (and the traversal stack).
const SAH_MAX_DEPTH: usize = 48;
const STACK_SIZE: usize = SAH_MAX_DEPTH + 64;

/// 32 bytes, two SIMD lanes of four: the box's corners in x, y, z, and in the fourth lanes
/// (as bits) `offset` and `count`. Leaf: first primitive and their number. Interior: the index
/// of the second child (the first follows the node), and count 0.
#[derive(Debug, Clone, Copy)]
struct Node {
    min: Vec4,
    max: Vec4,
}

impl Node {
    fn new(bounds: Aabb, offset: u32, count: u32) -> Self {
        Node {
            min: bounds.min.extend(f32::from_bits(offset)),
            max: bounds.max.extend(f32::from_bits(count)),
        }
    }

    #[inline]
    fn offset(&self) -> u32 {
        self.min.w.to_bits()
    }

    #[inline]
    fn count(&self) -> u32 {
        self.max.w.to_bits()
    }

    fn bounds(&self) -> Aabb {
        Aabb { min: self.min.truncate(), max: self.max.truncate() }
    }

    /// Slab test: the entry distance if the ray meets the box within (0, t_max).
    #[inline]
    fn entry(&self, origin: Vec3A, inv_dir: Vec3A, t_max: f32) -> Option<f32> {
        let t0 = (Vec3A::from_vec4(self.min) - origin) * inv_dir;
        let t1 = (Vec3A::from_vec4(self.max) - origin) * inv_dir;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max);
        (near <= far).then_some(near)
    }
}

#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
}

#[derive(Clone, Copy)]
struct Item {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

enum BuildNode {
    Leaf { bounds: Aabb, first: usize, count: usize },
    Interior { bounds: Aabb, children: Box<[BuildNode; 2]> },
}

impl Bvh {
    /// Builds over the given boxes. Returns the hierarchy and the order in which the primitives
    /// must be stored: leaf ranges index that order.
    pub fn build(bounds: &[Aabb]) -> (Bvh, Vec<u32>) {
        let mut items: Vec<Item> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| Item { bounds: *b, centroid: b.centroid(), index: i as u32 })
            .collect();
        if items.is_empty() {
            return (Bvh::default(), Vec::new());
        }
        let root = build_node(&mut items, 0, 0);
        let mut nodes = Vec::with_capacity(2 * items.len() / MAX_LEAF + 1);
        flatten(&root, &mut nodes);
        (Bvh { nodes }, items.iter().map(|it| it.index).collect())
    }

    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, Node::bounds)
    }

    /// Closest-hit traversal. `hit(i, t_max)` tests primitive `i` and returns its distance if it
    /// is hit before `t_max`; the closest such distance is returned. `preload(range)` is told
    /// of the primitives of a leaf the ray may visit soon, to start loading them (see `warm`).
    #[inline]
    pub fn closest(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut hit: impl FnMut(usize, f32) -> Option<f32>,
        preload: impl Fn(Range<usize>),
    ) -> f32 {
        if self.nodes.is_empty() {
            return t_max;
        }
        let (origin, inv_dir) = (Vec3A::from(ray.origin), Vec3A::from(ray.dir).recip());
        if self.nodes[0].entry(origin, inv_dir, t_max).is_none() {
            return t_max;
        }
        // Nodes still to visit, with the distance at which the ray enters them: a node entered
        // beyond the closest hit found since it was pushed is skipped. (Not zero-filled: rays
        // are many and most of the stack is never touched.)
        let mut stack = ArrayVec::<(u32, f32), STACK_SIZE>::new();
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.count() > 0 {
                let first = node.offset() as usize;
                for i in first..first + node.count() as usize {
                    if let Some(t) = hit(i, t_max) {
                        t_max = t;
                    }
                }
            } else {
                // Both children's boxes are tested here; the nearer is visited first.
                let (a, b) = (current + 1, node.offset() as usize);
                self.warm(a, &preload);
                self.warm(b, &preload);
                let enter_a = self.nodes[a].entry(origin, inv_dir, t_max);
                let enter_b = self.nodes[b].entry(origin, inv_dir, t_max);
                match (enter_a, enter_b) {
                    (Some(ta), Some(tb)) => {
                        let (near, far, t_far) = if ta <= tb { (a, b, tb) } else { (b, a, ta) };
                        stack.push((far as u32, t_far));
                        current = near;
                        continue;
                    }
                    (Some(_), None) => {
                        current = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        current = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            loop {
                let Some((node, enter)) = stack.pop() else {
                    return t_max;
                };
                if enter < t_max {
                    current = node as usize;
                    break;
                }
            }
        }
    }

    /// Any-hit traversal for shadow rays: stops at the first primitive for which `hit` is true.
    /// `preload` as for `closest`.
    #[inline]
    pub fn any(
        &self,
        ray: &Ray,
        t_max: f32,
        mut hit: impl FnMut(usize) -> bool,
        preload: impl Fn(Range<usize>),
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let (origin, inv_dir) = (Vec3A::from(ray.origin), Vec3A::from(ray.dir).recip());
        let mut stack = ArrayVec::<u32, STACK_SIZE>::new();
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.entry(origin, inv_dir, t_max).is_some() {
                if node.count() > 0 {
                    let first = node.offset() as usize;
                    if (first..first + node.count() as usize).any(&mut hit) {
                        return true;
                    }
                } else {
                    self.warm(current + 1, &preload);
                    self.warm(node.offset() as usize, &preload);
                    stack.push(node.offset());
                    current += 1;
                    continue;
                }
            }
            match stack.pop() {
                Some(node) => current = node as usize,
                None => return false,
            }
        }
    }

    /// Starts loading what visiting node `index` will read: its second child (the first is
    /// the next node, likely in the same cache line), or a leaf's primitives. Traversal of a
    /// large mesh waits on memory; a load issued (and kept by `black_box`) while this level's
    /// boxes are tested overlaps with that work instead of stalling the next step. Measured on
    /// S6: 8-10% faster.
    #[inline]
    fn warm(&self, index: usize, preload: &impl Fn(Range<usize>)) {
        let node = &self.nodes[index];
        let first = node.offset() as usize;
        match node.count() {
            0 => {
                std::hint::black_box(self.nodes[first].min.x);
            }
            count => preload(first..first + count as usize),
        }
    }
}

fn build_node(items: &mut [Item], first: usize, depth: usize) -> BuildNode {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    if items.len() <= 1 {
        return BuildNode::Leaf { bounds, first, count: items.len() };
    }
    let sah = if depth < SAH_MAX_DEPTH { split_sah(items, bounds) } else { None };
    let mid = match sah {
        Some(split) => split,
        // A leaf is cheaper by SAH, or the centroids coincide and there are few enough.
        None if items.len() <= 4 * MAX_LEAF => {
            return BuildNode::Leaf { bounds, first, count: items.len() };
        }
        None => split_median(items),
    };
    let (left, right) = items.split_at_mut(mid);
    let (a, b) = if left.len() + right.len() >= PARALLEL_MIN {
        rayon::join(
            || build_node(left, first, depth + 1),
            || build_node(right, first + mid, depth + 1),
        )
    } else {
        (build_node(left, first, depth + 1), build_node(right, first + mid, depth + 1))
    };
    BuildNode::Interior { bounds, children: Box::new([a, b]) }
}

/// Halves `items` at the median centroid along the widest axis.
fn split_median(items: &mut [Item]) -> usize {
    let centroid_bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let axis = centroid_bounds.extent().max_position();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    mid
}

/// Chooses the cheapest binned SAH split over all three axes and partitions `items` by it.
/// Returns the size of the first part, or `None` when a leaf is cheaper or no
/// split separates the centroids.
fn split_sah(items: &mut [Item], bounds: Aabb) -> Option<usize> {
    let centroid_bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let extent = centroid_bounds.extent();
    let bin_of = |c: Vec3, axis: usize| {
        let f = (c[axis] - centroid_bounds.min[axis]) / extent[axis] * BINS as f32;
        (f as usize).min(BINS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let mut bin_bounds = [Aabb::EMPTY; BINS];
        let mut bin_counts = [0usize; BINS];
        for it in items.iter() {
            let b = bin_of(it.centroid, axis);
            bin_bounds[b] = bin_bounds[b].union(it.bounds);
            bin_counts[b] += 1;
        }
        // Sweep from the right to get the cost of every right part, then from the left.
        let mut right_area = [0.0f32; BINS];
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for b in (1..BINS).rev() {
            acc = acc.union(bin_bounds[b]);
            count += bin_counts[b];
            right_area[b] = acc.surface_area() * count as f32;
        }
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for b in 0..BINS - 1 {
            acc = acc.union(bin_bounds[b]);
            count += bin_counts[b];
            if count == 0 || count == items.len() {
                continue;
            }
            let cost = acc.surface_area() * count as f32 + right_area[b + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    let (cost, axis, bin) = best?;
    let split_cost = TRAVERSAL_COST + cost / bounds.surface_area().max(f32::MIN_POSITIVE);
    if items.len() <= MAX_LEAF && split_cost >= items.len() as f32 {
        return None;
    }
    let mid = partition(items, |it| bin_of(it.centroid, axis) <= bin);
    Some(mid)
}

/// In-place partition; returns the number of items for which `left` holds (they come first).
fn partition(items: &mut [Item], left: impl Fn(&Item) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

fn flatten(node: &BuildNode, nodes: &mut Vec<Node>) {
    match node {
        BuildNode::Leaf { bounds, first, count } => {
            nodes.push(Node::new(*bounds, *first as u32, *count as u32));
        }
        BuildNode::Interior { bounds, children } => {
            let at = nodes.len();
            nodes.push(Node::new(*bounds, 0, 0));
            flatten(&children[0], nodes);
            nodes[at] = Node::new(*bounds, nodes.len() as u32, 0);
            flatten(&children[1], nodes);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{PlanarKind, Shape};
    use crate::sampling::{Sampler, uniform_sphere};

    /// Random small triangles and spheres in the unit cube, as a BVH would see a scene.
    fn random_shapes(n: usize) -> Vec<Shape> {
        let mut s = Sampler::new(1, 2, 3);
        let mut point = || Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
        (0..n)
            .map(|i| {
                let origin = point() * 2.0 - Vec3::ONE;
                if i % 5 == 0 {
                    Shape::Sphere { center: origin, radius: 0.05 * point().x + 0.001 }
                } else {
                    let (edge1, edge2) = ((point() - 0.5) * 0.2, (point() - 0.5) * 0.2);
                    let normal = edge1.cross(edge2).normalize();
                    Shape::Planar { kind: PlanarKind::Triangle, origin, edge1, edge2, normal }
                }
            })
            .collect()
    }

    #[test]
    fn closest_hit_equals_brute_force() {
        let shapes = random_shapes(3000);
        let bounds: Vec<Aabb> = shapes.iter().map(|s| s.bounds().unwrap()).collect();
        let (bvh, order) = Bvh::build(&bounds);
        let mut sorted: Vec<u32> = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..shapes.len() as u32).collect::<Vec<_>>(), "a permutation");
        let ordered: Vec<&Shape> = order.iter().map(|&i| &shapes[i as usize]).collect();
        let mut sampler = Sampler::new(9, 9, 9);
        let mut hits = 0;
        for _ in 0..2000 {
            let origin = uniform_sphere(sampler.next_2d()) * 1.5 * sampler.next_1d();
            let ray = Ray::new(origin, uniform_sphere(sampler.next_2d()));
            let brute = shapes
                .iter()
                .filter_map(|s| s.intersect(&ray, f32::INFINITY))
                .map(|h| h.t)
                .fold(f32::INFINITY, f32::min);
            let mut found = None;
            let test = |i: usize, t_max| {
                let hit = ordered[i].intersect(&ray, t_max)?;
                found = Some(i);
                Some(hit.t)
            };
            let t = bvh.closest(&ray, f32::INFINITY, test, |_| {});
            assert_eq!(t, brute);
            let occludes = |i: usize| ordered[i].intersect(&ray, f32::INFINITY).is_some();
            let any = bvh.any(&ray, f32::INFINITY, occludes, |_| {});
            assert_eq!(any, brute.is_finite());
            hits += usize::from(found.is_some());
        }
        assert!(hits > 500, "the test rays hit something ({hits})");
    }

    #[test]
    fn coincident_centroids_still_build_small_leaves() {
        let bounds = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 1000];
        let (bvh, order) = Bvh::build(&bounds);
        assert_eq!(order.len(), 1000);
        assert!(bvh.nodes.iter().all(|n| n.count() as usize <= 4 * MAX_LEAF));
    }
}
