//! The rough lobes (`docs/language.md`) against the model written out here independently, in f64:
//! GGX D, Smith's G1, reflection ks D G / (4 |n.o| |n.i|), Walter's refraction. Integrals over
//! directions are taken over microfacet normals m, in the variable u = tan^2 / (alpha^2 + tan^2)
//! (the share of projected microfacet area within theta_m), where D(m) cos dm = du dphi / 2 pi: the
//! peak of D needs no finer grid than its tails.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use raydiance::material::{Bsdf, LobeFlags, Material, TransportMode, fresnel_dielectric};
use raydiance::sampling::Sampler;

const IOR: f32 = 1.5;

/// Relative error of the quadratures: the grid over m cuts the horizon (where reflected or
/// refracted directions leave their side) cell by cell.
const QUADRATURE: f64 = 1e-3;

fn material(specular: f32, transmission: f32, fresnel: bool, alpha: f32) -> Material {
    Material {
        specular: Vec3::splat(specular),
        transmission: Vec3::splat(transmission),
        ior: IOR,
        fresnel,
        roughness: alpha,
        ..Material::default()
    }
}

/// Smith's G1 for GGX, from Lambda in its tangent form (Walter 2007, eq. 34).
fn g1(alpha: f64, w: DVec3) -> f64 {
    let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The microfacet normals of GGX alpha as midpoints of a grid in (v, phi), u = 1 - v^2, each
/// with its weight D(m) cos(theta_m) dm (the weights add up to 1). In v rather than u, the
/// integrands' 1 / cos(theta_m) ~ (1 - u)^(-1/2) near the horizon becomes smooth.
fn normals(alpha: f64, steps: usize) -> impl Iterator<Item = (DVec3, f64)> {
    (0..steps * steps).map(move |k| {
        let v = ((k / steps) as f64 + 0.5) / steps as f64;
        let phi = ((k % steps) as f64 + 0.5) / steps as f64 * 2.0 * PI;
        let tan2 = alpha * alpha * (1.0 - v * v) / (v * v);
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).sqrt();
        (DVec3::new(sin * phi.cos(), sin * phi.sin(), cos), 2.0 * v / (steps * steps) as f64)
    })
}

/// Directional albedo of the model, ∫ f |cos i| di, reflection and transmission apart, from
/// `wo` (local, above); eta = eta_t / eta_i seen from wo; importance transport (no 1/eta^2).
/// Over m: di = 4 (o.m) dm for reflection and (i.m + o.m / eta)^2 / |i.m| dm for refraction,
/// so both reduce to G1(o) G1(i) (o.m) / (o.z cos theta_m) times the share at m.
fn model_albedo(alpha: f64, wo: DVec3, eta: f64, split: impl Fn(f64) -> (f64, f64)) -> (f64, f64) {
    let (mut reflect, mut transmit) = (0.0, 0.0);
    for (m, weight) in normals(alpha, 600) {
        let om = wo.dot(m);
        if om <= 0.0 {
            continue;
        }
        let (r, t) = split(om);
        let common = g1(alpha, wo) * om / (wo.z * m.z) * weight;
        let wi = 2.0 * om * m - wo;
        if wi.z > 0.0 {
            reflect += r * g1(alpha, wi) * common;
        }
        let sin2_t = (1.0 - om * om) / (eta * eta);
        if sin2_t < 1.0 {
            let wt = -wo / eta + (om / eta - (1.0 - sin2_t).sqrt()) * m;
            if wt.z < 0.0 {
                transmit += t * g1(alpha, wt) * common;
            }
        }
    }
    (reflect, transmit)
}

/// ∫ f |cos i| di of the code's `eval`, reflection and transmission apart, by the same grid
/// over m and the Jacobians above.
fn eval_albedo(
    bsdf: &Bsdf,
    frame: (Vec3, Vec3, Vec3),
    alpha: f64,
    wo: DVec3,
    eta: f64,
) -> (f64, f64) {
    let world = |v: DVec3| v.x as f32 * frame.0 + v.y as f32 * frame.1 + v.z as f32 * frame.2;
    let d = |m: DVec3| {
        let t = m.x * m.x + m.y * m.y + alpha * alpha * m.z * m.z;
        alpha * alpha / (PI * t * t)
    };
    let (mut reflect, mut transmit) = (0.0, 0.0);
    for (m, weight) in normals(alpha, 600) {
        let om = wo.dot(m);
        if om <= 0.0 {
            continue;
        }
        let dm = weight / (d(m) * m.z);
        let wi = 2.0 * om * m - wo;
        if wi.z > 0.0 {
            let f = f64::from(bsdf.eval(world(wo), world(wi)).x);
            reflect += f * wi.z * 4.0 * om * dm;
        }
        let sin2_t = (1.0 - om * om) / (eta * eta);
        if sin2_t < 1.0 {
            let wt = -wo / eta + (om / eta - (1.0 - sin2_t).sqrt()) * m;
            if wt.z < 0.0 {
                let f = f64::from(bsdf.eval(world(wo), world(wt)).x);
                let denominator = wt.dot(m) + om / eta;
                transmit += f * -wt.z * denominator * denominator / -wt.dot(m) * dm;
            }
        }
    }
    (reflect, transmit)
}

/// The mean of `sample`'s weights (its estimate of the albedo), reflection and transmission
/// apart, and the standard error of their sum.
fn sampled_albedo(bsdf: &Bsdf, n: Vec3, wo: Vec3) -> (f64, f64, f64) {
    let count = 200_000;
    let (mut reflect, mut transmit, mut squares) = (0.0, 0.0, 0.0);
    for i in 0..count {
        let mut s = Sampler::new(3, i, 0);
        let Some(sample) = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL) else {
            continue;
        };
        let w = f64::from(sample.weight.x);
        if sample.wi.dot(n) * wo.dot(n) > 0.0 {
            reflect += w
        } else {
            transmit += w
        }
        squares += w * w;
    }
    let n = count as f64;
    let mean = (reflect + transmit) / n;
    (reflect / n, transmit / n, ((squares / n - mean * mean) / n).sqrt())
}

/// An orthonormal frame (t, b, n) and a direction at angle theta from n (or from -n, below).
fn setup(theta: f32, below: bool) -> ((Vec3, Vec3, Vec3), Vec3, DVec3) {
    let n = Vec3::new(0.2, 0.3, 0.9).normalize();
    let (t, b) = n.any_orthonormal_pair();
    let local = DVec3::new(f64::from(theta.sin()), 0.0, f64::from(theta.cos()));
    let sign = if below { -1.0 } else { 1.0 };
    // Below, the frame turns over with its normal (t, -b, -n stays right-handed).
    let frame = (t, sign * b, sign * n);
    let wo = local.x as f32 * frame.0 + local.y as f32 * frame.1 + local.z as f32 * frame.2;
    (frame, wo, local)
}

#[test]
fn rough_reflection_albedo_matches_a_quadrature_of_the_model() {
    for alpha in [0.1f32, 0.3, 0.6, 1.0] {
        for theta in [0.0f32, 0.7, 1.2, 1.5] {
            let (frame, wo, local) = setup(theta, false);
            let metal = material(1.0, 0.0, false, alpha);
            let bsdf = metal.bsdf(frame.2, TransportMode::Radiance);
            let (model, none) = model_albedo(f64::from(alpha), local, 1.5, |_| (1.0, 0.0));
            assert_eq!(none, 0.0);
            let (eval, no_transmission) = eval_albedo(&bsdf, frame, f64::from(alpha), local, 1.5);
            let (sampled, sampled_transmission, error) = sampled_albedo(&bsdf, frame.2, wo);
            let what = format!("alpha {alpha}, theta {theta}");
            assert!(model <= 1.0 && model > 0.0, "{what}: albedo {model}");
            assert!(
                (eval - model).abs() < QUADRATURE * model,
                "{what}: eval {eval}, model {model}"
            );
            assert_eq!((no_transmission, sampled_transmission), (0.0, 0.0), "{what}");
            assert!(
                (sampled - model).abs() < 5.0 * error + QUADRATURE * model,
                "{what}: {sampled} vs {model}"
            );
        }
    }
}

#[test]
fn rough_dielectric_reflects_and_transmits_at_most_what_arrives() {
    for alpha in [0.05f32, 0.15, 0.5, 1.0] {
        for theta in [0.0f32, 0.5, 0.9, 1.4] {
            for below in [false, true] {
                let (frame, wo, local) = setup(theta, below);
                let n = if below { -frame.2 } else { frame.2 };
                let glass = material(0.0, 1.0, true, alpha);
                let bsdf = glass.bsdf(n, TransportMode::Importance);
                let eta = if below { 1.0 / 1.5 } else { 1.5 };
                let fresnel = |om: f64| {
                    let f = f64::from(fresnel_dielectric(om as f32, eta as f32));
                    (f, 1.0 - f)
                };
                let a = f64::from(alpha);
                let (r, t) = model_albedo(a, local, eta, fresnel);
                let (er, et) = eval_albedo(&bsdf, frame, a, local, eta);
                let (sr, st, error) = sampled_albedo(&bsdf, n, wo);
                let what = format!("alpha {alpha}, theta {theta}, from below {below}");
                assert!(r + t <= 1.0 + 1e-6 && r + t > 0.0, "{what}: R {r} + T {t}");
                assert!((er - r).abs() < QUADRATURE * (r + t), "{what}: R eval {er}, model {r}");
                assert!((et - t).abs() < QUADRATURE * (r + t), "{what}: T eval {et}, model {t}");
                let (sum, model) = (sr + st, r + t);
                assert!(
                    (sum - model).abs() < 5.0 * error + QUADRATURE * model,
                    "{what}: {sum} vs {model}"
                );
                assert!((sr - r).abs() < 0.02 * model, "{what}: R sampled {sr}, model {r}");
            }
        }
    }
}

#[test]
fn rough_reflection_is_reciprocal() {
    let n = Vec3::new(-0.3, 0.5, 0.8).normalize();
    let mut s = Sampler::new(8, 0, 0);
    for m in [
        material(0.8, 0.0, false, 0.3),
        material(0.0, 1.0, true, 0.2),
        material(0.3, 0.6, false, 0.7),
    ] {
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let bsdf = m.bsdf(n, mode);
            let mut checked = 0;
            for _ in 0..2000 {
                let (a, b) = (
                    raydiance::sampling::uniform_sphere(s.next_2d()),
                    raydiance::sampling::uniform_sphere(s.next_2d()),
                );
                if a.dot(n) * b.dot(n) <= 0.0 {
                    continue;
                }
                let (f, g) = (bsdf.eval(a, b), bsdf.eval(b, a));
                assert!((f - g).abs().max_element() <= 1e-4 * f.max_element(), "{m:?}: {f} vs {g}");
                checked += usize::from(f.max_element() > 0.0);
            }
            assert!(checked > 500);
        }
    }
}

/// E[weight g(wi)] over `bsdf.sample` for a smooth g.
fn expected(bsdf: &Bsdf, wo: Vec3, g: impl Fn(Vec3) -> f32) -> Vec3 {
    let count = 20_000;
    let mut sum = Vec3::ZERO;
    for i in 0..count {
        let mut s = Sampler::new(4, i, 0);
        if let Some(sample) = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL) {
            sum += sample.weight * g(sample.wi);
        }
    }
    sum / count as f32
}

#[test]
fn rough_lobes_approach_the_perfect_ones_as_alpha_goes_to_zero() {
    let n = Vec3::new(0.1, -0.2, 0.95).normalize();
    let (t, _) = n.any_orthonormal_pair();
    let g = |wi: Vec3| 1.0 + 0.5 * wi.x + 0.3 * wi.y * wi.z;
    // Entering, leaving below and beyond the critical angle (0.73 rad), grazing.
    for theta in [0.0f32, 0.5, 0.9, 1.4] {
        for side in [1.0, -1.0] {
            let wo = side * (theta.cos() * n + theta.sin() * t);
            for m in [
                material(0.9, 0.0, false, 0.0),
                material(0.0, 1.0, true, 0.0),
                material(0.2, 0.7, false, 0.0),
                material(0.1, 0.6, true, 0.0),
            ] {
                let smooth = expected(&m.bsdf(n, TransportMode::Radiance), wo, g);
                let mut previous = f32::INFINITY;
                for alpha in [0.1, 0.01, 0.001] {
                    let rough = Material { roughness: alpha, ..m.clone() };
                    let rough = expected(&rough.bsdf(n, TransportMode::Radiance), wo, g);
                    let difference = (rough - smooth).abs().max_element();
                    if alpha == 0.001 {
                        assert!(
                            difference < 0.01 * smooth.max_element() + 1e-3,
                            "{m:?} from {wo}: {rough} vs {smooth}"
                        );
                    }
                    assert!(
                        difference <= previous + 2e-3,
                        "{m:?} from {wo}, alpha {alpha}: {difference} after {previous}"
                    );
                    previous = difference;
                }
            }
        }
    }
}
