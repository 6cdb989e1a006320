//! `raydiance bench`: renders fixed scenes and prints throughput, to compare with other renderers
//! run on the same machine at the same time (`shared/bench/`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::pipeline::{RenderRequest, load};
use crate::render::{Silent, render};

/// The benchmark scenes S1-S6 of `shared/bench/scenes.md`, as shipped in `scenes/` (S5 and S6
/// read their meshes from `../shared/data/`).
pub const DEFAULT_SCENES: [&str; 6] = [
    "scenes/lab4-direct.scn",
    "scenes/lab4-gi-point.scn",
    "scenes/cornell-area.scn",
    "scenes/cornell-specular.scn",
    "scenes/mesh-bunny.scn",
    "scenes/mesh-heavy.scn",
];

/// Renders each scene at 256x256 with each sample count (`"16,64"`) `repeats` times after one
/// warm-up, and prints build time, median seconds and samples per second.
pub fn run(scenes: &[PathBuf], samples: &str, repeats: usize) -> Result<(), String> {
    let counts: Vec<u32> = samples
        .split(',')
        .map(|s| {
            s.trim().parse().map_err(|_| format!("error: --samples `{s}` is not a whole number"))
        })
        .collect::<Result<_, _>>()?;
    let default: Vec<PathBuf> = DEFAULT_SCENES.iter().map(PathBuf::from).collect();
    let scenes = if scenes.is_empty() { &default } else { scenes };
    println!("threads={}", rayon::current_num_threads());
    for path in scenes {
        for &spp in &counts {
            bench_one(path, spp, repeats.max(1))?;
        }
    }
    Ok(())
}

fn bench_one(path: &Path, spp: u32, repeats: usize) -> Result<(), String> {
    let request = RenderRequest {
        samples: Some(spp),
        width: Some(256),
        height: Some(256),
        ..Default::default()
    };
    let start = Instant::now();
    let scene = load(path, &request).map_err(|e| e.to_string())?;
    let load_seconds = start.elapsed().as_secs_f64();
    render(&scene, &Silent);
    let mut seconds: Vec<f64> = (0..repeats).map(|_| render(&scene, &Silent).1.seconds).collect();
    seconds.sort_by(f64::total_cmp);
    let median = seconds[seconds.len() / 2];
    let samples = 256.0 * 256.0 * f64::from(spp);
    println!(
        "{} spp={spp:4} load+build={load_seconds:.3}s median={median:.3}s {:.2} Msamples/s times={:?}",
        path.display(),
        samples / median / 1e6,
        seconds.iter().map(|s| (s * 1000.0).round() / 1000.0).collect::<Vec<_>>(),
    );
    Ok(())
}
