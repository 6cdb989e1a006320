//! Shares of the sample set and tiles of the image, rendered apart into part files and merged in
//! any order, make the image of one render (within 1e-6 relative per pixel).

use crate::common;

use std::path::PathBuf;

use proptest::prelude::*;
use raydiance::image::Image;
use raydiance::progress::Silent;
use raydiance::region::{Crop, Region, Share};
use raydiance::render::{render, render_region};
use raydiance::scene::Scene;
use raydiance::split::merge::merge;
use raydiance::split::part_file::{self, PartHeader};

/// A small scene with glass, a mirror, an area light and depth of field: every integrator
/// dimension and a lens sample per camera sample.
fn scene(integrator: &str, samples: u32) -> Scene {
    common::scene(&format!(
        "{}
        settings {{ resolution 11, 7  samples {samples}  integrator {integrator}  seed 5 }}
        camera {{ location <0, 0, -3>  look_at <0, 0, 0>  angle 50  aperture 0.05  focal_distance 3 }}
        plane {{ <0, 0, 1>, 3  material {{ diffuse rgb 0.5 }} }}
        quad {{ <-0.3, 0.99, -0.3>, <0.6, 0, 0>, <0, 0, 0.6>  material {{ emission rgb 8 }} }}
        sphere {{ <-0.4, -0.6, 0>, 0.35  material {{ transmission rgb 1  ior 1.5  fresnel }} }}
        sphere {{ <0.45, -0.6, 0.2>, 0.35  material {{ specular rgb 0.9 }} }}",
        common::LAB_WALLS
    ))
}

/// Renders `region` of `scene` into a part file in `dir`.
fn render_part(scene: &Scene, region: Region, dir: &std::path::Path, name: &str) -> PathBuf {
    let (film, stats) = render_region(scene, &region, &Silent);
    let s = &scene.settings;
    let path = dir.join(name);
    let header = PartHeader {
        path: path.clone(),
        width: s.width,
        height: s.height,
        region,
        taken: stats.samples_per_pixel,
        seed: s.seed,
        integrator: s.integrator.name().to_string(),
        max_depth: s.max_depth,
        digest: "same".to_string(),
        frame: Default::default(),
        seconds: stats.seconds,
        aovs: Default::default(),
    };
    part_file::write(&path, &film, &header).unwrap();
    path
}

fn assert_close(merged: &Image, single: &Image) {
    assert_eq!((merged.width, merged.height), (single.width, single.height));
    for (i, (a, b)) in merged.pixels.iter().zip(&single.pixels).enumerate() {
        for c in 0..3 {
            let (a, b) = (a[c], b[c]);
            assert!(
                (a - b).abs() <= 1e-6 * a.abs().max(b.abs()),
                "pixel {i} channel {c}: merged {a}, single {b}"
            );
        }
    }
}

/// Cuts `crop` into tiles: `cuts` says, one decision a tile, whether to cut it in two (and
/// where), across its longer side.
fn tiles(crop: Crop, cuts: &mut impl Iterator<Item = (bool, u32)>, depth: u32) -> Vec<Crop> {
    let (cut, at) = cuts.next().unwrap_or((false, 0));
    let long_x = crop.width() >= crop.height();
    let side = if long_x { crop.width() } else { crop.height() };
    if !cut || side < 2 || depth > 3 {
        return vec![crop];
    }
    let at = 1 + at % (side - 1);
    let (a, b) = if long_x {
        (Crop { x1: crop.x0 + at, ..crop }, Crop { x0: crop.x0 + at, ..crop })
    } else {
        (Crop { y1: crop.y0 + at, ..crop }, Crop { y0: crop.y0 + at, ..crop })
    };
    let mut out = tiles(a, cuts, depth + 1);
    out.extend(tiles(b, cuts, depth + 1));
    out
}

/// Splits share `share` of a tile of `total` samples into a random partition: each share is
/// kept or split into its two halves (`2I/2N`, `2I+1/2N`).
fn partition(share: Share, total: u64, splits: &mut impl Iterator<Item = bool>) -> Vec<Share> {
    let finer = u64::from(share.count) * 2;
    if !splits.next().unwrap_or(false) || finer > total || share.count >= 64 {
        return vec![share];
    }
    let half = |index| Share::new(index, share.count * 2).unwrap();
    let mut out = partition(half(share.index * 2), total, splits);
    out.extend(partition(half(share.index * 2 + 1), total, splits));
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn random_shares_and_tiles_merge_into_the_single_render(
        samples in 1u32..9,
        path in any::<bool>(),
        cuts in proptest::collection::vec((any::<bool>(), any::<u32>()), 0..16),
        splits in proptest::collection::vec(any::<bool>(), 0..64),
        order in any::<u64>(),
    ) {
        let scene = scene(if path { "path" } else { "direct" }, samples);
        let single = render(&scene, &Silent).0.image();
        let dir = tempfile::tempdir().unwrap();
        let (mut cuts, mut splits) = (cuts.into_iter(), splits.into_iter());
        let mut paths = Vec::new();
        for crop in tiles(Crop::whole(11, 7), &mut cuts, 0) {
            let total = crop.pixels() * u64::from(samples);
            for share in partition(Share::WHOLE, total, &mut splits) {
                let region = Region { crop, share, samples };
                let name = format!("{}-{}-{}.exr", crop, share.index, share.count);
                paths.push(render_part(&scene, region, dir.path(), &name));
            }
        }
        // Any order: a fixed shuffle drawn from `order`.
        let mut state = order;
        for i in (1..paths.len()).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            paths.swap(i, (state >> 33) as usize % (i + 1));
        }
        let merged = merge(&paths, false).unwrap();
        prop_assert_eq!(merged.samples, (samples, samples));
        prop_assert_eq!(merged.info.samples_per_pixel, samples);
        assert_close(&merged.image, &single);
    }
}

#[test]
fn more_shares_than_samples_per_pixel_split_within_the_pixels() {
    // 2 spp in 5 shares: most pixels get 0 or 1 sample of a share.
    let scene = scene("path", 2);
    let single = render(&scene, &Silent).0.image();
    let dir = tempfile::tempdir().unwrap();
    let paths: Vec<PathBuf> = (0..5)
        .map(|i| {
            let region = Region::whole(11, 7, 2);
            let region = Region { share: Share::new(i, 5).unwrap(), ..region };
            render_part(&scene, region, dir.path(), &format!("{i}.exr"))
        })
        .collect();
    let merged = merge(&paths, false).unwrap();
    assert_close(&merged.image, &single);
    // A part's own RGB is the mean of its samples: a viewer shows it as an image.
    let part = raydiance::image::exr::read(&paths[0]).unwrap();
    assert_eq!((part.width, part.height), (11, 7));
}

#[test]
fn a_crop_and_a_share_take_the_same_samples_as_the_single_render() {
    // Share 1 of 2 of a 4 spp render is sample indices 2 and 3 of each pixel: in a crop too.
    let scene = scene("direct", 4);
    let (film, _) = render(&scene, &Silent);
    let crop = Crop { x0: 3, x1: 8, y0: 2, y1: 6 };
    let first = Region { crop, share: Share::new(0, 2).unwrap(), samples: 4 };
    let second = Region { share: Share::new(1, 2).unwrap(), ..first };
    let (a, _) = render_region(&scene, &first, &Silent);
    let (b, _) = render_region(&scene, &second, &Silent);
    for y in 0..4 {
        for x in 0..5 {
            let whole = film.sum[(y + 2) * 11 + x + 3];
            let parts = a.sum[y * 5 + x] + b.sum[y * 5 + x];
            assert!((whole - parts).abs().max_element() <= 1e-9 * whole.max_element(), "{x},{y}");
        }
    }
}
