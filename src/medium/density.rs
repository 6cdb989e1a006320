//! How densely a medium fills space: evenly, or as ground fog that thins with height (POV-Ray's
//! `fog_type 2`). A medium's coefficients are those at density 1; along a ray what matters is
//! the density-weighted length (`depth`), over which the medium acts as a homogeneous one over
//! that length does.

use glam::Vec3;

use crate::ray::Ray;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Density {
    Uniform,
    /// 1 up to height `offset` along the unit vector `up`, and 1 / (1 + (h - offset) /
    /// `falloff`)² at height h above it (a quarter at `falloff` above `offset`).
    Ground {
        up: Vec3,
        offset: f32,
        falloff: f32,
    },
}

impl Density {
    /// The integral of the density over the ray's first `distance` (which may be infinite).
    pub fn depth(&self, ray: &Ray, distance: f32) -> f32 {
        match *self {
            Density::Uniform => distance,
            Density::Ground { up, offset, falloff } => {
                let (height, rise) =
                    (Vec3::from(ray.origin).dot(up) - offset, ray.dir.dot(up.into()));
                if rise.abs() < 1e-6 {
                    return distance * ground(height, falloff);
                }
                let end = height + rise * distance;
                (level(end, falloff) - level(height, falloff)) / rise
            }
        }
    }

    /// The distance along the ray over which the density integrates to `depth`; infinite
    /// where it never does (a ray rising out of ground fog crosses a finite depth of it).
    pub fn distance(&self, ray: &Ray, depth: f32) -> f32 {
        match *self {
            Density::Uniform => depth,
            Density::Ground { up, offset, falloff } => {
                let (height, rise) =
                    (Vec3::from(ray.origin).dot(up) - offset, ray.dir.dot(up.into()));
                if rise.abs() < 1e-6 {
                    return depth / ground(height, falloff);
                }
                let target = level(height, falloff) + rise * depth;
                if target >= falloff {
                    return f32::INFINITY;
                }
                ((height_at(target, falloff) - height) / rise).max(0.0)
            }
        }
    }
}

/// The ground fog's density at height h above its offset.
fn ground(h: f32, falloff: f32) -> f32 {
    if h <= 0.0 { 1.0 } else { 1.0 / (1.0 + h / falloff).powi(2) }
}

/// An antiderivative of `ground` in h: h below the offset, falloff x / (1 + x) above (x = h /
/// falloff), rising to `falloff` at infinite height.
fn level(h: f32, falloff: f32) -> f32 {
    if h <= 0.0 {
        return h;
    }
    let x = h / falloff;
    if x.is_infinite() { falloff } else { falloff * x / (1.0 + x) }
}

/// The height whose `level` is `v` (below `falloff`).
fn height_at(v: f32, falloff: f32) -> f32 {
    if v <= 0.0 { v } else { falloff * v / (falloff - v) }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FOG: Density = Density::Ground { up: Vec3::Y, offset: 0.5, falloff: 2.0 };

    /// The depth in closed form against the midpoint rule, for rays rising, sinking, level,
    /// starting above and below the offset; `distance` inverts it.
    #[test]
    fn ground_depth_integrates_the_density() {
        let rays = [
            Ray::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(1.0, 0.6, 0.0).normalize()),
            Ray::new(Vec3::new(0.0, 4.0, 0.0), Vec3::new(0.3, -0.8, 0.2).normalize()),
            Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::X),
            Ray::new(Vec3::new(0.0, 0.0, 0.0), Vec3::Y),
        ];
        for ray in &rays {
            let distance = 7.0;
            let n = 100_000;
            let step = distance / n as f32;
            let numeric: f64 = (0..n)
                .map(|i| {
                    let h = ray.at((i as f32 + 0.5) * step).y - 0.5;
                    f64::from(ground(h, 2.0) * step)
                })
                .sum();
            let depth = FOG.depth(ray, distance);
            assert!((f64::from(depth) - numeric).abs() < 1e-3 * numeric, "{depth} vs {numeric}");
            let back = FOG.distance(ray, depth);
            assert!((back - distance).abs() < 1e-3 * distance, "{back} vs {distance}");
        }
        // Rising for ever from the offset crosses a depth of `falloff`, no more.
        let up = Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Y);
        assert!((FOG.depth(&up, f32::INFINITY) - 2.0).abs() < 1e-6);
        assert_eq!(FOG.distance(&up, 2.5), f32::INFINITY);
    }
}
