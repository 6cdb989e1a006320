//! Lanes: paths, rays and hits traced together, one per SIMD lane. Each coordinate is a `Vec4`,
//! so one SIMD operation does the work of four scalar ones. Operations round as glam's `Vec3`
//! ones do (same operations in the same order), so a lane computes exactly what one path alone
//! would. Below the shapes and the acceleration structures, which both work in lanes.

use std::ops::{Add, Div, Mul, Neg, Sub};

use glam::{BVec4A, Vec3, Vec4};

use crate::ray::{Hit, Ray};

/// Paths, rays and shadow rays traced together.
pub const LANES: usize = 4;

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

impl Lane<Vec3> for Vec3x4 {
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

/// Three coordinates of four vectors, one per lane.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Vec3x4 {
    pub x: Vec4,
    pub y: Vec4,
    pub z: Vec4,
}

impl Vec3x4 {
    pub const ZERO: Self = Vec3x4 { x: Vec4::ZERO, y: Vec4::ZERO, z: Vec4::ZERO };

    #[inline]
    pub fn from_lanes<V: Into<Vec3>>(v: [V; LANES]) -> Self {
        let [a, b, c, d] = v.map(Into::into);
        Vec3x4 {
            x: Vec4::new(a.x, b.x, c.x, d.x),
            y: Vec4::new(a.y, b.y, c.y, d.y),
            z: Vec4::new(a.z, b.z, c.z, d.z),
        }
    }

    #[inline]
    pub fn splat(v: Vec3) -> Self {
        Vec3x4 { x: Vec4::splat(v.x), y: Vec4::splat(v.y), z: Vec4::splat(v.z) }
    }

    /// Per lane, `if_true` where `mask` is set, else `if_false`.
    #[inline]
    pub fn select(mask: BVec4A, if_true: Self, if_false: Self) -> Self {
        Vec3x4 {
            x: Vec4::select(mask, if_true.x, if_false.x),
            y: Vec4::select(mask, if_true.y, if_false.y),
            z: Vec4::select(mask, if_true.z, if_false.z),
        }
    }

    #[inline]
    pub fn dot(self, rhs: Self) -> Vec4 {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    #[inline]
    pub fn length_squared(self) -> Vec4 {
        self.dot(self)
    }

    /// In glam's order of operations, so the lanes round as `Vec3::cross` does.
    #[inline]
    pub fn cross(self, rhs: Self) -> Self {
        Vec3x4 {
            x: self.y * rhs.z - rhs.y * self.z,
            y: self.z * rhs.x - rhs.z * self.x,
            z: self.x * rhs.y - rhs.x * self.y,
        }
    }

    #[inline]
    pub fn abs(self) -> Self {
        Vec3x4 { x: self.x.abs(), y: self.y.abs(), z: self.z.abs() }
    }

    /// The largest coordinate per lane, compared as `Vec3::max_element` does (`a > b`, in
    /// its order), so lanes pick what it picks.
    #[inline]
    pub fn max_element(self) -> Vec4 {
        let max = |a: Vec4, b: Vec4| Vec4::select(a.cmpgt(b), a, b);
        max(max(self.x, self.y), self.z)
    }

    /// Per lane, whether all three coordinates are zero (as `v == Vec3::ZERO`).
    #[inline]
    pub fn is_zero(self) -> BVec4A {
        self.x.cmpeq(Vec4::ZERO) & self.y.cmpeq(Vec4::ZERO) & self.z.cmpeq(Vec4::ZERO)
    }
}

/// The hits of four lanes, coordinate by coordinate: the fields of `Hit` that shading reads.
#[derive(Debug, Clone, Copy, Default)]
pub struct HitLanes {
    pub point: Vec3x4,
    pub normal: Vec3x4,
    pub shading_normal: Vec3x4,
    pub error: Vec4,
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

    /// `offset_origin` in four lanes.
    #[inline]
    pub fn offset_origin(&self, dir: Vec3x4) -> Vec3x4 {
        let offset = self.normal * self.error;
        let outside = self.normal.dot(dir).cmpge(Vec4::ZERO);
        Vec3x4::select(outside, self.point + offset, self.point - offset)
    }
}

/// Rays, coordinate by coordinate.
#[derive(Debug, Clone, Copy)]
pub struct RayLanes {
    pub origin: Vec3x4,
    pub dir: Vec3x4,
}

impl RayLanes {
    #[inline]
    pub fn new(rays: &[Ray; LANES]) -> Self {
        RayLanes {
            origin: Vec3x4::from_lanes(rays.map(|r| r.origin)),
            dir: Vec3x4::from_lanes(rays.map(|r| r.dir)),
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

impl Add for Vec3x4 {
    type Output = Self;
    #[inline]
    fn add(self, rhs: Self) -> Self {
        Vec3x4 { x: self.x + rhs.x, y: self.y + rhs.y, z: self.z + rhs.z }
    }
}

impl Sub for Vec3x4 {
    type Output = Self;
    #[inline]
    fn sub(self, rhs: Self) -> Self {
        Vec3x4 { x: self.x - rhs.x, y: self.y - rhs.y, z: self.z - rhs.z }
    }
}

impl Neg for Vec3x4 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Vec3x4 { x: -self.x, y: -self.y, z: -self.z }
    }
}

/// Coordinate by coordinate (colours).
impl Mul for Vec3x4 {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        Vec3x4 { x: self.x * rhs.x, y: self.y * rhs.y, z: self.z * rhs.z }
    }
}

/// Each lane's vector by that lane's scalar.
impl Mul<Vec4> for Vec3x4 {
    type Output = Self;
    #[inline]
    fn mul(self, s: Vec4) -> Self {
        Vec3x4 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

impl Mul<Vec3x4> for Vec4 {
    type Output = Vec3x4;
    #[inline]
    fn mul(self, v: Vec3x4) -> Vec3x4 {
        Vec3x4 { x: self * v.x, y: self * v.y, z: self * v.z }
    }
}

/// Each lane's vector divided by that lane's scalar (a division per coordinate, as glam's).
impl Div<Vec4> for Vec3x4 {
    type Output = Self;
    #[inline]
    fn div(self, s: Vec4) -> Self {
        Vec3x4 { x: self.x / s, y: self.y / s, z: self.z / s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_lane_writes_that_lane_alone_and_lane_reads_it() {
        for lane in 0..LANES {
            let mut v = Vec4::new(1.0, 2.0, 3.0, 4.0);
            v.set_lane(lane, -1.0);
            let expected: [f32; LANES] =
                std::array::from_fn(|i| if i == lane { -1.0 } else { i as f32 + 1.0 });
            assert_eq!(v.to_array(), expected);

            let mut mask = BVec4A::new(true, false, true, false);
            mask.set_lane(lane, lane % 2 == 1);
            assert_eq!(mask.bitmask(), 0b0101 ^ (1 << lane));
            for i in 0..LANES {
                assert_eq!(mask.lane(i), (i % 2 == 0) != (i == lane), "lane {i}");
            }

            let mut v3 = Vec3x4::from_lanes([Vec3::ONE; LANES]);
            v3.set_lane(lane, Vec3::new(5.0, 6.0, 7.0));
            for i in 0..LANES {
                let expected = if i == lane { Vec3::new(5.0, 6.0, 7.0) } else { Vec3::ONE };
                assert_eq!(v3.lane(i), expected);
            }
        }
    }
}
