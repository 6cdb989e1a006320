//! Chi-square goodness-of-fit of every sampling routine against its own pdf (after Mitsuba's
//! harness): directions are binned over the sphere and the counts compared with the integral of
//! the pdf over each bin.

mod common;

use std::f32::consts::PI;

use glam::Vec3;
use raydiance::geometry::{Hit, Ray};
use raydiance::material::Material;
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
    // Expected counts: the pdf integrated over each bin (8x8 midpoint rule in cos theta, phi).
    let sub = 8;
    let mut expected = vec![0.0f64; COS_BINS * PHI_BINS];
    for c in 0..COS_BINS * sub {
        for p in 0..PHI_BINS * sub {
            let cos_theta = -1.0 + (c as f32 + 0.5) * 2.0 / (COS_BINS * sub) as f32;
            let phi = (p as f32 + 0.5) * 2.0 * PI / (PHI_BINS * sub) as f32;
            let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
            let d = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
            let cell = (2.0 / (COS_BINS * sub) as f32) * (2.0 * PI / (PHI_BINS * sub) as f32);
            expected[bin_of(d)] += f64::from(pdf(d) * cell) * SAMPLES as f64;
        }
    }
    // Pool the bins expecting fewer than 5 samples, as the test requires.
    let (mut chi2, mut dof, mut pooled_o, mut pooled_e) = (0.0, 0usize, 0.0, 0.0);
    for (o, e) in observed.iter().zip(&expected) {
        if *e < 5.0 {
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
        for wo in [wo, -wo] {
            chi_square(
                name,
                |s| {
                    let sample = m.sample(n, wo, s.next_1d(), s.next_2d())?;
                    (!sample.specular).then_some(sample.wi)
                },
                |wi| m.pdf(n, wo, wi),
            );
        }
    }
}

fn light_sampling(scene_text: &str, point: Vec3, normal: Vec3) {
    let scene = common::scene(scene_text);
    let shading = Hit { t: 1.0, point, normal, error: 0.0, primitive: u32::MAX };
    let light = &scene.lights[0];
    chi_square(
        scene_text,
        |s| light.sample(&scene, &shading, s.next_2d()).map(|l| l.wi),
        |wi| match scene.intersect(&Ray::new(point, wi)) {
            Some(hit) if scene.primitives[hit.primitive as usize].light == Some(0) => {
                light.pdf(&scene, point, &hit)
            }
            _ => 0.0,
        },
    );
}

#[test]
fn light_sampling_matches_light_pdf() {
    let camera = "camera { location <0, 0, -5>  look_at <0, 0, 0>  angle 40 }";
    // A sphere sampled by its cone of directions, from near and from far.
    for point in [Vec3::new(0.0, 0.0, -1.5), Vec3::new(0.3, 0.2, -6.0)] {
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
        "triangle { <-1, 1, -1>, <1, 1, -1>, <0, 1.5, 1> }",
    ] {
        let emissive = shape.replace(" }", "  material { emission rgb 1 } }");
        light_sampling(&format!("{camera} {emissive}"), Vec3::new(0.2, -0.5, 0.1), Vec3::Y);
    }
    // A cylinder under a similarity: tube and caps are three lights; test the tube.
    light_sampling(
        &format!(
            "{camera} cylinder {{ <0, 0, 0>, <0, 2, 0>, 0.5  rotate <30, 0, 0>  material {{ emission rgb 1 }} }}"
        ),
        Vec3::new(1.5, 0.3, -0.5),
        Vec3::NEG_X,
    );
}
