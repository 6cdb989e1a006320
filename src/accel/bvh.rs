//! A bounding volume hierarchy: binned SAH build (in parallel), flattened depth-first nodes,
//! front-to-back traversal.

use std::ops::Range;

use arrayvec::ArrayVec;
use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A, Vec4};

use super::HugeArray;
use crate::aabb::Aabb;
use crate::ray::Ray;

const BINS: usize = 16;
const MAX_LEAF: usize = 4;
/// Cost of a binary split relative to one primitive test (SAH). Four-wide nodes test four boxes
/// at once, so a split costs about one test. (Measured with four-wide nodes: 1 renders S3, S5
/// and S6 3-4% faster than 2 and 1.5; 0.5 is no faster and builds S6 slower; 3 is 20% slower.)
const TRAVERSAL_COST: f32 = 1.0;
/// Below this many primitives a subtree is built on the current thread.
const PARALLEL_MIN: usize = 4096;
/// Past this depth splits are by median, which bounds the depth (and the traversal stack).
const SAH_MAX_DEPTH: usize = 48;
/// Deepest binary hierarchy: median splits take at most 24 more levels to bring
/// `MAX_PRIMITIVES` down to leaves.
const MAX_DEPTH: usize = SAH_MAX_DEPTH + 32;
/// A visit pushes at most four children and pops one; a node's nearest child may be only one
/// binary level down, so the stack grows by at most three per binary level.
const STACK_SIZE: usize = 3 * MAX_DEPTH + 1;

/// A link to a child: a node's index, or a leaf's groups of primitives (flag bit, count - 1 in
/// four bits, first group in the rest), or no child. A group is one primitive, or `width` of
/// them tested at once (see `Bvh::build`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
#[repr(transparent)]
struct Link(u32);

impl Link {
    const NONE: Link = Link(u32::MAX);
    const LEAF: u32 = 1 << 31;
    /// Leaves hold at most 16 groups, the first below 2^27.
    const FIRST_BITS: u32 = 27;

    fn leaf(first: usize, count: usize) -> Link {
        debug_assert!((1..=16).contains(&count) && first < 1 << Self::FIRST_BITS);
        Link(Self::LEAF | ((count as u32 - 1) << Self::FIRST_BITS) | first as u32)
    }

    /// The groups of a leaf, or `None` for a node. (Not for `NONE`, which callers skip.)
    #[inline]
    fn primitives(self) -> Option<Range<usize>> {
        (self.0 & Self::LEAF != 0).then(|| {
            let first = (self.0 & ((1 << Self::FIRST_BITS) - 1)) as usize;
            first..first + ((self.0 >> Self::FIRST_BITS) & 15) as usize + 1
        })
    }
}

/// Most primitives one hierarchy can hold (the leaf links' limit: groups are no more than
/// primitives).
pub const MAX_PRIMITIVES: usize = 1 << Link::FIRST_BITS;

/// 64 bytes, one cache line: up to four children, their boxes quantized to 8 bits per plane on
/// a grid over this node's box (`origin + q * step`, rounded outwards), as in Embree's and
/// Ylitie et al.'s compressed wide BVHs. Traversal of a large mesh waits on memory: half the
/// bytes per box and half the depth of a binary hierarchy of full boxes mean fewer waits.
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
#[repr(C, align(64))]
struct Node {
    origin: [f32; 3],
    step: [f32; 3],
    /// Per axis, per child: the grid cells of the box's lower and upper planes.
    lo: [[u8; 4]; 3],
    hi: [[u8; 4]; 3],
    children: [Link; 4],
}

impl Node {
    /// A node over `bounds` with the given children (at most four).
    fn new(bounds: Aabb, children: &[(Aabb, Link)]) -> Self {
        let mut node = Node {
            origin: bounds.min.to_array(),
            step: [0.0; 3],
            lo: [[u8::MAX; 4]; 3],
            hi: [[0; 4]; 3],
            children: [Link::NONE; 4],
        };
        for axis in 0..3 {
            let origin = node.origin[axis];
            // The smallest step whose grid reaches the upper bound.
            let mut step = (bounds.max[axis] - origin) / 255.0;
            while origin + 255.0 * step < bounds.max[axis] {
                step = f32::from_bits(step.to_bits() + 1); // the next float up (step >= 0)
            }
            node.step[axis] = step;
            // The same expression as `plane`, so the rounding is the same.
            let at = |q: u8| origin + f32::from(q) * step;
            let cell =
                |x: f32| if step > 0.0 { ((x - origin) / step).clamp(0.0, 255.0) } else { 0.0 };
            for (i, (b, _)) in children.iter().enumerate() {
                let mut lo = cell(b.min[axis]).floor() as u8;
                while lo > 0 && at(lo) > b.min[axis] {
                    lo -= 1;
                }
                let mut hi = cell(b.max[axis]).ceil() as u8;
                while hi < u8::MAX && at(hi) < b.max[axis] {
                    hi += 1;
                }
                node.lo[axis][i] = lo;
                node.hi[axis][i] = hi;
            }
        }
        for (slot, (_, link)) in node.children.iter_mut().zip(children) {
            *slot = *link;
        }
        node
    }

    /// The four children's planes on one axis, from their grid cells.
    #[inline]
    fn plane(&self, axis: usize, cells: &[u8; 4]) -> Vec4 {
        let cells = Vec4::new(
            f32::from(cells[0]),
            f32::from(cells[1]),
            f32::from(cells[2]),
            f32::from(cells[3]),
        );
        Vec4::splat(self.origin[axis]) + cells * self.step[axis]
    }

    /// Slab test of the four children at once: their entry distances, and a bit per child
    /// the ray meets within (0, t_max). Empty slots may have bits set too.
    #[inline]
    fn entries(&self, ray: &RayBox, t_max: f32) -> (Vec4, u32) {
        let mut near = Vec4::ZERO;
        let mut far = Vec4::splat(t_max);
        for axis in 0..3 {
            let (entry, exit) = if ray.positive[axis] {
                (&self.lo[axis], &self.hi[axis])
            } else {
                (&self.hi[axis], &self.lo[axis])
            };
            let (o, inv_dir) = (ray.origin[axis], ray.inv_dir[axis]);
            // A NaN (a ray in a slab's plane, 0 * inf) is on the left of max/min, which with
            // SSE's maxps/minps returns the right operand: that slab is ignored.
            near = ((self.plane(axis, entry) - o) * inv_dir).max(near);
            far = ((self.plane(axis, exit) - o) * inv_dir).min(far);
        }
        // Ize, "Robust BVH ray traversal" (2013): exit distances scaled by 1 + 2 gamma(3) keep
        // the test conservative under rounding.
        (near, near.cmple(far * ROBUST_EXIT).bitmask())
    }

    /// A child's box as traversal sees it.
    #[cfg(test)]
    fn child_bounds(&self, i: usize) -> Aabb {
        let plane = |axis: usize, cells: &[[u8; 4]; 3]| self.plane(axis, &cells[axis])[i];
        Aabb {
            min: Vec3::new(plane(0, &self.lo), plane(1, &self.lo), plane(2, &self.lo)),
            max: Vec3::new(plane(0, &self.hi), plane(1, &self.hi), plane(2, &self.hi)),
        }
    }
}

/// 1 + 2 gamma(3), gamma(n) = n u / (1 - n u) with u the unit roundoff (pbrt's error bounds).
const ROBUST_EXIT: f32 = {
    let gamma3 = 3.0 * f32::EPSILON * 0.5 / (1.0 - 3.0 * f32::EPSILON * 0.5);
    1.0 + 2.0 * gamma3
};

/// What the slab tests need of a ray, in `Vec3A` as the ray is. (When a `Vec3` was converted
/// here, LLVM loaded 16 bytes and multiplied the stray fourth lane, a denormal: a microcode
/// assist that made S3 30% slower in a trial build.)
struct RayBox {
    origin: Vec3A,
    inv_dir: Vec3A,
    /// Per axis, whether the ray goes towards +: the lower plane is then the one it enters by.
    positive: [bool; 3],
}

impl RayBox {
    fn new(ray: &Ray) -> Self {
        let inv_dir = ray.dir.recip();
        let positive = inv_dir.to_array().map(|d| d >= 0.0);
        RayBox { origin: ray.origin, inv_dir, positive }
    }

    /// Slab test of one full-precision box: whether the ray meets it within (0, t_max).
    #[inline]
    fn enters(&self, bounds: &Aabb, t_max: f32) -> bool {
        let t0 = (Vec3A::from(bounds.min) - self.origin) * self.inv_dir;
        let t1 = (Vec3A::from(bounds.max) - self.origin) * self.inv_dir;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max) * ROBUST_EXIT;
        near <= far
    }
}

#[derive(Debug)]
pub struct Bvh {
    nodes: HugeArray<Node>,
    /// The whole hierarchy: a node, or for a few primitives a leaf (no node at all).
    root: Link,
    bounds: Aabb,
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

impl BuildNode {
    fn bounds(&self) -> Aabb {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => *bounds,
        }
    }
}

impl Bvh {
    /// Builds over the given boxes (at most `MAX_PRIMITIVES`) for primitives tested `width` at
    /// a time. Returns the hierarchy and the order in which the primitives must be stored, in
    /// groups of `width` slots, a leaf's last group padded with `None`: leaf ranges index the
    /// groups.
    pub fn build(bounds: &[Aabb], width: usize) -> (Bvh, Vec<Option<u32>>) {
        assert!(bounds.len() <= MAX_PRIMITIVES, "callers check the primitive count");
        let mut items: Vec<Item> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| Item { bounds: *b, centroid: b.centroid(), index: i as u32 })
            .collect();
        let mut nodes = Vec::with_capacity(items.len() / MAX_LEAF + 1);
        let mut order = Vec::with_capacity(items.len());
        let (root, bounds) = if items.is_empty() {
            (Link::NONE, Aabb::EMPTY)
        } else {
            // Two primitives are one leaf: their own tests cost less than decoding a node
            // (measured: S1 and S2, two spheres, 10% faster than a node over two leaves). Only
            // the root needs this: below it, leaves share their parent's four-wide node.
            let root = if items.len() <= 2 {
                let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
                BuildNode::Leaf { bounds, first: 0, count: items.len() }
            } else {
                build_node(&mut items, 0, 0, width)
            };
            let mut flat = Flattened { nodes: &mut nodes, items: &items, order: &mut order, width };
            (flat.link_of(&root), root.bounds())
        };
        (Bvh { nodes: HugeArray::new(nodes), root, bounds }, order)
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Closest-hit traversal. `hit(i, t_max)` tests group `i` and returns the distance of its
    /// closest primitive hit before `t_max`, if any; the closest such distance is returned.
    /// `preload(range)` is told of the groups of a leaf the ray will visit, to start loading
    /// them (see `prefetch`).
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    pub fn closest(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut hit: impl FnMut(usize, f32) -> Option<f32>,
        preload: impl Fn(Range<usize>),
    ) -> f32 {
        let ray = RayBox::new(ray);
        let Some(mut link) = self.start(&ray, t_max) else {
            return t_max;
        };
        let nodes = &*self.nodes;
        // Children still to visit, with the distance at which the ray enters them: one entered
        // beyond the closest hit found since it was pushed is skipped. (Not zero-filled: rays
        // are many and most of the stack is never touched.)
        let mut stack = ArrayVec::<(Link, f32), STACK_SIZE>::new();
        loop {
            match link.primitives() {
                Some(primitives) => {
                    for i in primitives {
                        if let Some(t) = hit(i, t_max) {
                            t_max = t;
                        }
                    }
                }
                None => {
                    let node = &nodes[link.0 as usize];
                    let (enter, mask) = node.entries(&ray, t_max);
                    let enter = enter.to_array();
                    if mask.is_power_of_two() {
                        // One child met (most visits on a mesh): on to it, as if it were pushed
                        // and popped.
                        let i = mask.trailing_zeros() as usize;
                        if node.children[i] != Link::NONE && enter[i] < t_max {
                            link = node.children[i];
                            continue;
                        }
                    } else {
                        // The children met go on the stack farthest first, in the order of a
                        // stable sort (entry distances are never NaN or -0); the nearest is
                        // popped next.
                        let base = stack.len();
                        for i in hits(mask) {
                            if node.children[i] != Link::NONE {
                                warm(nodes, node.children[i], &preload);
                                let mut at = stack.len();
                                stack.push((node.children[i], enter[i]));
                                while at > base && stack[at - 1].1 < enter[i] {
                                    stack.swap(at - 1, at);
                                    at -= 1;
                                }
                            }
                        }
                    }
                }
            }
            loop {
                let Some((next, enter)) = stack.pop() else {
                    return t_max;
                };
                if enter < t_max {
                    link = next;
                    break;
                }
            }
        }
    }

    /// Where a traversal starts: the root, unless there is none or it is a leaf the ray misses
    /// the box of. (A root node tests its children's boxes itself.)
    #[inline]
    fn start(&self, ray: &RayBox, t_max: f32) -> Option<Link> {
        match self.root {
            Link::NONE => None,
            root if root.primitives().is_some() => ray.enters(&self.bounds, t_max).then_some(root),
            root => Some(root),
        }
    }

    /// Any-hit traversal for shadow rays: stops at the first group for which `hit` is true.
    /// `preload` as for `closest`.
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    pub fn any(
        &self,
        ray: &Ray,
        t_max: f32,
        mut hit: impl FnMut(usize) -> bool,
        preload: impl Fn(Range<usize>),
    ) -> bool {
        let ray = RayBox::new(ray);
        let Some(mut link) = self.start(&ray, t_max) else {
            return false;
        };
        let nodes = &*self.nodes;
        let mut stack = ArrayVec::<Link, STACK_SIZE>::new();
        loop {
            match link.primitives() {
                Some(mut primitives) => {
                    if primitives.any(&mut hit) {
                        return true;
                    }
                }
                None => {
                    let node = &nodes[link.0 as usize];
                    let (_, mask) = node.entries(&ray, t_max);
                    // One child met: on to it, as if it were pushed and popped.
                    if mask.is_power_of_two()
                        && node.children[mask.trailing_zeros() as usize] != Link::NONE
                    {
                        link = node.children[mask.trailing_zeros() as usize];
                        continue;
                    }
                    for i in hits(mask) {
                        if node.children[i] != Link::NONE {
                            warm(nodes, node.children[i], &preload);
                            stack.push(node.children[i]);
                        }
                    }
                }
            }
            match stack.pop() {
                Some(next) => link = next,
                None => return false,
            }
        }
    }
}

/// Starts loading what visiting a child the ray meets will read: its node, or its leaf's
/// primitives, so that the loads overlap with the work on the other children.
#[inline]
fn warm(nodes: &[Node], child: Link, preload: &impl Fn(Range<usize>)) {
    match child.primitives() {
        Some(primitives) => preload(primitives),
        None => super::prefetch(&nodes[child.0 as usize]),
    }
}

/// The indices of the set bits of a mask, lowest first.
#[inline]
fn hits(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            i
        })
    })
}

/// The flat hierarchy as it is written.
struct Flattened<'a> {
    nodes: &'a mut Vec<Node>,
    /// In the build's order: each leaf a range of them.
    items: &'a [Item],
    order: &'a mut Vec<Option<u32>>,
    width: usize,
}

impl Flattened<'_> {
    /// Flattens a subtree depth first and returns its link. A node takes up to four children
    /// by opening the binary hierarchy's largest interior children. A leaf's primitives go to
    /// `order` in groups of `width`.
    fn link_of(&mut self, node: &BuildNode) -> Link {
        let (bounds, children) = match node {
            BuildNode::Leaf { first, count, .. } => {
                let group = self.order.len() / self.width;
                let items = &self.items[*first..first + count];
                self.order.extend(items.iter().map(|it| Some(it.index)));
                let groups = count.div_ceil(self.width);
                self.order.resize(self.width * (group + groups), None);
                return Link::leaf(group, groups);
            }
            BuildNode::Interior { bounds, children } => (bounds, children),
        };
        let mut wide: ArrayVec<&BuildNode, 4> = children.iter().collect();
        while wide.len() < 4 {
            let largest = (0..wide.len())
                .filter(|&i| matches!(wide[i], BuildNode::Interior { .. }))
                .max_by(|&i, &j| {
                    wide[i].bounds().surface_area().total_cmp(&wide[j].bounds().surface_area())
                });
            let Some(i) = largest else { break };
            if let BuildNode::Interior { children, .. } = wide[i] {
                wide[i] = &children[0];
                wide.insert(i + 1, &children[1]);
            }
        }
        let at = self.nodes.len();
        self.nodes.push(Node::new(*bounds, &[]));
        let links: ArrayVec<(Aabb, Link), 4> =
            wide.iter().map(|child| (child.bounds(), self.link_of(child))).collect();
        self.nodes[at] = Node::new(*bounds, &links);
        Link(at as u32)
    }
}

/// Subtrees of up to `width` primitives are leaves: their group's test costs what one
/// primitive's does, and a split would add a node's test to it.
fn build_node(items: &mut [Item], first: usize, depth: usize, width: usize) -> BuildNode {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    if items.len() <= width {
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
            || build_node(left, first, depth + 1, width),
            || build_node(right, first + mid, depth + 1, width),
        )
    } else {
        (
            build_node(left, first, depth + 1, width),
            build_node(right, first + mid, depth + 1, width),
        )
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Planar, PlanarKind, Shape};
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
                    Shape::Planar(Planar {
                        kind: PlanarKind::Triangle,
                        origin,
                        edge1,
                        edge2,
                        normal,
                        hole: 0.0,
                    })
                }
            })
            .collect()
    }

    /// Primitives one at a time, and in groups of four (with padding in their leaves' last
    /// groups) as meshes store them.
    #[test]
    fn closest_hit_equals_brute_force() {
        let shapes = random_shapes(3000);
        let bounds: Vec<Aabb> = shapes.iter().map(|s| s.bounds().unwrap()).collect();
        for width in [1, 4] {
            let (bvh, order) = Bvh::build(&bounds, width);
            assert_eq!(order.len() % width, 0);
            let mut sorted: Vec<u32> = order.iter().flatten().copied().collect();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..shapes.len() as u32).collect::<Vec<_>>(), "a permutation");
            let ordered: Vec<Option<&Shape>> =
                order.iter().map(|i| i.map(|i| &shapes[i as usize])).collect();
            let group = |i: usize| ordered[width * i..width * (i + 1)].iter().flatten();
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
                let test = |i: usize, t_max: f32| {
                    let mut t = None;
                    for shape in group(i) {
                        if let Some(hit) = shape.intersect(&ray, t.unwrap_or(t_max)) {
                            (found, t) = (Some(i), Some(hit.t));
                        }
                    }
                    t
                };
                let t = bvh.closest(&ray, f32::INFINITY, test, |_| {});
                assert_eq!(t, brute);
                let occludes =
                    |i: usize| group(i).any(|s| s.intersect(&ray, f32::INFINITY).is_some());
                let any = bvh.any(&ray, f32::INFINITY, occludes, |_| {});
                assert_eq!(any, brute.is_finite());
                hits += usize::from(found.is_some());
            }
            assert!(hits > 500, "the test rays hit something ({hits})");
        }
    }

    /// Boxes shrinking geometrically towards a point make SAH peel off one at a time: a comb as
    /// deep as the build allows, with up to four children met per node. A ray through all of
    /// them must test every one, without overflowing the traversal stack.
    #[test]
    fn a_comb_of_maximal_depth_is_traversed_completely() {
        let bounds: Vec<Aabb> = (0..120)
            .map(|i| {
                let (center, size) = (Vec3::X * 0.5f32.powi(i), Vec3::splat(0.4 * 0.5f32.powi(i)));
                Aabb { min: center - size, max: center + size }
            })
            .collect();
        let (bvh, _) = Bvh::build(&bounds, 1);
        fn depth(bvh: &Bvh, link: Link) -> usize {
            match link.primitives() {
                Some(_) => 0,
                None => {
                    let children = bvh.nodes[link.0 as usize].children;
                    1 + children
                        .iter()
                        .filter(|&&c| c != Link::NONE)
                        .map(|&c| depth(bvh, c))
                        .max()
                        .unwrap_or(0)
                }
            }
        }
        assert!(
            depth(&bvh, bvh.root) >= SAH_MAX_DEPTH / 2,
            "a deep comb: {}",
            depth(&bvh, bvh.root)
        );
        let ray = Ray::new(Vec3::new(-2.0, 0.0, 0.0), Vec3::X);
        let mut tested = 0;
        bvh.closest(
            &ray,
            f32::INFINITY,
            |_, _| {
                tested += 1;
                None
            },
            |_| {},
        );
        assert_eq!(tested, bounds.len(), "closest tests every primitive");
        let mut tested = 0;
        assert!(!bvh.any(
            &ray,
            f32::INFINITY,
            |_| {
                tested += 1;
                false
            },
            |_| {}
        ));
        assert_eq!(tested, bounds.len(), "any tests every primitive");
    }

    /// No primitives: nothing is tested. A few: one leaf and no node, behind the box test.
    #[test]
    fn empty_and_single_leaf_hierarchies() {
        let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        let (empty, _) = Bvh::build(&[], 1);
        assert_eq!(empty.closest(&ray, 7.0, |_, _| panic!("nothing to test"), |_| {}), 7.0);
        assert!(!empty.any(&ray, 7.0, |_| panic!("nothing to test"), |_| {}));

        let unit = Aabb { min: Vec3::ZERO, max: Vec3::ONE };
        let (leaf, order) = Bvh::build(&[unit, unit], 1);
        assert!(leaf.nodes.is_empty() && leaf.root.primitives().is_some());
        assert_eq!(order.len(), 2);
        let mut tested = Vec::new();
        let t = leaf.closest(
            &ray,
            7.0,
            |i, t_max| {
                tested.push(i);
                let t = 2.0 - i as f32;
                (t < t_max).then_some(t)
            },
            |_| {},
        );
        assert_eq!((t, tested), (1.0, vec![0, 1]));
        assert!(leaf.any(&ray, 7.0, |_| true, |_| {}));
        let away = Ray::new(Vec3::new(0.5, 2.0, -1.0), Vec3::Z);
        assert!(!leaf.any(&away, 7.0, |_| panic!("the box is missed"), |_| {}));
    }

    #[test]
    fn coincident_centroids_still_build_small_leaves() {
        let bounds = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 1000];
        let (bvh, order) = Bvh::build(&bounds, 1);
        assert_eq!(order.len(), 1000);
        let leaves = leaf_ranges(&bvh);
        assert!(leaves.iter().all(|r| r.len() <= 4 * MAX_LEAF));
        assert_eq!(leaves.iter().map(Range::len).sum::<usize>(), 1000);
    }

    /// The leaves' primitive ranges, depth first.
    fn leaf_ranges(bvh: &Bvh) -> Vec<Range<usize>> {
        fn walk(bvh: &Bvh, link: Link, out: &mut Vec<Range<usize>>) {
            match link.primitives() {
                Some(primitives) => out.push(primitives),
                None => {
                    for child in bvh.nodes[link.0 as usize].children {
                        if child != Link::NONE {
                            walk(bvh, child, out);
                        }
                    }
                }
            }
        }
        let mut out = Vec::new();
        walk(bvh, bvh.root, &mut out);
        out
    }

    /// Every quantized child box holds the boxes of all the primitives below it, and every
    /// primitive is in exactly one leaf.
    #[test]
    fn quantized_boxes_hold_their_subtrees() {
        let shapes = random_shapes(5000);
        let bounds: Vec<Aabb> = shapes.iter().map(|s| s.bounds().unwrap()).collect();
        let (bvh, order) = Bvh::build(&bounds, 1);
        let ordered: Vec<Aabb> = order.iter().flatten().map(|&i| bounds[i as usize]).collect();
        fn check(bvh: &Bvh, link: Link, ordered: &[Aabb]) -> Aabb {
            match link.primitives() {
                Some(primitives) => {
                    ordered[primitives].iter().fold(Aabb::EMPTY, |b, p| b.union(*p))
                }
                None => {
                    let node = &bvh.nodes[link.0 as usize];
                    let mut all = Aabb::EMPTY;
                    for (i, child) in node.children.into_iter().enumerate() {
                        if child == Link::NONE {
                            continue;
                        }
                        let exact = check(bvh, child, ordered);
                        let quantized = node.child_bounds(i);
                        assert!(
                            quantized.min.cmple(exact.min).all()
                                && quantized.max.cmpge(exact.max).all(),
                            "{quantized:?} holds {exact:?}"
                        );
                        all = all.union(exact);
                    }
                    all
                }
            }
        }
        let all = check(&bvh, bvh.root, &ordered);
        assert_eq!(all.min, bvh.bounds().min);
        assert_eq!(all.max, bvh.bounds().max);
        let mut covered: Vec<usize> = leaf_ranges(&bvh).into_iter().flatten().collect();
        covered.sort_unstable();
        assert_eq!(covered, (0..5000).collect::<Vec<_>>());
        assert!(bvh.nodes.len() < 5000 / 2, "four-wide nodes: {}", bvh.nodes.len());
    }
}
