//! The picture of a failed comparison: where the tiles' z-scores lie, over a dim copy of the new
//! render for orientation.

use std::path::Path;

use glam::Vec3;

use super::{Comparison, Estimate, Rect};
use crate::image::{ImageError, png};

/// The heat map is enlarged (nearest pixel) until its longer side is at least this.
const MIN_SIDE: usize = 256;

/// Writes the heat map: grey is the new render's luminance at a third of its brightness; over it,
/// each finest tile is red where the new render is brighter and blue where it is darker, the
/// more so the larger its |z|, in full colour where it fails; a failing tile of a coarser level
/// (a change too faint for the finest tiles) is outlined in its colour.
pub fn write(path: &Path, comparison: &Comparison, new: &Estimate) -> Result<(), ImageError> {
    let scores = comparison.pixel_scores();
    let luminance: Vec<f32> = new.mean.iter().map(|&m| crate::tonemap::luminance(m)).collect();
    let brightest = luminance.iter().copied().fold(0.0, f32::max).max(1e-30);
    let hue = |score: f32| match score > 0.0 {
        true => Vec3::new(1.0, 0.15, 0.1),
        false => Vec3::new(0.1, 0.35, 1.0),
    };
    let (width, height) = (comparison.width, comparison.height);
    let scale = MIN_SIDE.div_ceil(width.max(height).max(1)).max(1);
    let mut pixels: Vec<Vec3> = (0..height * scale)
        .flat_map(|y| (0..width * scale).map(move |x| (y / scale) * width + x / scale))
        .map(|i| {
            let grey = Vec3::splat((luminance[i] / brightest).clamp(0.0, 1.0).sqrt() / 3.0);
            let score = scores[i];
            let weight = if score.abs() > 1.0 { 1.0 } else { 0.6 * score * score };
            grey.lerp(hue(score), weight)
        })
        .collect();
    let coarse_failures = comparison.failing().filter(|t| t.level > 0);
    for tile in coarse_failures {
        let Rect { x0, x1, y0, y1 } = tile.rect;
        let (x0, x1, y0, y1) = (x0 * scale, x1 * scale - 1, y0 * scale, y1 * scale - 1);
        let row = width * scale;
        for x in x0..=x1 {
            pixels[y0 * row + x] = hue(tile.worst_z());
            pixels[y1 * row + x] = hue(tile.worst_z());
        }
        for y in y0..=y1 {
            pixels[y * row + x0] = hue(tile.worst_z());
            pixels[y * row + x1] = hue(tile.worst_z());
        }
    }
    let bytes: Vec<[u8; 3]> =
        pixels.iter().map(|p| (*p * 255.0).round().to_array().map(|c| c as u8)).collect();
    png::write(path, width * scale, height * scale, &bytes)
}
