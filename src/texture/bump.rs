//! Bump mapping (`normal { PATTERN AMOUNT }`): the shading normal tilts as POV-Ray 3.7 tilts it
//! (its normal.cpp, `Perturb_Normal`). The normal is taken into the pattern's space (by the
//! inverse transpose of the pattern's transform) and kept unit there; a pattern tilts it against
//! its value's gradient times 2/15 the amount, or by its own rule (bumps, dents, wrinkles,
//! ripples, waves); then it goes back. The tilt so does not depend on the pattern's scale, as in
//! POV-Ray (a bump scaled down is not steeper), unlike a height field's.

use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};

use super::field::{shaped_value, wave_sources};
use super::image_map::{Curve, ImageMap, ImageMapError};
use super::noise::{noise, vector_noise};
use super::warp::warped;
use crate::graph::{Field, FieldShape, ImageLook, NormalNode, NormalPattern, SlopeMap, compose};

/// POV-Ray's weights of a colour's gray (its `Greyscale`): a bump_map's heights.
const GRAY: Vec3 = Vec3::new(0.297, 0.589, 0.114);

/// The tilt per unit of amount and of the value's gradient. POV-Ray adds -5 amount (0.02 /
/// accuracy) f(q + accuracy v_i) v_i over the four unit vectors v_i to a regular tetrahedron's
/// corners; as sum v_i v_i^T = 4/3 I, that is -5 * 0.02 * 4/3 = -2/15 times amount times the
/// gradient, whatever the accuracy.
const GRADIENT_TILT: f32 = 2.0 / 15.0;

/// The span of the central differences that take the height's gradient when `accuracy` is not
/// given, in pattern space (patterns vary over about a unit there; POV-Ray's default, 0.02, is
/// coarser).
pub const DEFAULT_ACCURACY: f32 = 2e-3;

#[derive(Debug, Clone)]
pub struct Bump {
    kind: Kind,
    /// Object space to pattern space.
    to_pattern: Affine3A,
    /// Its linear part, transposed: takes a normal's tilt from pattern space to object space.
    tilt_to_object: Mat3,
    /// The inverse of that: takes a normal from object space to pattern space.
    normal_to_pattern: Mat3,
}

#[derive(Debug, Clone)]
enum Kind {
    Height {
        shape: FieldShape,
        amount: f32,
        slopes: SlopeMap,
        /// Half the span of the differences.
        step: f32,
    },
    Map {
        shape: FieldShape,
        map: Vec<(f32, Bump)>,
    },
    /// Weights normalised to sum to 1.
    Average(Vec<(f32, Bump)>),
    /// A bump_map: the image's gray as heights.
    Image {
        image: Arc<ImageMap>,
        look: ImageLook,
        curve: Curve,
        amount: f32,
    },
}

impl Bump {
    /// Compiles a normal; `load` reads `bump_map` images (errors are the caller's).
    pub fn new(
        node: &NormalNode,
        load: &mut dyn FnMut(&Path) -> Result<Arc<ImageMap>, ImageMapError>,
    ) -> Result<Bump, ImageMapError> {
        let entries = |map: &[(f32, NormalNode)],
                       load: &mut dyn FnMut(&Path) -> Result<Arc<ImageMap>, ImageMapError>|
         -> Result<Vec<(f32, Bump)>, ImageMapError> {
            map.iter().map(|(t, n)| Ok((*t, Bump::new(n, load)?))).collect()
        };
        let kind = match &node.pattern {
            NormalPattern::Bumps { shape, amount, slopes, accuracy } => Kind::Height {
                shape: (**shape).clone(),
                amount: *amount,
                slopes: slopes.clone(),
                step: 0.5 * accuracy,
            },
            NormalPattern::Map { shape, map } => {
                Kind::Map { shape: (**shape).clone(), map: entries(map, load)? }
            }
            NormalPattern::Average(map) => {
                let total: f32 = map.iter().map(|(w, _)| w).sum();
                let map = entries(map, load)?.into_iter().map(|(w, b)| (w / total, b)).collect();
                Kind::Average(map)
            }
            NormalPattern::Image { path, look, amount } => Kind::Image {
                image: load(path)?,
                look: *look,
                curve: Curve::new(look.gamma),
                amount: *amount,
            },
        };
        let to_pattern = compose(&node.transforms).inverse();
        let tilt_to_object = Mat3::from(to_pattern.matrix3).transpose();
        let normal_to_pattern = tilt_to_object.inverse();
        Ok(Bump { kind, to_pattern, tilt_to_object, normal_to_pattern })
    }

    /// The tilt t of the unit normal `n` at `p` (both in object space), in object space: the
    /// shading normal becomes n - t, normalised. POV-Ray's n' = normalise(M^-T (n_p - t_p)),
    /// with n_p = M^T n / |M^T n| in pattern space (M: pattern to object), is n - |M^T n| M^-T t_p.
    pub fn perturbation(&self, p: Vec3, n: Vec3) -> Vec3 {
        let q = self.to_pattern.transform_point3(p);
        let normal = self.normal_to_pattern * n;
        let length = normal.length();
        if length == 0.0 {
            return Vec3::ZERO;
        }
        let n = normal / length;
        let in_pattern = match &self.kind {
            Kind::Height { shape, amount, slopes, step } => {
                if let Some(own) = own_perturbation(shape, q) {
                    // POV-Ray adds amount times its own vector to the normal.
                    -own * *amount
                } else {
                    let height = |q: Vec3| profile(slopes, shaped_value(shape, q));
                    let axis =
                        |d: Vec3| (height(q + d * *step) - height(q - d * *step)) / (2.0 * step);
                    Vec3::new(axis(Vec3::X), axis(Vec3::Y), axis(Vec3::Z))
                        * (*amount * GRADIENT_TILT)
                }
            }
            Kind::Map { shape, map } => {
                if map.is_empty() {
                    return Vec3::ZERO;
                }
                let (i, j, s) = super::bracket(map.iter().map(|e| e.0), shaped_value(shape, q));
                let a = map[i].1.perturbation(q, n);
                a + (map[j].1.perturbation(q, n) - a) * s
            }
            Kind::Average(map) => map.iter().map(|(w, b)| b.perturbation(q, n) * *w).sum(),
            Kind::Image { image, look, curve, amount } => {
                // Central differences a texel wide (bilinear heights are linear across it).
                let height = |q: Vec3| image.sample(q, look, curve).dot(GRAY);
                let (du, dv) = image.texel();
                let axis = |d: Vec3| (height(q + d * 0.5) - height(q - d * 0.5)) / d.length();
                let step = du.min(dv);
                Vec3::new(axis(Vec3::X * du), axis(Vec3::Y * dv), axis(Vec3::Z * step)) * *amount
            }
        };
        // The entries' tilts are in this node's pattern space.
        self.tilt_to_object * in_pattern * length
    }
}

/// POV-Ray's own perturbation of the normal (pattern space, per unit of amount) by the patterns
/// that have one (normal.cpp: bumps, dents, wrinkles, ripples, waves), at `q` before the warps;
/// none for the patterns that tilt against their value's gradient.
fn own_perturbation(shape: &FieldShape, q: Vec3) -> Option<Vec3> {
    // POV-Ray's DNoise spans about [-0.5, 0.5], half of vector_noise's span.
    let dnoise = |q: Vec3| 0.5 * vector_noise(q);
    let q = warped(shape, q);
    match shape.field {
        Field::Bumps => Some(dnoise(q)),
        Field::Dents => Some(dnoise(q) * noise(q).powi(3)),
        Field::Wrinkles => {
            // Ten octaves of |DNoise|, each at twice the frequency and half the weight.
            let (mut sum, mut scale) = (Vec3::ZERO, 1.0);
            for _ in 0..10 {
                sum += (dnoise(q * scale) / scale).abs();
                scale *= 2.0;
            }
            Some(sum)
        }
        Field::Ripples | Field::Waves => {
            // Along each source's radius by the wave's sine there, averaged over the sources.
            let sources = wave_sources();
            let count = sources.len() as f32;
            let sum = sources
                .iter()
                .map(|&source| {
                    let radius = q - source;
                    let length = radius.length();
                    let crest = length * shape.frequency + shape.phase;
                    (std::f32::consts::TAU * crest).sin() * radius.normalize_or_zero()
                })
                .sum::<Vec3>();
            Some(sum / count)
        }
        Field::Agate { .. }
        | Field::Bozo
        | Field::Brick { .. }
        | Field::Cells
        | Field::Checker
        | Field::Crackle(_)
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
        | Field::Marble
        | Field::Onion
        | Field::Quilted { .. }
        | Field::Radial
        | Field::Spiral1 { .. }
        | Field::Spiral2 { .. }
        | Field::Spotted
        | Field::Wood => None,
    }
}

/// The height at pattern value `v`: `v` itself without a slope map, else the cubic (Hermite)
/// through the entries' heights with their slopes, clamped at the ends.
pub fn profile(slopes: &SlopeMap, v: f32) -> f32 {
    if slopes.is_empty() {
        return v;
    }
    let (i, j, s) = super::bracket(slopes.iter().map(|e| e.0), v);
    let ((t0, h0, m0), (t1, h1, m1)) = (slopes[i], slopes[j]);
    if i == j {
        return h0;
    }
    let d = t1 - t0;
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * h0
        + (s3 - 2.0 * s2 + s) * d * m0
        + (-2.0 * s3 + 3.0 * s2) * h1
        + (s3 - s2) * d * m1
}

/// The shading normal `shading` tilted by `by` (`Bump::perturbation`), kept on the side of
/// the geometric normal `geometric` that `wo` (towards the viewer) is on, so that the viewer
/// never sees the back of a bumped surface (no black rims at grazing angles): where the tilt
/// would hide `wo`, the normal is bent back towards `wo` until it sees it at a small angle
/// (Keller et al. 2017, "The Iray light transport system", A.3).
pub fn tilt(shading: Vec3, by: Vec3, geometric: Vec3, wo: Vec3) -> Vec3 {
    let across = by - shading * by.dot(shading);
    // Without a tilt the surface is as it is, bit for bit (amount 0 is no bump).
    if across == Vec3::ZERO {
        return shading;
    }
    let n = (shading - across).normalize_or(shading);
    // The side wo is on; the tilted normal must see wo from that side.
    let side = if wo.dot(geometric) >= 0.0 { 1.0 } else { -1.0 };
    const MIN_COS: f32 = 0.01;
    let cos = side * wo.dot(n);
    if cos >= MIN_COS {
        return n;
    }
    // n + k wo has side * wo.(n + k wo) = cos + side * k: raised to MIN_COS, then normalised
    // (which keeps the sign).
    (n + wo * side * (MIN_COS - cos)).normalize_or(shading)
}

#[cfg(test)]
mod tests {
    use std::f32::consts::{PI, TAU};

    use super::*;
    use crate::graph::{Field, Transform, Wave};

    fn compile(node: &NormalNode) -> Bump {
        Bump::new(node, &mut |_| unreachable!("no image")).unwrap()
    }

    fn gradient_x(amount: f32, transforms: Vec<Transform>) -> Bump {
        let shape = FieldShape {
            field: Field::Gradient(Vec3::X),
            turbulence: None,
            warps: Vec::new(),
            wave: Wave::Ramp,
            frequency: 1.0,
            phase: 0.0,
        };
        compile(&NormalNode {
            pattern: NormalPattern::Bumps {
                shape: Box::new(shape),
                amount,
                slopes: Vec::new(),
                accuracy: DEFAULT_ACCURACY,
            },
            transforms,
        })
    }

    /// A ramp tilts the normal by 2/15 of its slope times the amount (POV-Ray's four samples on
    /// a tetrahedron, normal.cpp), the same whatever the pattern's scale.
    #[test]
    fn a_ramp_tilts_by_two_fifteenths_of_its_slope_times_the_amount() {
        let k = 0.5 * 2.0 / 15.0;
        let t = gradient_x(0.5, Vec::new()).perturbation(Vec3::new(0.3, 0.2, 0.7), Vec3::Z);
        assert!((t - Vec3::new(k, 0.0, 0.0)).length() < 1e-4, "{t}");
        let scaled = gradient_x(0.5, vec![Transform::Scale(Vec3::splat(0.1))]);
        let t = scaled.perturbation(Vec3::new(0.03, 0.02, 0.07), Vec3::Z);
        assert!((t - Vec3::new(k, 0.0, 0.0)).length() < 1e-4, "scale 0.1: {t}");
        assert_eq!(gradient_x(0.0, Vec::new()).perturbation(Vec3::splat(0.4), Vec3::Z), Vec3::ZERO);
    }

    /// Stretched unevenly, the normal tilts as POV-Ray tilts it: into pattern space by M^T,
    /// tilted there, back by M^-T (M = scale <2, 1, 1>).
    #[test]
    fn a_stretched_pattern_tilts_as_in_pattern_space() {
        let m = Vec3::new(2.0, 1.0, 1.0);
        let bump = gradient_x(0.5, vec![Transform::Scale(m)]);
        for n in [Vec3::new(1.0, 1.0, 0.0), Vec3::new(-0.3, 1.0, 0.5), Vec3::new(0.2, 0.1, 1.0)] {
            let n = n.normalize();
            let seen = (n - bump.perturbation(Vec3::new(0.6, 0.2, 0.7), n)).normalize();
            let in_pattern = (n * m).normalize() - Vec3::new(0.5 * 2.0 / 15.0, 0.0, 0.0);
            let expected = (in_pattern / m).normalize();
            assert!((seen - expected).length() < 1e-4, "{n}: {seen} {expected}");
        }
    }

    /// Bumps, dents, wrinkles, ripples and waves tilt by their own rules: not at all with amount
    /// 0, and as much at scale 0.1 as at scale 1 (at the same pattern point).
    #[test]
    fn own_perturbations_scale_with_the_amount_not_the_pattern() {
        let bump = |field: Field, amount: f32, scale: f32| {
            let shape = FieldShape {
                field,
                turbulence: None,
                warps: Vec::new(),
                wave: Wave::Ramp,
                frequency: 1.0,
                phase: 0.0,
            };
            let pattern = NormalPattern::Bumps {
                shape: Box::new(shape),
                amount,
                slopes: Vec::new(),
                accuracy: 0.02,
            };
            compile(&NormalNode { pattern, transforms: vec![Transform::Scale(Vec3::splat(scale))] })
        };
        for field in [Field::Bumps, Field::Dents, Field::Wrinkles, Field::Ripples, Field::Waves] {
            let mut largest = 0.0f32;
            for i in 0..50 {
                let q = Vec3::new(i as f32 * 0.173, 0.31 - i as f32 * 0.07, 0.5 + i as f32 * 0.11);
                assert_eq!(bump(field.clone(), 0.0, 1.0).perturbation(q, Vec3::Y), Vec3::ZERO);
                let t = bump(field.clone(), 0.8, 1.0).perturbation(q, Vec3::Y);
                let small = bump(field.clone(), 0.8, 0.1).perturbation(q * 0.1, Vec3::Y);
                assert!((t - small).length() < 1e-4, "{field:?} at {q}: {t} {small}");
                // POV-Ray's noise vectors are under 1 long; ripples' mean sine is at most 1.
                assert!(t.length() < 0.8 * 1.8, "{field:?} at {q}: {t}");
                largest = largest.max(t.length());
            }
            assert!(largest > 0.02, "{field:?} tilts: {largest}");
        }
    }

    /// The gradient is a central difference `accuracy` wide: across a sine wave of period 1
    /// (0.5 + 0.5 sin 2πx) it is cos(2πx) sin(πh) / h for a span h, the derivative π cos(2πx)
    /// as h shrinks.
    #[test]
    fn accuracy_is_the_span_of_the_differences() {
        let sine = |accuracy: f32| {
            let shape = FieldShape {
                field: Field::Gradient(Vec3::X),
                turbulence: None,
                warps: Vec::new(),
                wave: Wave::Sine,
                frequency: 1.0,
                phase: 0.0,
            };
            let pattern = NormalPattern::Bumps {
                shape: Box::new(shape),
                amount: 1.0,
                slopes: Vec::new(),
                accuracy,
            };
            compile(&NormalNode { pattern, transforms: Vec::new() })
        };
        for x in [0.1f32, 0.3, 0.45] {
            let p = Vec3::new(x, 0.2, 0.3);
            let expected = |h: f32| (TAU * x).cos() * (PI * h).sin() / h;
            for h in [0.5, 0.2, DEFAULT_ACCURACY] {
                let g = sine(h).perturbation(p, Vec3::Z) / (2.0 / 15.0);
                assert!((g.x - expected(h)).abs() < 1e-3, "h {h} at {x}: {g}");
                assert_eq!((g.y, g.z), (0.0, 0.0));
            }
        }
    }

    #[test]
    fn normal_maps_interpolate_their_entries_perturbations() {
        let shape = FieldShape {
            field: Field::Gradient(Vec3::Y),
            turbulence: None,
            warps: Vec::new(),
            wave: Wave::Ramp,
            frequency: 1.0,
            phase: 0.0,
        };
        let entry = |amount: f32| NormalNode {
            pattern: NormalPattern::Bumps {
                shape: Box::new(FieldShape { field: Field::Gradient(Vec3::X), ..shape.clone() }),
                amount,
                slopes: Vec::new(),
                accuracy: DEFAULT_ACCURACY,
            },
            transforms: Vec::new(),
        };
        let map = compile(&NormalNode {
            pattern: NormalPattern::Map {
                shape: Box::new(shape.clone()),
                map: vec![(0.0, entry(0.0)), (1.0, entry(1.0))],
            },
            transforms: Vec::new(),
        });
        // At y = 0.25 the map is a quarter of the way to the second entry.
        let g = map.perturbation(Vec3::new(0.4, 0.25, 0.0), Vec3::Z);
        assert!((g - Vec3::new(0.25 * 2.0 / 15.0, 0.0, 0.0)).length() < 1e-4, "{g}");
    }

    #[test]
    fn slope_maps_pass_through_their_heights_with_their_slopes() {
        let slopes = vec![(0.0, 0.0, 1.0), (0.5, 1.0, 0.0), (1.0, 0.0, -1.0)];
        assert_eq!(profile(&slopes, 0.0), 0.0);
        assert_eq!(profile(&slopes, 0.5), 1.0);
        assert_eq!(profile(&slopes, 1.0), 0.0);
        let d = (profile(&slopes, 0.001) - profile(&slopes, 0.0)) / 0.001;
        assert!((d - 1.0).abs() < 0.01, "slope at 0: {d}");
        let d = (profile(&slopes, 0.501) - profile(&slopes, 0.499)) / 0.002;
        assert!(d.abs() < 0.01, "slope at the top: {d}");
        assert_eq!(profile(&Vec::new(), 0.3), 0.3, "no map: the value");
    }

    #[test]
    fn tilted_normals_are_unit_and_face_the_viewer() {
        let n = Vec3::Y;
        assert_eq!(tilt(n, Vec3::ZERO, n, Vec3::new(0.0, 1.0, 0.0)), n, "no gradient, no tilt");
        for i in 0..200 {
            let a = i as f32 * 0.1;
            let gradient = Vec3::new(a.sin(), 0.3, a.cos()) * (i as f32 * 0.05);
            // Down to grazing views, from above and below.
            let elevation = (i % 20) as f32 * 0.004 - 0.04;
            let wo = Vec3::new(a.cos(), elevation, -a.sin()).normalize();
            let t = tilt(n, gradient, n, wo);
            assert!((t.length() - 1.0).abs() < 1e-5);
            let side = if wo.y >= 0.0 { 1.0 } else { -1.0 };
            assert!(side * wo.dot(t) > 0.0, "{wo} sees the back of {t}");
        }
    }
}
