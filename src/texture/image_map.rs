//! `image_map`: a PNG or JPEG, its values decoded to linear (sRGB or a power), projected onto
//! the x-y unit square (repeating, or once), a sphere, a cylinder or a torus, nearest or
//! bilinear.

use std::f32::consts::{PI, TAU};
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3, Vec4};

use crate::graph::{ImageChannel, ImageLook, ImageProjection};
use crate::mesh::heights::packed_sample;

#[derive(Debug)]
pub struct ImageMap {
    width: usize,
    height: usize,
    /// The file's 8-bit values, RGBA, rows top to bottom; decoded to linear as they are read
    /// (the curve is the `image_map`'s).
    texels: Vec<[u8; 4]>,
    /// A palette PNG's index of each texel, in the same order (a bump_map's `use_index`).
    indices: Option<Vec<u8>>,
}

/// The most texels one image may have (8192 × 8192).
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
    #[error(transparent)]
    Palette(#[from] png::DecodingError),
    #[error("{width} x {height} texels, more than raydiance reads in one image ({MAX_TEXELS})")]
    TooLarge { width: u32, height: u32 },
}

impl ImageMap {
    pub fn load(path: &Path) -> Result<ImageMap, ImageMapError> {
        ImageMap::decode(path)
            .map_err(|problem| ImageMapError { path: path.to_path_buf(), problem })
    }

    /// Whether the file has an alpha channel, from its header alone.
    pub fn has_alpha(path: &Path) -> Result<bool, ImageMapError> {
        let header = || -> Result<bool, Unreadable> {
            let bytes = crate::input::read(path, crate::input::MAX_IMAGE_BYTES)?;
            let decoder = image::ImageReader::new(std::io::Cursor::new(&bytes))
                .with_guessed_format()?
                .into_decoder()?;
            Ok(image::ImageDecoder::color_type(&decoder).has_alpha())
        };
        header().map_err(|problem| ImageMapError { path: path.to_path_buf(), problem })
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
        let decoded = reader()?.decode()?.to_rgba8();
        let (width, height) = (decoded.width() as usize, decoded.height() as usize);
        let texels = decoded.pixels().map(|p| p.0).collect();
        let indices = match reader()?.format() {
            Some(image::ImageFormat::Png) => palette_indices(&bytes)?,
            _ => None,
        };
        Ok(ImageMap { width, height, texels, indices })
    }

    /// The width of one texel in (u, v), along u and along v.
    pub fn texel(&self) -> (f32, f32) {
        (1.0 / self.width as f32, 1.0 / self.height as f32)
    }

    /// The image's part `look.channel` at `p`, a point of the pattern's space, projected as
    /// `look` says; `curve` decodes the file's values to linear.
    pub fn sample(&self, p: Vec3, look: &ImageLook, curve: &Curve) -> Vec3 {
        let (u, v) = project(p, look.projection);
        let outside = !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v);
        if look.once && outside {
            return match look.channel {
                ImageChannel::Colour | ImageChannel::Filter(_) | ImageChannel::Index => Vec3::ZERO,
                ImageChannel::Through(_) => Vec3::ONE,
            };
        }
        let texel = |x: isize, y: isize| -> Vec4 {
            // Texel (x, y) counts from the bottom row; outside the image it repeats, or with
            // `once` the edge texel stands.
            let (w, h) = (self.width as isize, self.height as isize);
            let (x, y) = if look.once {
                (x.clamp(0, w - 1), y.clamp(0, h - 1))
            } else {
                (x.rem_euclid(w), y.rem_euclid(h))
            };
            let i = (h - 1 - y) as usize * self.width + x as usize;
            if let (ImageChannel::Index, Some(indices)) = (look.channel, &self.indices) {
                return Vec4::splat(f32::from(indices[i]));
            }
            let [r, g, b, a] = self.texels[i];
            Vec4::new(curve.0[r as usize], curve.0[g as usize], curve.0[b as usize], a as f32)
                / Vec4::new(1.0, 1.0, 1.0, 255.0)
        };
        let (x, y) = (u * self.width as f32, v * self.height as f32);
        let value = if look.bilinear {
            // Between the four texel centres around the point.
            let (x, y) = (x - 0.5, y - 0.5);
            let (x0, y0) = (x.floor(), y.floor());
            let (sx, sy) = (x - x0, y - y0);
            let (i, j) = (x0 as isize, y0 as isize);
            let bottom = texel(i, j).lerp(texel(i + 1, j), sx);
            let top = texel(i, j + 1).lerp(texel(i + 1, j + 1), sx);
            bottom.lerp(top, sy)
        } else {
            let (i, j) = (x.floor() as isize, y.floor() as isize);
            texel(i, j)
        };
        match look.channel {
            // An image without a palette gives its colours for its indices, as POV-Ray's.
            ImageChannel::Colour | ImageChannel::Index => value.truncate(),
            ImageChannel::Filter(f) => Vec3::splat(f),
            ImageChannel::Through(t) => Vec3::splat((t + 1.0 - value.w).min(1.0)),
        }
    }
}

/// A palette PNG's index of each texel, rows top to bottom; `None` for other PNGs.
fn palette_indices(bytes: &[u8]) -> Result<Option<Vec<u8>>, Unreadable> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let header = decoder.read_header_info()?;
    if header.color_type != png::ColorType::Indexed {
        return Ok(None);
    }
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info()?;
    let mut buffer = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let frame = reader.next_frame(&mut buffer)?;
    let bits = frame.bit_depth as u32;
    let (width, height) = (frame.width as usize, frame.height as usize);
    let indices = buffer
        .chunks_exact(frame.line_size)
        .take(height)
        .flat_map(|line| (0..width).map(move |x| packed_sample(line, x, bits) as u8))
        .collect();
    Ok(Some(indices))
}

/// The image's (u, v) of a point of the pattern's space (POV-Ray's `map_type`s).
fn project(p: Vec3, projection: ImageProjection) -> (f32, f32) {
    // The longitude around y, from +x towards +z, in [0, 1).
    let longitude = || {
        if p.x * p.x + p.z * p.z > 1e-12 { (p.z.atan2(p.x) / TAU).rem_euclid(1.0) } else { 0.0 }
    };
    match projection {
        ImageProjection::Planar => (p.x, p.y),
        ImageProjection::Spherical => {
            let len = p.length();
            if len == 0.0 {
                return (0.0, 0.5);
            }
            (longitude(), 0.5 + (p.y / len).clamp(-1.0, 1.0).asin() / PI)
        }
        ImageProjection::Cylindrical => (longitude(), p.y),
        ImageProjection::Torus => {
            // Across the tube: from the ring of radius 1 to the point, in the (r, y) plane
            // (POV-Ray's torus_image_map: phi = acos(-r / |q|), 2 pi - phi above the ring).
            let across = Vec2::new((p.x * p.x + p.z * p.z).sqrt() - 1.0, p.y);
            let length = across.length();
            if length == 0.0 {
                return (longitude(), 0.0);
            }
            let phi = (-across.x / length).clamp(-1.0, 1.0).acos();
            (longitude(), if p.y > 0.0 { 1.0 - phi / TAU } else { phi / TAU })
        }
    }
}

/// The file's 8-bit values decoded to linear: the sRGB curve or a power.
#[derive(Debug, Clone)]
pub struct Curve(Box<[f32; 256]>);

impl Curve {
    pub fn new(gamma: Option<f32>) -> Curve {
        Curve(Box::new(std::array::from_fn(|c| match gamma {
            None => srgb_to_linear(c as u8),
            Some(g) => (c as f32 / 255.0).powf(g),
        })))
    }
}

/// The sRGB transfer function inverted (IEC 61966-2-1).
fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two texels side by side: red on the left, blue (half transparent) on the right.
    fn red_blue() -> ImageMap {
        ImageMap {
            width: 2,
            height: 1,
            texels: vec![[255, 0, 0, 255], [0, 0, 255, 128]],
            indices: None,
        }
    }

    fn look(once: bool, bilinear: bool, channel: ImageChannel) -> ImageLook {
        ImageLook { projection: ImageProjection::Planar, once, bilinear, gamma: Some(1.0), channel }
    }

    #[test]
    fn planar_images_repeat_or_stand_once_nearest_or_bilinear() {
        let (image, linear) = (red_blue(), Curve::new(Some(1.0)));
        let at = |x: f32, look: ImageLook| image.sample(Vec3::new(x, 0.5, 7.0), &look, &linear);
        let nearest = look(false, false, ImageChannel::Colour);
        assert_eq!(at(0.25, nearest), Vec3::X);
        assert_eq!(at(0.75, nearest), Vec3::Z);
        assert_eq!(at(1.25, nearest), Vec3::X, "repeats");
        assert_eq!(at(-0.25, nearest), Vec3::Z, "repeats below 0");
        // Bilinear: the texels' own colours at their centres, their mean halfway, and across
        // the repeat's seam the two again.
        let smooth = look(false, true, ImageChannel::Colour);
        assert_eq!(at(0.25, smooth), Vec3::X);
        assert!((at(0.5, smooth) - Vec3::new(0.5, 0.0, 0.5)).length() < 1e-6);
        assert!((at(1.0, smooth) - Vec3::new(0.5, 0.0, 0.5)).length() < 1e-6);
        // Once: black and all light through outside the unit square; inside, the texel's
        // transparency (1 - alpha) added to `filter all` + `transmit all`.
        assert_eq!(at(1.25, look(true, false, ImageChannel::Colour)), Vec3::ZERO);
        assert_eq!(at(1.25, look(true, false, ImageChannel::Through(0.1))), Vec3::ONE);
        assert_eq!(at(1.25, look(true, false, ImageChannel::Filter(0.1))), Vec3::ZERO);
        let opaque = at(0.25, look(true, false, ImageChannel::Through(0.1)));
        assert!((opaque - Vec3::splat(0.1)).length() < 1e-6, "{opaque}");
        let half = at(0.75, look(true, false, ImageChannel::Through(0.1)));
        assert!((half - Vec3::splat(0.1 + 127.0 / 255.0)).length() < 1e-6, "{half}");
        assert_eq!(at(0.75, look(true, false, ImageChannel::Through(0.9))), Vec3::ONE);
    }

    /// POV-Ray's map_type 1, 2 and 5: u the longitude about y from +x towards +z, v the latitude
    /// (sphere), the height (cylinder) or the angle around the torus' tube.
    #[test]
    fn spherical_and_cylindrical_projections_follow_povray_s_definitions() {
        let close = |(u, v): (f32, f32), (eu, ev): (f32, f32)| {
            assert!((u - eu).abs() < 1e-6 && (v - ev).abs() < 1e-6, "({u}, {v}) not ({eu}, {ev})");
        };
        let sphere = |p| project(p, ImageProjection::Spherical);
        close(sphere(Vec3::X * 3.0), (0.0, 0.5));
        close(sphere(Vec3::Z), (0.25, 0.5));
        close(sphere(-Vec3::X), (0.5, 0.5));
        close(sphere(Vec3::new(0.0, 2.0, 0.0)), (0.0, 1.0));
        close(sphere(Vec3::new(1.0, -1.0, 0.0)), (0.0, 0.25));
        let cylinder = |p| project(p, ImageProjection::Cylindrical);
        close(cylinder(Vec3::new(0.0, 0.3, -2.0)), (0.75, 0.3));
        close(project(Vec3::new(0.2, 0.7, 5.0), ImageProjection::Planar), (0.2, 0.7));
        // map_type 5: around the tube of the torus of major radius 1 from its inner equator,
        // under it first.
        let torus = |p| project(p, ImageProjection::Torus);
        close(torus(Vec3::new(0.7, 0.0, 0.0)), (0.0, 0.0));
        close(torus(Vec3::new(0.0, -0.3, 1.0)), (0.25, 0.25));
        close(torus(Vec3::new(-1.2, 0.0, 0.0)), (0.5, 0.5));
        close(torus(Vec3::new(0.0, 0.5, -1.0)), (0.75, 0.75));
        close(torus(Vec3::new(1.0 + 0.5f32.sqrt(), -0.5f32.sqrt(), 0.0)), (0.0, 0.375));
    }

    /// The file's values to linear: the sRGB curve by default, a power with `gamma`.
    #[test]
    fn the_curve_decodes_srgb_or_a_power() {
        let srgb = Curve::new(None);
        assert_eq!((srgb.0[0], srgb.0[255]), (0.0, 1.0));
        assert!((srgb.0[188] - 0.5029).abs() < 1e-3, "{}", srgb.0[188]);
        let power = Curve::new(Some(2.2));
        assert!((power.0[128] - (128.0f32 / 255.0).powf(2.2)).abs() < 1e-6);
    }
}
