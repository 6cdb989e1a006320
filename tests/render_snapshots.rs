//! Small fixed-seed renders of the shipped scenes, tone-mapped to 8 bits and snapshotted as hex
//! rows. Each was reviewed as a picture (`target/snapshots/*.png` is written for that) before
//! it was accepted.

mod common;

use raydiance::tonemap::{ToneMap, quantise, tonemap};

fn snapshot(scene: &str) -> String {
    let mut s = common::scene_file(&format!("scenes/{scene}.scn"));
    s.settings.width = 32;
    s.settings.height = 32;
    s.settings.samples = 8;
    s.settings.seed = 1;
    let image = common::render_image(&s);
    let pixels = quantise(&tonemap(&image, &ToneMap::default()));
    let review = std::path::Path::new("target/snapshots");
    std::fs::create_dir_all(review).unwrap();
    raydiance::image::png::write(&review.join(format!("{scene}.png")), 32, 32, &pixels).unwrap();
    pixels
        .chunks(32)
        .map(|row| {
            row.iter()
                .map(|[r, g, b]| format!("{r:02x}{g:02x}{b:02x}"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn lab4_direct() {
    insta::assert_snapshot!(snapshot("lab4-direct"));
}

#[test]
fn lab4_gi_point() {
    insta::assert_snapshot!(snapshot("lab4-gi-point"));
}

#[test]
fn cornell_area() {
    insta::assert_snapshot!(snapshot("cornell-area"));
}

#[test]
fn cornell_specular() {
    insta::assert_snapshot!(snapshot("cornell-specular"));
}
