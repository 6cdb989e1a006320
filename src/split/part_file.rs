//! A part file: an OpenEXR image whose RGB is the part's own mean (a viewer opens it as an
//! image), its data window the crop and its display window the whole image, with what an exact
//! merge needs: per-pixel sample counts (`samples`, 32-bit unsigned) and second moments
//! (`moment2.R`, `moment2.G`, `moment2.B`: the mean of the squared radiance), and in the header
//! the share, the crop, the image size, the seed, the sample count of the whole render and a
//! digest of the scene and settings (`exrheader` shows them all). A render with AOVs adds their
//! channels (`albedo.R`, ...), the part's own means as RGB's.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use ::exr::block::reader::ChunksReader;
use ::exr::meta::header::Header;
use ::exr::prelude::*;

type Result<T, E = PartFileError> = std::result::Result<T, E>;
use glam::DVec3;

use crate::animation::Frame;
use crate::aov::AovList;
use crate::diagnostic::printable;
use crate::film::Film;
use crate::graph::{IntegratorKind, Settings};
use crate::image::{ImageError, write_atomic};
use crate::region::{Crop, MAX_RESOLUTION, Region, RegionError, Share};

/// The channel of per-pixel sample counts.
const SAMPLES: &str = "samples";
/// The channels of per-pixel means of the squared radiance.
const MOMENT2: [&str; 3] = ["moment2.R", "moment2.G", "moment2.B"];

/// Why a part file cannot be read; the message names the file.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct PartFileError {
    pub path: PathBuf,
    pub problem: PartProblem,
}

#[derive(Debug, thiserror::Error)]
pub enum PartProblem {
    #[error("{0}")]
    Io(std::io::Error),
    #[error("not a regular file")]
    NotRegular,
    #[error("not a readable OpenEXR file ({0})")]
    NotExr(::exr::error::Error),
    #[error("not a part: a part file has one layer")]
    Layers,
    #[error("not a part (it has no raydiance:part: render parts with --part or --crop)")]
    NotAPart,
    #[error("its header has no valid raydiance:{0}")]
    Missing(&'static str),
    /// Its integrator (escaped) is not one whose renders split into parts.
    #[error("its raydiance:integrator `{0}` is not one that renders parts")]
    NotSplittable(String),
    #[error("its header is inconsistent: {0}")]
    Inconsistent(RegionError),
    #[error(
        "its data and display windows do not match raydiance:crop {crop} and \
         raydiance:image_size {size}"
    )]
    Windows { crop: Crop, size: String },
    #[error("it has no {kind:?} channel `{name}`")]
    NoChannel { kind: SampleType, name: &'static str },
    #[error("it has some channels of an AOV but not `{0}`")]
    PartOfAnAov(&'static str),
    #[error("cannot read its pixels (truncated or damaged?): {0}")]
    Pixels(::exr::error::Error),
    /// What the reader of its pixels found wrong with them.
    #[error("{0} (the file is damaged)")]
    Damaged(DamagedPixel),
}

/// A pixel of a part that no render writes (`read_pixels`' reader finds them).
#[derive(Debug, thiserror::Error)]
pub enum DamagedPixel {
    #[error("pixel {0} lies outside its crop")]
    OutsideCrop(usize),
    #[error("pixel {pixel} of the crop holds {count} samples where share {share} has {expected}")]
    Samples { pixel: usize, count: u32, share: Share, expected: u32 },
    /// Radiance is finite and never negative.
    #[error("pixel {pixel} of the crop holds the mean {mean}")]
    Mean { pixel: usize, mean: DVec3 },
    #[error("pixel {pixel} of the crop holds the AOV value {value}")]
    Aov { pixel: usize, value: f32 },
}

/// What a part's header says.
#[derive(Debug, Clone, PartialEq)]
pub struct PartHeader {
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    /// The crop, the share, and the samples per pixel of the whole render they split.
    pub region: Region,
    /// The samples per pixel taken of each pixel's share (fewer than `Region::most_samples`
    /// when the render was stopped).
    pub taken: u32,
    pub seed: u64,
    pub integrator: String,
    /// The longest path (the one integrator parameter of the integrators that split).
    pub max_depth: u32,
    /// Digest of the scene's text, its includes, the settings and the frame.
    pub digest: String,
    pub frame: Frame,
    pub seconds: f64,
    /// The AOVs it carries (from its channels).
    pub aovs: AovList,
}

impl PartHeader {
    /// True when every pixel holds all the samples of its share.
    pub fn complete(&self) -> bool {
        self.taken >= self.region.most_samples()
    }
}

fn key(name: &str) -> Text {
    Text::from(format!("raydiance:{name}").as_str())
}

fn text(value: impl ToString) -> AttributeValue {
    AttributeValue::Text(Text::from(value.to_string().as_str()))
}

/// Writes the part rendered into `film` (the crop's, `film.samples` of each pixel's share taken).
pub fn write(path: &Path, film: &Film, header: &PartHeader) -> Result<(), ImageError> {
    let region = &header.region;
    let layout = region.layout();
    let pixels = film.width * film.height;
    let mut channels: Vec<Vec<f32>> = (0..6).map(|_| Vec::with_capacity(pixels)).collect();
    let mut counts = Vec::with_capacity(pixels);
    for (pixel, (sum, squares)) in film.sum.iter().zip(&film.sum_squares).enumerate() {
        let count = layout.samples_of(pixel as u64).len().min(film.samples as usize) as u32;
        let scale = 1.0 / f64::from(count.max(1));
        let (mean, moment2) = ((*sum * scale).as_vec3(), (*squares * scale).as_vec3());
        for (channel, value) in
            channels.iter_mut().zip(mean.to_array().into_iter().chain(moment2.to_array()))
        {
            channel.push(value);
        }
        counts.push(count);
    }
    let names = ["R", "G", "B", MOMENT2[0], MOMENT2[1], MOMENT2[2]];
    let mut list: Vec<AnyChannel<FlatSamples>> = names
        .iter()
        .zip(channels)
        .map(|(name, values)| AnyChannel::new(*name, FlatSamples::F32(values)))
        .collect();
    for (name, plane) in film.aovs.iter().flat_map(|aovs| aovs.channels()) {
        list.push(AnyChannel::new(name, FlatSamples::F32(plane.to_vec())));
    }
    list.push(AnyChannel::new(SAMPLES, FlatSamples::U32(counts)));
    let crop = region.crop;
    let mut attributes = LayerAttributes::named("");
    attributes.software_name = Some(Text::from("raydiance"));
    attributes.layer_position = Vec2(crop.x0 as i32, crop.y0 as i32);
    let layer = Layer::new(
        (film.width, film.height),
        attributes,
        Encoding { line_order: LineOrder::Increasing, ..Encoding::SMALL_LOSSLESS },
        AnyChannels::sort(SmallVec::from_vec(list)),
    );
    let mut image = ::exr::image::Image::from_layer(layer);
    image.attributes.display_window =
        IntegerBounds::from_dimensions((header.width as usize, header.height as usize));
    let other = &mut image.attributes.other;
    let int = |n: u32| AttributeValue::I32(i32::try_from(n).unwrap_or(i32::MAX));
    other.insert(key("samples_per_pixel"), int(header.taken));
    other.insert(key("integrator"), text(&header.integrator));
    other.insert(key("max_depth"), int(header.max_depth));
    other.insert(key("seed"), text(header.seed));
    other.insert(key("render_seconds"), AttributeValue::F64(header.seconds));
    other.insert(key("part"), text(region.share));
    other.insert(key("crop"), text(crop));
    other.insert(key("image_size"), text(format!("{}x{}", header.width, header.height)));
    other.insert(key("render_samples"), int(region.samples));
    other.insert(key("digest"), text(&header.digest));
    other.insert(key("frame"), int(header.frame.number));
    other.insert(key("clock"), AttributeValue::F64(header.frame.clock));
    write_atomic(path, |writer| {
        image.write().to_buffered(writer).map_err(|e| ImageError::format(path, e.to_string()))
    })
}

/// Opens a regular file for reading (a FIFO or a folder is an error, not a hang).
fn open(path: &Path) -> Result<BufReader<File>, PartProblem> {
    let metadata = std::fs::metadata(path).map_err(PartProblem::Io)?;
    if !metadata.is_file() {
        return Err(PartProblem::NotRegular);
    }
    File::open(path).map(BufReader::new).map_err(PartProblem::Io)
}

/// Reads and checks a part's header; the message names the file.
pub fn read_header(path: &Path) -> Result<PartHeader> {
    let named = |problem| PartFileError { path: path.to_path_buf(), problem };
    let reader = open(path).map_err(named)?;
    let meta =
        MetaData::read_from_buffered(reader, false).map_err(|e| named(PartProblem::NotExr(e)))?;
    let [header] = &meta.headers[..] else {
        return Err(named(PartProblem::Layers));
    };
    parse_header(path, header).map_err(named)
}

fn parse_header(path: &Path, header: &Header) -> Result<PartHeader, PartProblem> {
    let get = |name: &str| {
        let key = key(name);
        header.own_attributes.other.get(&key).or_else(|| header.shared_attributes.other.get(&key))
    };
    if get("part").is_none() {
        return Err(PartProblem::NotAPart);
    }
    let missing = PartProblem::Missing;
    let text_of = |name: &'static str| match get(name) {
        Some(AttributeValue::Text(t)) => Ok(t.to_string()),
        _ => Err(missing(name)),
    };
    let int_of = |name: &'static str| match get(name) {
        Some(AttributeValue::I32(n)) => u32::try_from(*n).map_err(|_| missing(name)),
        _ => Err(missing(name)),
    };
    let float_of = |name: &'static str| match get(name) {
        Some(AttributeValue::F64(x)) => Ok(*x),
        _ => Err(missing(name)),
    };
    let share: Share = text_of("part")?.parse().map_err(|_| missing("part"))?;
    let crop: Crop = text_of("crop")?.parse().map_err(|_| missing("crop"))?;
    let size = text_of("image_size")?;
    let (width, height) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| (1..=MAX_RESOLUTION).contains(&w) && (1..=MAX_RESOLUTION).contains(&h))
        .ok_or_else(|| missing("image_size"))?;
    let integrator = text_of("integrator")?;
    let splits = |kind| {
        let settings = Settings { integrator: kind, ..Settings::default() };
        crate::integrator::of(&settings).samples_are_independent()
    };
    if !IntegratorKind::named(&integrator).is_some_and(splits) {
        return Err(PartProblem::NotSplittable(printable(&integrator)));
    }
    let region = Region { crop, share, samples: int_of("render_samples")? };
    region.check(width, height).map_err(PartProblem::Inconsistent)?;
    // The EXR windows must say what the attributes say.
    let display = header.shared_attributes.display_window;
    let data = IntegerBounds::new(header.own_attributes.layer_position, header.layer_size);
    let expected_data = IntegerBounds::new(
        Vec2(crop.x0 as i32, crop.y0 as i32),
        (crop.width() as usize, crop.height() as usize),
    );
    if display != IntegerBounds::from_dimensions((width as usize, height as usize))
        || data != expected_data
    {
        return Err(PartProblem::Windows { crop, size });
    }
    for (name, kind) in [
        ("R", SampleType::F32),
        ("G", SampleType::F32),
        ("B", SampleType::F32),
        (SAMPLES, SampleType::U32),
    ] {
        if !header.channels.list.iter().any(|c| c.name == *name && c.sample_type == kind) {
            return Err(PartProblem::NoChannel { kind, name });
        }
    }
    let names: Vec<String> = header.channels.list.iter().map(|c| c.name.to_string()).collect();
    let aovs = AovList::in_channels(&names).map_err(PartProblem::PartOfAnAov)?;
    for name in aovs.channels() {
        let kind = SampleType::F32;
        if !header.channels.list.iter().any(|c| c.name == *name && c.sample_type == kind) {
            return Err(PartProblem::NoChannel { kind, name });
        }
    }
    Ok(PartHeader {
        path: path.to_path_buf(),
        width,
        height,
        region,
        taken: int_of("samples_per_pixel")?,
        seed: text_of("seed")?.parse().map_err(|_| missing("seed"))?,
        integrator,
        max_depth: int_of("max_depth")?,
        digest: printable(&text_of("digest")?),
        // A part records its frame's number and clock, which say which image it is a part of.
        frame: Frame { number: int_of("frame")?, clock: float_of("clock")?, step: None },
        seconds: float_of("render_seconds")?,
        aovs,
    })
}

/// Reads a part's pixels block by block (never the whole part at once), calling `visit` with
/// each pixel's position in the crop (row-major), sum of radiance (mean times count), count and
/// AOV means (in the order of `PartHeader::aovs`' channels).
pub fn read_pixels(
    part: &PartHeader,
    mut visit: impl FnMut(usize, DVec3, u32, &[f32]) -> Result<(), DamagedPixel>,
) -> Result<()> {
    let named = |problem| PartFileError { path: part.path.clone(), problem };
    let reader = open(&part.path).map_err(named)?;
    let width = part.region.crop.width() as usize;
    let aov_channels: Vec<&str> = part.aovs.channels().collect();
    let mut error = None;
    let result = ::exr::block::read(reader, false)
        .and_then(|reader| reader.all_chunks(false))
        .and_then(|chunks| {
            chunks.decompress_parallel(false, |meta, block| {
                let header = &meta.headers[block.index.layer];
                let size = block.index.pixel_size;
                let pixels = size.width() * size.height();
                let mut rgb = [vec![0f32; pixels], vec![0f32; pixels], vec![0f32; pixels]];
                let mut aovs = vec![vec![0f32; pixels]; aov_channels.len()];
                let mut counts = vec![0u32; pixels];
                for line in block.lines(&header.channels) {
                    let name = &header.channels.list[line.location.channel].name;
                    let row = line.location.position.y() - block.index.pixel_position.y();
                    let at = row * size.width()..(row + 1) * size.width();
                    let channel = ["R", "G", "B"].iter().position(|c| name == *c);
                    let aov = aov_channels.iter().position(|c| name == *c);
                    match (channel, aov) {
                        (Some(c), _) => line.read_samples_into_slice(&mut rgb[c][at])?,
                        (None, Some(a)) => line.read_samples_into_slice(&mut aovs[a][at])?,
                        (None, None) if name == SAMPLES => {
                            line.read_samples_into_slice(&mut counts[at])?
                        }
                        (None, None) => {}
                    }
                }
                let (x0, y0) = (block.index.pixel_position.x(), block.index.pixel_position.y());
                let mut pixel_aovs = vec![0f32; aov_channels.len()];
                for i in 0..pixels {
                    let (x, y) = (x0 + i % size.width(), y0 + i / size.width());
                    let mean = DVec3::new(rgb[0][i].into(), rgb[1][i].into(), rgb[2][i].into());
                    let count = counts[i];
                    for (value, plane) in pixel_aovs.iter_mut().zip(&aovs) {
                        *value = plane[i];
                    }
                    let sum = mean * f64::from(count);
                    if let Err(damage) = visit(y * width + x, sum, count, &pixel_aovs) {
                        error.get_or_insert(damage);
                        return Err(Error::Aborted);
                    }
                }
                Ok(())
            })
        });
    match (error, result) {
        (Some(damage), _) => Err(named(PartProblem::Damaged(damage))),
        (None, Err(e)) => Err(named(PartProblem::Pixels(e))),
        (None, Ok(())) => Ok(()),
    }
}
