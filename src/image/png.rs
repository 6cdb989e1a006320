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
    write_atomic(path, |writer| {
        encode(writer, width, height, pixels).map_err(|e| ImageError::png(path, e))
    })
}

/// Encodes the pixels as a PNG file's bytes into `writer`.
pub fn encode(
    writer: impl std::io::Write,
    width: usize,
    height: usize,
    pixels: &[[u8; 3]],
) -> Result<(), image::ImageError> {
    let bytes: Vec<u8> = pixels.iter().flatten().copied().collect();
    PngEncoder::new(writer).write_image(
        &bytes,
        width as u32,
        height as u32,
        image::ExtendedColorType::Rgb8,
    )
}
