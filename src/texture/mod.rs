//! Procedural textures (`docs/language.md`, Textures): patterns evaluated in object space, moved by
//! their own transforms (the value at p is the plain pattern's at T^-1(p)).

mod bump;
mod field;
mod fractal;
mod image_map;
mod noise;
mod warp;

pub use bump::{Bump, DEFAULT_ACCURACY, tilt};
pub use field::{default_wave, shaped_value, wave};
pub use image_map::{Curve, ImageMap, ImageMapError};
pub use noise::{Octaves, fbm, noise, perlin};

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{Affine3A, Vec3};

use crate::graph::{ColorMap, FieldShape, ImageLook, Pattern, TextureNode, Warp, compose};

#[derive(Debug, Clone)]
pub struct Texture {
    kind: Kind,
    /// Object space to pattern space: the inverse of the texture's transforms.
    to_pattern: Affine3A,
}

#[derive(Debug, Clone)]
enum Kind {
    Solid(Vec3),
    Checker(Box<Texture>, Box<Texture>),
    Stripes {
        a: Box<Texture>,
        b: Box<Texture>,
        axis: Vec3,
    },
    Gradient {
        axis: Vec3,
        map: ColorMap,
    },
    Noise {
        octaves: u32,
        map: ColorMap,
    },
    Marble {
        turbulence: f32,
        octaves: u32,
        map: ColorMap,
    },
    Wood {
        turbulence: f32,
        octaves: u32,
        map: ColorMap,
    },
    Image {
        image: Arc<ImageMap>,
        look: ImageLook,
        curve: Curve,
    },
    Mix {
        a: Box<Texture>,
        b: Box<Texture>,
        t: Box<Texture>,
    },
    Field {
        shape: FieldShape,
        map: Vec<(f32, Texture)>,
    },
    /// Weights normalised to sum to 1.
    Average(Vec<(f32, Texture)>),
    Warped {
        warp: Warp,
        texture: Box<Texture>,
    },
}

/// Nudge applied to points before cell-based patterns: a plane that lies exactly on a cell
/// boundary (`checker` on the floor y = -1) would otherwise flip between cells with the
/// rounding of each hit point. Shifting by a fixed tiny amount puts such a plane inside one
/// cell consistently, without visibly moving the pattern.
pub(crate) const BOUNDARY_NUDGE: Vec3 = Vec3::new(1.1e-4, 1.3e-4, 1.7e-4);

impl Texture {
    /// Compiles a texture node; `load` reads `image_map` files (errors are the caller's).
    pub fn new(
        node: &TextureNode,
        load: &mut dyn FnMut(&std::path::Path) -> Result<Arc<ImageMap>, ImageMapError>,
    ) -> Result<Texture, ImageMapError> {
        let mut sub = |t: &TextureNode| Texture::new(t, load).map(Box::new);
        let kind = match &node.pattern {
            Pattern::Solid(c) => Kind::Solid(*c),
            Pattern::Checker(a, b) => Kind::Checker(sub(a)?, sub(b)?),
            Pattern::Stripes { a, b, axis } => {
                Kind::Stripes { a: sub(a)?, b: sub(b)?, axis: axis.normalize() }
            }
            Pattern::Gradient { axis, map } => {
                Kind::Gradient { axis: axis.normalize(), map: map.clone() }
            }
            Pattern::Noise { octaves, map } => Kind::Noise { octaves: *octaves, map: map.clone() },
            Pattern::Marble { turbulence, octaves, map } => {
                Kind::Marble { turbulence: *turbulence, octaves: *octaves, map: map.clone() }
            }
            Pattern::Wood { turbulence, octaves, map } => {
                Kind::Wood { turbulence: *turbulence, octaves: *octaves, map: map.clone() }
            }
            Pattern::Image { path, look } => {
                Kind::Image { image: load(path)?, look: *look, curve: Curve::new(look.gamma) }
            }
            Pattern::Mix { a, b, t } => Kind::Mix { a: sub(a)?, b: sub(b)?, t: sub(t)? },
            Pattern::Field { shape, map } => {
                let mut entries = Vec::with_capacity(map.len());
                for (position, node) in map {
                    entries.push((*position, *sub(node)?));
                }
                Kind::Field { shape: (**shape).clone(), map: entries }
            }
            Pattern::Average(map) => {
                let total: f32 = map.iter().map(|(weight, _)| weight).sum();
                let mut entries = Vec::with_capacity(map.len());
                for (weight, node) in map {
                    entries.push((weight / total, *sub(node)?));
                }
                Kind::Average(entries)
            }
            Pattern::Warped { warp, node } => Kind::Warped { warp: *warp, texture: sub(node)? },
        };
        Ok(Texture { kind, to_pattern: compose(&node.transforms).inverse() })
    }

    /// The mean of its three channels at `p`: one grey value, as a filter, a see-through part
    /// or a mix's weight is read.
    #[inline]
    pub fn grey(&self, p: Vec3) -> f32 {
        self.eval(p).dot(Vec3::splat(1.0 / 3.0))
    }

    /// The texture's value at `p`, a point in the object's own space.
    pub fn eval(&self, p: Vec3) -> Vec3 {
        let q = self.to_pattern.transform_point3(p);
        match &self.kind {
            Kind::Solid(c) => *c,
            Kind::Checker(a, b) => {
                let cell = (q + BOUNDARY_NUDGE).floor();
                let even = (cell.x + cell.y + cell.z).rem_euclid(2.0) == 0.0;
                if even { a.eval(q) } else { b.eval(q) }
            }
            Kind::Stripes { a, b, axis } => {
                let band = (q.dot(*axis) + BOUNDARY_NUDGE.x).floor();
                if band.rem_euclid(2.0) == 0.0 { a.eval(q) } else { b.eval(q) }
            }
            Kind::Gradient { axis, map } => lookup(map, (q.dot(*axis)).rem_euclid(1.0)),
            Kind::Noise { octaves, map } => lookup(map, fbm(q, *octaves)),
            Kind::Marble { turbulence, octaves, map } => {
                // Bands along x, bent by turbulence (POV-Ray's marble: a triangle wave).
                let s = q.x + turbulence * (2.0 * fbm(q, *octaves) - 1.0) * 4.0;
                lookup(map, 0.5 + 0.5 * (PI * s).sin())
            }
            Kind::Wood { turbulence, octaves, map } => {
                // Rings around the z axis, bent by turbulence.
                let r =
                    (q.x * q.x + q.y * q.y).sqrt() + turbulence * (2.0 * fbm(q, *octaves) - 1.0);
                lookup(map, r.rem_euclid(1.0))
            }
            Kind::Image { image, look, curve } => image.sample(q, look, curve),
            Kind::Mix { a, b, t } => {
                let t = t.grey(q).clamp(0.0, 1.0);
                a.eval(q) * (1.0 - t) + b.eval(q) * t
            }
            Kind::Field { shape, map } => {
                let (i, j, s) = bracket(map.iter().map(|e| e.0), shaped_value(shape, q));
                let a = map[i].1.eval(q);
                if i == j { a } else { a + (map[j].1.eval(q) - a) * s }
            }
            Kind::Average(map) => map.iter().map(|(weight, t)| t.eval(q) * *weight).sum(),
            Kind::Warped { warp, texture } => texture.eval(warp::apply(*warp, q)),
        }
    }
}

/// Linear interpolation in a color_map (clamped at its ends); black to white when empty.
fn lookup(map: &ColorMap, t: f32) -> Vec3 {
    if map.is_empty() {
        return Vec3::splat(t);
    }
    let (i, j, s) = bracket(map.iter().map(|e| e.0), t);
    map[i].1 + (map[j].1 - map[i].1) * s
}

/// Where `t` falls in a map of ascending positions (at least one): the entries either side and
/// how far from the first to the second, clamped to the first and last entries.
pub fn bracket(positions: impl ExactSizeIterator<Item = f32>, t: f32) -> (usize, usize, f32) {
    let last = positions.len() - 1;
    let mut previous: Option<f32> = None;
    for (j, t1) in positions.enumerate() {
        if t <= t1 {
            return match previous {
                None => (0, 0, 0.0),
                Some(t0) => (j - 1, j, if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 }),
            };
        }
        previous = Some(t1);
    }
    (last, last, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Transform;

    fn texture(pattern: Pattern, transforms: Vec<Transform>) -> Texture {
        Texture::new(&TextureNode { pattern, transforms }, &mut |_| unreachable!("no image"))
            .unwrap()
    }

    fn solid(c: f32) -> Box<TextureNode> {
        Box::new(TextureNode::solid(Vec3::splat(c)))
    }

    #[test]
    fn checker_parity() {
        let t = texture(Pattern::Checker(solid(1.0), solid(0.0)), vec![]);
        assert_eq!(t.eval(Vec3::new(0.5, 0.5, 0.5)), Vec3::ONE, "cell (0,0,0): even, first");
        assert_eq!(t.eval(Vec3::new(1.5, 0.5, 0.5)), Vec3::ZERO);
        assert_eq!(t.eval(Vec3::new(1.5, 1.5, 0.5)), Vec3::ONE);
        assert_eq!(t.eval(Vec3::new(-0.5, 0.5, 0.5)), Vec3::ZERO, "floor(-0.5) = -1: odd");
        // On a cell boundary (the floor y = -1) the value is the same however the point rounds.
        let on_plane = |y: f32| t.eval(Vec3::new(0.3, y, 0.7));
        assert_eq!(on_plane(-1.0), on_plane(-1.0 + 1e-6));
        assert_eq!(on_plane(-1.0), on_plane(-1.0 - 1e-6));
    }

    #[test]
    fn transforms_move_the_pattern_not_the_points() {
        let scaled = texture(
            Pattern::Checker(solid(1.0), solid(0.0)),
            vec![Transform::Scale(Vec3::splat(0.25))],
        );
        assert_eq!(scaled.eval(Vec3::new(0.1, 0.1, 0.1)), Vec3::ONE);
        assert_eq!(scaled.eval(Vec3::new(0.3, 0.1, 0.1)), Vec3::ZERO, "cells a quarter unit wide");
        let plain = texture(Pattern::Checker(solid(1.0), solid(0.0)), vec![]);
        let moved =
            texture(Pattern::Checker(solid(1.0), solid(0.0)), vec![Transform::Translate(Vec3::X)]);
        for p in [Vec3::new(0.2, 0.3, 0.4), Vec3::new(-1.7, 2.2, 0.9)] {
            assert_eq!(
                moved.eval(p),
                plain.eval(p - Vec3::X),
                "value at p = plain value at T^-1(p)"
            );
        }
    }

    #[test]
    fn stripes_gradient_and_color_map() {
        let stripes =
            texture(Pattern::Stripes { a: solid(1.0), b: solid(0.0), axis: Vec3::Z }, vec![]);
        assert_eq!(stripes.eval(Vec3::new(5.0, 5.0, 0.5)), Vec3::ONE);
        assert_eq!(stripes.eval(Vec3::new(5.0, 5.0, 1.5)), Vec3::ZERO);
        let map = vec![(0.0, Vec3::ZERO), (0.5, Vec3::new(1.0, 0.0, 0.0)), (1.0, Vec3::ONE)];
        let gradient = texture(Pattern::Gradient { axis: Vec3::Y, map }, vec![]);
        assert!(
            (gradient.eval(Vec3::new(0.0, 0.25, 0.0)) - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6
        );
        assert!(
            (gradient.eval(Vec3::new(0.0, 0.75, 0.0)) - Vec3::new(1.0, 0.5, 0.5)).length() < 1e-6
        );
        assert!(
            (gradient.eval(Vec3::new(0.0, 1.25, 0.0)) - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6,
            "repeats"
        );
    }

    #[test]
    fn mix_interpolates_with_a_texture_as_t() {
        let t = texture(
            Pattern::Mix {
                a: solid(0.2),
                b: solid(0.8),
                t: Box::new(TextureNode {
                    pattern: Pattern::Gradient {
                        axis: Vec3::X,
                        map: vec![(0.0, Vec3::ZERO), (1.0, Vec3::ONE)],
                    },
                    transforms: vec![],
                }),
            },
            vec![],
        );
        assert!((t.eval(Vec3::new(0.5, 0.0, 0.0)) - Vec3::splat(0.5)).length() < 1e-6);
        assert!((t.eval(Vec3::new(0.25, 0.0, 0.0)) - Vec3::splat(0.35)).length() < 1e-6);
    }
}
