//! Constructive solid geometry: one bounded primitive whose surface is made of parts of its
//! operands' surfaces. Along a ray each operand answers where it is crossed (`Crossings`); the
//! operation composes those answers into the result's crossings, the first of which is the hit.
//! The operands are world-space solids (transforms are applied when the scene is built), so a
//! tree of nested CSG, instances and transforms is one flat list of operands under a tree of
//! operations.

use arrayvec::ArrayVec;
use glam::Vec3;

use super::crossings::{Crossing, Crossings};
use super::shape::Intersection;
use super::{Aabb, Hit, Ray, Shape};

/// How a CSG node combines its children.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CsgOp {
    /// Inside every child.
    Intersection,
    /// Inside the first child and none of the others.
    Difference,
    /// Inside any child (the union's outer surface only).
    Merge,
    /// Outside every child: the complement of their merge (POV-Ray's `inverse`, which turns
    /// inside out).
    Inverse,
    /// The first child's surface where it is inside all the others, whose own surfaces are not
    /// part of it (POV-Ray's `clipped_by`: the result is open where they cut it).
    Clip,
}

impl CsgOp {
    /// Whether a point is inside `op(a, b)`, given that it is inside `a` (the children folded
    /// so far: for `Inverse` the first child already turned inside out) and inside `b`.
    fn combine(self, a: bool, b: bool) -> bool {
        match self {
            CsgOp::Intersection | CsgOp::Clip => a && b,
            CsgOp::Difference | CsgOp::Inverse => a && !b,
            CsgOp::Merge => a || b,
        }
    }
}

/// A node of the tree of operations: an operand (index into `Csg::operands`) or an operation
/// on nodes, folded left to right.
#[derive(Debug, Clone)]
pub enum CsgNode {
    Operand(u32),
    Operation { op: CsgOp, children: Vec<CsgNode> },
}

#[derive(Debug, Clone)]
pub struct Csg {
    pub root: CsgNode,
    /// World-space solids; none is itself a CSG.
    pub operands: Vec<Shape>,
    /// Index of the first of the scene's primitives that stand for the operands' surfaces
    /// (material and texture space), in operand order: a hit on operand i is named
    /// `surfaces + i`.
    pub surfaces: u32,
    bounds: Option<Aabb>,
}

impl Csg {
    /// Set in `Intersection::part` when the operand's normal is turned (a subtracted operand's
    /// surface faces into the cut).
    pub const TURNED: u32 = 1 << 31;

    pub fn new(root: CsgNode, operands: Vec<Shape>) -> Self {
        let bounds = node_bounds(&root, &operands);
        Csg { root, operands, surfaces: 0, bounds }
    }

    /// `None` when the solid is unbounded (e.g. it merges a half-space).
    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    /// The operand an intersection is on.
    pub fn operand(at: &Intersection) -> u32 {
        at.part & !Csg::TURNED
    }

    pub fn intersection(&self, ray: &Ray, t_max: f32) -> Option<Intersection> {
        let crossings = self.node_crossings(&self.root, ray, t_max);
        crossings.list.first().map(|c| {
            let turned = if c.entering != c.entering_operand { Csg::TURNED } else { 0 };
            Intersection { part: c.at.part | turned, ..c.at }
        })
    }

    pub fn hit(&self, ray: &Ray, at: &Intersection) -> Hit {
        let operand = &self.operands[Csg::operand(at) as usize];
        let hit = operand.hit(ray, &Intersection { part: 0, ..*at });
        if at.part & Csg::TURNED != 0 {
            Hit { normal: -hit.normal, shading_normal: -hit.shading_normal, ..hit }
        } else {
            hit
        }
    }

    pub fn crossings(&self, ray: &Ray, t_max: f32) -> Crossings {
        let mut crossings = self.node_crossings(&self.root, ray, t_max);
        // Seen from outside, this solid's crossings are its own (normals as its result's).
        for c in &mut crossings.list {
            if c.entering != c.entering_operand {
                c.at.part |= Csg::TURNED;
            }
        }
        crossings
    }

    pub fn contains(&self, p: Vec3) -> bool {
        self.node_contains(&self.root, p)
    }

    fn node_contains(&self, node: &CsgNode, p: Vec3) -> bool {
        match node {
            CsgNode::Operand(i) => self.operands[*i as usize].contains(p),
            CsgNode::Operation { op, children } => {
                let mut inside = children.iter().map(|c| self.node_contains(c, p));
                let first = inside.next().unwrap_or(false) != (*op == CsgOp::Inverse);
                inside.fold(first, |acc, b| op.combine(acc, b))
            }
        }
    }

    fn node_crossings(&self, node: &CsgNode, ray: &Ray, t_max: f32) -> Crossings {
        match node {
            CsgNode::Operand(i) => {
                let mut crossings = self.operands[*i as usize].crossings(ray, t_max);
                for c in &mut crossings.list {
                    c.at.part = *i;
                }
                crossings
            }
            CsgNode::Operation { op, children } => {
                let mut children = children.iter();
                let Some(first) = children.next() else { return Crossings::outside() };
                let mut acc = self.node_crossings(first, ray, t_max);
                if *op == CsgOp::Inverse {
                    acc.inside_at_start = !acc.inside_at_start;
                    for c in &mut acc.list {
                        c.entering = !c.entering;
                    }
                }
                for child in children {
                    // Nothing more can enter an intersection or a difference that is empty.
                    if *op != CsgOp::Merge && !acc.inside_at_start && acc.list.is_empty() {
                        return acc;
                    }
                    acc = combine(*op, &acc, &self.node_crossings(child, ray, t_max));
                }
                acc
            }
        }
    }
}

/// Crossings of the two operands closer than this, relative to their distance, are one
/// crossing of coincident surfaces (about 32 units in the last place: what two transforms of one
/// face round to).
const COINCIDENT: f32 = 32.0 * f32::EPSILON;

/// The crossings of `op(a, b)`: walk both lists in order, keeping the crossings where the
/// result changes between inside and outside. Crossings of coincident surfaces (operands that
/// share a face) are taken together, and count only if together they change the result: one
/// after the other, in whatever order their rounding puts them, they made a sliver of the
/// result between them (a box less a box sharing its faces showed those faces).
fn combine(op: CsgOp, a: &Crossings, b: &Crossings) -> Crossings {
    let (mut in_a, mut in_b) = (a.inside_at_start, b.inside_at_start);
    let mut inside = op.combine(in_a, in_b);
    let mut out = Crossings { inside_at_start: inside, list: ArrayVec::new() };
    let (mut i, mut j) = (0, 0);
    let next_t = |i: usize, j: usize| {
        let t = |list: &[Crossing], k: usize| list.get(k).map_or(f32::INFINITY, |c| c.at.t);
        t(&a.list, i).min(t(&b.list, j))
    };
    while i < a.list.len() || j < b.list.len() {
        let first = next_t(i, j);
        let together = first + COINCIDENT * first.abs();
        // The last crossing of the group that changed the result (and whether it is a's): its
        // surface is the one seen.
        let mut changed_by = None;
        loop {
            let before = op.combine(in_a, in_b);
            let take_a =
                j == b.list.len() || (i < a.list.len() && a.list[i].at.t <= b.list[j].at.t);
            let crossing: Crossing = if take_a {
                in_a = a.list[i].entering;
                i += 1;
                a.list[i - 1]
            } else {
                in_b = b.list[j].entering;
                j += 1;
                b.list[j - 1]
            };
            if op.combine(in_a, in_b) != before {
                changed_by = Some((crossing, take_a));
            }
            // (At least one crossing a turn, so a NaN distance cannot stall the walk.)
            let more = i < a.list.len() || j < b.list.len();
            if !(more && next_t(i, j) <= together) {
                break;
            }
        }
        let now = op.combine(in_a, in_b);
        if let (true, Some((crossing, of_a))) = (now != inside, changed_by) {
            inside = now;
            // A clipping solid's surface is not the result's: the result is open there.
            let surface = of_a || op != CsgOp::Clip;
            if surface && out.list.try_push(Crossing { entering: now, ..crossing }).is_err() {
                break;
            }
        }
    }
    out
}

fn node_bounds(node: &CsgNode, operands: &[Shape]) -> Option<Aabb> {
    match node {
        CsgNode::Operand(i) => operands[*i as usize].bounds(),
        CsgNode::Operation { op, children } => {
            let mut bounds = children.iter().map(|c| node_bounds(c, operands));
            match op {
                CsgOp::Difference => bounds.next().flatten(),
                CsgOp::Merge => bounds.try_fold(Aabb::EMPTY, |acc, b| Some(acc.union(b?))),
                // Everything outside a bounded solid is unbounded.
                CsgOp::Inverse => None,
                CsgOp::Intersection | CsgOp::Clip => bounds
                    .flatten()
                    .reduce(|a, b| Aabb { min: a.min.max(b.min), max: a.max.min(b.max) }),
            }
        }
    }
}
