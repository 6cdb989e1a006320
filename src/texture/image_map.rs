//! `image_map`: a PNG or JPEG decoded from sRGB to linear, projected onto the x-y unit square
//! (repeating).

use std::path::{Path, PathBuf};

use glam::Vec3;

#[derive(Debug)]
pub struct ImageMap {
    width: usize,
    height: usize,
    /// Linear RGB, rows top to bottom.
    texels: Vec<Vec3>,
}

/// The most texels one image may have (8192 × 8192): decoded, each takes 12 bytes.
pub const MAX_TEXELS: u64 = 1 << 26;

/// An image file that cannot be an `image_map`.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct ImageMapError {
    pub path: PathBuf,
    pub problem: Unreadable,
}

/// Why an image file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum Unreadable {
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    #[error(transparent)]
    Format(#[from] std::io::Error),
    #[error(transparent)]
    Decode(#[from] image::ImageError),
    #[error("{width} x {height} texels, more than raydiance reads in one image ({MAX_TEXELS})")]
    TooLarge { width: u32, height: u32 },
}

impl ImageMap {
    pub fn load(path: &Path) -> Result<ImageMap, ImageMapError> {
        ImageMap::decode(path)
            .map_err(|problem| ImageMapError { path: path.to_path_buf(), problem })
    }

    fn decode(path: &Path) -> Result<ImageMap, Unreadable> {
        let bytes = crate::input::read(path, crate::input::MAX_IMAGE_BYTES)?;
        let reader = || image::ImageReader::new(std::io::Cursor::new(&bytes)).with_guessed_format();
        // The header's size is checked before anything is decoded: a small file can declare a
        // huge image.
        let (width, height) = reader()?.into_dimensions()?;
        if u64::from(width) * u64::from(height) > MAX_TEXELS {
            return Err(Unreadable::TooLarge { width, height });
        }
        let decoded = reader()?.decode()?.to_rgb8();
        let (width, height) = (decoded.width() as usize, decoded.height() as usize);
        let texels = decoded.pixels().map(|p| Vec3::from(p.0.map(srgb_to_linear))).collect();
        Ok(ImageMap { width, height, texels })
    }

    /// The colour at (u, v) of the unit square, v = 0 at the image's bottom row (POV-Ray's
    /// planar map), repeating outside it; the nearest texel (POV-Ray's default, no
    /// interpolation).
    pub fn lookup(&self, u: f32, v: f32) -> Vec3 {
        let x = ((u.rem_euclid(1.0) * self.width as f32) as usize).min(self.width - 1);
        let y = (((1.0 - v.rem_euclid(1.0)) * self.height as f32) as usize).min(self.height - 1);
        self.texels[y * self.width + x]
    }
}

/// The sRGB transfer function inverted (IEC 61966-2-1).
fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}
