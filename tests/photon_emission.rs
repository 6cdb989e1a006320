//! Photon emission: every light's photons carry exactly its power, and the pass's photons are
//! shared out among the lights in proportion to power; photons aimed at the casters of caustics
//! carry the caustics' power.

use crate::common;

use std::f32::consts::PI;

use glam::Vec3;
use raydiance::light::Light;
use raydiance::photon::{Arrival, Emission, Projection, trace_photon};
use raydiance::sampling::Sampler;

/// Two point lights, a quad, a sphere and a disk emitting, one emitter with no power.
const LIGHTS: &str = r#"
light_source { <0, 0.5, 0>  power rgb <1, 2, 3> }
light_source { <0.3, -0.2, 0.1>  power rgb 0.25 }
quad { <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5>  material { emission rgb <4, 3, 2> } }
sphere { <0.5, -0.5, 0>, 0.1  material { emission rgb 6 } }
disk { <-0.5, -0.9, 0>, <0, 1, 0>, 0.2  material { emission rgb <0, 1, 5> } }
sphere { <0, -0.5, 0.5>, 0.2  material { diffuse rgb 0.5 } }
"#;

/// The lights' power computed here from the text's numbers: 4 pi p for a point light, pi A Le
/// for a one-sided diffuse emitter of area A.
fn expected_power() -> Vec3 {
    let points = 4.0 * PI * (Vec3::new(1.0, 2.0, 3.0) + Vec3::splat(0.25));
    let quad = PI * 0.25 * Vec3::new(4.0, 3.0, 2.0);
    let sphere = PI * (4.0 * PI * 0.01) * Vec3::splat(6.0);
    let disk = PI * (PI * 0.04) * Vec3::new(0.0, 1.0, 5.0);
    points + quad + sphere + disk
}

#[test]
fn photons_carry_exactly_the_lights_power() {
    let scene = common::scene(&format!("{}{LIGHTS}", common::LAB_BOX));
    assert_eq!(scene.lights.len(), 5);
    for photons in [1, 5, 7, 1000, 123_457] {
        let emission = Emission::new(&scene.lights, photons);
        assert_eq!(emission.total(), photons.max(5), "every light emits at least one photon");
        let mut total = Vec3::ZERO;
        for (l, light) in scene.lights.iter().enumerate() {
            let mut sum = glam::DVec3::ZERO;
            for index in 0..emission.total() {
                let (light_of, count) = emission.light_of(index);
                if light_of != l {
                    continue;
                }
                assert_eq!(count, emission.photons_of(l));
                let mut s = Sampler::new(3, 9, u64::from(index));
                let photon = light.sample_emission(count, s.next_2d(), s.next_2d()).unwrap();
                sum += photon.power.as_dvec3();
            }
            let sum = sum.as_vec3();
            assert!(
                (sum - light.power_rgb()).abs().max_element()
                    <= 1e-5 * light.power_rgb().max_element(),
                "light {l} with {photons} photons: {sum} against {}",
                light.power_rgb()
            );
            total += sum;
            // In proportion to power: within one photon of the share, beyond the first.
            let share = f64::from(photons.saturating_sub(5)) * f64::from(light.power())
                / scene.lights.iter().map(|l| f64::from(l.power())).sum::<f64>();
            let count = f64::from(emission.photons_of(l));
            assert!(
                (count - 1.0 - share).abs() <= 1.0,
                "light {l}: {count} photons, share {share}"
            );
        }
        let expected = expected_power();
        assert!(
            (total - expected).abs().max_element() < 1e-4 * expected.max_element(),
            "{total} against {expected}"
        );
    }
}

/// Area lights' photons leave points on the surface, from the emitting side, cosine-weighted
/// about its normal (the mean cosine is 2/3); point lights' are uniform (mean direction 0).
#[test]
fn photons_leave_the_emitting_side_cosine_weighted() {
    let scene = common::scene(&format!("{}{LIGHTS}", common::LAB_BOX));
    let sphere_centre = Vec3::new(0.5, -0.5, 0.0);
    for light in &scene.lights {
        let n = 20_000;
        let (mut mean_cos, mut mean_dir) = (0.0f64, Vec3::ZERO);
        for i in 0..n {
            let mut s = Sampler::new(1, 2, i);
            let photon = light.sample_emission(1, s.next_2d(), s.next_2d()).unwrap();
            let (origin, dir) = (Vec3::from(photon.ray.origin), Vec3::from(photon.ray.dir));
            mean_dir += dir / n as f32;
            let normal = match light {
                Light::Point { position, .. } => {
                    assert_eq!(origin, *position);
                    continue;
                }
                // The quad faces edge1 x edge2 = x cross z = -y; the disk its normal +y.
                Light::Area { .. } if (origin.y - 0.99).abs() < 1e-4 => Vec3::NEG_Y,
                Light::Area { .. } if (origin.y + 0.9).abs() < 1e-4 => Vec3::Y,
                Light::Area { .. } => {
                    assert!((origin.distance(sphere_centre) - 0.1).abs() < 1e-4, "{origin}");
                    (origin - sphere_centre).normalize()
                }
                Light::Environment(_)
                | Light::Spot(_)
                | Light::Distant { .. }
                | Light::Modified { .. } => {
                    unreachable!("the lab box has point and area lights only")
                }
            };
            let cos = normal.dot(dir);
            assert!(cos >= 0.0, "photon {i} leaves the back of its light: {origin} {dir}");
            mean_cos += f64::from(cos) / f64::from(n as u32);
        }
        match light {
            Light::Point { .. } => assert!(mean_dir.length() < 0.02, "{mean_dir}"),
            Light::Area { .. } => {
                assert!((mean_cos - 2.0 / 3.0).abs() < 0.01, "mean cosine {mean_cos}")
            }
            Light::Environment(_)
            | Light::Spot(_)
            | Light::Distant { .. }
            | Light::Modified { .. } => {}
        }
    }
}

/// The caustic power the photons of `emission` deposit (light -> specular -> diffuse), their
/// sum, and that sum's standard error (photons independent).
fn caustic_power(scene: &raydiance::scene::Scene, emission: &Emission, pass: u64) -> (f64, f64) {
    let (mut sum, mut squares) = (0.0f64, 0.0f64);
    for index in 0..emission.total() {
        let mut power = 0.0f64;
        trace_photon(scene, emission, scene.settings.max_depth, pass, index, |d| {
            if d.arrival == Arrival::Caustic {
                power += f64::from(d.power.element_sum()) / 3.0;
            }
        });
        (sum, squares) = (sum + power, squares + power * power);
    }
    let n = f64::from(emission.total());
    (sum, (squares - sum * sum / n).max(0.0).sqrt())
}

/// Jensen's projection map (`photon::Projection`): photons aimed at a glass ball and a mirror
/// ball from a point light and an area light deposit the caustic power that photons sent
/// everywhere deposit, within 4 standard errors, with a tenth of the photons; per photon, the
/// aimed ones' noise is lower.
#[test]
fn aimed_caustic_photons_carry_the_power_of_unaimed_ones() {
    let scene = common::scene(&format!(
        "{}{}",
        common::LAB_BOX,
        r#"settings { max_depth 8 }
        light_source { <0.2, 0.6, 0>  power rgb 1 }
        quad { <-0.25, 0.99, -0.25>, <0.5, 0, 0>, <0, 0, 0.5>  material { emission rgb 2 } }
        sphere { <0, -0.6, 0>, 0.3  material { transmission rgb 1  ior 1.5  fresnel } }
        sphere { <0.6, -0.7, 0.3>, 0.2  material { specular rgb 0.9 } }
        sphere { <-0.5, -0.7, 0.3>, 0.2  material { diffuse rgb 0.5 } }"#
    ));
    let projection = Projection::of(&scene).expect("two casters");
    let everywhere = caustic_power(&scene, &Emission::new(&scene.lights, 200_000), 0);
    let aimed = caustic_power(&scene, &Emission::aimed(&scene.lights, projection, 20_000), 1);
    let both = everywhere.1.hypot(aimed.1);
    assert!(
        (aimed.0 - everywhere.0).abs() < 4.0 * both,
        "aimed {aimed:?} against sent everywhere {everywhere:?}"
    );
    // The standard error falls as one over the root of the photons: at equal counts, the
    // aimed pass's would be a root of ten below its own.
    let per_photon = aimed.1 / 10f64.sqrt();
    assert!(per_photon < everywhere.1, "aiming must lower the noise: {aimed:?} {everywhere:?}");
}

/// The sky's photons leave a disc across the sphere around the bounded objects (and the camera);
/// an infinite floor crosses that disc, and the sky's light from below the horizon, which the
/// floor stops before it reaches the disc, must not light what stands on it. A diffuse ball
/// (r = 0.5) above the floor under a white sky (L = 1) receives straight from the sky exactly
/// the light of the upper hemisphere: power L π r² 2π. Bound: 4 standard errors. (Photons
/// started on the disc whatever lay upstream lit the ball from below the horizon too, the part
/// of the disc above the floor sending them up: 56 % more, by a Monte Carlo of this geometry.)
#[test]
fn the_sky_below_an_infinite_floor_does_not_light_what_stands_on_it() {
    let scene = common::scene(
        "settings { background rgb 1  max_depth 1 }
        camera { location <0, 1, -3>  look_at <0, 1, 0> }
        plane { <0, 1, 0>, 0  material { diffuse rgb 0.5 } }
        sphere { <0, 1, 0>, 0.5  material { diffuse rgb 0.5 } }",
    );
    let emission = Emission::new(&scene.lights, 100_000);
    let (mut sum, mut squares) = (0.0f64, 0.0f64);
    for index in 0..emission.total() {
        let mut power = 0.0f64;
        trace_photon(&scene, &emission, 1, 0, index, |d| {
            if d.arrival == Arrival::Direct && d.hit.point.y > 0.25 {
                power += f64::from(d.power.element_sum()) / 3.0;
            }
        });
        (sum, squares) = (sum + power, squares + power * power);
    }
    let n = f64::from(emission.total());
    let error = (squares - sum * sum / n).max(0.0).sqrt();
    let expected = 2.0 * std::f64::consts::PI.powi(2) * 0.25;
    assert!(error < 0.03 * expected, "too noisy to tell: {sum} +- {error}");
    assert!((sum - expected).abs() < 4.0 * error, "{sum} +- {error}, expected {expected}");
}
