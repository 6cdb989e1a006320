//! OpenEXR: linear RGB, 32-bit float, scanlines top to bottom, with the render's metadata.

use std::path::Path;

use ::exr::prelude::*;
use glam::Vec3;

use crate::aov::{AovImage, AovList};

use super::{Image, ImageError, MAX_PIXELS, RenderInfo, write_atomic};

pub fn write(path: &Path, image: &Image, info: &RenderInfo) -> std::result::Result<(), ImageError> {
    write_with_aovs(path, image, None, info)
}

/// Writes the beauty as R, G, B and the AOVs, if any, as further channels of the same layer
/// (`albedo.R`, `normal.X`, ...: `AovList::channels`).
pub fn write_with_aovs(
    path: &Path,
    image: &Image,
    aovs: Option<&AovImage>,
    info: &RenderInfo,
) -> std::result::Result<(), ImageError> {
    let spp = i32::try_from(info.samples_per_pixel).unwrap_or(i32::MAX);
    let text = |value: &str| AttributeValue::Text(Text::from(value));
    let mut attributes = vec![
        ("samples_per_pixel".to_string(), AttributeValue::I32(spp)),
        ("integrator".to_string(), text(&info.integrator)),
        ("seed".to_string(), text(&info.seed.to_string())),
        ("render_seconds".to_string(), AttributeValue::F64(info.seconds)),
    ];
    for (name, value) in &info.parameters {
        attributes.push((name.to_string(), text(value)));
    }
    write_with_attributes(path, image, aovs, attributes)
}

/// Writes the beauty and the AOVs with `raydiance:NAME` attributes.
pub(crate) fn write_with_attributes(
    path: &Path,
    image: &Image,
    aovs: Option<&AovImage>,
    attributes: Vec<(String, AttributeValue)>,
) -> std::result::Result<(), ImageError> {
    let rgb = |c: usize| image.pixels.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let mut list: Vec<AnyChannel<FlatSamples>> = ["R", "G", "B"]
        .iter()
        .enumerate()
        .map(|(c, name)| AnyChannel::new(*name, FlatSamples::F32(rgb(c))))
        .collect();
    for (name, plane) in aovs.iter().flat_map(|aovs| aovs.channels()) {
        list.push(AnyChannel::new(name, FlatSamples::F32(plane.to_vec())));
    }
    let mut layer_attributes = LayerAttributes::named("");
    layer_attributes.software_name = Some(Text::from("raydiance"));
    let layer = Layer::new(
        (image.width, image.height),
        layer_attributes,
        Encoding { line_order: LineOrder::Increasing, ..Encoding::SMALL_LOSSLESS },
        AnyChannels::sort(SmallVec::from_vec(list)),
    );
    let mut exr_image = ::exr::image::Image::from_layer(layer);
    for (name, value) in attributes {
        exr_image.attributes.other.insert(Text::from(format!("raydiance:{name}").as_str()), value);
    }
    write_atomic(path, |writer| {
        exr_image.write().to_buffered(writer).map_err(|e| ImageError::exr(path, ExrError::Codec(e)))
    })
}

/// The `raydiance:NAME` attributes of an OpenEXR file's header, by NAME.
pub(crate) fn read_attributes(
    path: &Path,
) -> std::result::Result<Vec<(String, AttributeValue)>, ImageError> {
    let meta = ::exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| ImageError::exr(path, e.into()))?;
    let Some(header) = meta.headers.first() else { return Ok(Vec::new()) };
    let all = header.shared_attributes.other.iter().chain(&header.own_attributes.other);
    let named = all.filter_map(|(key, value)| {
        let name = key.to_string().strip_prefix("raydiance:")?.to_string();
        Some((name, value.clone()))
    });
    Ok(named.collect())
}

/// Reads the first RGB(A) layer of any OpenEXR file (alpha is ignored).
pub fn read(path: &Path) -> std::result::Result<Image, ImageError> {
    let bytes = crate::input::read(path, crate::input::MAX_HDR_BYTES)
        .map_err(|e| ImageError::input(path, e))?;
    read_bytes(&bytes).map_err(|e| ImageError::exr(path, e))
}

/// An OpenEXR file that raydiance does not read.
#[derive(Debug, thiserror::Error)]
pub enum ExrError {
    /// The decoder's words ("reference to missing bytes") need saying what failed.
    #[error("not a readable OpenEXR file ({0})")]
    Unreadable(#[from] ::exr::error::Error),
    #[error("the image is {width} x {height} pixels, more than raydiance reads ({MAX_PIXELS})")]
    TooLarge { width: usize, height: usize },
    /// Writing, or reading the header of a file raydiance wrote: the codec's words say enough.
    #[error("{0}")]
    Codec(::exr::error::Error),
}

/// Refuses, from its headers, a file with more pixels than raydiance reads.
fn check_size(bytes: &[u8]) -> std::result::Result<(), ExrError> {
    let meta = ::exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)?;
    for header in &meta.headers {
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        if width.saturating_mul(height) > MAX_PIXELS {
            return Err(ExrError::TooLarge { width, height });
        }
    }
    Ok(())
}

/// Reads the AOV channels (`albedo.R`, `normal.X`, ...) of the first layer of an OpenEXR file
/// (none: an empty list).
pub fn read_aovs(path: &Path) -> std::result::Result<AovImage, ImageError> {
    let bytes = crate::input::read(path, crate::input::MAX_HDR_BYTES)
        .map_err(|e| ImageError::input(path, e))?;
    check_size(&bytes).map_err(|e| ImageError::exr(path, e))?;
    let image = read_all_channels(&bytes).map_err(|e| ImageError::exr(path, e.into()))?;
    let layer = image.layer_data;
    let channels = &layer.channel_data.list;
    let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
    let list = AovList::in_channels(&names).map_err(|name| {
        ImageError::format(path, format!("it has some channels of an AOV but not `{name}`"))
    })?;
    let planes = list
        .channels()
        .filter_map(|name| channels.iter().find(|c| c.name == *name))
        .map(|c| c.sample_data.values_as_f32().collect())
        .collect();
    let (width, height) = (layer.size.width(), layer.size.height());
    Ok(AovImage { list, width, height, planes })
}

/// Every channel of a file's first layer, with its header's attributes: what AOVs and snapshot
/// files are read from.
pub fn read_all_channels(
    bytes: &[u8],
) -> ::exr::error::Result<
    ::exr::image::Image<::exr::image::Layer<::exr::image::AnyChannels<::exr::image::FlatSamples>>>,
> {
    ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
}

/// Decodes an OpenEXR file's contents.
pub fn read_bytes(bytes: &[u8]) -> std::result::Result<Image, ExrError> {
    check_size(bytes)?;
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
        .from_buffered(std::io::Cursor::new(bytes))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The samples per pixel recorded in a file raydiance wrote.
pub fn read_samples_per_pixel(path: &Path) -> std::result::Result<Option<i32>, ImageError> {
    let meta = ::exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| ImageError::exr(path, ExrError::Codec(e)))?;
    let key = Text::from("raydiance:samples_per_pixel");
    Ok(meta.headers.first().and_then(|h| {
        match h.shared_attributes.other.get(&key).or_else(|| h.own_attributes.other.get(&key)) {
            Some(AttributeValue::I32(n)) => Some(*n),
            _ => None,
        }
    }))
}
