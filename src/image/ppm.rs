//! PPM with the course's `#MAX=` comment: the real value the largest stored integer stands for.
//! Written as P3; read as P3 or P6 (1 or 2 bytes per sample), with or without `#MAX`.

use std::io::Write;
use std::path::Path;

use glam::Vec3;

use super::{Image, ImageError, MAX_PIXELS, write_atomic};
use crate::diagnostic::printable;

/// The integer that MAX stands for in HDR files written by `render` (the course's images).
pub const HDR_RES: u32 = 10_000_000;

/// Writes linear values: stored = round(clamp(real / MAX, 0, 1) * res), MAX the largest component.
pub fn write_hdr(path: &Path, image: &Image, res: u32) -> Result<(), ImageError> {
    let max = image.max_component();
    // An all-black image has MAX 0; its samples are all 0 and decode to 0.
    let scale = if max > 0.0 { f64::from(res) / f64::from(max) } else { 0.0 };
    let quantise = |c: f32| (f64::from(c.max(0.0)) * scale).round().min(f64::from(res)) as u32;
    write(
        path,
        image.width,
        image.height,
        max,
        res,
        image.pixels.iter().map(|p| p.to_array().map(quantise)),
    )
}

/// Writes tone-mapped 8-bit values: `#MAX=1`, res 255.
pub fn write_ldr(
    path: &Path,
    width: usize,
    height: usize,
    pixels: &[[u8; 3]],
) -> Result<(), ImageError> {
    write(path, width, height, 1.0, 255, pixels.iter().map(|p| p.map(u32::from)))
}

fn write(
    path: &Path,
    width: usize,
    height: usize,
    max: f32,
    res: u32,
    samples: impl Iterator<Item = [u32; 3]>,
) -> Result<(), ImageError> {
    // The name goes into a comment line: a line break in it would end the comment, and what
    // followed would be read as the header (`#MAX=` included).
    let name =
        path.file_name().map_or(String::new(), |n| n.to_string_lossy().escape_debug().to_string());
    write_atomic(path, |w| {
        let io = |e| ImageError::io(path, e);
        write!(w, "P3\n#MAX={max}\n# {name}\n{width} {height}\n{res}\n").map_err(io)?;
        for (i, [r, g, b]) in samples.enumerate() {
            let end = if (i + 1) % width.max(1) == 0 { "\n" } else { "  " };
            write!(w, "{r} {g} {b}{end}").map_err(io)?;
        }
        Ok(())
    })
}

/// How much of a file `check_size` reads: a header with a `#MAX` comment fits many times over.
pub const HEADER_BYTES: u64 = 4096;

/// The header: P3 or P6, width, height and the largest stored integer (`res`).
struct Header {
    binary: bool,
    width: u64,
    height: u64,
    res: u64,
}

impl Header {
    fn read(reader: &mut Reader) -> Result<Header, PpmError> {
        let magic = reader.token()?.ok_or(PpmError::Empty)?;
        let binary = match magic.text {
            "P3" => false,
            "P6" => true,
            _ => {
                let (place, found) = (reader.place(magic.at), printable(magic.text));
                return Err(PpmError::Magic { place, found });
            }
        };
        let width = reader.number("the width", 1, u32::MAX.into())?;
        let height = reader.number("the height", 1, u32::MAX.into())?;
        // The course's HDR files use res 10000000; binary samples hold at most 16 bits.
        let res =
            reader.number("the maximum value", 1, if binary { 65535 } else { u32::MAX.into() })?;
        Ok(Header { binary, width, height, res })
    }

    fn check_size(&self) -> Result<(), PpmError> {
        let Header { width, height, .. } = *self;
        if width.saturating_mul(height) > MAX_PIXELS as u64 {
            return Err(PpmError::TooLarge { width, height });
        }
        Ok(())
    }
}

/// Refuses, from the start of a file, an image larger than raydiance reads. A header cut off
/// by the end of `start` passes (a number cut short only reads smaller): `parse` decides.
pub fn check_size(start: &[u8]) -> Result<(), PpmError> {
    let mut reader = Reader { bytes: start, at: 0, max: None };
    Header::read(&mut reader).map_or(Ok(()), |header| header.check_size())
}

/// Decodes a PPM: real value = stored * MAX / res (MAX = 1 without `#MAX`). Errors say where.
pub fn parse(bytes: &[u8]) -> Result<Image, PpmError> {
    let mut reader = Reader { bytes, at: 0, max: None };
    let header = Header::read(&mut reader)?;
    header.check_size()?;
    let Header { binary, width, height, res } = header;
    let count = width * height * 3;
    let mut samples = Vec::with_capacity((count as usize).min(bytes.len()));
    if binary {
        // Exactly one whitespace byte separates the header from the data.
        let start = reader.at + 1;
        let size = if res < 256 { 1 } else { 2 };
        let data = bytes.get(start..).unwrap_or(&[]);
        if (data.len() as u64) < count * size {
            let (read, at) = (data.len() as u64 / size, bytes.len());
            return Err(PpmError::DataEnds { read, count, at });
        }
        for (i, chunk) in data.chunks_exact(size as usize).take(count as usize).enumerate() {
            let value = if size == 1 {
                u64::from(chunk[0])
            } else {
                u64::from(u16::from_be_bytes([chunk[0], chunk[1]]))
            };
            if value > res {
                return Err(PpmError::ByteAbove { at: start + i * size as usize, value, res });
            }
            samples.push(value);
        }
    } else {
        for i in 0..count {
            let token = reader.token()?.ok_or_else(|| PpmError::TextEnds {
                place: reader.place(bytes.len()),
                read: i,
                count,
            })?;
            let value: u64 = token.text.parse().map_err(|_| PpmError::NotASample {
                place: reader.place(token.at),
                found: printable(token.text),
            })?;
            if value > res {
                return Err(PpmError::Above { place: reader.place(token.at), value, res });
            }
            samples.push(value);
        }
    }
    let max = f64::from(reader.max.unwrap_or(1.0));
    let scale = max / res as f64;
    let pixels = samples
        .chunks_exact(3)
        .map(|s| {
            Vec3::new(
                (s[0] as f64 * scale) as f32,
                (s[1] as f64 * scale) as f32,
                (s[2] as f64 * scale) as f32,
            )
        })
        .collect();
    Ok(Image { width: width as usize, height: height as usize, pixels })
}

struct Token<'a> {
    text: &'a str,
    /// The offset of its first byte (`Reader::place` turns it into a line and column, only
    /// for an error: counting lines for every token would make reading quadratic).
    at: usize,
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    /// The value of a `#MAX=` comment met so far.
    max: Option<f32>,
}

impl<'a> Reader<'a> {
    /// The next whitespace-separated token, skipping comments (and reading `#MAX=` ones).
    fn token(&mut self) -> Result<Option<Token<'a>>, PpmError> {
        loop {
            while self.bytes.get(self.at).is_some_and(u8::is_ascii_whitespace) {
                self.at += 1;
            }
            match self.bytes.get(self.at) {
                None => return Ok(None),
                Some(b'#') => {
                    let start = self.at;
                    let end = self.bytes[start..]
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(self.bytes.len(), |e| start + e);
                    let comment = String::from_utf8_lossy(&self.bytes[start..end]);
                    if let Some(value) = comment.trim_end().strip_prefix("#MAX=") {
                        // The line is file text: quoted clipped, its control characters escaped.
                        let quoted = printable(value);
                        let max: f32 =
                            value.trim().parse().map_err(|_| PpmError::MaxNotANumber {
                                place: self.place(start),
                                quoted: quoted.clone(),
                            })?;
                        if !(max.is_finite() && max >= 0.0) {
                            return Err(PpmError::MaxOutOfRange {
                                place: self.place(start),
                                quoted,
                            });
                        }
                        self.max = Some(max);
                    }
                    self.at = end;
                }
                Some(_) => {
                    let start = self.at;
                    while self
                        .bytes
                        .get(self.at)
                        .is_some_and(|b| !b.is_ascii_whitespace() && *b != b'#')
                    {
                        self.at += 1;
                    }
                    let text =
                        std::str::from_utf8(&self.bytes[start..self.at]).unwrap_or("<not text>");
                    return Ok(Some(Token { text, at: start }));
                }
            }
        }
    }

    fn number(&mut self, what: &'static str, min: u64, max: u64) -> Result<u64, PpmError> {
        let token = self
            .token()?
            .ok_or_else(|| PpmError::HeaderEnds { place: self.place(self.bytes.len()), what })?;
        match token.text.parse::<u64>() {
            Ok(n) if (min..=max).contains(&n) => Ok(n),
            _ => Err(PpmError::Number {
                place: self.place(token.at),
                what,
                min,
                max,
                found: printable(token.text),
            }),
        }
    }

    fn place(&self, offset: usize) -> Place {
        let before = &self.bytes[..offset];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let column = offset - before.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1) + 1;
        Place { line, column }
    }
}

/// Where in a PPM file's text: its line and column, from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Place {
    pub line: usize,
    pub column: usize,
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}, column {}", self.line, self.column)
    }
}

/// Why a PPM file cannot be read; where in it, when that is in its text. Values quoted from
/// the file are `printable`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PpmError {
    #[error("the file is empty")]
    Empty,
    #[error("{place}: expected `P3` or `P6`, found `{found}`")]
    Magic { place: Place, found: String },
    #[error("{place}: the header ends before {what}")]
    HeaderEnds { place: Place, what: &'static str },
    #[error("{place}: expected {what} (a whole number from {min} to {max}), found `{found}`")]
    Number { place: Place, what: &'static str, min: u64, max: u64, found: String },
    #[error("the image is {width} x {height} pixels, more than raydiance reads ({MAX_PIXELS})")]
    TooLarge { width: u64, height: u64 },
    #[error("{place}: `#MAX={quoted}` is not a number")]
    MaxNotANumber { place: Place, quoted: String },
    #[error("{place}: `#MAX={quoted}` must be a finite number >= 0")]
    MaxOutOfRange { place: Place, quoted: String },
    /// Binary (P6) data cut short.
    #[error("the pixel data ends after {read} of {count} samples (at byte {at})")]
    DataEnds { read: u64, count: u64, at: usize },
    #[error("byte {at}: sample {value} is above the maximum value {res}")]
    ByteAbove { at: usize, value: u64, res: u64 },
    /// Text (P3) data cut short.
    #[error("{place}: the pixel data ends after {read} of {count} samples")]
    TextEnds { place: Place, read: u64, count: u64 },
    #[error("{place}: expected a sample value, found `{found}`")]
    NotASample { place: Place, found: String },
    #[error("{place}: sample {value} is above the maximum value {res}")]
    Above { place: Place, value: u64, res: u64 },
}

#[cfg(test)]
mod tests {
    use super::*;

    const TINY: &str = "P3\n#MAX=4.5\n# tiny.ppm\n2 1\n255\n255 0 0     51 51 51\n";

    #[test]
    fn the_spec_example_decodes() {
        let image = parse(TINY.as_bytes()).unwrap();
        assert_eq!((image.width, image.height), (2, 1));
        assert!((image.pixels[0] - Vec3::new(4.5, 0.0, 0.0)).abs().max_element() < 1e-6);
        assert!((image.pixels[1] - Vec3::splat(0.9)).abs().max_element() < 1e-6);
    }

    #[test]
    fn header_variants_read_the_same() {
        let reference = parse(TINY.as_bytes()).unwrap();
        for text in [
            "P3\n# tiny.ppm\n2 1\n#MAX=4.5\n255\n255 0 0 51 51 51\n",
            "P3\r\n#MAX=4.5\r\n2 # width\r\n1\r\n255\r\n255 0 0\r\n51 51 51\r\n",
            "P3 2 1 255 #MAX=4.5\n255 0 0 51 51 51",
        ] {
            assert_eq!(parse(text.as_bytes()).unwrap(), reference, "{text:?}");
        }
        let no_max = parse(b"P3 1 1 255 255 51 0").unwrap();
        assert!((no_max.pixels[0] - Vec3::new(1.0, 0.2, 0.0)).abs().max_element() < 1e-6);
    }

    #[test]
    fn binary_ppm_with_one_and_two_bytes_per_sample() {
        let mut one = b"P6\n#MAX=4.5\n2 1\n255\n".to_vec();
        one.extend([255, 0, 0, 51, 51, 51]);
        assert_eq!(parse(&one).unwrap(), parse(TINY.as_bytes()).unwrap());
        let mut two = b"P6 1 1 65535\n".to_vec();
        two.extend([0xff, 0xff, 0x80, 0x00, 0x00, 0x00]);
        let image = parse(&two).unwrap();
        assert!(
            (image.pixels[0] - Vec3::new(1.0, 32768.0 / 65535.0, 0.0)).abs().max_element() < 1e-6
        );
    }
}
