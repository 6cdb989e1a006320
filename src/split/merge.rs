//! `raydiance merge`: the parts' headers are checked together first (`coverage`), then their
//! pixels are added one part at a time, block by block, into sums of the whole image: memory is
//! the output image's sums and one block of one part, however many parts there are.

use std::path::PathBuf;

use glam::DVec3;

use super::coverage;
use super::part_file::{self, DamagedPixel, PartFileError, PartHeader};
use crate::aov::{AovImage, AovSums};
use crate::image::{Image, ImageError, RenderInfo};
use crate::region::{Crop, Share};

/// Why parts do not merge, or the merge cannot be written; the messages name the files.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("error: {0}")]
    Part(#[from] PartFileError),
    #[error("error: no parts to merge")]
    NoParts,
    #[error(
        "error: merging a {width}x{height} image needs {:.1} GiB ({per_pixel} bytes a \
         pixel), more than the {:.1} GiB a merge may take",
        gib(*needed),
        gib(MAX_MERGE_BYTES)
    )]
    TooLarge { width: u32, height: u32, per_pixel: u64, needed: u64 },
    #[error(
        "error: cannot merge {} and {}: they are parts of renders with other {what} ({first_has} \
         and {other_has})",
        first.display(),
        other.display()
    )]
    OtherRenders {
        first: PathBuf,
        other: PathBuf,
        what: &'static str,
        first_has: String,
        other_has: String,
    },
    #[error(
        "error: {} (crop {first_crop}) and {} (crop {other_crop}) overlap: their crops share \
         pixels (the parts of one tile must all have the same --crop, and tiles must not overlap)",
        first.display(),
        other.display()
    )]
    CropsOverlap { first: PathBuf, first_crop: Crop, other: PathBuf, other_crop: Crop },
    #[error(
        "error: {} (share {first_share}) and {} (share {other_share}) overlap: they take the \
         same samples of crop {crop}",
        first.display(),
        other.display()
    )]
    SharesOverlap {
        first: PathBuf,
        first_share: Share,
        other: PathBuf,
        other_share: Share,
        crop: Crop,
    },
    #[error(
        "error: the parts given ({parts}) do not make the whole image:\n  {}\nrender what is \
         missing and merge again (or merge with --allow-partial)",
        missing.join("\n  ")
    )]
    Incomplete { parts: usize, missing: Vec<String> },
    #[error("error: {}: pixel {pixel} of its crop is missing (the file is damaged)", part.display())]
    PixelMissing { part: PathBuf, pixel: usize },
    #[error(
        "error: {} and {} are the same file: each part is given once",
        first.display(),
        second.display()
    )]
    GivenTwice { first: PathBuf, second: PathBuf },
    #[error("error: {}: is one of the parts; merging would replace it", .0.display())]
    OutputIsAPart(PathBuf),
    #[error("error: {0}")]
    Output(#[from] ImageError),
}

/// A merged image and what to say about it.
#[derive(Debug)]
pub struct Merged {
    pub image: Image,
    /// The parts' AOVs merged, if they carry some.
    pub aovs: Option<AovImage>,
    pub info: RenderInfo,
    /// The parts merged.
    pub parts: usize,
    /// What was missing (only with `allow_partial`; a merge without it refuses instead).
    pub missing: Vec<String>,
    /// The fewest and most samples a pixel holds.
    pub samples: (u32, u32),
}

/// Refuses a part file named twice (perhaps by two paths): its shares would be said to overlap
/// themselves. A name that cannot be resolved is left to reading it to report.
fn check_given_once(paths: &[PathBuf]) -> Result<(), MergeError> {
    let mut seen = std::collections::HashMap::new();
    for path in paths {
        let Ok(file) = std::fs::canonicalize(path) else { continue };
        if let Some(first) = seen.insert(file, path) {
            return Err(MergeError::GivenTwice { first: first.clone(), second: path.clone() });
        }
    }
    Ok(())
}

/// Merges the part files; with `allow_partial`, missing shares, tiles and samples are not an
/// error (the image is the mean of the samples there are, and records the fewest per pixel).
pub fn merge(paths: &[PathBuf], allow_partial: bool) -> Result<Merged, MergeError> {
    check_given_once(paths)?;
    let mut parts =
        paths.iter().map(|path| part_file::read_header(path)).collect::<Result<Vec<_>, _>>()?;
    coverage::check_same_render(&parts)?;
    let missing = coverage::missing_work(&parts)?;
    if !missing.is_empty() && !allow_partial {
        return Err(MergeError::Incomplete { parts: parts.len(), missing });
    }
    // A fixed order: the same image bit for bit whatever the order the parts were given in.
    parts.sort_by_key(|p| {
        (p.region.crop, p.region.share.numbers(p.region.total()).start, p.region.share.count)
    });
    let first = &parts[0];
    check_memory(first.width, first.height, first.aovs.channels().count() as u64)?;
    let (width, height) = (first.width as usize, first.height as usize);
    let mut sums = vec![DVec3::ZERO; width * height];
    let mut counts = vec![0u32; width * height];
    let mut aov_sums = AovSums::new(first.aovs, width * height);
    for part in &parts {
        add_part(part, width, &mut sums, &mut counts, &mut aov_sums)?;
    }
    let aovs = (!first.aovs.is_empty()).then(|| aov_sums.image(width, height, &counts));
    let least = counts.iter().copied().min().unwrap_or(0);
    let most = counts.iter().copied().max().unwrap_or(0);
    let pixels = sums
        .iter()
        .zip(&counts)
        .map(|(sum, count)| (*sum * (1.0 / f64::from((*count).max(1)))).as_vec3())
        .collect();
    let info = RenderInfo {
        samples_per_pixel: least,
        integrator: first.integrator.clone(),
        seed: first.seed,
        seconds: parts.iter().map(|p| p.seconds).sum(),
        parameters: vec![("max_depth", first.max_depth.to_string())],
    };
    Ok(Merged {
        image: Image { width, height, pixels },
        aovs,
        info,
        parts: parts.len(),
        missing,
        samples: (least, most),
    })
}

/// The most memory a merge may take: render's default `--max-memory`.
pub const MAX_MERGE_BYTES: u64 = 8 << 30;

/// Bytes a pixel of the image takes while merging: the sums (f64) and counts, the image made of
/// them, and its tone-mapped copy for a PNG.
const BYTES_PER_PIXEL: u64 = 24 + 4 + 12 + 12 + 3;

/// Bytes a pixel takes while merging for each channel of AOVs: its sum (f64), its mean (f32).
const BYTES_PER_AOV_CHANNEL: u64 = 8 + 4;

/// Refuses, from the headers and before anything is allocated, an image (with `aov_channels`
/// channels of AOVs) too large to merge.
fn check_memory(width: u32, height: u32, aov_channels: u64) -> Result<(), MergeError> {
    let per_pixel = BYTES_PER_PIXEL + aov_channels * BYTES_PER_AOV_CHANNEL;
    let needed = u64::from(width) * u64::from(height) * per_pixel;
    match needed <= MAX_MERGE_BYTES {
        true => Ok(()),
        false => Err(MergeError::TooLarge { width, height, per_pixel, needed }),
    }
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 30)
}

/// Adds a part's sums and counts into the image's, checking that each pixel's count is what
/// its header's share says and that every pixel of its crop is there once.
fn add_part(
    part: &PartHeader,
    width: usize,
    sums: &mut [DVec3],
    counts: &mut [u32],
    aov_sums: &mut AovSums,
) -> Result<(), MergeError> {
    let region = &part.region;
    let crop = region.crop;
    let layout = region.layout();
    let crop_width = crop.width() as usize;
    let mut seen = vec![false; crop.pixels() as usize];
    part_file::read_pixels(part, |pixel, sum, count, aovs| {
        let expected = layout.samples_of(pixel as u64).len().min(part.taken as usize) as u32;
        let Some(seen) = seen.get_mut(pixel) else {
            return Err(DamagedPixel::OutsideCrop(pixel));
        };
        if count != expected || std::mem::replace(seen, true) {
            return Err(DamagedPixel::Samples { pixel, count, share: region.share, expected });
        }
        // Radiance is finite and never negative: anything else is a forged or damaged file.
        if !sum.is_finite() || sum.min_element() < 0.0 {
            return Err(DamagedPixel::Mean { pixel, mean: sum / f64::from(count.max(1)) });
        }
        let (x, y) = (crop.x0 as usize + pixel % crop_width, crop.y0 as usize + pixel / crop_width);
        if let Some(&value) = aovs.iter().find(|v| !v.is_finite()) {
            return Err(DamagedPixel::Aov { pixel, value });
        }
        sums[y * width + x] += sum;
        counts[y * width + x] += count;
        for (plane, value) in aov_sums.sums.iter_mut().zip(aovs) {
            plane[y * width + x] += f64::from(*value) * f64::from(count);
        }
        Ok(())
    })?;
    if let Some(pixel) = seen.iter().position(|s| !s) {
        return Err(MergeError::PixelMissing { part: part.path.clone(), pixel });
    }
    Ok(())
}
