//! POV-Ray's warps: where a pattern is evaluated instead of the point itself. The classic
//! `turbulence` is the first warp, except for the patterns that add it themselves.

use std::f32::consts::TAU;

use glam::Vec3;

use super::noise::{Octaves, cell_random};
use crate::graph::{BlackHole, Field, FieldShape, Mapping, MappingSurface, Turbulence, Warp};

/// The point `p` moved by the pattern's turbulence (where it is a warp), then by its warps from
/// the last written to the first, as POV-Ray applies them (`Warp_EPoint` walks its list
/// backwards; measured with `povray`: `warp { repeat x*0.25 } warp { black_hole ... }` repeats
/// the black hole's output, not the other way round).
pub fn warped(shape: &FieldShape, p: Vec3) -> Vec3 {
    let classic = match shape.field {
        Field::Agate { .. }
        | Field::Marble
        | Field::Wood
        | Field::Spiral1 { .. }
        | Field::Spiral2 { .. } => None,
        Field::Bozo
        | Field::Brick { .. }
        | Field::Bumps
        | Field::Cells
        | Field::Checker
        | Field::Crackle(_)
        | Field::Dents
        | Field::Function(_)
        | Field::Gradient(_)
        | Field::Granite
        | Field::Hexagon
        | Field::Leopard
        | Field::Fractal(_)
        | Field::Planar
        | Field::Spherical
        | Field::Cylindrical
        | Field::Boxed
        | Field::Onion
        | Field::Quilted { .. }
        | Field::Radial
        | Field::Ripples
        | Field::Spotted
        | Field::Waves
        | Field::Wrinkles => shape.turbulence.map(Warp::Turbulence),
    };
    classic.iter().chain(shape.warps.iter().rev()).fold(p, |p, warp| apply(*warp, p))
}

/// One warp applied to `p`.
pub fn apply(warp: Warp, p: Vec3) -> Vec3 {
    match warp {
        Warp::Turbulence(Turbulence { amount, octaves, omega, lambda }) => {
            p + amount * Octaves { octaves, omega, lambda }.vector(p)
        }
        Warp::Repeat { axis, width, offset, flip } => {
            let copy = (p[axis] / width).floor();
            let mut q = p;
            q[axis] -= copy * width;
            if copy.rem_euclid(2.0) == 1.0 {
                for i in 0..3 {
                    if flip[i] != 0.0 {
                        // Mirrored within the slab along the axis, about 0 across it.
                        q[i] = if i == axis { width - q[i] } else { -q[i] };
                    }
                }
            }
            q + offset * copy
        }
        Warp::BlackHole(hole) => hole.apply(p),
        Warp::Mapping(mapping) => mapping.apply(p),
        Warp::Transform(inverse) => inverse.transform_point3(p),
    }
}

impl BlackHole {
    /// `p` moved by the hole nearest to it (POV-Ray's BlackHoleWarp::WarpPoint).
    fn apply(&self, p: Vec3) -> Vec3 {
        let mut centre = self.centre;
        if self.repeat != Vec3::ZERO {
            // The block p is in along each repeating axis (0 along the others).
            let repeats = self.repeat.cmpgt(Vec3::ZERO);
            let block = Vec3::select(repeats, (p / self.repeat).floor(), Vec3::ZERO);
            let cell = block.as_ivec3();
            let jitter = Vec3::new(
                cell_random(cell, JITTER_STREAM),
                cell_random(cell, JITTER_STREAM + 1),
                cell_random(cell, JITTER_STREAM + 2),
            );
            centre += self.jitter * jitter + self.repeat * block;
        }
        let d = p - centre;
        let distance = d.length();
        if distance >= self.radius {
            return p;
        }
        let s = (self.strength * (1.0 - distance / self.radius).powf(self.falloff)).min(1.0);
        if self.inverse { p - d * s } else { p + d * s }
    }
}

/// The streams of `cell_random` that place each repeated black hole (apart from the patterns').
const JITTER_STREAM: u32 = 40;

impl Mapping {
    /// `p` on the surface (POV-Ray's PlanarWarp, CylindricalWarp, SphericalWarp and
    /// ToroidalWarp::WarpPoint); a point where the angle has no value (on the axis) stays.
    fn apply(&self, p: Vec3) -> Vec3 {
        // The angle about y from +x towards +z, in turns [0, 1).
        let turns = |x: f32, z: f32| (z.atan2(x) / TAU).rem_euclid(1.0);
        let stretch = |d: f32| if self.dist_exp == 0.0 { 1.0 } else { d.powf(self.dist_exp) };
        let mapped = match self.surface {
            MappingSurface::Planar { offset } => Vec3::new(p.x, p.y, offset),
            MappingSurface::Cylindrical => {
                let d = (p.x * p.x + p.z * p.z).sqrt();
                if d == 0.0 {
                    return p;
                }
                Vec3::new(turns(p.x, p.z) * stretch(d), p.y, d)
            }
            MappingSurface::Spherical => {
                let d = p.length();
                if d == 0.0 {
                    return p;
                }
                let height = 0.5 + (p.y / d).clamp(-1.0, 1.0).asin() / std::f32::consts::PI;
                let u = if p.x == 0.0 && p.z == 0.0 { 0.0 } else { turns(p.x, p.z) };
                Vec3::new(u * stretch(d), height * stretch(d), d)
            }
            MappingSurface::Toroidal { major_radius } => {
                let r = (p.x * p.x + p.z * p.z).sqrt();
                if r == 0.0 {
                    return p;
                }
                // Across the tube, from its inner side (POV-Ray: acos(−x / len), the other
                // way round above the ring).
                let (across, y) = (r - major_radius, p.y);
                let d = (across * across + y * y).sqrt();
                let phi = if d == 0.0 { 0.0 } else { (-across / d).clamp(-1.0, 1.0).acos() };
                let phi = if y > 0.0 { TAU - phi } else { phi } / TAU;
                Vec3::new(turns(p.x, p.z) * stretch(d), phi * stretch(d), d)
            }
        };
        let o = self.orientation;
        if o == Vec3::Z {
            return mapped;
        }
        // POV-Ray's turn of the result towards the orientation, as written there.
        let Vec3 { x, y, z } = mapped;
        Vec3::new(
            o.x * z + o.y * x + o.z * x,
            o.x * y - o.y * z + o.z * y,
            -o.x * x + o.y * y + o.z * z,
        )
    }
}
