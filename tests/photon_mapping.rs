//! The `photon` and `sppm` integrators against closed forms, against `path`, against an
//! analytic caustic; determinism over threads; stopping between iterations.

mod common;

use std::sync::atomic::{AtomicU32, Ordering};

use common::{scene, scene_file};
use raydiance::film::Film;
use raydiance::render::{Progress, Silent, render};
use raydiance::scene::Scene;
use raydiance::scene::graph::IntegratorKind;

fn with(
    mut scene: Scene,
    integrator: IntegratorKind,
    size: u32,
    samples: u32,
    photons: u32,
) -> Scene {
    scene.settings.integrator = integrator;
    (scene.settings.width, scene.settings.height) = (size, size);
    scene.settings.samples = samples;
    scene.settings.photons = Some(photons);
    scene
}

/// The mean of the image and the standard error of that mean from the spread of its pixels
/// (each pixel an estimate of the same value, from photons far enough apart to be nearly
/// independent).
fn mean_and_standard_error(film: &Film) -> (f64, f64) {
    let values: Vec<f64> = film.image().pixels.iter().map(|p| f64::from(p.x)).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// A closed diffuse sphere (R = 2, albedo a = 0.5) with a point light of p = 4 pi at its
/// centre: wall radiance a p / (pi R^2 (1 - a)) = 1, of which next-event estimation gives the
/// direct a p / (pi R^2) = 0.5 exactly and photons the indirect 0.5.
const CLOSED_SPHERE: &str = "settings { max_depth 64  photon_k 100  photon_radius 0.05 }
    camera { location <0.3, -0.2, 0.1>  look_at <1, 0, 2>  angle 100 }
    light_source { <0, 0, 0>  power rgb 4 * pi }
    sphere { <0, 0, 0>, 2  material { diffuse rgb 0.5 } }";

/// `photon`: after the first bounce every photon lands uniformly on the sphere, so the k-th
/// nearest photon's cap (a cap of chord radius r has area exactly pi r^2) holds a Beta(k, M-k+1)
/// share of the M stored photons, and E[k / (pi r_k^2)] = M / (4 pi R^2) * k / (k - 1): the
/// estimate's bias is the factor k / (k - 1) on the indirect part, whatever the photon count.
/// Bound: that expectation, within 5 standard errors of the image mean (and within 3%).
#[test]
fn photon_closed_sphere_matches_the_closed_form() {
    let s = with(scene(CLOSED_SPHERE), IntegratorKind::Photon, 16, 2, 100_000);
    let k = f64::from(s.settings.photon_k);
    let expected = 0.5 + 0.5 * k / (k - 1.0);
    let (mean, error) = mean_and_standard_error(&render(&s, &Silent).0);
    assert!(error < 0.01, "too noisy to tell: standard error {error}");
    assert!((mean - expected).abs() < 5.0 * error, "mean {mean}, expected {expected} +- {error}");
    assert!((mean - 1.0).abs() < 0.03, "mean {mean}");
}

/// `sppm`: with photons of equal power (a grey albedo keeps Russian roulette's photons at
/// their power) and a uniform density, N / R^2 grows by M / R^2 at every update
/// (N' / R'^2 = (N + M) / R^2) and E[M] = lambda pi R^2, so E[N_n / (pi R_n^2)] is exactly n
/// iterations' photon density: the estimate is unbiased here. Bound: 5 standard errors.
#[test]
fn sppm_closed_sphere_matches_the_closed_form() {
    let s = with(scene(CLOSED_SPHERE), IntegratorKind::Sppm, 16, 16, 20_000);
    let (mean, error) = mean_and_standard_error(&render(&s, &Silent).0);
    assert!(error < 0.01, "too noisy to tell: standard error {error}");
    assert!((mean - 1.0).abs() < 5.0 * error, "mean {mean}, expected 1 +- {error}");
}

fn film_bits(film: &Film) -> Vec<[u64; 3]> {
    film.sum.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

#[test]
fn one_and_two_threads_give_bit_identical_films() {
    for integrator in [IntegratorKind::Photon, IntegratorKind::Sppm] {
        let s = with(scene_file("scenes/caustic-point.scn"), integrator, 24, 3, 20_000);
        let on = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| film_bits(&render(&s, &Silent).0))
        };
        assert_eq!(on(1), on(2), "{integrator:?}");
    }
}

/// Stops the render after `iterations` iterations (as Ctrl-C does, between them), or drops
/// the one under way once `advances` rows are done.
struct StopAfter {
    iterations: u32,
    advances: u32,
    seen: AtomicU32,
    rows: AtomicU32,
}

impl Progress for StopAfter {
    fn advance(&self, _: u64) {
        self.rows.fetch_add(1, Ordering::SeqCst);
    }
    fn pass_limit(&self, _: f64) -> Option<u32> {
        let seen = self.seen.fetch_add(1, Ordering::SeqCst) + 1;
        (seen >= self.iterations).then_some(0)
    }
    fn should_abandon(&self) -> bool {
        self.rows.load(Ordering::SeqCst) >= self.advances
    }
}

/// A stopped `sppm` render is the render of the iterations it completed, bit for bit.
#[test]
fn sppm_stopped_keeps_the_completed_iterations() {
    let caustic = |iterations| {
        with(scene_file("scenes/caustic-point.scn"), IntegratorKind::Sppm, 16, iterations, 5000)
    };
    let s = caustic(8);
    let stop = StopAfter { iterations: 3, advances: u32::MAX, seen: 0.into(), rows: 0.into() };
    let (stopped, stats) = render(&s, &stop);
    assert_eq!(stats.samples_per_pixel, 3);
    let three = render(&caustic(3), &Silent).0;
    assert_eq!(film_bits(&stopped), film_bits(&three));
    // Stopped within the fifth iteration's camera paths (16 rows each): four are kept.
    let stop =
        StopAfter { iterations: u32::MAX, advances: 4 * 16 + 5, seen: 0.into(), rows: 0.into() };
    let (stopped, stats) = render(&s, &stop);
    assert_eq!(stats.samples_per_pixel, 4);
    let four = render(&caustic(4), &Silent).0;
    assert_eq!(film_bits(&stopped), film_bits(&four));
}
