//! 8-bit PNG output of tone-mapped pixels.

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use super::{ImageError, write_atomic};

pub fn write(
    path: &Path,
    width: usize,
    height: usize,
    pixels: &[[u8; 3]],
) -> Result<(), ImageError> {
    let bytes: Vec<u8> = pixels.iter().flatten().copied().collect();
    write_atomic(path, |writer| {
        PngEncoder::new(writer)
            .write_image(&bytes, width as u32, height as u32, image::ExtendedColorType::Rgb8)
            .map_err(|e| ImageError::format(path, e.to_string()))
    })
}
