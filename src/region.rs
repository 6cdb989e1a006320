//! What one render takes of a frame's work: a rectangle of the image's pixels (`--crop`) and, in
//! each of them, a share of the sample indices (`--part I/N`).
//!
//! The samples of a crop are numbered sample-major, `g = s * P + p` for sample index `s` and
//! pixel `p` (row-major in the crop, `P` pixels), and share `I` of `N` takes the `g` in
//! `[floor(I T / N), floor((I + 1) T / N))` with `T = P S`. So each pixel's samples in a share
//! are a contiguous run of indices, the runs of the pixels differ in length by at most one, and
//! when `N` divides `S` share `I` is exactly the indices `[I S / N, (I + 1) S / N)` of every
//! pixel. Share `I` of `N` is the union of shares `2I` and `2I + 1` of `2N`.

use std::fmt;
use std::ops::Range;
use std::str::FromStr;

/// Largest image side accepted from the command line, as from `settings`, and from a part's
/// header.
pub const MAX_RESOLUTION: u32 = 65536;

/// Share `index` (0-based) of `count` disjoint shares of the sample set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Share {
    pub index: u32,
    pub count: u32,
}

/// A share or crop that names no work.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RegionError {
    #[error("share {index}/0: the count must be at least 1")]
    NoShares { index: u32 },
    #[error("share {index}/{count}: the index counts from 0, so it must be less than {count}")]
    ShareIndex { index: u32, count: u32 },
    #[error("--crop {0}: empty (X0 < X1 and Y0 < Y1 are needed)")]
    EmptyCrop(Crop),
    #[error("--crop {crop}: outside the {width}x{height} image")]
    CropOutside { crop: Crop, width: u32, height: u32 },
    #[error(
        "--part {}: more shares than the {total} samples of the {}x{} pixels at {} per pixel",
        region.share,
        region.crop.width(),
        region.crop.height(),
        region.samples
    )]
    MoreSharesThanSamples { region: Region, total: u64 },
    #[error("`{0}` is not a share I/N (e.g. 3/16: the 4th of 16)")]
    NotAShare(String),
    #[error("`{0}` is not a crop X0,X1,Y0,Y1 (pixels X0 <= x < X1, Y0 <= y < Y1)")]
    NotACrop(String),
}

impl Share {
    /// The whole sample set.
    pub const WHOLE: Share = Share { index: 0, count: 1 };

    pub fn new(index: u32, count: u32) -> Result<Share, RegionError> {
        if count == 0 {
            return Err(RegionError::NoShares { index });
        }
        if index >= count {
            return Err(RegionError::ShareIndex { index, count });
        }
        Ok(Share { index, count })
    }

    /// The range of sample numbers `g` (see the module) this share takes of `total`.
    pub fn numbers(self, total: u64) -> Range<u64> {
        let at = |i: u32| (u128::from(i) * u128::from(total) / u128::from(self.count)) as u64;
        at(self.index)..at(self.index + 1)
    }
}

impl fmt::Display for Share {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Share {
    type Err = RegionError;

    /// `I/N`.
    fn from_str(s: &str) -> Result<Share, RegionError> {
        let parse = |t: &str| t.trim().parse::<u32>().ok();
        match s.split_once('/').and_then(|(i, n)| Some((parse(i)?, parse(n)?))) {
            Some((index, count)) => Share::new(index, count),
            None => Err(RegionError::NotAShare(s.to_string())),
        }
    }
}

/// Pixels `x0 <= x < x1`, `y0 <= y < y1` of the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Crop {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

impl Crop {
    pub fn whole(width: u32, height: u32) -> Crop {
        Crop { x0: 0, x1: width, y0: 0, y1: height }
    }

    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    pub fn pixels(&self) -> u64 {
        u64::from(self.width()) * u64::from(self.height())
    }

    /// Checks that the crop is a non-empty rectangle inside a `width` x `height` image.
    pub fn check(&self, width: u32, height: u32) -> Result<(), RegionError> {
        if self.x0 >= self.x1 || self.y0 >= self.y1 {
            return Err(RegionError::EmptyCrop(*self));
        }
        if self.x1 > width || self.y1 > height {
            return Err(RegionError::CropOutside { crop: *self, width, height });
        }
        Ok(())
    }

    pub fn intersects(&self, other: &Crop) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
}

impl fmt::Display for Crop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

impl FromStr for Crop {
    type Err = RegionError;

    /// `X0,X1,Y0,Y1`.
    fn from_str(s: &str) -> Result<Crop, RegionError> {
        let values: Vec<Option<u32>> = s.split(',').map(|v| v.trim().parse().ok()).collect();
        match values[..] {
            [Some(x0), Some(x1), Some(y0), Some(y1)] => Ok(Crop { x0, x1, y0, y1 }),
            _ => Err(RegionError::NotACrop(s.to_string())),
        }
    }
}

/// A crop of the image and a share of its samples, for a render of `samples` per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    pub crop: Crop,
    pub share: Share,
    pub samples: u32,
}

impl Region {
    /// Every sample of every pixel.
    pub fn whole(width: u32, height: u32, samples: u32) -> Region {
        Region { crop: Crop::whole(width, height), share: Share::WHOLE, samples }
    }

    /// Checks the crop against the image and that the share takes at least one sample.
    pub fn check(&self, width: u32, height: u32) -> Result<(), RegionError> {
        self.crop.check(width, height)?;
        let total = self.total();
        if u64::from(self.share.count) > total {
            return Err(RegionError::MoreSharesThanSamples { region: *self, total });
        }
        Ok(())
    }

    /// Samples of the crop: pixels times samples per pixel.
    pub fn total(&self) -> u64 {
        self.crop.pixels() * u64::from(self.samples)
    }

    /// The sample indices the share takes in pixel `pixel` of the crop (row-major).
    pub fn samples_of(&self, pixel: u64) -> Range<u32> {
        self.layout().samples_of(pixel)
    }

    /// What `samples_of` needs, worked out once for many pixels.
    pub fn layout(&self) -> Layout {
        let numbers = self.share.numbers(self.total());
        Layout {
            numbers,
            pixels: self.crop.pixels(),
            whole: (self.share.count == 1).then_some(self.samples),
        }
    }

    /// The samples of the share taken when each pixel has taken at most `taken` of its own.
    pub fn samples_taken(&self, taken: u32) -> u64 {
        let layout = self.layout();
        (0..self.crop.pixels())
            .map(|p| u64::from(taken.min(layout.samples_of(p).len() as u32)))
            .sum()
    }

    /// The most samples any pixel takes in this share.
    pub fn most_samples(&self) -> u32 {
        let numbers = self.share.numbers(self.total());
        (numbers.end - numbers.start).div_ceil(self.crop.pixels()) as u32
    }
}

/// A share's sample numbers in a crop of `pixels` pixels: each pixel's sample indices.
#[derive(Debug, Clone)]
pub struct Layout {
    numbers: Range<u64>,
    pixels: u64,
    /// Every sample of every pixel: this many.
    whole: Option<u32>,
}

impl Layout {
    /// The sample indices the share takes in pixel `pixel` of the crop (row-major).
    #[inline]
    pub fn samples_of(&self, pixel: u64) -> Range<u32> {
        if let Some(samples) = self.whole {
            return 0..samples;
        }
        // The first s with s * P + pixel >= g.
        let first = |g: u64| g.saturating_sub(pixel).div_ceil(self.pixels) as u32;
        first(self.numbers.start)..first(self.numbers.end)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_take_each_sample_of_each_pixel_once() {
        for (width, height, samples, count) in
            [(3, 2, 4, 4), (3, 2, 4, 5), (5, 1, 3, 15), (2, 2, 1, 3)]
        {
            let crop = Crop::whole(width, height);
            for pixel in 0..crop.pixels() {
                let mut taken = Vec::new();
                for index in 0..count {
                    let region = Region { crop, share: Share::new(index, count).unwrap(), samples };
                    let range = region.samples_of(pixel);
                    assert!(range.len() as u32 <= region.most_samples());
                    taken.extend(range);
                }
                assert_eq!(taken, (0..samples).collect::<Vec<_>>(), "pixel {pixel} of {count}");
            }
        }
    }

    #[test]
    fn a_share_of_a_divisor_is_a_range_of_indices_in_every_pixel() {
        let region =
            Region { crop: Crop::whole(7, 3), share: Share::new(2, 4).unwrap(), samples: 16 };
        for pixel in 0..21 {
            assert_eq!(region.samples_of(pixel), 8..12);
        }
    }

    #[test]
    fn a_share_is_the_union_of_its_two_halves() {
        let total = 37;
        let share = Share::new(3, 5).unwrap();
        let (a, b) = (Share::new(6, 10).unwrap(), Share::new(7, 10).unwrap());
        assert_eq!(share.numbers(total).start, a.numbers(total).start);
        assert_eq!(a.numbers(total).end, b.numbers(total).start);
        assert_eq!(share.numbers(total).end, b.numbers(total).end);
    }

    #[test]
    fn shares_and_crops_parse_and_refuse_with_reasons() {
        assert_eq!("3/16".parse::<Share>(), Ok(Share { index: 3, count: 16 }));
        let index = RegionError::ShareIndex { index: 16, count: 16 };
        assert_eq!("16/16".parse::<Share>(), Err(index.clone()));
        assert!(index.to_string().contains("less than 16"));
        assert_eq!("1/0".parse::<Share>(), Err(RegionError::NoShares { index: 1 }));
        let not_a_share = "a/2".parse::<Share>().unwrap_err();
        assert_eq!(not_a_share, RegionError::NotAShare("a/2".into()));
        assert!(not_a_share.to_string().contains("not a share I/N"));
        assert_eq!("0, 4,1,3".parse::<Crop>(), Ok(Crop { x0: 0, x1: 4, y0: 1, y1: 3 }));
        assert_eq!("0,4,1".parse::<Crop>(), Err(RegionError::NotACrop("0,4,1".into())));
        let crop: Crop = "2,2,0,1".parse().unwrap();
        assert!(crop.check(4, 4).unwrap_err().to_string().contains("empty"));
        let crop: Crop = "0,5,0,1".parse().unwrap();
        assert!(crop.check(4, 4).unwrap_err().to_string().contains("outside the 4x4 image"));
        let region =
            Region { crop: Crop::whole(2, 1), share: Share::new(0, 5).unwrap(), samples: 2 };
        assert!(
            region.check(2, 1).unwrap_err().to_string().contains("more shares than the 4 samples")
        );
    }
}
