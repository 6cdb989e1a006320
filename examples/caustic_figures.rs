//! Caustic figures (issue 31): a scene rendered by converged `sppm` (the reference) and by
//! `photon` and `final_gather` with their default photons, compared on the image mean, the
//! caustic's core (the 3 x 3 pixels around the reference's brightest pixel on a diffuse
//! surface) and the ring around it (the diffuse pixels 2 to 6 pixels from that one).
//!
//! `cargo run --release --example caustic_figures -- SCENE SIZE ITERATIONS RADIUS SAMPLES [SEEDS]
//! [INTEGRATORS]`:
//! the reference is `sppm` with ITERATIONS iterations from `photon_radius` RADIUS; the others
//! take SAMPLES camera samples, averaged over SEEDS seeds (default 1): each figure's error
//! against the reference is the seeds' mean ± its standard error (the reference's own noise
//! not included). INTEGRATORS: those compared, by name, comma-separated (default
//! `photon,final_gather`).

use glam::Vec2;
use raydiance::graph::IntegratorKind;
use raydiance::image::Image;
use raydiance::progress::Silent;
use raydiance::render::render;
use raydiance::scene::Scene;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |i: usize| args.get(i).map(|a| a.parse::<f64>().expect("a number"));
    let (size, iterations, radius, samples) = (
        number(1).expect("SIZE") as u32,
        number(2).expect("ITERATIONS") as u32,
        number(3).expect("RADIUS") as f32,
        number(4).expect("SAMPLES") as u32,
    );
    let seeds = number(5).unwrap_or(1.0) as u64;
    let integrators: Vec<IntegratorKind> = (args
        .get(6)
        .map_or("photon,final_gather", String::as_str))
    .split(',')
    .map(|name| IntegratorKind::named(name).unwrap_or_else(|| panic!("no integrator {name}")))
    .collect();
    let load = |integrator, samples, seed| {
        let request = raydiance::RenderRequest {
            samples: Some(samples),
            width: Some(size),
            height: Some(size),
            seed: Some(seed),
            integrator: Some(integrator),
            ..Default::default()
        };
        let path = std::path::Path::new(&args[0]);
        raydiance::load(path, &request).unwrap_or_else(|e| panic!("{e}"))
    };
    // A seed none of the runs compared takes: their photons share none of its passes.
    let mut reference = load(IntegratorKind::Sppm, iterations, 1000);
    reference.settings.photon_radius = radius;
    let sppm = render(&reference, &Silent).0.image();
    let peak = brightest_diffuse(&reference, &sppm);
    let regions = regions(&reference, peak);
    let figures = |image: &Image| regions.each_ref().map(|pixels| mean(image, pixels));
    let expected = figures(&sppm);
    println!("sppm {iterations} iterations, radius {radius}: mean / core at {peak:?} / ring");
    println!("  {:.5} / {:.5} / {:.5}", expected[0], expected[1], expected[2]);
    for integrator in integrators {
        let start = std::time::Instant::now();
        let shown: Vec<[f64; 3]> = (0..seeds)
            .map(|seed| figures(&render(&load(integrator, samples, seed), &Silent).0.image()))
            .collect();
        let error = |r: usize| {
            let errors: Vec<f64> =
                shown.iter().map(|s| 100.0 * (s[r] / expected[r] - 1.0)).collect();
            let (mean, se) = mean_se(&errors);
            format!("{mean:+.1} ± {se:.1} %")
        };
        println!(
            "{} {samples} samples, {seeds} seeds ({:.1} s): {} / {} / {}",
            integrator.name(),
            start.elapsed().as_secs_f64(),
            error(0),
            error(1),
            error(2)
        );
    }
}

/// The mean of `values` and its standard error (NaN for one value).
fn mean_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Whether pixel (x, y)'s centre sees a surface with a diffuse lobe.
fn sees_diffuse(scene: &Scene, x: usize, y: usize) -> bool {
    let (w, h) = (scene.settings.width as f32, scene.settings.height as f32);
    let ray = scene.camera.ray((x as f32 + 0.5) / w, (y as f32 + 0.5) / h, Vec2::ZERO);
    scene
        .intersect(&ray)
        .is_some_and(|hit| scene.material(hit.primitive, hit.point).diffuse.max_element() > 0.0)
}

fn brightest_diffuse(scene: &Scene, image: &Image) -> (usize, usize) {
    let pixels = (0..image.height).flat_map(|y| (0..image.width).map(move |x| (x, y)));
    let grey = |&(x, y): &(usize, usize)| image.get(x, y).element_sum();
    pixels
        .filter(|&(x, y)| sees_diffuse(scene, x, y))
        .max_by(|a, b| grey(a).total_cmp(&grey(b)))
        .expect("a diffuse pixel")
}

/// The whole image, the core and the ring (`main`).
fn regions(scene: &Scene, (px, py): (usize, usize)) -> [Vec<(usize, usize)>; 3] {
    let (w, h) = (scene.settings.width as usize, scene.settings.height as usize);
    let all: Vec<(usize, usize)> = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).collect();
    let distance = |&(x, y): &(usize, usize)| x.abs_diff(px).max(y.abs_diff(py));
    let core = all.iter().copied().filter(|p| distance(p) <= 1).collect();
    let ring = (all.iter().copied())
        .filter(|p| (2..=6).contains(&distance(p)) && sees_diffuse(scene, p.0, p.1))
        .collect();
    [all, core, ring]
}

fn mean(image: &Image, pixels: &[(usize, usize)]) -> f64 {
    let sum: f64 =
        pixels.iter().map(|&(x, y)| f64::from(image.get(x, y).element_sum()) / 3.0).sum();
    sum / pixels.len() as f64
}
