//! How the snapshot comparison behaves at its defaults (64 pixels on the longer side, 64 spp):
//! how often renders that differ only in their seed fail a tile (the bound aims at 1 in 10,000),
//! and the smallest change of brightness it finds on S3 (`scenes/cornell-area.scn`).
//!
//! `cargo run --release --example snapshot_calibration [-- SEED_PAIRS]` (default 20).

use std::path::Path;

use raydiance::progress::Silent;
use raydiance::render::render;
use raydiance::snapshot::{self, Estimate, compare};

const SCENES: [&str; 7] = [
    "lab4-direct",
    "lab4-gi-point",
    "cornell-area",
    "cornell-specular",
    "gallery-textures",
    "gallery-bunnies",
    "mesh-bunny",
];

fn estimate(scene: &str, seed: u64) -> Estimate {
    let path = format!("scenes/{scene}.scn");
    let mut graph = raydiance::lang::load_scene(Path::new(&path)).unwrap();
    let longer = graph.settings.width.max(graph.settings.height) as f64;
    let side = |s: u32| ((f64::from(s) * 64.0 / longer).round() as u32).max(1);
    (graph.settings.width, graph.settings.height) =
        (side(graph.settings.width), side(graph.settings.height));
    graph.settings.samples = snapshot::DEFAULT_SAMPLES;
    graph.settings.seed = seed;
    let scene = raydiance::scene::build(&graph).unwrap();
    Estimate::from_film(&render(&scene, &Silent).0).unwrap()
}

/// The same render with every radiance scaled: what a light `factor` times as bright gives in
/// a scene lit by that light alone.
fn scaled(estimate: &Estimate, factor: f32) -> Estimate {
    Estimate {
        mean: estimate.mean.iter().map(|m| *m * factor).collect(),
        variance: estimate.variance.iter().map(|v| *v * factor * factor).collect(),
        ..estimate.clone()
    }
}

fn main() {
    let pairs: u64 = std::env::args().nth(1).map_or(20, |n| n.parse().expect("a count"));
    let (mut tiles, mut failures) = (0, 0);
    for scene in SCENES {
        let (mut scene_tiles, mut scene_failures) = (0, 0);
        for pair in 0..pairs {
            let c = compare(&estimate(scene, 2 * pair), &estimate(scene, 2 * pair + 1)).unwrap();
            scene_tiles += c.tiles.len();
            scene_failures += c.failing().count();
        }
        println!("{scene}: {scene_failures} failing of {scene_tiles} tiles");
        (tiles, failures) = (tiles + scene_tiles, failures + scene_failures);
    }
    println!("seed-only changes: {failures} failing of {tiles} tiles");
    let renders: Vec<_> = (0..2 * pairs).map(|seed| estimate("cornell-area", seed)).collect();
    for percent in [0.25f32, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0] {
        let found = (0..pairs as usize)
            .filter(|&p| {
                let brighter = scaled(&renders[2 * p + 1], 1.0 + percent / 100.0);
                !compare(&renders[2 * p], &brighter).unwrap().matches()
            })
            .count();
        println!("cornell-area {percent}% brighter: found in {found} of {pairs} pairs");
    }
}
