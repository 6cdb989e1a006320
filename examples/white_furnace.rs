//! How much light rough metal and rough glass keep (`docs/language.md`, Materials): a unit sphere
//! of `specular rgb 1` or of `transmission rgb 1  ior 1.5  fresnel`, at each roughness, under a
//! uniform background of radiance 1 (a white furnace), seen from far away with `path`. A lossless
//! surface shows 1 everywhere; GGX with Smith masking-shadowing scatters once and loses the light
//! that would scatter again between microfacets, more the rougher it is.
//!
//! Prints, for each, the sphere seen head-on (its middle 4x4 pixels, |n . wo| > 0.99) and its mean
//! over the silhouette (the cosine-weighted average over view directions), found from the image's
//! mean and the known share of the frame the silhouette covers.
//!
//! `cargo run --release --example white_furnace`

use std::path::Path;

use raydiance::progress::Silent;
use raydiance::render::render;

const SIDE: usize = 64;
const DISTANCE: f64 = 100.0;
/// Horizontal field of view, degrees: the silhouette fills most of the frame.
const ANGLE: f64 = 1.2;

fn main() {
    // The silhouette's share of the (square) frame, in the image plane at unit distance.
    let silhouette = (1.0 / DISTANCE).asin().tan();
    let half_frame = (ANGLE / 2.0).to_radians().tan();
    let covered = std::f64::consts::PI * silhouette * silhouette / (2.0 * half_frame).powi(2);
    let materials =
        [("metal", "specular rgb 1"), ("glass", "transmission rgb 1  ior 1.5  fresnel")];
    for (name, material) in materials {
        for roughness in [0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0] {
            let text = format!(
                "settings {{ resolution {SIDE}, {SIDE}  samples 256  integrator path  max_depth 64  \
                 background rgb 1 }}
                 camera {{ location <0, 0, -{DISTANCE}>  look_at <0, 0, 0>  angle {ANGLE} }}
                 sphere {{ <0, 0, 0>, 1  material {{ {material}  roughness {roughness} }} }}"
            );
            let graph = raydiance::lang::parse_scene(Path::new("furnace.scn"), &text)
                .unwrap_or_else(|e| panic!("{e}"));
            let scene = raydiance::scene::build(&graph).unwrap_or_else(|e| panic!("{e}"));
            let image = render(&scene, &Silent).0.image();
            let mean = |pixels: &mut dyn Iterator<Item = glam::Vec3>| {
                let (sum, count) = pixels
                    .fold((0.0, 0), |(s, n), p| (s + f64::from(p.element_sum()) / 3.0, n + 1));
                sum / f64::from(count)
            };
            let frame = mean(&mut image.pixels.iter().copied());
            let middle = SIDE / 2 - 2..SIDE / 2 + 2;
            let head_on = mean(&mut middle.clone().flat_map(|y| {
                let image = &image;
                middle.clone().map(move |x| image.pixels[y * SIDE + x])
            }));
            let average = 1.0 - (1.0 - frame) / covered;
            println!(
                "{name} roughness {roughness}: head-on {:.1} %, over the sphere {:.1} %",
                100.0 * head_on,
                100.0 * average
            );
        }
    }
}
