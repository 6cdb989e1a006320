//! The coated plastic lobe (`coat` in `docs/language.md`) against its model written out here
//! independently, in f64: a GGX dielectric coat c F(o.m) D G / (4 |n.o| |n.i|) of ior 1.5 over
//! a Lambertian base kd / pi (1 - F(n.o)) (1 - F(n.i)). The coat is integrated over microfacet
//! normals as in `rough_bsdf.rs`, the base over a grid in (cos theta, phi).

use crate::common;

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use raydiance::graph::{Covers, MaterialDesc};
use raydiance::material::{Bsdf, Coat, LobeFlags, Material, NO_DIRECTION, TransportMode};
use raydiance::sampling::Sampler;

const IOR: f64 = 1.5;

/// Relative error of the quadratures.
const QUADRATURE: f64 = 2e-3;

fn plastic(diffuse: f32, strength: f32, alpha: f32) -> Material {
    Material {
        diffuse: Vec3::splat(diffuse),
        coat: Some(Coat { strength, roughness: alpha, covers: Covers::Base }),
        ..Material::default()
    }
}

/// Unpolarised Fresnel reflectance of a dielectric of index `IOR` seen from outside.
fn fresnel(cos_i: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let cos_t = (1.0 - (1.0 - cos_i * cos_i) / (IOR * IOR)).sqrt();
    let parallel = (IOR * cos_i - cos_t) / (IOR * cos_i + cos_t);
    let perpendicular = (cos_i - IOR * cos_t) / (cos_i + IOR * cos_t);
    0.5 * (parallel * parallel + perpendicular * perpendicular)
}

fn g1(alpha: f64, w: DVec3) -> f64 {
    let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

fn ggx_d(alpha: f64, m: DVec3) -> f64 {
    let t = m.x * m.x + m.y * m.y + alpha * alpha * m.z * m.z;
    alpha * alpha / (PI * t * t)
}

/// Microfacet normals of GGX alpha, each with its weight D(m) cos(theta_m) dm (`rough_bsdf.rs`).
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

/// Directions of the upper hemisphere as midpoints of a grid in (cos theta, phi), each with
/// its solid angle.
fn hemisphere(steps: usize) -> impl Iterator<Item = (DVec3, f64)> {
    let weight = 2.0 * PI / (steps * steps) as f64;
    (0..steps * steps).map(move |k| {
        let cos = ((k / steps) as f64 + 0.5) / steps as f64;
        let phi = ((k % steps) as f64 + 0.5) / steps as f64 * 2.0 * PI;
        let sin = (1.0 - cos * cos).sqrt();
        (DVec3::new(sin * phi.cos(), sin * phi.sin(), cos), weight)
    })
}

/// The model's directional albedo from `wo` (local, above): the coat's and the base's.
fn model_albedo(kd: f64, strength: f64, alpha: f64, wo: DVec3) -> (f64, f64) {
    let mut coat = 0.0;
    for (m, weight) in normals(alpha, 600) {
        let om = wo.dot(m);
        let wi = 2.0 * om * m - wo;
        if om > 0.0 && wi.z > 0.0 {
            // f cos di with di = 4 (o.m) dm and D(m) cos dm = weight.
            coat += fresnel(om) * g1(alpha, wo) * g1(alpha, wi) * om / (wo.z * m.z) * weight;
        }
    }
    // ∫ (1 - F(cos)) cos / pi di = 2 ∫ (1 - F(mu)) mu dmu.
    let steps = 100_000;
    let through: f64 = (0..steps)
        .map(|k| {
            let mu = (k as f64 + 0.5) / steps as f64;
            2.0 * (1.0 - fresnel(mu)) * mu / steps as f64
        })
        .sum();
    (strength * coat, kd * (1.0 - fresnel(wo.z)) * through)
}

/// A frame (t, b, n) and a direction at angle theta from n, in the world and local.
fn setup(theta: f64) -> ((Vec3, Vec3, Vec3), Vec3, DVec3) {
    let n = Vec3::new(0.2, 0.3, 0.9).normalize();
    let (t, b) = n.any_orthonormal_pair();
    let local = DVec3::new(theta.sin(), 0.0, theta.cos());
    let wo = local.x as f32 * t + local.y as f32 * b + local.z as f32 * n;
    ((t, b, n), wo, local)
}

/// ∫ f cos di of the code's `eval`: the coat alone (a black base) over microfacet normals, and
/// what the base adds over the hemisphere; `steps` of each grid's sides.
fn eval_albedo(
    material: &Material,
    frame: (Vec3, Vec3, Vec3),
    alpha: f64,
    wo: DVec3,
    steps: (usize, usize),
) -> (f64, f64) {
    let world = |v: DVec3| v.x as f32 * frame.0 + v.y as f32 * frame.1 + v.z as f32 * frame.2;
    let whole = material.bsdf(frame.2, TransportMode::Radiance);
    let coat_only = Material { diffuse: Vec3::ZERO, ..material.clone() };
    let coat_only = coat_only.bsdf(frame.2, TransportMode::Radiance);
    let mut coat = 0.0;
    for (m, weight) in normals(alpha, steps.0) {
        let om = wo.dot(m);
        let wi = 2.0 * om * m - wo;
        if om > 0.0 && wi.z > 0.0 {
            let f = f64::from(coat_only.eval(world(wo), world(wi)).x);
            coat += f * wi.z * 4.0 * om * weight / (ggx_d(alpha, m) * m.z);
        }
    }
    let mut base = 0.0;
    for (wi, weight) in hemisphere(steps.1) {
        let (o, i) = (world(wo), world(wi));
        let f = f64::from(whole.eval(o, i).x) - f64::from(coat_only.eval(o, i).x);
        base += f * wi.z * weight;
    }
    (coat, base)
}

/// The mean of `sample`'s weights and its standard error; and the share of samples returned.
fn sampled_albedo(bsdf: &Bsdf, wo: Vec3) -> (f64, f64, f64) {
    let count = 200_000;
    let (mut sum, mut squares, mut returned) = (0.0, 0.0, 0);
    for i in 0..count {
        let mut s = Sampler::new(3, i, 0);
        let Some(sample) = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL) else {
            continue;
        };
        let w = f64::from(sample.weight.x);
        sum += w;
        squares += w * w;
        returned += 1;
    }
    let n = count as f64;
    let mean = sum / n;
    (mean, ((squares / n - mean * mean) / n).sqrt(), returned as f64 / n)
}

#[test]
fn plastic_albedo_matches_a_quadrature_of_the_model() {
    for alpha in [0.05f32, 0.2, 0.5, 1.0] {
        for theta in [0.0, 0.7, 1.2, 1.5] {
            let (frame, wo, local) = setup(theta);
            let material = plastic(0.6, 0.8, alpha);
            let a = f64::from(alpha);
            let (model_coat, model_base) = model_albedo(0.6, 0.8, a, local);
            let (eval_coat, eval_base) = eval_albedo(&material, frame, a, local, (600, 1000));
            let model = model_coat + model_base;
            let what = format!("alpha {alpha}, theta {theta}");
            assert!(
                (eval_coat - model_coat).abs() < QUADRATURE * model,
                "{what}: coat eval {eval_coat}, model {model_coat}"
            );
            assert!(
                (eval_base - model_base).abs() < QUADRATURE * model,
                "{what}: base eval {eval_base}, model {model_base}"
            );
            let bsdf = material.bsdf(frame.2, TransportMode::Radiance);
            let (sampled, error, _) = sampled_albedo(&bsdf, wo);
            assert!(
                (sampled - model).abs() < 5.0 * error + QUADRATURE * model,
                "{what}: sampled {sampled} ± {error}, model {model}"
            );
        }
    }
}

/// White furnace of the lobe: under light of radiance 1 from every direction it returns at
/// most 1, whatever the coat's roughness, the base's albedo and the direction; with a white
/// base, about all of it (only the light the coat reflects back down is lost), and with a
/// black one what the coat alone reflects.
#[test]
fn plastic_scatters_at_most_what_arrives() {
    for alpha in [0.02f32, 0.1, 0.3, 0.6, 1.0] {
        for kd in [0.0f32, 0.5, 1.0] {
            for theta in [0.0, 0.5, 1.0, 1.3, 1.5, 1.56] {
                let (frame, wo, local) = setup(theta);
                let a = f64::from(alpha);
                let (coat, base) = model_albedo(f64::from(kd), 1.0, a, local);
                let what = format!("alpha {alpha}, kd {kd}, theta {theta}");
                assert!(coat + base <= 1.0, "{what}: model {coat} + {base}");
                let bsdf = plastic(kd, 1.0, alpha).bsdf(frame.2, TransportMode::Radiance);
                let (sampled, error, _) = sampled_albedo(&bsdf, wo);
                assert!(sampled <= 1.0 + 5.0 * error, "{what}: sampled {sampled} ± {error}");
                if kd == 1.0 && theta < 1.3 {
                    assert!(sampled > 0.85, "{what}: a white plastic keeps {sampled}");
                }
            }
        }
    }
}

/// The BSDF of the first object of a `.pov` scene.
fn pov_material(text: &str) -> Material {
    let graph = raydiance::lang::parse_scene(std::path::Path::new("tests/inline.pov"), text)
        .unwrap_or_else(|e| panic!("{e}"));
    Material::from(&**graph.objects[0].material.as_ref().expect("a material"))
}

/// White furnace of POV-Ray's highlight, a coat over everything (`docs/povray.md`, issue 33):
/// under light of radiance 1 from every direction, a surface returns at most 1 whatever lies
/// under its coat, and a coat over a clear pigment returns all of it, passing what it does not
/// reflect (it passed half). The coat and base by quadratures of `eval`, the mirror and the
/// transmission (delta lobes) by `sample`'s weights over a grid of its lobe choice.
#[test]
fn a_highlight_over_anything_scatters_at_most_what_arrives() {
    let materials = [
        ("rgbf 1", "phong 1", true),
        ("rgbt 1", "phong 0.4 phong_size 10", true),
        ("rgbt 0.5", "diffuse 0.8 phong 0.7", false),
        ("rgbf <1, 0.6, 0.3, 0.6>", "diffuse 1 phong 1 reflection 0.3", false),
    ];
    for (pigment, finish, lossless) in materials {
        let material = pov_material(&format!(
            "sphere {{ 0, 1 pigment {{ {pigment} }} finish {{ {finish} }} }}"
        ));
        let alpha = f64::from(material.coat.expect("a coat").roughness);
        for theta in [0.0, 0.6, 1.0] {
            let (frame, wo, local) = setup(theta);
            let (coat, base) = eval_albedo(&material, frame, alpha, local, (150, 200));
            let bsdf = material.bsdf(frame.2, TransportMode::Radiance);
            let choices = 64;
            let delta: f64 = (0..choices)
                .filter_map(|k| {
                    let u_lobe = (k as f32 + 0.5) / choices as f32;
                    bsdf.sample(wo, u_lobe, NO_DIRECTION, LobeFlags::DELTA)
                })
                .map(|sample| f64::from(sample.weight.x) / f64::from(choices))
                .sum();
            let total = coat + base + delta;
            let what = format!("{pigment} {finish}, theta {theta}: {coat} + {base} + {delta}");
            assert!(total <= 1.0 + QUADRATURE, "{what} = {total}");
            if lossless {
                assert!(total > 0.99, "{what} = {total}");
            }
        }
    }
}

/// pdf is the density of `sample`'s directions: it integrates over the hemisphere to the share
/// of samples returned (a coat sample reflected below the surface is none), and its value at
/// each sample is the pdf the sample carries.
#[test]
fn plastic_pdf_integrates_to_the_share_of_samples_returned() {
    for alpha in [0.1f32, 0.4, 1.0] {
        for theta in [0.0, 0.9, 1.45] {
            let (frame, wo, _) = setup(theta);
            let world =
                |v: DVec3| v.x as f32 * frame.0 + v.y as f32 * frame.1 + v.z as f32 * frame.2;
            let bsdf = plastic(0.4, 1.0, alpha).bsdf(frame.2, TransportMode::Radiance);
            let total: f64 = hemisphere(1500)
                .map(|(wi, weight)| f64::from(bsdf.pdf(wo, world(wi), LobeFlags::ALL)) * weight)
                .sum();
            let (_, _, returned) = sampled_albedo(&bsdf, wo);
            let what = format!("alpha {alpha}, theta {theta}");
            assert!((total - returned).abs() < 0.01, "{what}: ∫ pdf {total}, returned {returned}");
            for i in 0..1000 {
                let mut s = Sampler::new(9, i, 0);
                let Some(sample) = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL) else {
                    continue;
                };
                let pdf = bsdf.pdf(wo, sample.wi, LobeFlags::ALL);
                assert!((sample.pdf - pdf).abs() <= 1e-4 * pdf, "{what}: {} vs {pdf}", sample.pdf);
                let f = bsdf.eval(wo, sample.wi) * sample.wi.dot(frame.2) / pdf;
                assert!((sample.weight - f).abs().max_element() <= 1e-4 * f.max_element());
            }
        }
    }
}

#[test]
fn plastic_is_reciprocal_and_reflects_on_either_side_only() {
    let n = Vec3::new(-0.3, 0.5, 0.8).normalize();
    let mut s = Sampler::new(8, 0, 0);
    let bsdf = Material { diffuse: Vec3::new(0.7, 0.2, 0.1), ..plastic(0.0, 0.9, 0.3) }
        .bsdf(n, TransportMode::Radiance);
    let mut checked = 0;
    for _ in 0..2000 {
        let (a, b) = (
            raydiance::sampling::uniform_sphere(s.next_2d()),
            raydiance::sampling::uniform_sphere(s.next_2d()),
        );
        let (f, g) = (bsdf.eval(a, b), bsdf.eval(b, a));
        if a.dot(n) * b.dot(n) <= 0.0 {
            assert_eq!((f, g), (Vec3::ZERO, Vec3::ZERO), "across the surface");
            continue;
        }
        assert!((f - g).abs().max_element() <= 1e-4 * f.max_element(), "{f} vs {g}");
        checked += 1;
    }
    assert!(checked > 500);
}

/// The coat is what makes the highlight: head-on it reflects F = 4 % of a mirror's peak into
/// the mirror direction, and the base keeps (1 - F)^2 kd / pi away from it.
#[test]
fn plastic_reflects_four_percent_head_on_and_the_base_the_rest() {
    let n = Vec3::Z;
    let alpha = 0.2f32;
    let bsdf = plastic(0.5, 1.0, alpha).bsdf(n, TransportMode::Radiance);
    let f0 = fresnel(1.0);
    assert!((f0 - 0.04).abs() < 1e-9);
    let peak = f64::from(bsdf.eval(Vec3::Z, Vec3::Z).x);
    let d = 1.0 / (PI * f64::from(alpha * alpha));
    let base = 0.5 / PI * (1.0 - f0) * (1.0 - f0);
    assert!((peak - (f0 * d / 4.0 + base)).abs() < 1e-4 * peak, "{peak}");
    // 60 degrees away from a narrow coat's peak, the base alone.
    let narrow = plastic(0.5, 1.0, 0.05).bsdf(n, TransportMode::Radiance);
    let wi = Vec3::new(0.75f32.sqrt(), 0.0, 0.5);
    let away = f64::from(narrow.eval(Vec3::Z, wi).x);
    let expected = 0.5 / PI * (1.0 - f0) * (1.0 - fresnel(0.5));
    assert!((away - expected).abs() < 0.005 * expected, "{away} vs {expected}");
}

/// `.scn`'s `coat` and `coat_roughness` make the plastic lobe; `coat_roughness` alone is
/// warned about; a coat with a mirror within the energy rule is accepted.
#[test]
fn scn_coat_makes_the_plastic_lobe() {
    let parse = |text: &str| {
        let text = format!("camera {{ location <0, 0, -3>  look_at <0, 0, 0> }}\n{text}");
        raydiance::lang::parse_scene(std::path::Path::new("tests/inline.scn"), &text)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let graph = parse(
        "sphere { 0, 1  material { diffuse rgb 0.5  coat 0.8  coat_roughness 0.3  specular rgb 0.2 } }",
    );
    let desc = graph.objects[0].material.as_ref().unwrap();
    let material = Material::from(&**desc);
    assert_eq!(material.coat, Some(Coat { strength: 0.8, roughness: 0.3, covers: Covers::Base }));
    let flags = material.bsdf(Vec3::Z, TransportMode::Radiance).flags();
    let expected =
        LobeFlags::GLOSSY | LobeFlags::DIFFUSE | LobeFlags::DELTA | LobeFlags::REFLECTION;
    assert_eq!(flags, expected);
    let graph = parse("sphere { 0, 1  material { diffuse rgb 0.5  coat 1 } }");
    let material = Material::from(&**graph.objects[0].material.as_ref().unwrap());
    assert_eq!(
        material.coat,
        Some(Coat {
            strength: 1.0,
            roughness: MaterialDesc::DEFAULT_COAT_ROUGHNESS,
            covers: Covers::Base
        })
    );
    let plain = parse("sphere { 0, 1  material { diffuse rgb 0.5  coat_roughness 0.3 } }");
    assert_eq!(Material::from(&**plain.objects[0].material.as_ref().unwrap()).coat, None);
    let scene_warnings = raydiance::scene::build(&plain).unwrap().warnings;
    assert!(
        scene_warnings.iter().any(|w| w.contains("`coat_roughness` has no effect without `coat`")),
        "{scene_warnings:?}"
    );
}

/// The integrators take the coat through `Bsdf` like any lobe: in a white furnace (a
/// background of radiance 1, nothing else) a coated white sphere seen head-on shows the
/// lobe's directional albedo there, by `path` and by `direct`.
#[test]
fn a_coated_sphere_in_a_white_furnace_shows_its_albedo() {
    let (model_coat, model_base) = model_albedo(1.0, 1.0, 0.1, DVec3::Z);
    let model = model_coat + model_base;
    for integrator in ["path", "direct"] {
        let scene = common::scene(&format!(
            "settings {{ resolution 3, 3  samples 4096  integrator {integrator}  background rgb 1 }}\n\
             camera {{ location <0, 0, -10>  look_at <0, 0, 0>  angle 2 }}\n\
             sphere {{ 0, 1  material {{ diffuse rgb 1  coat 1  coat_roughness 0.1 }} }}"
        ));
        let middle = f64::from(common::render_image(&scene).get(1, 1).x);
        assert!((middle - model).abs() < 0.01, "{integrator}: {middle} vs the model's {model}");
    }
}
