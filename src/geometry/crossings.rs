//! What a solid answers besides its closest hit: where a ray crosses its surface, in order,
//! and whether the ray starts inside. CSG (`csg.rs`) composes these answers.

use arrayvec::ArrayVec;

use super::shape::Intersection;

/// At most this many crossings of one solid (or CSG subtree) are kept along a ray segment;
/// later ones are dropped (only a mesh or a deep CSG tree can have more).
pub const MAX_CROSSINGS: usize = 32;

/// Where a ray crosses a solid's surface: the intersection (on the operand that owns the
/// surface), whether the ray goes into the solid there, and whether it goes into that operand
/// (the two differ on a surface of a subtracted operand, whose normal is then turned).
#[derive(Debug, Clone, Copy)]
pub struct Crossing {
    pub at: Intersection,
    pub entering: bool,
    pub entering_operand: bool,
}

/// A solid along a ray segment (0, t_max): whether the segment starts inside, and its
/// crossings in order (each one toggles inside and outside).
#[derive(Debug, Clone)]
pub struct Crossings {
    pub inside_at_start: bool,
    pub list: ArrayVec<Crossing, MAX_CROSSINGS>,
}

impl Crossings {
    pub fn outside() -> Self {
        Crossings { inside_at_start: false, list: ArrayVec::new() }
    }

    /// A convex solid met along the whole line from `t_in` to `t_out`.
    #[inline]
    pub fn convex(
        t_in: f32,
        t_out: f32,
        t_max: f32,
        at_in: impl FnOnce() -> Intersection,
        at_out: impl FnOnce() -> Intersection,
    ) -> Self {
        let mut crossings =
            Crossings { inside_at_start: t_in <= 0.0 && t_out > 0.0, list: ArrayVec::new() };
        if t_in > 0.0 && t_in < t_max {
            crossings.push(at_in(), true);
        }
        if t_out > 0.0 && t_out < t_max {
            crossings.push(at_out(), false);
        }
        crossings
    }

    /// A convex solid whose surface the ray's whole line meets at `roots` (in order), if at all.
    pub fn between(roots: Option<(f32, f32)>, t_max: f32) -> Self {
        match roots {
            Some((t0, t1)) => {
                Crossings::convex(t0, t1, t_max, || Intersection::at(t0), || Intersection::at(t1))
            }
            None => Crossings::outside(),
        }
    }

    /// All the roots along the whole line of a bounded solid's surface, in order: the ray is
    /// outside before the first.
    pub fn from_roots(roots: &[f32], t_max: f32, at: impl Fn(f32) -> Intersection) -> Self {
        let before = roots.iter().filter(|&&t| t <= 0.0).count();
        let ahead = roots.iter().filter(|&&t| t > 0.0 && t < t_max).map(|&t| at(t));
        Crossings::alternating(before % 2 == 1, ahead)
    }

    /// Crossings that enter and leave in turn, from inside or outside at the ray's start.
    pub fn alternating(
        inside_at_start: bool,
        ahead: impl IntoIterator<Item = Intersection>,
    ) -> Self {
        let mut crossings = Crossings { inside_at_start, list: ArrayVec::new() };
        let mut inside = inside_at_start;
        for at in ahead {
            inside = !inside;
            crossings.push(at, inside);
        }
        crossings
    }

    #[inline]
    pub fn push(&mut self, at: Intersection, entering: bool) {
        let crossing = Crossing { at, entering, entering_operand: entering };
        let _ = self.list.try_push(crossing);
    }
}
