//! Bump mapping (`normal { PATTERN AMOUNT }`): the surface is displaced along its normal by a
//! height field, and the shading normal tilts against the height's gradient (Blinn 1978). The
//! height and its gradient live in the object's own space, as textures do.

use glam::{Affine3A, Mat3, Vec3};

use super::field::shaped_value;
use crate::graph::{FieldShape, NormalNode, NormalPattern, SlopeMap, compose};

/// Half the step of the central differences that take the height's gradient, in pattern space
/// (patterns vary over about a unit there).
const STEP: f32 = 1e-3;

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
    },
    Map {
        shape: FieldShape,
        map: Vec<(f32, Bump)>,
    },
    /// Weights normalised to sum to 1.
    Average(Vec<(f32, Bump)>),
}

impl Bump {
    pub fn new(node: &NormalNode) -> Bump {
        let kind = match &node.pattern {
            NormalPattern::Bumps { shape, amount, slopes } => {
                Kind::Height { shape: (**shape).clone(), amount: *amount, slopes: slopes.clone() }
            }
            NormalPattern::Map { shape, map } => Kind::Map {
                shape: (**shape).clone(),
                map: map.iter().map(|(t, n)| (*t, Bump::new(n))).collect(),
            },
            NormalPattern::Average(map) => {
                let total: f32 = map.iter().map(|(w, _)| w).sum();
                Kind::Average(map.iter().map(|(w, n)| (w / total, Bump::new(n))).collect())
            }
        };
        let to_pattern = compose(&node.transforms).inverse();
        Bump { kind, to_pattern, gradient_to_object: Mat3::from(to_pattern.matrix3).transpose() }
    }

    /// The gradient of the displacement at `p` (object space), in object space: the shading
    /// normal n becomes n minus this gradient's part across n.
    pub fn gradient(&self, p: Vec3) -> Vec3 {
        let q = self.to_pattern.transform_point3(p);
        let in_pattern = match &self.kind {
            Kind::Height { shape, amount, slopes } => {
                let height = |q: Vec3| profile(slopes, shaped_value(shape, q));
                let axis = |d: Vec3| (height(q + d * STEP) - height(q - d * STEP)) / (2.0 * STEP);
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
    use super::*;
    use crate::graph::{Field, Transform, Wave};

    fn gradient_x(amount: f32, transforms: Vec<Transform>) -> Bump {
        let shape = FieldShape {
            field: Field::Gradient(Vec3::X),
            turbulence: None,
            warps: Vec::new(),
            wave: Wave::Ramp,
            frequency: 1.0,
            phase: 0.0,
        };
        Bump::new(&NormalNode {
            pattern: NormalPattern::Bumps { shape: Box::new(shape), amount, slopes: Vec::new() },
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
            },
            transforms: Vec::new(),
        };
        let map = Bump::new(&NormalNode {
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
