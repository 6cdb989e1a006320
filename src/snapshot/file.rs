//! A snapshot file: OpenEXR with the mean radiance as RGB (so any viewer shows the picture) and
//! the variance of each pixel's mean as `variance.R`, `variance.G`, `variance.B`.

use std::path::Path;

use ::exr::prelude::*;
use glam::Vec3;

use super::Estimate;
use crate::image::{ImageError, write_atomic};

const SAMPLES_ATTRIBUTE: &str = "raydiance:samples_per_pixel";
const CHANNELS: [&str; 6] = ["R", "G", "B", "variance.R", "variance.G", "variance.B"];

pub fn write(path: &Path, estimate: &Estimate) -> std::result::Result<(), ImageError> {
    let values = |channel: usize| -> Vec<f32> {
        let (pixels, component) = match channel {
            0..3 => (&estimate.mean, channel),
            _ => (&estimate.variance, channel - 3),
        };
        pixels.iter().map(|p| p[component]).collect()
    };
    let list = CHANNELS
        .iter()
        .enumerate()
        .map(|(i, name)| AnyChannel::new(*name, FlatSamples::F32(values(i))))
        .collect::<Vec<_>>();
    let mut attributes = LayerAttributes::named("");
    attributes.software_name = Some(Text::from("raydiance snapshot"));
    let layer = Layer::new(
        (estimate.width, estimate.height),
        attributes,
        Encoding { line_order: LineOrder::Increasing, ..Encoding::SMALL_LOSSLESS },
        AnyChannels::sort(list.into()),
    );
    let mut image = ::exr::image::Image::from_layer(layer);
    let samples = i32::try_from(estimate.samples_per_pixel).unwrap_or(i32::MAX);
    image.attributes.other.insert(Text::from(SAMPLES_ATTRIBUTE), AttributeValue::I32(samples));
    write_atomic(path, |writer| {
        image.write().to_buffered(writer).map_err(|e| ImageError::format(path, e.to_string()))
    })
}

/// Reads a snapshot; anything else (another EXR, a damaged file) is an error naming the file.
pub fn read(path: &Path) -> std::result::Result<Estimate, ImageError> {
    let bytes = crate::input::read(path, crate::input::MAX_HDR_BYTES)
        .map_err(|e| ImageError::input(path, e))?;
    read_bytes(&bytes).map_err(|problem| {
        ImageError::format(path, format!("not a readable raydiance snapshot: {problem}"))
    })
}

/// Why a file is not a readable snapshot.
#[derive(Debug, thiserror::Error)]
enum Unreadable {
    #[error("{0}")]
    Exr(#[from] ::exr::error::Error),
    #[error("the file has no image")]
    NoImage,
    #[error(transparent)]
    TooLarge(#[from] super::TooLarge),
    #[error("no `{SAMPLES_ATTRIBUTE}` of at least 2 in its header")]
    NoSampleCount,
    #[error("it has no channel `{0}`")]
    NoChannel(&'static str),
    #[error("pixel {0} has a mean that is not a finite number")]
    Mean(usize),
    #[error("pixel {0} has a variance that is not a finite number ≥ 0")]
    Variance(usize),
    #[error(
        "pixel {pixel}'s variance {variance:e} is more than the square of its mean {mean:e} (no \
         render gives that)"
    )]
    VarianceAboveMean { pixel: usize, variance: f32, mean: f32 },
}

fn read_bytes(bytes: &[u8]) -> std::result::Result<Estimate, Unreadable> {
    let meta = ::exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)?;
    let header = meta.headers.first().ok_or(Unreadable::NoImage)?;
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    super::check_size(width, height)?;
    let samples_per_pixel = match header.own_attributes.other.get(&Text::from(SAMPLES_ATTRIBUTE)) {
        Some(AttributeValue::I32(n)) if *n >= 2 => *n as u32,
        _ => return Err(Unreadable::NoSampleCount),
    };
    let image = crate::image::exr::read_all_channels(bytes)?;
    let channels = &image.layer_data.channel_data.list;
    let values = |name: &'static str| -> std::result::Result<Vec<f32>, Unreadable> {
        let channel =
            channels.iter().find(|c| c.name == *name).ok_or(Unreadable::NoChannel(name))?;
        Ok(channel.sample_data.values_as_f32().collect())
    };
    let [r, g, b, vr, vg, vb] = CHANNELS.map(values);
    let pixels = |r: Vec<f32>, g: Vec<f32>, b: Vec<f32>| -> Vec<Vec3> {
        r.into_iter().zip(g).zip(b).map(|((r, g), b)| Vec3::new(r, g, b)).collect()
    };
    let mean = pixels(r?, g?, b?);
    let variance = pixels(vr?, vg?, vb?);
    if let Some(i) = mean.iter().position(|m| !m.is_finite()) {
        return Err(Unreadable::Mean(i));
    }
    if let Some(i) = variance.iter().position(|v| !(v.is_finite() && v.min_element() >= 0.0)) {
        return Err(Unreadable::Variance(i));
    }
    // Samples are never negative, so the variance of their mean is at most its square (all in one
    // sample): a larger one (1e30) would make every render match, and is a forged or damaged file.
    let values = mean.iter().zip(&variance).flat_map(|(m, v)| (0..3).map(move |c| (m[c], v[c])));
    let too_large = |(m, v): &(f32, f32)| f64::from(*v) > f64::from(*m).powi(2) * 1.001 + 1e-30;
    if let Some((k, (mean, variance))) = values.enumerate().find(|(_, p)| too_large(p)) {
        return Err(Unreadable::VarianceAboveMean { pixel: k / 3, variance, mean });
    }
    Ok(Estimate { width, height, mean, variance, samples_per_pixel })
}
