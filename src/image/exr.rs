//! OpenEXR: linear RGB, 32-bit float, scanlines top to bottom, with the render's metadata.

use std::path::Path;

use ::exr::prelude::*;
use glam::Vec3;

use super::{Image, ImageError, MAX_PIXELS, RenderInfo, write_atomic};

pub fn write(path: &Path, image: &Image, info: &RenderInfo) -> std::result::Result<(), ImageError> {
    let channels = SpecificChannels::rgb(|position: Vec2<usize>| {
        let p = image.get(position.x(), position.y());
        (p.x, p.y, p.z)
    });
    let mut layer_attributes = LayerAttributes::named("");
    layer_attributes.software_name = Some(Text::from("raydiance"));
    let layer = Layer::new(
        (image.width, image.height),
        layer_attributes,
        Encoding { line_order: LineOrder::Increasing, ..Encoding::SMALL_LOSSLESS },
        channels,
    );
    let mut exr_image = ::exr::image::Image::from_layer(layer);
    let other = &mut exr_image.attributes.other;
    let spp = i32::try_from(info.samples_per_pixel).unwrap_or(i32::MAX);
    other.insert(Text::from("raydiance:samples_per_pixel"), AttributeValue::I32(spp));
    other.insert(
        Text::from("raydiance:integrator"),
        AttributeValue::Text(Text::from(info.integrator.as_str())),
    );
    other.insert(
        Text::from("raydiance:seed"),
        AttributeValue::Text(Text::from(info.seed.to_string().as_str())),
    );
    other.insert(Text::from("raydiance:render_seconds"), AttributeValue::F64(info.seconds));
    for (name, value) in &info.parameters {
        other.insert(
            Text::from(format!("raydiance:{name}").as_str()),
            AttributeValue::Text(Text::from(value.as_str())),
        );
    }
    write_atomic(path, |writer| {
        exr_image.write().to_buffered(writer).map_err(|e| ImageError::format(path, e.to_string()))
    })
}

/// Reads the first RGB(A) layer of any OpenEXR file (alpha is ignored).
pub fn read(path: &Path) -> std::result::Result<Image, ImageError> {
    let bytes = crate::input::read(path, crate::input::MAX_HDR_BYTES)
        .map_err(|e| ImageError::input(path, e))?;
    read_bytes(&bytes).map_err(|message| ImageError::format(path, message))
}

/// Decodes an OpenEXR file's contents.
pub fn read_bytes(bytes: &[u8]) -> std::result::Result<Image, String> {
    // The decoder's words ("reference to missing bytes") need saying what failed.
    let unreadable = |e: ::exr::error::Error| format!("not a readable OpenEXR file ({e})");
    let meta = ::exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(unreadable)?;
    for header in &meta.headers {
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        if width.saturating_mul(height) > MAX_PIXELS {
            return Err(format!(
                "the image is {width} x {height} pixels, more than raydiance reads ({MAX_PIXELS})"
            ));
        }
    }
    let image = ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| Image::new(resolution.width(), resolution.height()),
            |image: &mut Image, position, (r, g, b, _a): (f32, f32, f32, f32)| {
                let width = image.width;
                image.pixels[position.y() * width + position.x()] = Vec3::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(unreadable)?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The samples per pixel recorded in a file raydiance wrote.
pub fn read_samples_per_pixel(path: &Path) -> std::result::Result<Option<i32>, ImageError> {
    let meta = ::exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| ImageError::format(path, e.to_string()))?;
    let key = Text::from("raydiance:samples_per_pixel");
    Ok(meta.headers.first().and_then(|h| {
        match h.shared_attributes.other.get(&key).or_else(|| h.own_attributes.other.get(&key)) {
            Some(AttributeValue::I32(n)) => Some(*n),
            _ => None,
        }
    }))
}
