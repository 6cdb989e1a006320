//! Chi-square goodness-of-fit of every sampling routine against its own pdf (after Mitsuba's
//! harness): directions are binned over the sphere and the counts compared with the integral of
//! the pdf over each bin.

mod common;

use std::f32::consts::PI;

use glam::Vec3;
use raydiance::geometry::{Hit, Ray, Shape};
use raydiance::light::Light;
use raydiance::material::{Material, TransportMode};
use raydiance::sampling::{Sampler, cosine_hemisphere};

const COS_BINS: usize = 16;
const PHI_BINS: usize = 32;
const SAMPLES: usize = 200_000;

fn bin_of(d: Vec3) -> usize {
    let c = ((d.z + 1.0) * 0.5 * COS_BINS as f32).clamp(0.0, COS_BINS as f32 - 1.0) as usize;
    let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
    let p = (phi / (2.0 * PI) * PHI_BINS as f32).min(PHI_BINS as f32 - 1.0) as usize;
    c * PHI_BINS + p
}

/// Draws SAMPLES directions (`None`: a sample that is discrete or failed, left out) and tests
/// them against `pdf` (solid angle, over the continuous part).
fn chi_square(
    what: &str,
    mut sample: impl FnMut(&mut Sampler) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) {
    let mut observed = vec![0.0f64; COS_BINS * PHI_BINS];
    for i in 0..SAMPLES {
        let mut sampler = Sampler::new(11, i as u64, 0);
        if let Some(d) = sample(&mut sampler) {
            observed[bin_of(d)] += 1.0;
        }
    }
    // Expected counts: the pdf integrated over each bin by the midpoint rule. Where a coarse
    // and a fine grid disagree the bin is cut by an edge of the distribution (a cone's rim, a
    // light's outline) that the rule resolves poorly: such bins are pooled with the sparse ones.
    let integrate = |bin: usize, sub: usize| {
        let (c0, p0) = (bin / PHI_BINS, bin % PHI_BINS);
        let (dc, dp) = (2.0 / (COS_BINS * sub) as f32, 2.0 * PI / (PHI_BINS * sub) as f32);
        let mut sum = 0.0f64;
        for c in 0..sub {
            for p in 0..sub {
                let cos_theta = -1.0 + ((c0 * sub + c) as f32 + 0.5) * dc;
                let phi = ((p0 * sub + p) as f32 + 0.5) * dp;
                let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
                let d = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
                sum += f64::from(pdf(d) * dc * dp);
            }
        }
        sum * SAMPLES as f64
    };
    let (mut chi2, mut dof, mut pooled_o, mut pooled_e) = (0.0, 0usize, 0.0, 0.0);
    for (bin, o) in observed.iter().enumerate() {
        let (coarse, e) = (integrate(bin, 8), integrate(bin, 32));
        if (e - coarse).abs() > 0.01 * e + 0.5 {
            pooled_o += o;
            pooled_e += integrate(bin, 256);
        } else if e < 5.0 {
            pooled_o += o;
            pooled_e += e;
        } else {
            chi2 += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    if pooled_e >= 5.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        dof += 1;
    } else {
        assert!(
            pooled_o < 10.0 + 3.0 * pooled_e,
            "{what}: {pooled_o} samples where the pdf expects {pooled_e}"
        );
    }
    assert!(dof > 10, "{what}: only {dof} bins resolve the distribution: too coarse a test");
    let k = (dof - 1) as f64;
    // Wilson–Hilferty: (chi2 / k)^(1/3) is close to normal; z > 4.5 has probability < 4e-6.
    let z = ((chi2 / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    assert!(z < 4.5, "{what}: chi2 = {chi2:.1} with {k} degrees of freedom (z = {z:.2})");
}

#[test]
fn cosine_hemisphere_matches_its_pdf() {
    chi_square(
        "cosine hemisphere",
        |s| Some(cosine_hemisphere(s.next_2d())),
        |d| d.z.max(0.0) / PI,
    );
}

#[test]
fn cosine_hemisphere_test_detects_a_wrong_pdf() {
    // The harness itself must fail on a mismatch: uniform hemisphere pdf against cosine samples.
    let result = std::panic::catch_unwind(|| {
        chi_square(
            "mismatch",
            |s| Some(cosine_hemisphere(s.next_2d())),
            |d| if d.z > 0.0 { 0.5 / PI } else { 0.0 },
        )
    });
    assert!(result.is_err());
}

fn material(diffuse: f32, specular: f32, transmission: f32, fresnel: bool) -> Material {
    Material {
        diffuse: Vec3::splat(diffuse),
        specular: Vec3::splat(specular),
        transmission: Vec3::splat(transmission),
        ior: 1.5,
        emission: Vec3::ZERO,
        fresnel,
    }
}

#[test]
fn bsdf_sampling_matches_bsdf_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let wo = Vec3::new(-0.5, 0.4, 0.6).normalize();
    for (m, name) in [
        (material(0.8, 0.0, 0.0, false), "diffuse"),
        (material(0.5, 0.3, 0.0, false), "diffuse + mirror"),
        (material(0.3, 0.0, 0.6, true), "diffuse + fresnel glass"),
    ] {
        let bsdf = m.bsdf(n, TransportMode::Radiance);
        for wo in [wo, -wo] {
            chi_square(
                name,
                |s| {
                    let sample = bsdf.sample(wo, s.next_1d(), s.next_2d())?;
                    (!sample.delta).then_some(sample.wi)
                },
                |wi| bsdf.pdf(wo, wi),
            );
        }
    }
}

fn light_sampling(scene_text: &str, point: Vec3, normal: Vec3) {
    let scene = common::scene(scene_text);
    let shading =
        Hit { t: 1.0, point, normal, shading_normal: normal, error: 0.0, primitive: u32::MAX };
    // The light under test: the tube of a cylinder (not its caps), else the only one.
    let index = (0..scene.lights.len())
        .find(|&i| match scene.lights[i] {
            Light::Area { ref shape, .. } => matches!(shape, Shape::Quadric { .. }),
            Light::Point { .. } => false,
        })
        .unwrap_or(0);
    let light = &scene.lights[index];
    chi_square(
        &format!("{scene_text} from {point}"),
        |s| light.sample(&shading, s.next_2d()).map(|l| l.wi),
        |wi| match scene.intersect(&Ray::new(point, wi)) {
            Some(hit) if scene.primitives[hit.primitive as usize].light == Some(index as u32) => {
                light.pdf(point, &hit)
            }
            _ => 0.0,
        },
    );
}

#[test]
fn light_sampling_matches_light_pdf() {
    let camera = "camera { location <0, 0, -5>  look_at <0, 0, 0>  angle 40 }";
    // A sphere sampled by its cone of directions, from near and from far.
    for point in [Vec3::new(0.0, 0.0, -1.5), Vec3::new(0.3, 0.2, -2.5)] {
        light_sampling(
            &format!("{camera} sphere {{ <0, 0, 0>, 1  material {{ emission rgb 1 }} }}"),
            point,
            Vec3::NEG_Z,
        );
    }
    // A quad, a disk and a triangle sampled by area, converted to solid angle.
    for shape in [
        "quad { <-1, 1, -1>, <2, 0, 0>, <0, 0, 2> }",
        "disk { <0, 1, 0>, <0, -1, 0>, 1.5 }",
        "triangle { <-1.5, 1, -1.5>, <1.5, 1, -1.5>, <0, 1.3, 2> }",
    ] {
        let emissive = shape.replace(" }", "  material { emission rgb 1 } }");
        light_sampling(&format!("{camera} {emissive}"), Vec3::new(0.2, 0.6, 0.1), Vec3::Y);
    }
    // A cylinder under a similarity: tube and caps are three lights; test the tube.
    light_sampling(
        &format!(
            "{camera} cylinder {{ <0, 0, 0>, <0, 2, 0>, 0.5  rotate <30, 0, 0>  material {{ emission rgb 1 }} }}"
        ),
        Vec3::new(0.8, 0.3, -0.5),
        Vec3::NEG_X,
    );
}
