//! Photon mapping's figures on `scenes/caustic-point.scn`: photons traced per second (one pass,
//! all threads), photons stored and bytes per stored photon, and the k-d tree's build time.
//!
//! `cargo run --release --example photon_figures [-- PHOTONS]` (default 10,000,000 emitted).

use std::time::Instant;

use raydiance::integrator::trace_pass;
use raydiance::photon::{Arrival, Deposit, Emission, Photon, PhotonMap};
use raydiance::progress::Silent;

fn main() {
    let photons: u32 = std::env::args().nth(1).map_or(10_000_000, |a| a.parse().expect("a count"));
    let scene = raydiance::load(
        std::path::Path::new("scenes/caustic-point.scn"),
        &raydiance::RenderRequest::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let emission = Emission::new(&scene.lights, photons);
    let start = Instant::now();
    // `photon`'s map: every photon after one bounce or more.
    let kept = |d: &Deposit| [d.arrival != Arrival::Direct];
    let [stored] = trace_pass(&scene, &emission, 0, &Silent, kept).expect("not stopped");
    let tracing = start.elapsed().as_secs_f64();
    let count = stored.len();
    let start = Instant::now();
    let map = PhotonMap::build(stored);
    let building = start.elapsed().as_secs_f64();
    // Each stored photon, and the position and index the tree keeps of it in its leaves.
    let bytes = std::mem::size_of::<Photon>() + std::mem::size_of::<([f32; 3], u32)>();
    println!(
        "{} photons emitted in {tracing:.2} s: {:.2} M photons/s; {count} stored ({:.2} per \
         photon emitted), {bytes} bytes each ({:.0} MB); k-d tree of {} photons built in \
         {building:.2} s on {} threads",
        emission.total(),
        f64::from(emission.total()) / tracing / 1e6,
        count as f64 / f64::from(emission.total()),
        (count * bytes) as f64 / 1e6,
        map.len(),
        rayon::current_num_threads()
    );
}
