//! POV-Ray's warps: where a pattern is evaluated instead of the point itself. The classic
//! `turbulence` is the first warp, except for the patterns that add it themselves.

use glam::Vec3;

use super::noise::Octaves;
use crate::graph::{Field, FieldShape, Turbulence, Warp};

/// The point `p` moved by the pattern's turbulence (where it is a warp) and warps, in order.
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
    classic.iter().chain(&shape.warps).fold(p, |p, warp| apply(*warp, p))
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
        Warp::BlackHole { centre, radius, strength, falloff, inverse } => {
            let d = p - centre;
            let distance = d.length();
            if distance >= radius {
                return p;
            }
            let pull = (strength * (1.0 - distance / radius).powf(falloff)).min(1.0);
            if inverse { p + d * pull } else { p - d * pull }
        }
    }
}
