//! An image file read as POV-Ray 3.7 reads a height field's (`image_height_at`): each pixel a
//! height from 0 to 65535, which the height field divides by 65535. A palette image gives its
//! index × 256 (so 255 is 65280, as in POV-Ray), a gray image its value over its full range, a
//! 16-bit colour image its gray (0.297 red + 0.589 green + 0.114 blue), and an 8-bit colour
//! image red as the high byte and green as the low one (the 16-bit heights of TGA and PPM
//! height-field files). The values are taken as stored: no gamma is applied.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use png::{BitDepth, ColorType, Transformations};

/// A grid of heights in [0, 1], rows as the image's from its top, columns from its left.
#[derive(Debug, Clone, PartialEq)]
pub struct Heights {
    pub columns: usize,
    pub rows: usize,
    /// `rows * columns` heights, row by row.
    pub values: Vec<f32>,
}

/// The most pixels a height field's image or function may have (2048 × 2048): each pixel is
/// two triangles of the mesh made from it.
pub const MAX_HEIGHT_SAMPLES: usize = 1 << 22;

/// The image formats a height field is read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeightFormat {
    Png,
    Jpeg,
    /// PGM or PPM, plain or raw: POV-Ray reads both kinds under either word.
    Netpbm,
    Tga,
}

/// An image file that cannot give a height field.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct HeightsError {
    pub path: PathBuf,
    pub problem: HeightsProblem,
}

#[derive(Debug, thiserror::Error)]
pub enum HeightsProblem {
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    #[error(transparent)]
    Png(#[from] png::DecodingError),
    #[error(transparent)]
    Decode(#[from] image::ImageError),
    #[error(transparent)]
    Data(#[from] super::height_images::ImageDataError),
    #[error(
        "{columns} x {rows} pixels: a height field has at most {MAX_HEIGHT_SAMPLES} and at least \
         2 x 2"
    )]
    Size { columns: usize, rows: usize },
}

/// The heights of the image file at `path`, decoded as `format`.
pub fn read(path: &Path, format: HeightFormat) -> Result<Heights, HeightsError> {
    let decode = |bytes: &[u8]| match format {
        HeightFormat::Png => from_png(bytes),
        HeightFormat::Jpeg => from_jpeg(bytes),
        HeightFormat::Netpbm | HeightFormat::Tga => {
            let decoded = if format == HeightFormat::Tga {
                super::height_images::from_tga(bytes)
            } else {
                super::height_images::from_netpbm(bytes)
            };
            decoded.map(|(columns, rows, values)| Heights { columns, rows, values })
        }
    };
    crate::input::read(path, crate::input::MAX_IMAGE_BYTES)
        .map_err(HeightsProblem::from)
        .and_then(|bytes| decode(&bytes))
        .map_err(|problem| HeightsError { path: path.to_path_buf(), problem })
}

/// Checks a grid's size before anything is decoded or evaluated: a small file can declare a huge
/// image.
pub fn check_size(columns: usize, rows: usize) -> Result<(), HeightsProblem> {
    let samples = columns.saturating_mul(rows);
    if columns < 2 || rows < 2 || samples > MAX_HEIGHT_SAMPLES {
        return Err(HeightsProblem::Size { columns, rows });
    }
    Ok(())
}

fn from_png(bytes: &[u8]) -> Result<Heights, HeightsProblem> {
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    let info = decoder.read_header_info()?;
    let (columns, rows) = (info.width as usize, info.height as usize);
    check_size(columns, rows)?;
    // A palette image's indices are the heights: kept, not expanded to colours.
    let indexed = info.color_type == ColorType::Indexed;
    decoder.set_transformations(if indexed {
        Transformations::IDENTITY
    } else {
        Transformations::EXPAND
    });
    let mut reader = decoder.read_info()?;
    let mut buffer = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let frame = reader.next_frame(&mut buffer)?;
    let bits: u32 = match frame.bit_depth {
        BitDepth::One => 1,
        BitDepth::Two => 2,
        BitDepth::Four => 4,
        BitDepth::Eight => 8,
        BitDepth::Sixteen => 16,
    };
    let channels = frame.color_type.samples();
    let mut values = Vec::with_capacity(columns * rows);
    for line in buffer.chunks_exact(frame.line_size).take(rows) {
        let sample =
            |column: usize, channel: usize| packed_sample(line, column * channels + channel, bits);
        for column in 0..columns {
            let height = match frame.color_type {
                ColorType::Indexed => sample(column, 0) * 256,
                ColorType::Grayscale | ColorType::GrayscaleAlpha => {
                    full_range(sample(column, 0), bits)
                }
                ColorType::Rgb | ColorType::Rgba => {
                    let [r, g, b] = [0, 1, 2].map(|c| sample(column, c));
                    colour_height(r, g, b, bits)
                }
            };
            values.push(height as f32 / 65535.0);
        }
    }
    Ok(Heights { columns, rows, values })
}

/// Sample `index` of a PNG scan line of `bits`-deep samples (1, 2 and 4 bits packed from the
/// high bits of each byte, 16 bits big-endian).
pub fn packed_sample(line: &[u8], index: usize, bits: u32) -> u32 {
    let bit = index * bits as usize;
    match bits {
        16 => u32::from(u16::from_be_bytes([line[bit / 8], line[bit / 8 + 1]])),
        8 => u32::from(line[bit / 8]),
        _ => u32::from(line[bit / 8] >> (8 - bits as usize - bit % 8)) & ((1 << bits) - 1),
    }
}

fn from_jpeg(bytes: &[u8]) -> Result<Heights, HeightsProblem> {
    let reader = || image::ImageReader::with_format(Cursor::new(bytes), image::ImageFormat::Jpeg);
    let (columns, rows) = reader().into_dimensions()?;
    check_size(columns as usize, rows as usize)?;
    let decoded = reader().decode()?;
    let values: Vec<f32> = match decoded {
        image::DynamicImage::ImageLuma8(gray) => {
            gray.pixels().map(|p| full_range(u32::from(p.0[0]), 8) as f32 / 65535.0).collect()
        }
        other => other
            .to_rgb8()
            .pixels()
            .map(|p| {
                let [r, g, b] = p.0.map(u32::from);
                colour_height(r, g, b, 8) as f32 / 65535.0
            })
            .collect(),
    };
    Ok(Heights { columns: columns as usize, rows: rows as usize, values })
}

/// A gray sample of `bits` over 0 to 65535 (POV-Ray's gray value × 65535: 8-bit v is v × 257).
pub(super) fn full_range(value: u32, bits: u32) -> u32 {
    value * 65535 / ((1u32 << bits) - 1)
}

/// A colour pixel's height: 8-bit red and green as the high and low bytes; deeper pixels by
/// their gray.
pub(super) fn colour_height(r: u32, g: u32, b: u32, bits: u32) -> u32 {
    if bits <= 8 {
        return r * 256 + g;
    }
    let max = ((1u32 << bits) - 1) as f32;
    let gray = 0.297 * r as f32 / max + 0.589 * g as f32 / max + 0.114 * b as f32 / max;
    (gray.clamp(0.0, 1.0) * 65535.0) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode(width: u32, height: u32, colour: ColorType, depth: BitDepth, data: &[u8]) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(colour);
        encoder.set_depth(depth);
        if colour == ColorType::Indexed {
            encoder.set_palette(vec![0u8; 3 * 16]);
        }
        encoder.write_header().unwrap().write_image_data(data).unwrap();
        bytes
    }

    #[test]
    fn each_kind_of_png_gives_povray_s_heights() {
        // Gray 8-bit: the full range (255 is 1).
        let gray =
            from_png(&encode(2, 2, ColorType::Grayscale, BitDepth::Eight, &[0, 51, 255, 128]))
                .unwrap();
        assert_eq!(gray.values, vec![0.0, 0.2, 1.0, 128.0 * 257.0 / 65535.0]);
        // A 4-bit palette: the index × 256, packed two to a byte.
        let indexed =
            from_png(&encode(2, 2, ColorType::Indexed, BitDepth::Four, &[0x0f, 0x31])).unwrap();
        let expected: Vec<f32> =
            [0u32, 15, 3, 1].iter().map(|i| (i * 256) as f32 / 65535.0).collect();
        assert_eq!(indexed.values, expected);
        // 8-bit colour: red high, green low, blue ignored.
        let rgb = from_png(&encode(
            2,
            2,
            ColorType::Rgb,
            BitDepth::Eight,
            &[1, 2, 99, 0, 0, 0, 255, 255, 0, 0, 7, 0],
        ))
        .unwrap();
        assert_eq!(rgb.values, [258u32, 0, 65535, 7].map(|h| h as f32 / 65535.0).to_vec());
        // 16-bit gray: the value itself.
        let deep = from_png(&encode(
            2,
            2,
            ColorType::Grayscale,
            BitDepth::Sixteen,
            &[0x12, 0x34, 0, 0, 0xff, 0xff, 0, 1],
        ))
        .unwrap();
        assert_eq!(deep.values, [0x1234u32, 0, 65535, 1].map(|h| h as f32 / 65535.0).to_vec());
    }

    #[test]
    fn a_grid_too_small_or_too_large_is_refused_before_decoding() {
        let line = encode(3, 1, ColorType::Grayscale, BitDepth::Eight, &[1, 2, 3]);
        assert!(matches!(from_png(&line), Err(HeightsProblem::Size { columns: 3, rows: 1 })));
        assert!(check_size(4096, 4096).is_err());
        assert!(check_size(usize::MAX, 2).is_err());
        assert!(check_size(2048, 2048).is_ok());
    }
}
