//! Bump mapping (`normal { PATTERN AMOUNT }`): the surface is displaced along its normal by a
//! height field, and the shading normal tilts against the height's gradient (Blinn 1978). The
//! height and its gradient live in the object's own space, as textures do.

use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};

use super::field::shaped_value;
use super::image_map::{Curve, ImageMap, ImageMapError};
use crate::graph::{FieldShape, ImageLook, NormalNode, NormalPattern, SlopeMap, compose};

/// POV-Ray's weights of a colour's gray (its `Greyscale`): a bump_map's heights.
const GRAY: Vec3 = Vec3::new(0.297, 0.589, 0.114);

/// The span of the central differences that take the height's gradient when `accuracy` is not
/// given, in pattern space (patterns vary over about a unit there; POV-Ray's default, 0.02, is
/// coarser).
pub const DEFAULT_ACCURACY: f32 = 2e-3;

#[derive(Debug, Clone)]
pub struct Bump {
    kind: Kind,
    /// Object space to pattern space.
    to_pattern: Affine3A,
    /// Its linear part, transposed: takes a gradient from pattern space to object space.
    gradient_to_object: Mat3,
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
        let gradient_to_object = Mat3::from(to_pattern.matrix3).transpose();
        Ok(Bump { kind, to_pattern, gradient_to_object })
    }

    /// The gradient of the displacement at `p` (object space), in object space: the shading
    /// normal n becomes n minus this gradient's part across n.
    pub fn gradient(&self, p: Vec3) -> Vec3 {
        let q = self.to_pattern.transform_point3(p);
        let in_pattern = match &self.kind {
            Kind::Height { shape, amount, slopes, step } => {
                let height = |q: Vec3| profile(slopes, shaped_value(shape, q));
                let axis = |d: Vec3| (height(q + d * *step) - height(q - d * *step)) / (2.0 * step);
                return self.gradient_to_object
                    * Vec3::new(axis(Vec3::X), axis(Vec3::Y), axis(Vec3::Z))
                    * *amount;
            }
            Kind::Map { shape, map } => {
                if map.is_empty() {
                    return Vec3::ZERO;
                }
                let (i, j, s) = super::bracket(map.iter().map(|e| e.0), shaped_value(shape, q));
                let a = map[i].1.gradient(q);
                a + (map[j].1.gradient(q) - a) * s
            }
            Kind::Average(map) => map.iter().map(|(w, b)| b.gradient(q) * *w).sum(),
            Kind::Image { image, look, curve, amount } => {
                // Central differences a texel wide (bilinear heights are linear across it).
                let height = |q: Vec3| image.sample(q, look, curve).dot(GRAY);
                let (du, dv) = image.texel();
                let axis = |d: Vec3| (height(q + d * 0.5) - height(q - d * 0.5)) / d.length();
                let step = du.min(dv);
                Vec3::new(axis(Vec3::X * du), axis(Vec3::Y * dv), axis(Vec3::Z * step)) * *amount
            }
        };
        // The entries' gradients are in this node's pattern space.
        self.gradient_to_object * in_pattern
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

/// The shading normal `shading` tilted by the displacement's `gradient`, kept on the side of
/// the geometric normal `geometric` that `wo` (towards the viewer) is on, so that the viewer
/// never sees the back of a bumped surface (no black rims at grazing angles): where the tilt
/// would hide `wo`, the normal is bent back towards `wo` until it sees it at a small angle
/// (Keller et al. 2017, "The Iray light transport system", A.3).
pub fn tilt(shading: Vec3, gradient: Vec3, geometric: Vec3, wo: Vec3) -> Vec3 {
    let across = gradient - shading * gradient.dot(shading);
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

    #[test]
    fn the_gradient_of_a_ramp_is_its_slope_times_the_amount() {
        let g = gradient_x(0.5, Vec::new()).gradient(Vec3::new(0.3, 0.2, 0.7));
        assert!((g - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-3, "{g}");
        // Scaled by 2 along x, the ramp is half as steep in object space.
        let g = gradient_x(0.5, vec![Transform::Scale(Vec3::new(2.0, 1.0, 1.0))])
            .gradient(Vec3::new(0.6, 0.2, 0.7));
        assert!((g - Vec3::new(0.25, 0.0, 0.0)).length() < 1e-3, "{g}");
        assert_eq!(gradient_x(0.0, Vec::new()).gradient(Vec3::splat(0.4)), Vec3::ZERO);
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
                let g = sine(h).gradient(p);
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
        let g = map.gradient(Vec3::new(0.4, 0.25, 0.0));
        assert!((g - Vec3::new(0.25, 0.0, 0.0)).length() < 1e-3, "{g}");
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
