//! POV-Ray's patterns as scalar fields (`docs/language.md`, Patterns): each pattern's value in
//! [0, 1] at a point of pattern space, then shaped by `frequency`, `phase` and the wave. Same
//! scale, contrast and orientation as POV-Ray's, not its noise bit for bit.

use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::sync::LazyLock;

use glam::{IVec3, Vec2, Vec3};

use super::BOUNDARY_NUDGE;
use super::fractal::fractal;
use super::noise::{Octaves, cell_random, noise};
use super::warp::warped;
use crate::graph::{Crackle, Field, FieldShape, Turbulence, Wave};

/// The shaped value of a pattern at `p` (pattern space), in [0, 1].
pub fn shaped_value(shape: &FieldShape, p: Vec3) -> f32 {
    let q = warped(shape, p);
    let field = &shape.field;
    match field {
        // Their cells are values, not a ramp: no wave (as POV-Ray's block patterns).
        Field::Checker | Field::Brick { .. } | Field::Hexagon => raw(field, q, shape),
        // Their `frequency` and `phase` are crests per unit of distance, taken by the sources.
        Field::Ripples | Field::Waves => wave(shape.wave, 1.0, 0.0, raw(field, q, shape)),
        Field::Agate { .. }
        | Field::Bozo
        | Field::Bumps
        | Field::Cells
        | Field::Crackle(_)
        | Field::Dents
        | Field::Function(_)
        | Field::Gradient(_)
        | Field::Granite
        | Field::Leopard
        | Field::Fractal(_)
        | Field::Planar
        | Field::Spherical
        | Field::Cylindrical
        | Field::Boxed
        | Field::Marble
        | Field::Onion
        | Field::Quilted { .. }
        | Field::Radial
        | Field::Spiral1 { .. }
        | Field::Spiral2 { .. }
        | Field::Spotted
        | Field::Wood
        | Field::Wrinkles => wave(shape.wave, shape.frequency, shape.phase, raw(field, q, shape)),
    }
}

/// The wave type a pattern takes unless told (POV-Ray's: triangle for marble, wood and the
/// spirals).
pub fn default_wave(field: &Field) -> Wave {
    match field {
        Field::Marble | Field::Wood | Field::Spiral1 { .. } | Field::Spiral2 { .. } => {
            Wave::Triangle
        }
        Field::Agate { .. }
        | Field::Bozo
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
        | Field::Wrinkles => Wave::Ramp,
    }
}

/// `frequency` and `phase`, then the wave: v * frequency + phase wrapped into [0, 1] (a value
/// already in [0, 1] stays, so that 1 is not 0, as in POV-Ray), shaped.
pub fn wave(wave: Wave, frequency: f32, phase: f32, v: f32) -> f32 {
    let v = v * frequency + phase;
    let v = if (0.0..=1.0).contains(&v) { v } else { v.rem_euclid(1.0) };
    match wave {
        Wave::Ramp => v,
        Wave::Sine => 0.5 + 0.5 * (TAU * v).sin(),
        Wave::Triangle => 1.0 - (2.0 * v - 1.0).abs(),
        Wave::Scallop => (PI * v).sin().abs(),
        Wave::Cubic => v * v * (3.0 - 2.0 * v),
        Wave::Poly(exponent) => v.powf(exponent),
    }
}

/// The classic turbulence's octaves, or POV-Ray's defaults.
fn octaves(turbulence: Option<Turbulence>) -> Octaves {
    turbulence.map_or(Octaves::DEFAULT, |t| Octaves {
        octaves: t.octaves,
        omega: t.omega,
        lambda: t.lambda,
    })
}

/// The pattern's own value at `q` (after the warps), before the wave.
fn raw(field: &Field, q: Vec3, shape: &FieldShape) -> f32 {
    let turbulence = shape.turbulence;
    let amount = turbulence.map_or(Vec3::ZERO, |t| t.amount);
    match field {
        Field::Agate { turbulence: scale } => {
            let turb = scale * octaves(turbulence).scalar(q);
            let v = 0.5 * ((TAU * (1.3 * turb + 1.1 * q.z)).sin() + 1.0);
            v.clamp(0.0, 1.0).powf(0.77)
        }
        Field::Bozo | Field::Bumps | Field::Spotted => noise(q),
        Field::Brick { size, mortar } => brick(q, *size, *mortar),
        Field::Cells => cell_random(q.floor().as_ivec3(), 0),
        Field::Checker => {
            let cell = (q + BOUNDARY_NUDGE).floor();
            (cell.x + cell.y + cell.z).rem_euclid(2.0)
        }
        Field::Crackle(parameters) => crackle(q, parameters),
        Field::Dents => noise(q).powi(3),
        Field::Function(function) => {
            let v = function.0.value(q.as_dvec3()) as f32;
            // A pole or a root of a negative number colours as 0 rather than poisoning the map.
            if v.is_finite() { v } else { 0.0 }
        }
        Field::Gradient(axis) => q.dot(*axis),
        Field::Granite => {
            let mut sum = 0.0;
            for octave in 0..6 {
                let frequency = (1 << octave) as f32;
                sum += (0.5 - noise(q * 4.0 * frequency)).abs() / frequency;
            }
            sum.min(1.0)
        }
        Field::Hexagon => hexagon(Vec2::new(q.x, q.z)),
        Field::Leopard => {
            let s = (q.x.sin() + q.y.sin() + q.z.sin()) / 3.0;
            s * s
        }
        Field::Fractal(f) => fractal(f, Vec2::new(q.x, q.y)),
        Field::Planar => 1.0 - q.y.abs().min(1.0),
        Field::Spherical => 1.0 - q.length().min(1.0),
        Field::Cylindrical => 1.0 - Vec2::new(q.x, q.z).length().min(1.0),
        Field::Boxed => 1.0 - q.abs().max_element().min(1.0),
        Field::Marble => q.x + amount.x * octaves(turbulence).scalar(q),
        Field::Onion => q.length(),
        Field::Quilted { control0, control1 } => {
            let f = q + BOUNDARY_NUDGE - (q + BOUNDARY_NUDGE).floor() - Vec3::splat(0.5);
            let t = 2.0 * f.abs().max_element();
            let s = 1.0 - t;
            3.0 * s * s * t * control0 + 3.0 * s * t * t * control1 + t * t * t
        }
        Field::Radial => {
            if q.x.abs() < 1e-6 && q.z.abs() < 1e-6 {
                0.25
            } else {
                0.25 + (q.x.atan2(q.z) + PI) / TAU
            }
        }
        Field::Ripples | Field::Waves => sources(field, q, shape.frequency, shape.phase),
        Field::Spiral1 { arms } => spiral(q, *arms, amount.x * octaves(turbulence).scalar(q)),
        Field::Spiral2 { arms } => {
            // POV-Ray's: the spiral's triangle wave over the rings' (measured with `povray`).
            let turbulence = amount.x * octaves(turbulence).scalar(q);
            let triangle = |v| wave(Wave::Triangle, 1.0, 0.0, v);
            triangle(Vec2::new(q.x, q.y).length()) + triangle(spiral(q, *arms, turbulence))
        }
        Field::Wood => {
            let d = amount * octaves(turbulence).vector(q);
            Vec2::new(q.x + d.x, q.y + d.y).length()
        }
        Field::Wrinkles => {
            let (mut sum, mut amplitude, mut frequency) = (0.0, 1.0, 1.0);
            for _ in 0..10 {
                sum += amplitude * (2.0 * noise(q * frequency) - 1.0).abs();
                amplitude *= 0.5;
                frequency *= 2.0;
            }
            // The sum's typical range is about [0, 1] (the first octaves dominate).
            sum.min(1.0)
        }
    }
}

/// POV-Ray's spiral about z: z plus the distance from the axis plus `arms` times the part of a
/// turn from −y (plus turbulence), so that each arm rises one unit a turn and one a unit out.
fn spiral(q: Vec3, arms: f32, turbulence: f32) -> f32 {
    let radius = Vec2::new(q.x, q.y).length();
    let turn = if radius == 0.0 { 0.0 } else { (q.y.atan2(q.x) + FRAC_PI_2).rem_euclid(TAU) / TAU };
    q.z + radius + arms * turn + turbulence
}

/// POV-Ray's brick: 1 in a brick, 0 in the mortar.
fn brick(q: Vec3, size: Vec3, mortar: f32) -> f32 {
    let q = q + BOUNDARY_NUDGE;
    let row = (q.y / size.y).floor();
    // Every other row (and layer in z) is shifted by half a brick.
    let shift = if row.rem_euclid(2.0) == 1.0 { 0.5 } else { 0.0 };
    let layer = (q.z / size.z).floor();
    let shift_x = if (row + layer).rem_euclid(2.0) == 1.0 { 0.5 } else { 0.0 };
    let local = Vec3::new(
        (q.x / size.x + shift_x).rem_euclid(1.0) * size.x,
        q.y - row * size.y,
        (q.z / size.z + shift).rem_euclid(1.0) * size.z,
    );
    let half = 0.5 * mortar;
    let in_mortar = (0..3).any(|i| local[i] < half || local[i] > size[i] - half);
    if in_mortar { 0.0 } else { 1.0 }
}

/// One random feature point per unit cube (POV-Ray's crackle): the form's weighted sum of the
/// distances to the three nearest points in the metric, or with `solid` the nearest point's
/// cell's random value. The points of the 27 cubes around the point's own are searched: the
/// nearest always lies among them, the second and third all but always.
fn crackle(q: Vec3, parameters: &Crackle) -> f32 {
    let Crackle { form, metric, offset, solid } = *parameters;
    let home = q.floor().as_ivec3();
    // The three smallest sums |d|^m (the m-th powers of the distances) and the nearest's cell.
    let mut nearest = [f32::MAX; 3];
    let mut nearest_cell = home;
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let cell = home + IVec3::new(dx, dy, dz);
                let jitter =
                    Vec3::new(cell_random(cell, 1), cell_random(cell, 2), cell_random(cell, 3));
                let d = (cell.as_vec3() + jitter - q).abs();
                let sum = if metric == 2.0 {
                    d.length_squared()
                } else {
                    d.x.powf(metric) + d.y.powf(metric) + d.z.powf(metric)
                };
                if sum < nearest[0] {
                    nearest = [sum, nearest[0], nearest[1]];
                    nearest_cell = cell;
                } else if sum < nearest[1] {
                    nearest = [nearest[0], sum, nearest[1]];
                } else if sum < nearest[2] {
                    nearest[2] = sum;
                }
            }
        }
    }
    if solid {
        return cell_random(nearest_cell, 4);
    }
    let distance = |sum: f32| (sum + offset).max(0.0).powf(1.0 / metric);
    form.x * distance(nearest[0]) + form.y * distance(nearest[1]) + form.z * distance(nearest[2])
}

/// Hexagons of unit side, corners towards ±z, in the x-z plane (centres √3 apart along x); the
/// colour of each is 0, 0.5 or 1 by (column - row) mod 3, so that no two neighbours share one.
fn hexagon(p: Vec2) -> f32 {
    // Axial coordinates of a pointy grid, rounded in cube coordinates.
    let q = (3f32.sqrt() / 3.0 * p.x - p.y / 3.0) + BOUNDARY_NUDGE.x;
    let r = 2.0 / 3.0 * p.y + BOUNDARY_NUDGE.z;
    let s = -q - r;
    let (mut rq, mut rr, rs) = (q.round(), r.round(), s.round());
    let (dq, dr, ds) = ((rq - q).abs(), (rr - r).abs(), (rs - s).abs());
    if dq > dr && dq > ds {
        rq = -rr - rs;
    } else if dr > ds {
        rr = -rq - rs;
    }
    ((rq - rr).rem_euclid(3.0)) / 2.0
}

/// Waves from ten fixed sources in the unit cube, `frequency` crests per unit of distance:
/// ripples' sines, waves' cosines fading with distance; their sum over its spread (that of a
/// sum of waves of random phases) mapped to [0, 1].
fn sources(field: &Field, q: Vec3, frequency: f32, phase: f32) -> f32 {
    let (mut sum, mut spread) = (0.0, 0.0);
    for &source in wave_sources() {
        let d = q.distance(source);
        let crest = TAU * (d * frequency + phase);
        let weight = if *field == Field::Waves { 1.0 / (1.0 + d) } else { 1.0 };
        sum += weight * if *field == Field::Waves { crest.cos() } else { crest.sin() };
        spread += weight * weight;
    }
    (0.5 + 0.25 * sum / spread.sqrt()).clamp(0.0, 1.0)
}

/// The ten fixed sources of ripples and waves, in the unit cube: hashed once, not at every
/// shading point.
pub fn wave_sources() -> &'static [Vec3; 10] {
    static SOURCES: LazyLock<[Vec3; 10]> = LazyLock::new(|| {
        std::array::from_fn(|i| {
            let i = i as u32;
            Vec3::new(
                cell_random(IVec3::ZERO, 10 + 3 * i),
                cell_random(IVec3::ZERO, 11 + 3 * i),
                cell_random(IVec3::ZERO, 12 + 3 * i),
            )
        })
    });
    &SOURCES
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::{BlackHole, Fractal, FractalColouring, FractalSet, Warp};
    use crate::texture::warp;

    fn plain(field: &Field) -> FieldShape {
        FieldShape {
            wave: default_wave(field),
            field: field.clone(),
            turbulence: None,
            warps: Vec::new(),
            frequency: 1.0,
            phase: 0.0,
        }
    }

    const MANDEL: Fractal = Fractal {
        set: FractalSet::Mandel,
        exponent: 2,
        iterations: 30,
        interior: FractalColouring { kind: 0, factor: 1.0 },
        exterior: FractalColouring { kind: 1, factor: 1.0 },
    };

    const ALL: [Field; 24] = [
        Field::Agate { turbulence: 1.0 },
        Field::Bozo,
        Field::Brick { size: Vec3::new(8.0, 3.0, 4.5), mortar: 0.5 },
        Field::Bumps,
        Field::Cells,
        Field::Checker,
        Field::Crackle(Crackle::DEFAULT),
        Field::Dents,
        Field::Gradient(Vec3::Y),
        Field::Granite,
        Field::Hexagon,
        Field::Leopard,
        Field::Fractal(MANDEL),
        Field::Marble,
        Field::Onion,
        Field::Quilted { control0: 1.0, control1: 1.0 },
        Field::Radial,
        Field::Ripples,
        Field::Spiral1 { arms: 3.0 },
        Field::Spiral2 { arms: 3.0 },
        Field::Spotted,
        Field::Waves,
        Field::Wood,
        Field::Wrinkles,
    ];

    fn points() -> impl Iterator<Item = Vec3> {
        (0..3000).map(|i| {
            let i = i as f32;
            Vec3::new((i * 0.731).sin() * 7.0, (i * 0.377).cos() * 5.0, i * 0.0123 - 18.0)
        })
    }

    #[test]
    fn every_pattern_stays_in_zero_to_one_and_varies() {
        let turbulence =
            Turbulence { amount: Vec3::splat(0.8), octaves: 6, omega: 0.5, lambda: 2.0 };
        for field in ALL {
            for shape in
                [plain(&field), FieldShape { turbulence: Some(turbulence), ..plain(&field) }]
            {
                let (mut lo, mut hi) = (f32::MAX, f32::MIN);
                for p in points() {
                    let v = shaped_value(&shape, p);
                    assert!((0.0..=1.0).contains(&v), "{field:?} at {p}: {v}");
                    (lo, hi) = (lo.min(v), hi.max(v));
                }
                // Contrast: each pattern covers a good part of its range (mandel's set is
                // small in this region, so its values sit at the escape counts).
                assert!(hi - lo > 0.3, "{field:?}: only {lo}..{hi}");
            }
        }
    }

    #[test]
    fn periodic_patterns_repeat_with_their_period() {
        let value = |field: &Field, p: Vec3| shaped_value(&plain(field), p);
        for p in points().step_by(37) {
            let near = |a: f32, b: f32| (a - b).abs() < 2e-3;
            assert_eq!(value(&Field::Checker, p), value(&Field::Checker, p + Vec3::X * 2.0));
            assert_ne!(value(&Field::Checker, p), value(&Field::Checker, p + Vec3::Z));
            assert!(near(value(&Field::Gradient(Vec3::Y), p), (p.y).rem_euclid(1.0)));
            assert!(near(
                value(&Field::Marble, p),
                value(&Field::Marble, p + Vec3::new(1.0, 3.0, 5.0))
            ));
            assert!(near(value(&Field::Leopard, p), value(&Field::Leopard, p + Vec3::Y * TAU)));
            let onion = value(&Field::Onion, p);
            assert!(near(onion, value(&Field::Onion, p * (1.0 + 1.0 / p.length()))), "onion");
            assert!(near(value(&Field::Wood, p), value(&Field::Wood, p + Vec3::Z * 3.7)), "wood");
            let ring = Vec2::new(p.x, p.y).length();
            assert!(near(value(&Field::Wood, p), 1.0 - (2.0 * ring.rem_euclid(1.0) - 1.0).abs()));
            let hexagon = value(&Field::Hexagon, p);
            assert_eq!(hexagon, value(&Field::Hexagon, p + Vec3::X * 3.0 * 3f32.sqrt()));
            assert_ne!(hexagon, value(&Field::Hexagon, p + Vec3::X * 3f32.sqrt()));
            let size = Vec3::new(8.0, 3.0, 4.5);
            let brick = Field::Brick { size, mortar: 0.5 };
            assert_eq!(value(&brick, p), value(&brick, p + size * 2.0), "brick");
            let cells = Field::Cells;
            assert_eq!(value(&cells, p), value(&cells, p.floor() + Vec3::splat(0.5)));
        }
        // Radial: a quarter turn about y is a quarter of the range.
        let radial = |angle: f32| value(&Field::Radial, Vec3::new(angle.sin(), 0.3, angle.cos()));
        assert!(((radial(0.3 + PI / 2.0) - radial(0.3)).rem_euclid(1.0) - 0.25).abs() < 1e-5);
        // Spiral1 with 3 arms: a third of a turn about z at the same z is the same value.
        let spiral = |angle: f32| {
            value(&Field::Spiral1 { arms: 3.0 }, Vec3::new(angle.cos(), angle.sin(), 0.4) * 2.0)
        };
        assert!((spiral(0.2) - spiral(0.2 + TAU / 3.0)).abs() < 1e-4);
        // Brick: mortar on the rows' joints, brick in the middle of a brick.
        let brick = Field::Brick { size: Vec3::new(8.0, 3.0, 4.5), mortar: 0.5 };
        assert_eq!(value(&brick, Vec3::new(4.0, 0.0, 2.0)), 0.0);
        assert_eq!(value(&brick, Vec3::new(2.0, 1.5, 1.0)), 1.0);
        // Mandel: the origin is in the set, a far point escapes at once.
        assert_eq!(value(&Field::Fractal(MANDEL), Vec3::ZERO), 1.0);
        assert_eq!(value(&Field::Fractal(MANDEL), Vec3::new(3.0, 3.0, 0.0)), 0.0);
        // planar, spherical, cylindrical, boxed: 1 at their centre, 0 from distance 1 on,
        // linear between (y, |p|, the distance from y, the largest coordinate).
        let at = |field: Field, p: Vec3| value(&field, p);
        for (field, half) in [
            (Field::Planar, Vec3::new(7.0, -0.5, 3.0)),
            (Field::Spherical, Vec3::new(0.3, 0.4, 0.0)),
            (Field::Cylindrical, Vec3::new(0.3, 9.0, -0.4)),
            (Field::Boxed, Vec3::new(0.2, -0.5, 0.4)),
        ] {
            assert!((at(field.clone(), half) - 0.5).abs() < 1e-6, "{field:?} at {half}");
            assert_eq!(at(field.clone(), half * 2.5), 0.0, "{field:?} beyond 1");
        }
        assert_eq!(at(Field::Spherical, Vec3::ZERO), 1.0);
        assert_eq!(at(Field::Planar, Vec3::new(5.0, 0.0, -2.0)), 1.0);
        // Quilted: 0 at a cube's centre, 1 on its faces.
        let quilted = Field::Quilted { control0: 1.0, control1: 1.0 };
        assert!(value(&quilted, Vec3::splat(0.5)) < 0.01);
        assert!(value(&quilted, Vec3::new(0.5, 0.5, 0.9999)) > 0.99);
    }

    /// The distances to the nearest points of a wider search (5³ cubes) than crackle's, in
    /// the m-norm, sorted.
    fn brute_force_distances(q: Vec3, metric: f32) -> Vec<f32> {
        let home = q.floor().as_ivec3();
        let mut distances = Vec::new();
        for dz in -2..=2 {
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let cell = home + IVec3::new(dx, dy, dz);
                    let jitter =
                        Vec3::new(cell_random(cell, 1), cell_random(cell, 2), cell_random(cell, 3));
                    let d = (cell.as_vec3() + jitter - q).abs();
                    let sum = d.x.powf(metric) + d.y.powf(metric) + d.z.powf(metric);
                    distances.push(sum.powf(1.0 / metric));
                }
            }
        }
        distances.sort_by(f32::total_cmp);
        distances
    }

    #[test]
    fn crackle_weighs_the_nearest_distances_in_its_metric() {
        let raw_crackle = |crackle: Crackle, q: Vec3| {
            raw(&Field::Crackle(crackle), q, &plain(&Field::Crackle(crackle)))
        };
        for metric in [1.0, 2.0, 3.0] {
            for q in points().step_by(61) {
                let d = brute_force_distances(q, metric);
                let form = |form: Vec3, offset: f32| {
                    raw_crackle(Crackle { form, metric, offset, solid: false }, q)
                };
                let near = |a: f32, b: f32| (a - b).abs() < 1e-4 * (1.0 + b.abs());
                assert!(near(form(Vec3::X, 0.0), d[0]), "metric {metric} at {q}: nearest");
                assert!(near(form(Vec3::Y, 0.0), d[1]), "second nearest");
                assert!(near(form(Vec3::Z, 0.0), d[2]), "third nearest");
                assert!(near(form(Vec3::new(-1.0, 1.0, 0.0), 0.0), d[1] - d[0]), "the default");
                // The offset is added under the root: (d^m + offset)^(1/m).
                let lifted = (d[0].powf(metric) + 0.3).powf(1.0 / metric);
                assert!(near(form(Vec3::X, 0.3), lifted), "offset");
            }
        }
        // Solid: one value over each cell, the nearest point's, which differs between cells.
        let solid = Crackle { solid: true, ..Crackle::DEFAULT };
        let mut values = Vec::new();
        for q in points().step_by(61) {
            let cell = q.floor().as_ivec3();
            let point = cell.as_vec3()
                + Vec3::new(cell_random(cell, 1), cell_random(cell, 2), cell_random(cell, 3));
            // A step a hundredth of the way towards the cell's own point stays in its cell.
            let v = raw_crackle(solid, point);
            assert_eq!(v, raw_crackle(solid, point + (q - point) * 0.01), "flat near {point}");
            values.push(v);
        }
        values.dedup();
        assert!(values.len() > 10, "cells differ: {values:?}");
    }

    #[test]
    fn waves_frequency_and_phase_shape_the_value() {
        let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
        assert!(close(wave(Wave::Ramp, 1.0, 0.0, 0.3), 0.3));
        assert!(close(wave(Wave::Ramp, 2.0, 0.0, 0.3), 0.6));
        assert!(close(wave(Wave::Ramp, 1.0, 0.25, 0.9), 0.15), "wrapped");
        assert!(close(wave(Wave::Ramp, 1.0, 0.0, 1.0), 1.0), "1 stays 1");
        assert!(close(wave(Wave::Sine, 1.0, 0.0, 0.25), 1.0));
        assert!(close(wave(Wave::Sine, 1.0, 0.0, 0.75), 0.0));
        assert!(close(wave(Wave::Triangle, 1.0, 0.0, 0.5), 1.0));
        assert!(close(wave(Wave::Triangle, 1.0, 0.0, 0.25), 0.5));
        assert!(close(wave(Wave::Scallop, 1.0, 0.0, 0.5), 1.0));
        assert!(close(wave(Wave::Scallop, 1.0, 0.0, 1.0 / 6.0), 0.5));
        assert!(close(wave(Wave::Cubic, 1.0, 0.0, 0.25), 0.15625));
        assert!(close(wave(Wave::Poly(3.0), 1.0, 0.0, 0.5), 0.125));
    }

    #[test]
    fn warps_move_the_points() {
        let gradient = plain(&Field::Gradient(Vec3::X));
        // Repeat: the slab [0, 0.5) along x repeats, each copy lifted by 1 in y.
        let repeat = Warp::Repeat { axis: 0, width: 0.5, offset: Vec3::Y, flip: Vec3::ZERO };
        let repeated = FieldShape { warps: vec![repeat], ..gradient.clone() };
        for x in [0.1f32, 0.3, 0.45] {
            let v = shaped_value(&repeated, Vec3::new(x, 0.0, 0.0));
            assert!((shaped_value(&repeated, Vec3::new(x + 1.5, 0.0, 0.0)) - v).abs() < 1e-5);
        }
        let flip = Warp::Repeat { axis: 0, width: 0.5, offset: Vec3::ZERO, flip: Vec3::X };
        let flipped = FieldShape { warps: vec![flip], ..gradient.clone() };
        // The odd copy [0.5, 1) mirrors the slab: 0.6 reads 0.5 - 0.1.
        assert!((shaped_value(&flipped, Vec3::new(0.6, 0.0, 0.0)) - 0.4).abs() < 1e-5);
        // Black hole (POV-Ray's, measured with `povray`): no effect outside its radius; inside,
        // p + s (p - c) with s = strength (1 - d / r)^falloff, so that the pattern looks drawn
        // in; `inverse` moves p the other way.
        let hole = BlackHole::default();
        let far = Vec3::new(1.5, 0.2, 0.0);
        assert_eq!(warp::apply(Warp::BlackHole(hole), far), far);
        let near = Vec3::new(0.5, 0.0, 0.0);
        let drawn = warp::apply(Warp::BlackHole(hole), near);
        assert!((drawn - Vec3::new(0.625, 0.0, 0.0)).length() < 1e-6, "{drawn}");
        let pushed = warp::apply(Warp::BlackHole(BlackHole { inverse: true, ..hole }), near);
        assert!((pushed - Vec3::new(0.375, 0.0, 0.0)).length() < 1e-6, "{pushed}");
        // Repeated every 4 along x and 3 along y (not along z): the hole at the origin stands
        // again at <4k, 3m, 0>, and nowhere else along z.
        let repeated = Warp::BlackHole(BlackHole { repeat: Vec3::new(4.0, 3.0, 0.0), ..hole });
        for block in [Vec3::new(4.0, 0.0, 0.0), Vec3::new(-8.0, 6.0, 0.0)] {
            let moved = warp::apply(repeated, block + near);
            assert!((moved - (block + Vec3::new(0.625, 0.0, 0.0))).length() < 1e-5, "{moved}");
        }
        let beside = Vec3::new(0.5, 0.0, 4.0);
        assert_eq!(warp::apply(repeated, beside), beside, "z does not repeat");
        // Jittered: each block's hole moves by a random part of the jitter (within [0, 1)² of
        // the block's corner here), so points farther than the radius from that square never
        // move, and the blocks' holes differ.
        let jittered = Warp::BlackHole(BlackHole {
            radius: 0.5,
            repeat: Vec3::new(4.0, 4.0, 0.0),
            jitter: Vec3::new(1.0, 1.0, 0.0),
            ..hole
        });
        let mut moves = Vec::new();
        for block in 0..8 {
            let corner = Vec3::new(4.0 * block as f32, 4.0, 0.0);
            let mut moved = Vec::new();
            for i in 0..24 {
                for j in 0..24 {
                    let offset = Vec3::new(i as f32 * 0.1 - 0.4, j as f32 * 0.1 - 0.4, 0.0);
                    let p = corner + offset;
                    let shift = warp::apply(jittered, p) - p;
                    if shift != Vec3::ZERO {
                        assert!(offset.x.max(offset.y) < 1.5, "{offset}");
                        assert!(offset.x.min(offset.y) > -0.5, "{offset}");
                        moved.push((i, j));
                    }
                }
            }
            assert!(!moved.is_empty(), "block {block} has its hole");
            moves.push(moved);
        }
        assert!(moves.windows(2).any(|w| w[0] != w[1]), "the holes are jittered");
        // Turbulence moves points by at most its amount times the octaves' total weight.
        let turbulence =
            Turbulence { amount: Vec3::splat(0.1), octaves: 3, omega: 0.5, lambda: 2.0 };
        for p in points().step_by(100) {
            let moved = warp::apply(Warp::Turbulence(turbulence), p);
            assert!((moved - p).abs().max_element() <= 0.1 * 1.75 * 1.01, "{p} -> {moved}");
        }
    }
}
