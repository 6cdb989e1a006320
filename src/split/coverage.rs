//! Whether a set of parts makes one image, from their headers alone: the same scene, seed,
//! settings, resolution and frame; crops that are equal or disjoint; within a crop, shares that
//! do not overlap; and together every sample of every pixel (or, with `--allow-partial`, what is
//! there, with the missing work listed). Messages name the files.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::ops::Range;

use super::merge::MergeError;
use super::part_file::PartHeader;
use crate::region::{Crop, Share};

/// How many missing pieces a message lists before "and N more".
const LISTED: usize = 8;

/// Refuses parts that do not belong to one render; the message names two files that differ.
pub fn check_same_render(parts: &[PartHeader]) -> Result<(), MergeError> {
    let Some(first) = parts.first() else {
        return Err(MergeError::NoParts);
    };
    for part in &parts[1..] {
        let differ = |what: &'static str, first_has: String, other_has: String| {
            Err(MergeError::OtherRenders {
                first: first.path.clone(),
                other: part.path.clone(),
                what,
                first_has,
                other_has,
            })
        };
        if (first.width, first.height) != (part.width, part.height) {
            let size = |p: &PartHeader| format!("{}x{}", p.width, p.height);
            return differ("resolutions", size(first), size(part));
        }
        if first.seed != part.seed {
            return differ("seeds", first.seed.to_string(), part.seed.to_string());
        }
        if first.region.samples != part.region.samples {
            let spp = |p: &PartHeader| format!("{} samples per pixel", p.region.samples);
            return differ("settings", spp(first), spp(part));
        }
        if first.integrator != part.integrator {
            let integrator = |p: &PartHeader| format!("integrator {}", p.integrator);
            return differ("settings", integrator(first), integrator(part));
        }
        if first.frame.number != part.frame.number || first.frame.clock != part.frame.clock {
            let frame =
                |p: &PartHeader| format!("frame {} at clock {}", p.frame.number, p.frame.clock);
            return differ("frames", frame(first), frame(part));
        }
        if first.digest != part.digest {
            let digest = |p: &PartHeader| format!("digest {}", p.digest);
            return differ("scenes or settings", digest(first), digest(part));
        }
        if first.aovs != part.aovs {
            let aovs = |p: &PartHeader| match p.aovs.is_empty() {
                true => "no AOVs".to_string(),
                false => format!("--aov {}", p.aovs),
            };
            return differ("AOVs", aovs(first), aovs(part));
        }
    }
    Ok(())
}

/// Refuses overlapping parts; returns what is missing (empty when the parts cover every sample
/// of every pixel), one line each, saying how to render it: the first `LISTED` lines, then how
/// many more there are.
pub fn missing_work(parts: &[PartHeader]) -> Result<Vec<String>, MergeError> {
    let mut tiles: BTreeMap<Crop, Vec<&PartHeader>> = BTreeMap::new();
    for part in parts {
        tiles.entry(part.region.crop).or_default().push(part);
    }
    let (width, height) = parts.first().map_or((0, 0), |p| (p.width, p.height));
    let crops: Vec<Crop> = tiles.keys().copied().collect();
    let holes = match sweep(&crops, width, height) {
        Sweep::Holes(holes) => holes,
        Sweep::Overlap(a, b) => {
            return Err(MergeError::CropsOverlap {
                first: tiles[&a][0].path.clone(),
                first_crop: a,
                other: tiles[&b][0].path.clone(),
                other_crop: b,
            });
        }
    };
    let mut missing = Vec::new();
    for (crop, tile) in &mut tiles {
        missing.extend(missing_shares(crop, tile)?);
    }
    missing.extend(
        holes
            .into_iter()
            .map(|crop| format!("no part covers crop {crop}: render it with --crop {crop}")),
    );
    for part in parts.iter().filter(|p| !p.complete()) {
        missing.push(format!(
            "{} is incomplete: {} of the {} samples per pixel of share {} (its render was \
             stopped): render it again",
            part.path.display(),
            part.taken,
            part.region.most_samples(),
            part.region.share
        ));
    }
    if missing.len() > LISTED {
        let more = missing.len() - LISTED;
        missing.truncate(LISTED);
        missing.push(format!("and {more} more pieces of missing work"));
    }
    Ok(missing)
}

/// The shares of one tile: refuses two that take the same samples; lists the samples no part
/// takes, as the shares to render.
fn missing_shares(crop: &Crop, tile: &mut [&PartHeader]) -> Result<Vec<String>, MergeError> {
    let total = tile[0].region.total();
    tile.sort_by_key(|p| (p.region.share.numbers(total).start, p.region.share.count));
    let mut gaps: Vec<Range<u64>> = Vec::new();
    let mut covered = 0;
    for pair in tile.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if a.region.share.numbers(total).end > b.region.share.numbers(total).start {
            return Err(MergeError::SharesOverlap {
                first: a.path.clone(),
                first_share: a.region.share,
                other: b.path.clone(),
                other_share: b.region.share,
                crop: *crop,
            });
        }
    }
    for part in tile.iter() {
        let numbers = part.region.share.numbers(total);
        if numbers.start > covered {
            gaps.push(covered..numbers.start);
        }
        covered = numbers.end;
    }
    if covered < total {
        gaps.push(covered..total);
    }
    let files: Vec<String> = tile.iter().map(|p| p.path.display().to_string()).collect();
    let whole = *crop == Crop::whole(tile[0].width, tile[0].height);
    let (place, with_crop) = if whole {
        (format!("of the image (there are {})", listed(&files)), String::new())
    } else {
        (format!("of crop {crop} (there are {})", listed(&files)), format!(" with --crop {crop}"))
    };
    let count = tile[0].region.share.count;
    let one_split = tile.iter().all(|p| p.region.share.count == count);
    let mut lines = Vec::new();
    for gap in gaps {
        if one_split {
            let indices = shares_within(&gap, count, total);
            let shares: Vec<String> = indices
                .clone()
                .take(LISTED)
                .map(|index| format!("--part {}", Share { index, count }))
                .collect();
            let more = match indices.len().saturating_sub(LISTED) {
                0 => String::new(),
                n => format!(" and {n} more"),
            };
            lines.push(format!(
                "missing shares {place}: render {}{more}{with_crop}",
                shares.join(", ")
            ));
        } else {
            lines.push(format!(
                "missing samples {}..{} of the {total} {place}: the shares given split it \
                 differently",
                gap.start, gap.end
            ));
        }
    }
    Ok(lines)
}

/// The indices of the shares of `count` (of `total` samples) that lie within `gap`, found
/// arithmetically (a split into 10^8 shares is not listed one by one): share i takes the
/// numbers from floor(i total / count), so it starts at or after `gap.start` when
/// i >= gap.start count / total, and ends by `gap.end` when (i + 1) total < (gap.end + 1) count.
fn shares_within(gap: &Range<u64>, count: u32, total: u64) -> Range<u32> {
    let (count, total) = (u128::from(count), u128::from(total));
    let first = (u128::from(gap.start) * count).div_ceil(total);
    let end = (u128::from(gap.end + 1) * count).div_ceil(total) - 1;
    first.min(count) as u32..end.clamp(first, count) as u32
}

/// What a sweep of the crops down the image finds.
#[derive(Debug, PartialEq)]
enum Sweep {
    /// Two crops that overlap.
    Overlap(Crop, Crop),
    /// The crops are disjoint, and these rectangles no crop covers: in each band between
    /// consecutive crop edges, the runs of columns no crop spans.
    Holes(Vec<Crop>),
}

/// Sweeps the bands between the crops' horizontal edges, top to bottom, keeping the crops that
/// span the band ordered by left edge: two crops that overlap are then neighbours in some band.
/// The work is the crops spanning each band summed over the bands (the number of crops, for a
/// grid of tiles), not the cells of the grid the edges make times the crops (cubic).
fn sweep(crops: &[Crop], width: u32, height: u32) -> Sweep {
    let mut starts: Vec<&Crop> = crops.iter().collect();
    starts.sort_unstable_by_key(|c| c.y0);
    let mut edges: Vec<u32> = crops.iter().flat_map(|c| [c.y0, c.y1]).chain([0, height]).collect();
    edges.sort_unstable();
    edges.dedup();
    let mut spanning: BTreeMap<(u32, u32, u32, u32), Crop> = BTreeMap::new();
    let mut next = 0;
    let mut holes = Vec::new();
    for band in edges.windows(2) {
        let (y0, y1) = (band[0], band[1]);
        spanning.retain(|_, c| c.y1 > y0);
        while let Some(&&crop) = starts.get(next).filter(|c| c.y0 <= y0) {
            spanning.insert((crop.x0, crop.x1, crop.y0, crop.y1), crop);
            next += 1;
        }
        let mut covered_to = 0;
        let mut previous: Option<Crop> = None;
        for crop in spanning.values() {
            if let Some(left) = previous.filter(|left| left.x1 > crop.x0) {
                return Sweep::Overlap(left, *crop);
            }
            if crop.x0 > covered_to {
                holes.push(Crop { x0: covered_to, x1: crop.x0, y0, y1 });
            }
            covered_to = crop.x1;
            previous = Some(*crop);
        }
        if covered_to < width {
            holes.push(Crop { x0: covered_to, x1: width, y0, y1 });
        }
    }
    Sweep::Holes(holes)
}

/// The items, joined, at most `LISTED` of them.
fn listed(items: &[String]) -> String {
    let mut text = items.iter().take(LISTED).cloned().collect::<Vec<_>>().join(", ");
    if items.len() > LISTED {
        let _ = write!(text, " and {} more", items.len() - LISTED);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shares_within_a_gap_are_those_a_search_finds() {
        for (count, total) in [(1, 1), (3, 10), (7, 7), (10, 1000), (13, 40)] {
            for start in 0..=total {
                for end in start..=total {
                    let searched: Vec<u32> = (0..count)
                        .filter(|&index| {
                            let numbers = Share { index, count }.numbers(total);
                            numbers.start >= start && numbers.end <= end
                        })
                        .collect();
                    let found: Vec<u32> = shares_within(&(start..end), count, total).collect();
                    assert_eq!(found, searched, "{count} shares of {total}, gap {start}..{end}");
                }
            }
        }
    }

    fn crop(s: &str) -> Crop {
        s.parse().unwrap()
    }

    #[test]
    fn the_holes_between_crops_are_listed_as_crops() {
        let holes =
            |crops: &[&str]| sweep(&crops.iter().map(|s| crop(s)).collect::<Vec<_>>(), 4, 3);
        assert_eq!(holes(&["0,4,0,2", "0,4,2,3"]), Sweep::Holes(vec![]));
        assert_eq!(holes(&["0,2,0,2"]), Sweep::Holes(vec![crop("2,4,0,2"), crop("0,4,2,3")]));
        assert_eq!(holes(&[]), Sweep::Holes(vec![crop("0,4,0,3")]));
        // A hole between two crops of a band, and one band whose crops meet edge to edge.
        assert_eq!(holes(&["0,1,0,3", "3,4,0,1", "1,4,1,3"]), Sweep::Holes(vec![crop("1,3,0,1")]));
    }

    #[test]
    fn overlapping_crops_are_found_in_the_band_they_share() {
        let crops = [crop("0,2,0,1"), crop("0,1,1,3"), crop("0,4,2,3")];
        assert_eq!(sweep(&crops, 4, 3), Sweep::Overlap(crops[1], crops[2]));
        // Overlapping only through a crop between them in the order of left edges.
        let crops = [crop("0,4,0,1"), crop("1,2,0,1"), crop("3,4,0,1")];
        assert_eq!(sweep(&crops, 4, 3), Sweep::Overlap(crops[0], crops[1]));
    }

    /// A grid of 300 x 300 one-pixel tiles, one missing: the sweep ends at once (the grid's
    /// cells times the crops would be 8 * 10^14 tests) and finds the one hole.
    #[test]
    fn many_crops_are_swept_in_near_linear_time() {
        let side = 300;
        let crops: Vec<Crop> = (0..side * side)
            .filter(|&i| i != side * side / 2 + side / 2)
            .map(|i| Crop { x0: i % side, x1: i % side + 1, y0: i / side, y1: i / side + 1 })
            .collect();
        let started = std::time::Instant::now();
        let found = sweep(&crops, side, side);
        assert!(started.elapsed().as_secs() < 5, "{:?}", started.elapsed());
        let (x, y) = (side / 2, side / 2);
        assert_eq!(found, Sweep::Holes(vec![Crop { x0: x, x1: x + 1, y0: y, y1: y + 1 }]));
    }
}
