//! Lanes: paths, rays and hits traced together, one per SIMD lane: eight where the CPU has AVX2
//! (`wide::f32x8`), else four (`Vec4`), so one SIMD operation does the work of that many scalar
//! ones. Kernels are written once over `Real` and `Vector`: `f32` is their one-ray instance and
//! `Floats` their lanes, so a lane computes exactly what one ray alone would. (`Vector<f32>` rounds as glam's `Vec3`: same
//! operations in the same order.) Below the shapes and the acceleration structures, which both
//! work in lanes.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::{BVec4A, Vec3, Vec4};
use wide::{f32x8, f32x16};

use crate::ray::{Hit, Ray};

/// A number per lane: eight where the CPU has AVX2 (AVX-512 too: sixteen lanes, `f32x16`, were
/// timed against eight on S1–S3 without a settled gain, docs/benchmarks.md), four elsewhere.
#[cfg(target_feature = "avx2")]
pub type Floats = f32x8;
#[cfg(not(target_feature = "avx2"))]
pub type Floats = Vec4;

/// A bit per lane.
pub type Mask = <Floats as Real>::Mask;

/// Paths, rays and shadow rays traced together.
pub const LANES: usize = <Floats as Wide>::WIDTH;

/// Three coordinates per lane.
pub type Vec3Lanes = Vector<Floats>;

/// A `Real` of several lanes, read and written one lane at a time.
pub trait Wide: Real<Mask: MaskLanes> + Lane<f32> {
    const WIDTH: usize;
    /// The lanes `lane(0)`, `lane(1)`, ...
    fn from_fn(lane: impl FnMut(usize) -> f32) -> Self;
}

/// A bit per lane of a `Wide`.
pub trait MaskLanes: Copy + Lane<bool> {
    /// No lane set.
    fn none() -> Self;
    fn any(self) -> bool;
    /// Bit `i` is lane `i`'s.
    fn bitmask(self) -> u32;
}

/// The arithmetic of a kernel written once: one number (`f32`, `f64`, whose mask is a `bool`)
/// or a number per lane (`Vec4`, whose mask has a bit per lane). Comparisons are IEEE's: false
/// where a NaN takes part, so a NaN distance is never a hit.
pub trait Real:
    Copy
    + Neg<Output = Self>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    type Mask: Copy
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;
    const ZERO: Self;
    const ONE: Self;
    const NAN: Self;
    fn splat(value: f32) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// 1 with the sign of `self` (-1 for -0), NaN for NaN: `f32::signum`.
    fn signum(self) -> Self;
    fn gt(self, rhs: Self) -> Self::Mask;
    fn lt(self, rhs: Self) -> Self::Mask;
    fn ge(self, rhs: Self) -> Self::Mask;
    fn le(self, rhs: Self) -> Self::Mask;
    fn eq(self, rhs: Self) -> Self::Mask;
    fn ne(self, rhs: Self) -> Self::Mask;
    /// Per lane, `if_true` where `mask` is set, else `if_false`.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
}

/// `Real` for one number of a primitive float type.
macro_rules! real_for_float {
    ($t:ty) => {
        impl Real for $t {
            type Mask = bool;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const NAN: Self = <$t>::NAN;
            #[inline]
            fn splat(value: f32) -> Self {
                value.into()
            }
            #[inline]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline]
            fn signum(self) -> Self {
                <$t>::signum(self)
            }
            #[inline]
            fn gt(self, rhs: Self) -> bool {
                self > rhs
            }
            #[inline]
            fn lt(self, rhs: Self) -> bool {
                self < rhs
            }
            #[inline]
            fn ge(self, rhs: Self) -> bool {
                self >= rhs
            }
            #[inline]
            fn le(self, rhs: Self) -> bool {
                self <= rhs
            }
            #[inline]
            fn eq(self, rhs: Self) -> bool {
                self == rhs
            }
            #[inline]
            fn ne(self, rhs: Self) -> bool {
                self != rhs
            }
            #[inline]
            fn select(mask: bool, if_true: Self, if_false: Self) -> Self {
                if mask { if_true } else { if_false }
            }
        }
    };
}

real_for_float!(f32);
real_for_float!(f64);

impl Real for Vec4 {
    type Mask = BVec4A;
    const ZERO: Self = Vec4::ZERO;
    const ONE: Self = Vec4::ONE;
    const NAN: Self = Vec4::NAN;
    #[inline]
    fn splat(value: f32) -> Self {
        Vec4::splat(value)
    }
    #[inline]
    fn sqrt(self) -> Self {
        Vec4::sqrt(self)
    }
    #[inline]
    fn abs(self) -> Self {
        Vec4::abs(self)
    }
    #[inline]
    fn signum(self) -> Self {
        Vec4::signum(self)
    }
    #[inline]
    fn gt(self, rhs: Self) -> BVec4A {
        self.cmpgt(rhs)
    }
    #[inline]
    fn lt(self, rhs: Self) -> BVec4A {
        self.cmplt(rhs)
    }
    #[inline]
    fn ge(self, rhs: Self) -> BVec4A {
        self.cmpge(rhs)
    }
    #[inline]
    fn le(self, rhs: Self) -> BVec4A {
        self.cmple(rhs)
    }
    #[inline]
    fn eq(self, rhs: Self) -> BVec4A {
        self.cmpeq(rhs)
    }
    #[inline]
    fn ne(self, rhs: Self) -> BVec4A {
        self.cmpne(rhs)
    }
    #[inline]
    fn select(mask: BVec4A, if_true: Self, if_false: Self) -> Self {
        Vec4::select(mask, if_true, if_false)
    }
}

/// One lane of a vector of lanes. It is read from memory at the lane's offset (glam's `Index`
/// matches on the lane), and written by a select with the lane's mask, so the vector is
/// written whole: a scalar store into a vector that is then loaded whole cannot be forwarded
/// to that load, which waits for the store to reach the cache (writing lanes this way made S3
/// and S4 5% faster).
pub trait Lane<T> {
    fn lane(&self, lane: usize) -> T;
    fn set_lane(&mut self, lane: usize, value: T);
}

/// The mask of one lane.
#[inline]
fn lane_mask(lane: usize) -> BVec4A {
    Vec4::new(0.0, 1.0, 2.0, 3.0).cmpeq(Vec4::splat(lane as f32))
}

impl Lane<f32> for Vec4 {
    #[inline]
    fn lane(&self, lane: usize) -> f32 {
        self.as_ref()[lane]
    }

    #[inline]
    fn set_lane(&mut self, lane: usize, value: f32) {
        *self = Vec4::select(lane_mask(lane), Vec4::splat(value), *self);
    }
}

impl Lane<bool> for BVec4A {
    #[inline]
    fn lane(&self, lane: usize) -> bool {
        self.bitmask() & (1 << lane) != 0 // `test` matches on the lane
    }

    #[inline]
    fn set_lane(&mut self, lane: usize, value: bool) {
        let mask = lane_mask(lane);
        *self = if value { *self | mask } else { *self & !mask };
    }
}

impl Wide for Vec4 {
    const WIDTH: usize = 4;
    #[inline]
    fn from_fn(lane: impl FnMut(usize) -> f32) -> Self {
        Vec4::from_array(std::array::from_fn(lane))
    }
}

impl MaskLanes for BVec4A {
    #[inline]
    fn none() -> Self {
        BVec4A::FALSE
    }
    #[inline]
    fn any(self) -> bool {
        BVec4A::any(self)
    }
    #[inline]
    fn bitmask(self) -> u32 {
        BVec4A::bitmask(self)
    }
}

/// `Real`, `Lane` and `Wide` for one of `wide`'s vector types of `$width` lanes, and `$mask`,
/// its lanes where a comparison held: all bits set there, none elsewhere. (Without the CPU's
/// vectors of that width, `wide` computes the same in narrower ones.)
macro_rules! wide_lanes {
    ($floats:ident, $mask:ident, $width:literal) => {
        #[derive(Debug, Clone, Copy)]
        pub struct $mask($floats);

        impl $mask {
            /// The mask of one lane.
            #[inline]
            fn of_lane(lane: usize) -> $mask {
                let indices = $floats::new(std::array::from_fn(|i| i as f32));
                $mask(indices.simd_eq($floats::splat(lane as f32)))
            }
        }

        impl BitAnd for $mask {
            type Output = Self;
            #[inline]
            fn bitand(self, rhs: Self) -> Self {
                $mask(self.0 & rhs.0)
            }
        }

        impl BitOr for $mask {
            type Output = Self;
            #[inline]
            fn bitor(self, rhs: Self) -> Self {
                $mask(self.0 | rhs.0)
            }
        }

        impl Not for $mask {
            type Output = Self;
            #[inline]
            fn not(self) -> Self {
                $mask(!self.0)
            }
        }

        impl Lane<bool> for $mask {
            #[inline]
            fn lane(&self, lane: usize) -> bool {
                self.bitmask() & (1 << lane) != 0
            }

            #[inline]
            fn set_lane(&mut self, lane: usize, value: bool) {
                let mask = $mask::of_lane(lane);
                *self = if value { *self | mask } else { *self & !mask };
            }
        }

        impl MaskLanes for $mask {
            #[inline]
            fn none() -> Self {
                $mask($floats::ZERO)
            }
            #[inline]
            fn any(self) -> bool {
                self.0.any()
            }
            #[inline]
            fn bitmask(self) -> u32 {
                self.0.to_bitmask()
            }
        }

        impl Real for $floats {
            type Mask = $mask;
            const ZERO: Self = $floats::new([0.0; $width]);
            const ONE: Self = $floats::new([1.0; $width]);
            const NAN: Self = $floats::new([f32::NAN; $width]);
            #[inline]
            fn splat(value: f32) -> Self {
                $floats::splat(value)
            }
            #[inline]
            fn sqrt(self) -> Self {
                $floats::sqrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                $floats::abs(self)
            }
            #[inline]
            fn signum(self) -> Self {
                // The sign bit on 1's bits, as glam's `Vec4::signum`.
                let one = (self & $floats::splat(-0.0)) | $floats::ONE;
                self.is_nan().select(self, one)
            }
            #[inline]
            fn gt(self, rhs: Self) -> $mask {
                $mask(self.simd_gt(rhs))
            }
            #[inline]
            fn lt(self, rhs: Self) -> $mask {
                $mask(self.simd_lt(rhs))
            }
            #[inline]
            fn ge(self, rhs: Self) -> $mask {
                $mask(self.simd_ge(rhs))
            }
            #[inline]
            fn le(self, rhs: Self) -> $mask {
                $mask(self.simd_le(rhs))
            }
            #[inline]
            fn eq(self, rhs: Self) -> $mask {
                $mask(self.simd_eq(rhs))
            }
            #[inline]
            fn ne(self, rhs: Self) -> $mask {
                $mask(self.simd_ne(rhs))
            }
            #[inline]
            fn select(mask: $mask, if_true: Self, if_false: Self) -> Self {
                mask.0.select(if_true, if_false)
            }
        }

        impl Lane<f32> for $floats {
            #[inline]
            fn lane(&self, lane: usize) -> f32 {
                self.as_array()[lane]
            }

            #[inline]
            fn set_lane(&mut self, lane: usize, value: f32) {
                *self = $mask::of_lane(lane).0.select($floats::splat(value), *self);
            }
        }

        impl Wide for $floats {
            const WIDTH: usize = $width;
            #[inline]
            fn from_fn(lane: impl FnMut(usize) -> f32) -> Self {
                $floats::new(std::array::from_fn(lane))
            }
        }
    };
}

wide_lanes!(f32x8, Mask8, 8);
wide_lanes!(f32x16, Mask16, 16);

impl<F: Wide> Lane<Vec3> for Vector<F> {
    #[inline]
    fn lane(&self, lane: usize) -> Vec3 {
        Vec3::new(self.x.lane(lane), self.y.lane(lane), self.z.lane(lane))
    }

    #[inline]
    fn set_lane(&mut self, lane: usize, v: Vec3) {
        self.x.set_lane(lane, v.x);
        self.y.set_lane(lane, v.y);
        self.z.set_lane(lane, v.z);
    }
}

/// Three coordinates, each a `Real`: one vector, or a vector per lane.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Vector<F> {
    pub x: F,
    pub y: F,
    pub z: F,
}

/// Four vectors, one per lane.
pub type Vec3x4 = Vector<Vec4>;

impl Vec3Lanes {
    #[inline]
    pub fn from_lanes<V: Into<Vec3>>(v: [V; LANES]) -> Self {
        let v = v.map(Into::<Vec3>::into);
        Vector {
            x: Floats::from_fn(|lane| v[lane].x),
            y: Floats::from_fn(|lane| v[lane].y),
            z: Floats::from_fn(|lane| v[lane].z),
        }
    }
}

impl From<Vec3> for Vector<f32> {
    #[inline]
    fn from(v: Vec3) -> Self {
        Vector { x: v.x, y: v.y, z: v.z }
    }
}

impl From<Vector<f32>> for Vec3 {
    #[inline]
    fn from(v: Vector<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl<F: Real> Vector<F> {
    pub const ZERO: Self = Vector { x: F::ZERO, y: F::ZERO, z: F::ZERO };

    #[inline]
    pub fn splat(v: Vec3) -> Self {
        Vector { x: F::splat(v.x), y: F::splat(v.y), z: F::splat(v.z) }
    }

    /// Per lane, `if_true` where `mask` is set, else `if_false`.
    #[inline]
    pub fn select(mask: F::Mask, if_true: Self, if_false: Self) -> Self {
        Vector {
            x: F::select(mask, if_true.x, if_false.x),
            y: F::select(mask, if_true.y, if_false.y),
            z: F::select(mask, if_true.z, if_false.z),
        }
    }

    #[inline]
    pub fn dot(self, rhs: Self) -> F {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    #[inline]
    pub fn length_squared(self) -> F {
        self.dot(self)
    }

    /// In glam's order of operations, so it rounds as `Vec3::cross` does.
    #[inline]
    pub fn cross(self, rhs: Self) -> Self {
        Vector {
            x: self.y * rhs.z - rhs.y * self.z,
            y: self.z * rhs.x - rhs.z * self.x,
            z: self.x * rhs.y - rhs.x * self.y,
        }
    }

    #[inline]
    pub fn abs(self) -> Self {
        Vector { x: self.x.abs(), y: self.y.abs(), z: self.z.abs() }
    }

    /// The largest coordinate, compared as `Vec3::max_element` does (`a > b`, in its order),
    /// so it picks what that picks.
    #[inline]
    pub fn max_element(self) -> F {
        let max = |a: F, b: F| F::select(a.gt(b), a, b);
        max(max(self.x, self.y), self.z)
    }

    /// Whether all three coordinates are zero (as `v == Vec3::ZERO`).
    #[inline]
    pub fn is_zero(self) -> F::Mask {
        self.x.eq(F::ZERO) & self.y.eq(F::ZERO) & self.z.eq(F::ZERO)
    }
}

/// Ray origin for leaving `hit` towards `dir`: the hit point pushed past its error bound along
/// the normal, to the side `dir` goes (pbrt's robust spawning). Scales with the scene, so a scene
/// scaled by 1000 or 0.001 renders the same.
#[inline]
pub fn offset_origin(hit: &Hit, dir: Vec3) -> Vec3 {
    offset_point(hit.point.into(), hit.normal.into(), hit.error, dir.into()).into()
}

/// `offset_origin`, written once: `point` (of geometric `normal` and error bound `error`)
/// pushed past its error bound along the normal, to the side `dir` goes.
#[inline(always)]
pub fn offset_point<F: Real>(
    point: Vector<F>,
    normal: Vector<F>,
    error: F,
    dir: Vector<F>,
) -> Vector<F> {
    let offset = normal * error;
    Vector::select(normal.dot(dir).ge(F::ZERO), point + offset, point - offset)
}

/// The hits of four lanes, coordinate by coordinate: the fields of `Hit` that shading reads.
#[derive(Debug, Clone, Copy, Default)]
pub struct HitLanes {
    pub point: Vec3Lanes,
    pub normal: Vec3Lanes,
    pub shading_normal: Vec3Lanes,
    pub error: Floats,
}

impl HitLanes {
    #[inline]
    pub fn set_lane(&mut self, lane: usize, hit: &Hit) {
        self.point.set_lane(lane, hit.point);
        self.normal.set_lane(lane, hit.normal);
        self.shading_normal.set_lane(lane, hit.shading_normal);
        self.error.set_lane(lane, hit.error);
    }

    /// The hit record of a lane, for `primitive` at distance `t`.
    #[inline]
    pub fn lane(&self, lane: usize, primitive: u32, t: f32) -> Hit {
        Hit {
            t,
            point: self.point.lane(lane),
            normal: self.normal.lane(lane),
            shading_normal: self.shading_normal.lane(lane),
            error: self.error.lane(lane),
            primitive,
        }
    }

    /// `offset_origin` in lanes.
    #[inline]
    pub fn offset_origin(&self, dir: Vec3Lanes) -> Vec3Lanes {
        offset_point(self.point, self.normal, self.error, dir)
    }
}

/// Rays, coordinate by coordinate.
#[derive(Debug, Clone, Copy)]
pub struct RayLanes {
    pub origin: Vec3Lanes,
    pub dir: Vec3Lanes,
}

impl RayLanes {
    #[inline]
    pub fn new(rays: &[Ray; LANES]) -> Self {
        RayLanes {
            origin: Vec3Lanes::from_lanes(rays.map(|r| r.origin)),
            dir: Vec3Lanes::from_lanes(rays.map(|r| r.dir)),
        }
    }

    #[inline]
    pub fn lane(&self, lane: usize) -> Ray {
        Ray::new(self.origin.lane(lane), self.dir.lane(lane))
    }

    #[inline]
    pub fn set_lane(&mut self, lane: usize, ray: &Ray) {
        self.origin.set_lane(lane, ray.origin.into());
        self.dir.set_lane(lane, ray.dir.into());
    }
}

impl<F: Real> Add for Vector<F> {
    type Output = Self;
    #[inline]
    fn add(self, rhs: Self) -> Self {
        Vector { x: self.x + rhs.x, y: self.y + rhs.y, z: self.z + rhs.z }
    }
}

impl<F: Real> Sub for Vector<F> {
    type Output = Self;
    #[inline]
    fn sub(self, rhs: Self) -> Self {
        Vector { x: self.x - rhs.x, y: self.y - rhs.y, z: self.z - rhs.z }
    }
}

impl<F: Real> Neg for Vector<F> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Vector { x: -self.x, y: -self.y, z: -self.z }
    }
}

/// Coordinate by coordinate (colours).
impl<F: Real> Mul for Vector<F> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        Vector { x: self.x * rhs.x, y: self.y * rhs.y, z: self.z * rhs.z }
    }
}

/// Each lane's vector by that lane's scalar.
impl<F: Real> Mul<F> for Vector<F> {
    type Output = Self;
    #[inline]
    fn mul(self, s: F) -> Self {
        Vector { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

/// Each lane's vector divided by that lane's scalar (a division per coordinate, as glam's).
impl<F: Real> Div<F> for Vector<F> {
    type Output = Self;
    #[inline]
    fn div(self, s: F) -> Self {
        Vector { x: self.x / s, y: self.y / s, z: self.z / s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Vector<f32>`, which the shapes' kernels use for one ray, rounds as glam's `Vec3`, which
    /// the rest of the renderer uses: images do not depend on which one a shape computed with.
    #[test]
    fn one_vector_rounds_as_glam() {
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            f32::from_bits(0x3f80_0000 | (state >> 9)) * 3.0 - 4.5
        };
        for _ in 0..1000 {
            let (a, b) = (Vec3::new(next(), next(), next()), Vec3::new(next(), next(), next()));
            let (va, vb) = (Vector::from(a), Vector::from(b));
            assert_eq!(Vec3::from(va.cross(vb)), a.cross(b));
            assert_eq!(va.dot(vb), a.dot(b));
            assert_eq!(va.abs().max_element(), a.abs().max_element());
            let normalized = va * (1.0 / va.length_squared().sqrt());
            assert_eq!(Vec3::from(normalized), a.normalize());
            assert_eq!(Vec3::from(va + vb * 0.5 - va / 3.0), a + b * 0.5 - a / 3.0);
        }
    }

    /// For every lane type, whichever one the CPU's vectors make `Floats`.
    #[test]
    fn set_lane_writes_that_lane_alone_and_lane_reads_it() {
        lanes_write_and_read_alone::<Vec4>();
        lanes_write_and_read_alone::<f32x8>();
        lanes_write_and_read_alone::<f32x16>();
    }

    fn lanes_write_and_read_alone<F: Wide>() {
        for lane in 0..F::WIDTH {
            let mut v = F::from_fn(|i| i as f32 + 1.0);
            v.set_lane(lane, -1.0);
            for i in 0..F::WIDTH {
                assert_eq!(v.lane(i), if i == lane { -1.0 } else { i as f32 + 1.0 }, "lane {i}");
            }

            let even = F::from_fn(|i| (i % 2) as f32).eq(F::ZERO);
            let mut mask = even;
            mask.set_lane(lane, lane % 2 == 1);
            assert_eq!(mask.bitmask(), even.bitmask() ^ (1 << lane));
            for i in 0..F::WIDTH {
                assert_eq!(mask.lane(i), (i % 2 == 0) != (i == lane), "lane {i}");
            }
            assert!(mask.any() && !F::Mask::none().any());

            let mut v3 = Vector { x: F::ONE, y: F::ONE, z: F::ONE };
            v3.set_lane(lane, Vec3::new(5.0, 6.0, 7.0));
            for i in 0..F::WIDTH {
                let expected = if i == lane { Vec3::new(5.0, 6.0, 7.0) } else { Vec3::ONE };
                assert_eq!(v3.lane(i), expected);
            }
        }
    }
}
