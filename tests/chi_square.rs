//! Chi-square goodness-of-fit of every sampling routine against its own pdf (after Mitsuba's
//! harness): directions are binned over the sphere and the counts compared with the integral of
//! the pdf over each bin.

use crate::common;

use std::f32::consts::PI;

use glam::{Vec2, Vec3};
use raydiance::geometry::{Hit, Ray, Shape};
use raydiance::graph::Covers;
use raydiance::light::Light;
use raydiance::material::{Coat, LobeFlags, Material, TransportMode, refract};
use raydiance::sampling::{Sampler, cosine_hemisphere};

const COS_BINS: usize = 16;
const PHI_BINS: usize = 32;
const SAMPLES: usize = 200_000;

/// Bins over the sphere around `axis`: COS_BINS rings uniform in t, where 1 - cos(theta) = 2 t^zoom
/// (zoom 1: uniform in cos theta; larger zooms put more rings near the axis, for peaked lobes),
/// times PHI_BINS sectors.
#[derive(Clone, Copy)]
struct Bins {
    axis: Vec3,
    zoom: i32,
}

impl Bins {
    const SPHERE: Bins = Bins { axis: Vec3::Z, zoom: 1 };

    fn bin_of(&self, d: Vec3) -> usize {
        let (t1, t2) = self.axis.any_orthonormal_pair();
        // 1 - cos from the sine near the axis, where 1 - cos itself would round to 0.
        let cos = d.dot(self.axis).clamp(-1.0, 1.0);
        let sin2 = (d - cos * self.axis).length_squared();
        let one_minus_cos = if cos > 0.0 { sin2 / (1.0 + cos) } else { 1.0 - cos };
        let t = (one_minus_cos * 0.5).powf(1.0 / self.zoom as f32);
        let c = (t * COS_BINS as f32).clamp(0.0, COS_BINS as f32 - 1.0) as usize;
        let phi = d.dot(t2).atan2(d.dot(t1)).rem_euclid(2.0 * PI);
        let p = (phi / (2.0 * PI) * PHI_BINS as f32).min(PHI_BINS as f32 - 1.0) as usize;
        c * PHI_BINS + p
    }

    /// The direction at (t, phi), and the solid angle per unit t and phi there.
    fn direction(&self, t: f32, phi: f32) -> (Vec3, f32) {
        let (t1, t2) = self.axis.any_orthonormal_pair();
        let k = self.zoom as f32;
        let one_minus_cos = 2.0 * t.powi(self.zoom);
        let cos = 1.0 - one_minus_cos;
        let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let d = sin * phi.cos() * t1 + sin * phi.sin() * t2 + cos * self.axis;
        (d, 2.0 * k * t.powi(self.zoom - 1))
    }
}

/// Draws SAMPLES directions (`None`: a sample that is discrete or failed, left out) and tests
/// them against `pdf` (solid angle, over the continuous part), over the whole sphere.
fn chi_square(
    what: &str,
    sample: impl FnMut(&mut Sampler) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) {
    chi_square_in(Bins::SPHERE, 10, what, sample, pdf);
}

/// `chi_square` with the given bins, of which more than `resolved` must have enough samples
/// to be tested one by one (the others are pooled).
fn chi_square_in(
    bins: Bins,
    resolved: usize,
    what: &str,
    sample: impl FnMut(&mut Sampler) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) {
    chi_square_of(bins, resolved, what, draw(sample), pdf);
}

/// The directions of SAMPLES draws (`None`: a sample that is discrete or failed, left out).
fn draw(mut sample: impl FnMut(&mut Sampler) -> Option<Vec3>) -> Vec<Vec3> {
    (0..SAMPLES).filter_map(|i| sample(&mut Sampler::new(11, i as u64, 0))).collect()
}

/// `chi_square_in` of directions already drawn (SAMPLES draws, of which these are the ones
/// `pdf` describes).
fn chi_square_of(
    bins: Bins,
    resolved: usize,
    what: &str,
    directions: impl IntoIterator<Item = Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) {
    let mut observed = vec![0.0f64; COS_BINS * PHI_BINS];
    for d in directions {
        observed[bins.bin_of(d)] += 1.0;
    }
    // Expected counts: the pdf integrated over each bin by the midpoint rule. Where a coarse
    // and a fine grid disagree the bin is cut by an edge of the distribution (a cone's rim, a
    // light's outline) that the rule resolves poorly: such bins are pooled with the sparse ones.
    let integrate = |bin: usize, sub: usize| {
        let (c0, p0) = (bin / PHI_BINS, bin % PHI_BINS);
        let (dt, dp) = (1.0 / (COS_BINS * sub) as f32, 2.0 * PI / (PHI_BINS * sub) as f32);
        let mut sum = 0.0f64;
        for c in 0..sub {
            for p in 0..sub {
                let t = ((c0 * sub + c) as f32 + 0.5) * dt;
                let phi = ((p0 * sub + p) as f32 + 0.5) * dp;
                let (d, jacobian) = bins.direction(t, phi);
                sum += f64::from(pdf(d) * jacobian * dt * dp);
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
    assert!(dof > resolved, "{what}: only {dof} bins resolve the distribution: too coarse a test");
    if dof == 1 {
        // The pooled bin alone: a z-test of its count.
        let z = (pooled_o - pooled_e).abs() / pooled_e.sqrt();
        assert!(z < 4.5, "{what}: {pooled_o} samples where the pdf expects {pooled_e:.1}");
        return;
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
        two_sided: false,
        fresnel,
        roughness: 0.0,
        coat: None,
        beam: None,
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
                    let sample = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL)?;
                    (!sample.is_delta()).then_some(sample.wi)
                },
                |wi| bsdf.pdf(wo, wi, LobeFlags::ALL),
            );
        }
    }
}

/// A caller's mask of lobes (pbrt's sample flags): sampling under it draws only the lobes it
/// asks for, each sample's flags say which lobe it came from, and its directions follow
/// `pdf` under the same mask.
#[test]
fn masked_sampling_draws_the_lobes_asked_for_and_matches_the_masked_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let wo = Vec3::new(-0.5, 0.4, 0.6).normalize();
    let glossy = Material { roughness: 0.4, ..material(0.5, 0.4, 0.0, false) };
    for (m, mask, name) in [
        (material(0.5, 0.3, 0.0, false), LobeFlags::NON_DELTA, "diffuse of diffuse + mirror"),
        (material(0.3, 0.0, 0.6, true), LobeFlags::NON_DELTA, "diffuse of diffuse + glass"),
        (glossy.clone(), LobeFlags::DIFFUSE, "diffuse of diffuse + rough metal"),
        (glossy.clone(), LobeFlags::GLOSSY, "glossy of diffuse + rough metal"),
        (glossy, LobeFlags::NON_DELTA, "both of diffuse + rough metal"),
    ] {
        let bsdf = m.bsdf(n, TransportMode::Radiance);
        for wo in [wo, -wo] {
            chi_square(
                name,
                |s| {
                    let sample = bsdf.sample(wo, s.next_1d(), s.next_2d(), mask)?;
                    assert!(
                        sample.flags.is_in(mask),
                        "{name}: {:?} outside the mask",
                        sample.flags
                    );
                    assert!(bsdf.flags().contains(sample.flags), "{name}: {:?}", sample.flags);
                    Some(sample.wi)
                },
                |wi| bsdf.pdf(wo, wi, mask),
            );
        }
    }
    // Delta lobes alone: the mirror's one direction, always, with the whole of its weight.
    let bsdf = material(0.5, 0.3, 0.0, false).bsdf(n, TransportMode::Radiance);
    for u in [0.0, 0.3, 0.99] {
        let sample = bsdf.sample(wo, u, Vec2::ZERO, LobeFlags::DELTA).expect("a mirror sample");
        assert_eq!(sample.flags, LobeFlags::DELTA | LobeFlags::REFLECTION);
        assert!((sample.wi - (2.0 * n.dot(wo) * n - wo)).length() < 1e-5);
        assert!((sample.weight - Vec3::splat(0.3)).abs().max_element() < 1e-6);
        assert_eq!(sample.pdf, 1.0);
    }
    let diffuse = material(0.8, 0.0, 0.0, false).bsdf(n, TransportMode::Radiance);
    assert!(diffuse.sample(wo, 0.5, Vec2::splat(0.5), LobeFlags::DELTA).is_none());
}

/// Zoom of the bins around a lobe of GGX alpha: rings near the axis fine enough to resolve it.
fn zoom(alpha: f32) -> i32 {
    match alpha {
        a if a >= 0.5 => 1,
        a if a >= 0.1 => 3,
        _ => 5,
    }
}

/// Sampling of `bsdf` from `wo` against its pdf, the reflected and the transmitted directions
/// tested apart, each with bins around its lobe's centre: the mirror and the refracted
/// direction of the macro-surface. Where the macro-surface reflects totally, the microfacets
/// that refract send light along the surface ahead: bins around the horizon there. A side
/// that gets under 10% of the samples has too few to resolve many bins: it is tested on what
/// it resolves, and its sparse bins pooled.
fn rough_lobes_match_their_pdf(
    what: &str,
    bsdf: &raydiance::material::Bsdf,
    n: Vec3,
    wo: Vec3,
    alpha: f32,
    pdf: impl Fn(Vec3) -> f32,
) {
    let facing = if n.dot(wo) < 0.0 { -n } else { n };
    let eta = if n.dot(wo) < 0.0 { 1.0 / 1.5 } else { 1.5 };
    let mirror = 2.0 * wo.dot(facing) * facing - wo;
    let transmission = match refract(wo, facing, eta) {
        Some(refracted) => Bins { axis: refracted, zoom: zoom(alpha) },
        None => {
            let ahead = (wo.dot(facing) * facing - wo).normalize();
            Bins { axis: (ahead - 0.1 * facing).normalize(), zoom: 3 }
        }
    };
    let reflection = Bins { axis: mirror, zoom: zoom(alpha) };
    let reflected = |wi: Vec3| wi.dot(facing) > 0.0;
    let probes = 2000;
    let reflected_probes = (0..probes)
        .filter(|&i| {
            let mut s = Sampler::new(5, i, 0);
            bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL)
                .is_some_and(|s| reflected(s.wi))
        })
        .count();
    let transmitted_probes = (0..probes)
        .filter(|&i| {
            let mut s = Sampler::new(5, i, 0);
            bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL)
                .is_some_and(|s| !reflected(s.wi))
        })
        .count();
    let sparse = |count: usize| count * 10 < probes as usize;
    // One set of draws for both sides, each side's histogram taking the directions on its side.
    let directions = draw(|s| {
        let sample = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL)?;
        assert!(!sample.is_delta(), "{what}: a rough lobe is not delta");
        Some(sample.wi)
    });
    for (side, bins, count, sign) in [
        ("reflection", reflection, reflected_probes, true),
        ("transmission", transmission, transmitted_probes, false),
    ] {
        if count == 0 {
            continue; // a side it never samples: no transmission, or total internal reflection
        }
        let on_side = |wi: Vec3| reflected(wi) == sign;
        let resolved = if sparse(count) { 0 } else { 10 };
        chi_square_of(
            bins,
            resolved,
            &format!("{what}, {side}"),
            directions.iter().copied().filter(|&wi| on_side(wi)),
            |wi| if on_side(wi) { pdf(wi) } else { 0.0 },
        );
    }
}

fn rough(diffuse: f32, specular: f32, transmission: f32, fresnel: bool, alpha: f32) -> Material {
    Material { roughness: alpha, ..material(diffuse, specular, transmission, fresnel) }
}

/// Every rough lobe's sampling against its pdf: reflection and transmission, from both sides,
/// alpha from near-perfect to 1, incidence from normal to grazing.
fn rough_sampling_matches_pdf(
    name: &str,
    diffuse: f32,
    specular: f32,
    transmission: f32,
    fresnel: bool,
) {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let (t, _) = n.any_orthonormal_pair();
    for alpha in [0.01, 0.1, 0.5, 1.0] {
        let material = rough(diffuse, specular, transmission, fresnel, alpha);
        let bsdf = material.bsdf(n, TransportMode::Radiance);
        for theta in [0.0f32, 0.8, 1.45] {
            let wo = theta.cos() * n + theta.sin() * t;
            for wo in [wo, -wo] {
                let what = format!("{name}, alpha {alpha}, theta {theta}, wo {wo}");
                rough_lobes_match_their_pdf(&what, &bsdf, n, wo, alpha, |wi| {
                    bsdf.pdf(wo, wi, LobeFlags::ALL)
                });
            }
        }
    }
}

#[test]
fn rough_metal_sampling_matches_its_pdf() {
    rough_sampling_matches_pdf("rough metal", 0.0, 0.9, 0.0, false);
}

#[test]
fn rough_fresnel_glass_sampling_matches_its_pdf() {
    rough_sampling_matches_pdf("rough fresnel glass", 0.0, 0.0, 1.0, true);
}

#[test]
fn rough_transmission_sampling_matches_its_pdf() {
    rough_sampling_matches_pdf("rough transmission", 0.0, 0.2, 0.7, false);
}

#[test]
fn diffuse_with_rough_specular_sampling_matches_its_pdf() {
    rough_sampling_matches_pdf("diffuse + rough specular", 0.5, 0.4, 0.0, false);
}

/// The harness fails on a pdf slightly off: another alpha, or another ior (the split between
/// reflection and refraction at each microfacet, and the refraction's Jacobian).
#[test]
fn rough_sampling_test_detects_a_wrong_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let wo = Vec3::new(-0.5, 0.4, 0.6).normalize();
    for (sampled, wrong) in [
        (rough(0.0, 0.9, 0.0, false, 0.5), rough(0.0, 0.9, 0.0, false, 0.55)),
        (rough(0.0, 0.0, 1.0, true, 0.3), Material { ior: 1.6, ..rough(0.0, 0.0, 1.0, true, 0.3) }),
    ] {
        let (bsdf, wrong) =
            (sampled.bsdf(n, TransportMode::Radiance), wrong.bsdf(n, TransportMode::Radiance));
        let result = std::panic::catch_unwind(|| {
            rough_lobes_match_their_pdf("mutated", &bsdf, n, wo, 0.5, |wi| {
                wrong.pdf(wo, wi, LobeFlags::ALL)
            })
        });
        assert!(result.is_err(), "{sampled:?} passed against {wrong:?}");
    }
}

fn plastic(diffuse: f32, specular: f32, alpha: f32) -> Material {
    Material {
        coat: Some(Coat { strength: 1.0, roughness: alpha, covers: Covers::Base }),
        ..material(diffuse, specular, 0.0, false)
    }
}

/// The directions `bsdf` draws from `wo` with a density (a mirror's left out) against its pdf
/// under every lobe, in bins around the mirror direction fine enough for alpha.
fn plastic_lobe_matches_pdf(
    what: &str,
    bsdf: &raydiance::material::Bsdf,
    n: Vec3,
    wo: Vec3,
    alpha: f32,
    pdf: impl Fn(Vec3) -> f32,
) {
    let facing = if n.dot(wo) < 0.0 { -n } else { n };
    let mirror = 2.0 * wo.dot(facing) * facing - wo;
    chi_square_in(
        Bins { axis: mirror, zoom: zoom(alpha) },
        10,
        what,
        |s| {
            let sample = bsdf.sample(wo, s.next_1d(), s.next_2d(), LobeFlags::ALL)?;
            (!sample.is_delta()).then_some(sample.wi)
        },
        pdf,
    );
}

/// The coated plastic lobe (a glossy coat over a diffuse base), alone and beside a mirror
/// (POV-Ray's `phong` with `reflection`): alpha from narrow to 1, incidence from normal to
/// grazing, both sides.
#[test]
fn plastic_sampling_matches_its_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let (t, _) = n.any_orthonormal_pair();
    for alpha in [0.03, 0.1, 0.4, 1.0] {
        for (diffuse, specular) in [(0.5, 0.0), (0.0, 0.0), (0.4, 0.3)] {
            let bsdf = plastic(diffuse, specular, alpha).bsdf(n, TransportMode::Radiance);
            for theta in [0.0f32, 0.8, 1.45] {
                let wo = theta.cos() * n + theta.sin() * t;
                for wo in [wo, -wo] {
                    let what = format!(
                        "plastic kd {diffuse} + mirror {specular}, alpha {alpha}, theta {theta}, wo {wo}"
                    );
                    plastic_lobe_matches_pdf(&what, &bsdf, n, wo, alpha, |wi| {
                        bsdf.pdf(wo, wi, LobeFlags::ALL)
                    });
                }
            }
        }
    }
}

/// POV-Ray's highlight: a coat of weight 0.6 over a base, a mirror and a clear transmission
/// (`Covers::Everything`), which carry what it lets through, and so are chosen by shares it
/// takes from: its directions with a density follow its pdf, from near the normal and from
/// grazing on the other side.
#[test]
fn a_coat_over_everything_samples_as_its_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let (t, _) = n.any_orthonormal_pair();
    let bsdf = coated_over_everything(0.3, 0.2, 0.4).bsdf(n, TransportMode::Radiance);
    let (near, grazing) = (0.3f32, 1.4f32);
    let near = near.cos() * n + near.sin() * t;
    let grazing = grazing.cos() * n + grazing.sin() * t;
    for wo in [near, -grazing] {
        plastic_lobe_matches_pdf(&format!("wo {wo}"), &bsdf, n, wo, 0.2, |wi| {
            bsdf.pdf(wo, wi, LobeFlags::ALL)
        });
    }
}

/// The harness tells a coat over everything from the same coat over its base alone (`.scn`'s):
/// seen at a grazing angle, the coat takes a larger share from the transmission.
#[test]
fn a_coat_over_everything_is_told_from_one_over_its_base() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let (t, _) = n.any_orthonormal_pair();
    let wo = 1.4f32.cos() * n + 1.4f32.sin() * t;
    let sampled = coated_over_everything(0.4, 0.0, 0.5);
    let wrong = Material {
        coat: sampled.coat.map(|coat| Coat { covers: Covers::Base, ..coat }),
        ..sampled.clone()
    };
    let (bsdf, wrong) =
        (sampled.bsdf(n, TransportMode::Radiance), wrong.bsdf(n, TransportMode::Radiance));
    let result = std::panic::catch_unwind(|| {
        plastic_lobe_matches_pdf("mutated", &bsdf, n, wo, 0.2, |wi| {
            wrong.pdf(wo, wi, LobeFlags::ALL)
        })
    });
    assert!(result.is_err(), "{sampled:?} passed against {wrong:?}");
}

/// A base, a mirror and a straight transmission (ior 1, POV-Ray's filter and transmit) under
/// a coat of weight 0.6 and alpha 0.2 over them all.
fn coated_over_everything(diffuse: f32, specular: f32, transmission: f32) -> Material {
    let coat = Coat { strength: 0.6, roughness: 0.2, covers: Covers::Everything };
    Material { coat: Some(coat), ior: 1.0, ..material(diffuse, specular, transmission, false) }
}

/// The harness fails on the plastic's pdf with another coat alpha or another base.
#[test]
fn plastic_sampling_test_detects_a_wrong_pdf() {
    let n = Vec3::new(0.3, -0.2, 0.9).normalize();
    let wo = Vec3::new(-0.5, 0.4, 0.6).normalize();
    for (sampled, wrong) in [
        (plastic(0.5, 0.0, 0.3), plastic(0.5, 0.0, 0.33)),
        (plastic(0.2, 0.0, 0.1), plastic(0.3, 0.0, 0.1)),
    ] {
        let (bsdf, wrong) =
            (sampled.bsdf(n, TransportMode::Radiance), wrong.bsdf(n, TransportMode::Radiance));
        let result = std::panic::catch_unwind(|| {
            plastic_lobe_matches_pdf("mutated", &bsdf, n, wo, 0.3, |wi| {
                wrong.pdf(wo, wi, LobeFlags::ALL)
            })
        });
        assert!(result.is_err(), "{sampled:?} passed against {wrong:?}");
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
            Light::Point { .. }
            | Light::Environment(_)
            | Light::Spot(_)
            | Light::Distant { .. }
            | Light::Modified { .. } => false,
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

/// A sky that varies by direction (`sky_sphere`, turned so that its cells lie askew to the
/// bins): the environment light's samples, as next-event estimation draws them, against its pdf;
/// and the harness tells them from the constant sky's pdf.
#[test]
fn sky_sampling_matches_sky_pdf() {
    let text = "camera { location <0, 0, -5>  look_at <0, 0, 0> }
        sky_sphere {
            pigment { gradient y  color_map { [0 rgb 0.02] [0.6 rgb <0.2, 0.3, 0.9>] [0.95 rgb 1] [1 rgb 20] }
                      scale 2  translate -1 }
            rotate <30, 0, 20>
        }
        sphere { <0, 0, 0>, 1 }";
    let graph = raydiance::lang::parse_scene(std::path::Path::new("tests/inline.pov"), text)
        .unwrap_or_else(|e| panic!("{e}"));
    let scene = raydiance::scene::build(&graph).unwrap_or_else(|e| panic!("{e}"));
    let Some(light @ Light::Environment(sky)) = scene.lights.last() else { panic!("no sky") };
    let point = Vec3::new(0.0, 0.0, -3.0);
    let hit =
        Hit { t: 1.0, point, normal: Vec3::Y, shading_normal: Vec3::Y, error: 0.0, primitive: 0 };
    let sample = |s: &mut Sampler| light.sample(&hit, s.next_2d()).map(|l| l.wi);
    chi_square("a gradient sky", sample, |wi| sky.pdf(wi));
    let uniform = std::panic::catch_unwind(|| {
        chi_square("a gradient sky against uniform", sample, |_| 0.25 / PI)
    });
    assert!(uniform.is_err(), "the harness took the sky's samples for uniform ones");
}

/// Henyey–Greenstein sampling (isotropic, forward, backward, strongly forward) against its own
/// density, around the direction of travel (-wo); bins zoomed near the peak of peaked lobes.
#[test]
fn phase_function_sampling_matches_its_pdf() {
    use raydiance::medium::HenyeyGreenstein;
    let wo = Vec3::new(0.3, -0.5, 0.8).normalize();
    for (g, zoom) in [(0.0, 1), (0.5, 1), (-0.7, 1), (0.9, 2)] {
        let phase = HenyeyGreenstein { g };
        let axis = if g < 0.0 { wo } else { -wo };
        chi_square_in(
            Bins { axis, zoom },
            10,
            &format!("Henyey–Greenstein g {g}"),
            |s| Some(phase.sample(wo, s.next_2d()).0),
            |wi| phase.eval(wo, wi),
        );
    }
}

/// The phase test fails where the density is not the sampled one (g 0.5 drawn, 0.6 claimed).
#[test]
fn phase_function_test_detects_a_wrong_pdf() {
    use raydiance::medium::HenyeyGreenstein;
    let result = std::panic::catch_unwind(|| {
        let wo = Vec3::Z;
        let (drawn, claimed) = (HenyeyGreenstein { g: 0.5 }, HenyeyGreenstein { g: 0.6 });
        chi_square(
            "mismatch",
            |s| Some(drawn.sample(wo, s.next_2d()).0),
            |wi| claimed.eval(wo, wi),
        );
    });
    assert!(result.is_err());
}
