//! Images are a pure function of scene, settings and seed: not of threads, passes or runs.

use crate::common;

use common::scene_file;
use raydiance::progress::Silent;
use raydiance::render::render;

fn render_on(threads: usize, path: &str) -> Vec<glam::DVec3> {
    let mut scene = scene_file(path);
    scene.settings.width = 24;
    scene.settings.height = 24;
    scene.settings.samples = 5;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| render(&scene, &Silent).0.sum)
}

#[test]
fn one_and_two_threads_give_bit_identical_films() {
    for path in ["scenes/lab4-direct.scn", "scenes/cornell-specular.scn"] {
        let (one, two) = (render_on(1, path), render_on(2, path));
        assert!(
            one.iter()
                .zip(&two)
                .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)),
            "{path}"
        );
    }
}

#[test]
fn the_seed_changes_the_noise_and_only_the_seed() {
    let mut scene = scene_file("scenes/cornell-area.scn");
    scene.settings.width = 16;
    scene.settings.height = 16;
    scene.settings.samples = 2;
    let first = render(&scene, &Silent).0.sum;
    assert_eq!(first, render(&scene, &Silent).0.sum);
    scene.settings.seed = 1;
    assert_ne!(first, render(&scene, &Silent).0.sum);
}
