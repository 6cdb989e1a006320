//! raydiance's photon k-d tree against the `kiddo` crate's immutable k-d tree, on the photons
//! stored by one pass of `scenes/caustic-point.scn`: build time, and the time of `photon`'s
//! query (the k nearest photons) at stored photons' positions. Both on one thread.
//!
//! `cargo run --release --example kd_tree_against_kiddo [-- PHOTONS K QUERIES]`
//! (defaults: 2,000,000 emitted, k = 100, 200,000 queries).

use std::collections::BinaryHeap;
use std::num::NonZero;
use std::time::Instant;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use raydiance::integrator::trace_pass;
use raydiance::photon::{Emission, PhotonMap};
use raydiance::render::Silent;

fn main() {
    let arg = |i: usize, default: usize| {
        std::env::args().nth(i).map_or(default, |a| a.parse().expect("a count"))
    };
    let (photons, k, queries) = (arg(1, 2_000_000), arg(2, 100), arg(3, 200_000));
    let scene = raydiance::load(
        std::path::Path::new("scenes/caustic-point.scn"),
        &raydiance::RenderRequest::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let emission = Emission::new(&scene.lights, photons as u32);
    let stored = trace_pass(&scene, &emission, 0, &Silent).expect("not stopped");
    let points: Vec<[f32; 3]> = stored.iter().map(|p| p.position.to_array()).collect();
    // Query points: stored photons spread over the whole set.
    let step = (points.len() / queries).max(1);
    let at: Vec<glam::Vec3> = stored.iter().step_by(step).map(|p| p.position).collect();
    println!("{} photons stored, {} queries of k = {k}", points.len(), at.len());

    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for round in 0..3 {
        let (ours_build, ours_query, ours_sum) = pool.install(|| {
            let start = Instant::now();
            let map = PhotonMap::build(stored.clone());
            let build = start.elapsed().as_secs_f64();
            let start = Instant::now();
            let mut heap = BinaryHeap::new();
            let mut sum = 0.0f64;
            for &p in &at {
                heap.clear();
                map.nearest(p, k, &mut heap);
                sum += f64::from(heap.peek().map_or(0.0, |n| n.distance_squared));
            }
            (build, start.elapsed().as_secs_f64(), sum)
        });
        let start = Instant::now();
        let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice(&points);
        let kiddo_build = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let mut kiddo_sum = 0.0f64;
        let k_nonzero = NonZero::new(k).expect("k > 0");
        for p in &at {
            let found = tree.nearest_n::<SquaredEuclidean>(&p.to_array(), k_nonzero);
            kiddo_sum += f64::from(found.iter().map(|n| n.distance).fold(0.0, f32::max));
        }
        let kiddo_query = start.elapsed().as_secs_f64();
        // The same k-th distances, so the two answer the same question.
        assert!((ours_sum - kiddo_sum).abs() <= 1e-6 * ours_sum.abs().max(1.0));
        println!(
            "round {round}: build ours {ours_build:.3} s, kiddo {kiddo_build:.3} s; queries ours \
             {ours_query:.3} s, kiddo {kiddo_query:.3} s"
        );
    }
}
