//! Netpbm (PGM and PPM, plain and raw) and Targa files decoded into a height field's heights as
//! POV-Ray 3.7 reads them (`base/image/ppm.cpp`, `targa.cpp`): Netpbm samples scaled from the
//! file's largest value to 8 bits (to 16 above 255), a gray image over its full range, an 8-bit
//! colour image red as the high byte and green as the low one, a 16-bit colour image by its gray,
//! a Targa palette image by its index × 256 (`heights`). Every size is checked against
//! `check_size` before a pixel is read; a file that ends early or holds other data is an error.

use super::heights::{HeightsProblem, check_size, colour_height, full_range};

/// Why a Netpbm or Targa file gives no heights.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ImageDataError {
    #[error("not a PGM or PPM file (P2, P3, P5 or P6)")]
    NotNetpbm,
    #[error("a number of the Netpbm file is missing or not a whole number")]
    BadNumber,
    #[error("a Netpbm file's largest value is {0}: it must be 1 to 65535")]
    BadMaximum(u32),
    #[error("the file ends before its last pixel")]
    Truncated,
    #[error("a Targa image of type {0}: raydiance reads types 1, 2, 3, 9, 10 and 11")]
    TargaType(u8),
    #[error("a Targa image of {0} bits per pixel for its type")]
    TargaDepth(u8),
}

/// The heights of a PGM or PPM file.
pub fn from_netpbm(bytes: &[u8]) -> Result<(usize, usize, Vec<f32>), HeightsProblem> {
    let mut reader = Reader { bytes, at: 0 };
    let (gray, plain) = match bytes.get(..2) {
        Some(b"P2") => (true, true),
        Some(b"P3") => (false, true),
        Some(b"P5") => (true, false),
        Some(b"P6") => (false, false),
        _ => return Err(ImageDataError::NotNetpbm.into()),
    };
    reader.at = 2;
    let columns = reader.header_number()? as usize;
    let rows = reader.header_number()? as usize;
    check_size(columns, rows)?;
    let maximum = reader.header_number()?;
    if !(1..=65535).contains(&maximum) {
        return Err(ImageDataError::BadMaximum(maximum).into());
    }
    // One whitespace byte ends a raw file's header.
    reader.at += 1;
    let (deep, bits) = if maximum > 255 { (true, 16) } else { (false, 8) };
    let top = (1u32 << bits) - 1;
    let mut sample = || -> Result<u32, ImageDataError> {
        let value = if plain {
            reader.plain_number()?
        } else if deep {
            u32::from(u16::from_be_bytes([reader.byte()?, reader.byte()?]))
        } else {
            u32::from(reader.byte()?)
        };
        // Scaled to the stored range as POV-Ray's reader scales it (values above the maximum
        // are the file's error: clamped).
        Ok((value.min(maximum) * top + maximum / 2) / maximum)
    };
    let mut values = Vec::with_capacity(columns * rows);
    for _ in 0..columns * rows {
        let height = if gray {
            full_range(sample()?, bits)
        } else {
            let (r, g, b) = (sample()?, sample()?, sample()?);
            colour_height(r, g, b, bits)
        };
        values.push(height as f32 / 65535.0);
    }
    Ok((columns, rows, values))
}

/// The heights of a Targa file, rows from the image's top.
pub fn from_tga(bytes: &[u8]) -> Result<(usize, usize, Vec<f32>), HeightsProblem> {
    let header = bytes.get(..18).ok_or(ImageDataError::Truncated)?;
    let (id_length, map_type, kind) = (header[0], header[1], header[2]);
    let map_length = usize::from(u16::from_le_bytes([header[5], header[6]]));
    let map_depth = header[7];
    let columns = usize::from(u16::from_le_bytes([header[12], header[13]]));
    let rows = usize::from(u16::from_le_bytes([header[14], header[15]]));
    let (depth, descriptor) = (header[16], header[17]);
    check_size(columns, rows)?;
    let (base, compressed) = match kind {
        1..=3 => (kind, false),
        9..=11 => (kind - 8, true),
        other => return Err(ImageDataError::TargaType(other).into()),
    };
    let valid_depth = match base {
        1 => depth == 8,
        2 => matches!(depth, 15 | 16 | 24 | 32),
        _ => depth == 8,
    };
    if !valid_depth {
        return Err(ImageDataError::TargaDepth(depth).into());
    }
    // The colour map (a palette image's heights are its indices) is skipped.
    let map_bytes = if map_type == 1 { map_length * usize::from(map_depth).div_ceil(8) } else { 0 };
    let mut reader = Reader { bytes, at: 18 + usize::from(id_length) + map_bytes };
    let size = usize::from(depth).div_ceil(8);
    let height_of = |pixel: &[u8]| -> u32 {
        match (base, size) {
            (1, _) => u32::from(pixel[0]) * 256,
            (3, _) => full_range(u32::from(pixel[0]), 8),
            // 5-5-5 bits, blue lowest: each widened to 8 bits.
            (_, 2) => {
                let v = u32::from(u16::from_le_bytes([pixel[0], pixel[1]]));
                let widen = |c: u32| (c << 3) | (c >> 2);
                colour_height(widen((v >> 10) & 31), widen((v >> 5) & 31), widen(v & 31), 8)
            }
            // Blue, green, red (and alpha).
            _ => colour_height(u32::from(pixel[2]), u32::from(pixel[1]), u32::from(pixel[0]), 8),
        }
    };
    let mut pixels: Vec<u32> = Vec::with_capacity(columns * rows);
    while pixels.len() < columns * rows {
        let (count, repeated) = if compressed {
            let packet = reader.byte()?;
            (usize::from(packet & 0x7f) + 1, packet & 0x80 != 0)
        } else {
            (columns * rows, false)
        };
        let count = count.min(columns * rows - pixels.len());
        if repeated {
            let height = height_of(reader.take(size)?);
            pixels.extend(std::iter::repeat_n(height, count));
        } else {
            for _ in 0..count {
                pixels.push(height_of(reader.take(size)?));
            }
        }
    }
    // Rows are stored from the bottom unless the descriptor's bit 5 says from the top; columns
    // from the left unless its bit 4 says from the right.
    let (from_top, from_right) = (descriptor & 0x20 != 0, descriptor & 0x10 != 0);
    let mut values = Vec::with_capacity(columns * rows);
    for row in 0..rows {
        let stored_row = if from_top { row } else { rows - 1 - row };
        for column in 0..columns {
            let stored_column = if from_right { columns - 1 - column } else { column };
            values.push(pixels[stored_row * columns + stored_column] as f32 / 65535.0);
        }
    }
    Ok((columns, rows, values))
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn byte(&mut self) -> Result<u8, ImageDataError> {
        let byte = *self.bytes.get(self.at).ok_or(ImageDataError::Truncated)?;
        self.at += 1;
        Ok(byte)
    }

    fn take(&mut self, n: usize) -> Result<&[u8], ImageDataError> {
        let slice = self.bytes.get(self.at..self.at + n).ok_or(ImageDataError::Truncated)?;
        self.at += n;
        Ok(slice)
    }

    /// A header's number, past whitespace and `#` comments.
    fn header_number(&mut self) -> Result<u32, ImageDataError> {
        loop {
            match self.bytes.get(self.at) {
                Some(b'#') => {
                    while self.bytes.get(self.at).is_some_and(|&b| b != b'\n') {
                        self.at += 1;
                    }
                }
                Some(b) if b.is_ascii_whitespace() => self.at += 1,
                _ => break,
            }
        }
        self.plain_number()
    }

    /// A whole number in decimal digits, past whitespace, ending at whitespace or the file's end.
    fn plain_number(&mut self) -> Result<u32, ImageDataError> {
        while self.bytes.get(self.at).is_some_and(|b| b.is_ascii_whitespace()) {
            self.at += 1;
        }
        let start = self.at;
        let mut value: u32 = 0;
        while let Some(&b) = self.bytes.get(self.at).filter(|b| b.is_ascii_digit()) {
            value = value
                .checked_mul(10)
                .and_then(|v| v.checked_add(u32::from(b - b'0')))
                .ok_or(ImageDataError::BadNumber)?;
            self.at += 1;
        }
        if self.at == start {
            let ended = start >= self.bytes.len();
            return Err(if ended { ImageDataError::Truncated } else { ImageDataError::BadNumber });
        }
        if self.bytes.get(self.at).is_some_and(|b| !b.is_ascii_whitespace()) {
            return Err(ImageDataError::BadNumber);
        }
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn heights(values: &[u32]) -> Vec<f32> {
        values.iter().map(|&h| h as f32 / 65535.0).collect()
    }

    #[test]
    fn netpbm_files_give_povray_s_heights() {
        // Plain gray, largest value 15: scaled to 8 bits, then over the full range.
        let (c, r, values) = from_netpbm(b"P2\n# a comment\n2 2\n15\n0 15\n5 10\n").unwrap();
        assert_eq!((c, r), (2, 2));
        assert_eq!(values, heights(&[0, 65535, 85 * 257, 170 * 257]));
        // Raw colour, 8 bits: red high, green low.
        let mut raw = b"P6 2 2 255\n".to_vec();
        raw.extend([1, 2, 99, 0, 0, 0, 255, 255, 0, 0, 7, 0]);
        assert_eq!(from_netpbm(&raw).unwrap().2, heights(&[258, 0, 65535, 7]));
        // Raw gray, 16 bits: the value itself.
        let mut deep = b"P5 2 2 65535\n".to_vec();
        deep.extend([0x12, 0x34, 0, 0, 0xff, 0xff, 0, 1]);
        assert_eq!(from_netpbm(&deep).unwrap().2, heights(&[0x1234, 0, 65535, 1]));
    }

    #[test]
    fn targa_files_give_povray_s_heights_top_row_first() {
        let header = |kind: u8, depth: u8, descriptor: u8, map: bool| {
            let mut h = vec![0u8; 18];
            h[1] = u8::from(map);
            h[2] = kind;
            if map {
                h[5] = 2; // two palette entries of 24 bits
                h[7] = 24;
            }
            h[12] = 2;
            h[14] = 2;
            h[16] = depth;
            h[17] = descriptor;
            h
        };
        // Gray, stored bottom row first: the top row is the file's second.
        let mut gray = header(3, 8, 0, false);
        gray.extend([0, 255, 51, 1]);
        assert_eq!(from_tga(&gray).unwrap().2, heights(&[51 * 257, 257, 0, 65535]));
        // Palette indices × 256, top row first, after the palette.
        let mut palette = header(1, 8, 0x20, true);
        palette.extend([9; 6]);
        palette.extend([0, 1, 1, 0]);
        assert_eq!(from_tga(&palette).unwrap().2, heights(&[0, 256, 256, 0]));
        // Run-length colour (blue, green, red): one run of 3, then one raw pixel.
        let mut rle = header(10, 24, 0x20, false);
        rle.extend([0x82, 0, 2, 1, 0x00, 0, 0, 7]);
        assert_eq!(from_tga(&rle).unwrap().2, heights(&[258, 258, 258, 7 * 256]));
    }

    #[test]
    fn bad_files_are_errors_not_panics() {
        let error = |bytes: &[u8], netpbm: bool| {
            let result = if netpbm { from_netpbm(bytes) } else { from_tga(bytes) };
            result.err().map(|e| e.to_string()).unwrap_or_default()
        };
        assert!(error(b"P4 2 2 1\n", true).contains("not a PGM or PPM"));
        assert!(error(b"P5 2 2 0\n", true).contains("largest value is 0"));
        assert!(error(b"P5 2 2 255\n\x01\x02", true).contains("ends before"));
        assert!(error(b"P2 2 2 255\n1 2 x 4", true).contains("not a whole number"));
        assert!(error(b"P5 99999 99999 255\n", true).contains("pixels"));
        assert!(error(&[0u8; 10], false).contains("ends before"));
        let mut tga = vec![0u8; 18];
        tga[2] = 32;
        tga[12] = 2;
        tga[14] = 2;
        assert!(error(&tga, false).contains("type 32"));
    }
}
