//! Whether a set of parts makes one image, from their headers alone: the same scene, seed,
//! settings, resolution and frame; crops that are equal or disjoint; within a crop, shares that
//! do not overlap; and together every sample of every pixel (or, with `--allow-partial`, what is
//! there, with the missing work listed). Messages name the files.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::ops::Range;

use super::part_file::PartHeader;
use crate::region::{Crop, Share};

/// How many missing pieces a message lists before "and N more".
const LISTED: usize = 8;

/// Refuses parts that do not belong to one render; the message names two files that differ.
pub fn check_same_render(parts: &[PartHeader]) -> Result<(), String> {
    let Some(first) = parts.first() else {
        return Err("error: no parts to merge".to_string());
    };
    for part in &parts[1..] {
        let differ = |what: &str, a: String, b: String| {
            Err(format!(
                "error: cannot merge {} and {}: they are parts of renders with other {what} ({a} \
                 and {b})",
                first.path.display(),
                part.path.display()
            ))
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
    }
    Ok(())
}

/// Refuses overlapping parts; returns what is missing (empty when the parts cover every sample
/// of every pixel), one line each, saying how to render it.
pub fn missing_work(parts: &[PartHeader]) -> Result<Vec<String>, String> {
    let mut tiles: BTreeMap<Crop, Vec<&PartHeader>> = BTreeMap::new();
    for part in parts {
        tiles.entry(part.region.crop).or_default().push(part);
    }
    let crops: Vec<&Crop> = tiles.keys().collect();
    for (i, a) in crops.iter().enumerate() {
        if let Some(b) = crops[i + 1..].iter().find(|b| a.intersects(b)) {
            return Err(format!(
                "error: {} (crop {a}) and {} (crop {b}) overlap: their crops share pixels (the \
                 parts of one tile must all have the same --crop, and tiles must not overlap)",
                tiles[*a][0].path.display(),
                tiles[*b][0].path.display()
            ));
        }
    }
    let mut missing = Vec::new();
    for (crop, tile) in &mut tiles {
        missing.extend(missing_shares(crop, tile)?);
    }
    let (width, height) = parts.first().map_or((0, 0), |p| (p.width, p.height));
    missing.extend(
        uncovered(tiles.keys().copied().collect(), width, height)
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
    Ok(missing)
}

/// The shares of one tile: refuses two that take the same samples; lists the samples no part
/// takes, as the shares to render.
fn missing_shares(crop: &Crop, tile: &mut [&PartHeader]) -> Result<Vec<String>, String> {
    let total = tile[0].region.total();
    tile.sort_by_key(|p| (p.region.share.numbers(total).start, p.region.share.count));
    let mut gaps: Vec<Range<u64>> = Vec::new();
    let mut covered = 0;
    for pair in tile.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if a.region.share.numbers(total).end > b.region.share.numbers(total).start {
            return Err(format!(
                "error: {} (share {}) and {} (share {}) overlap: they take the same samples of \
                 crop {crop}",
                a.path.display(),
                a.region.share,
                b.path.display(),
                b.region.share
            ));
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

/// The parts of a `width` x `height` image that no crop covers (the crops are disjoint), as
/// rectangles of the grid their edges make, joined along rows.
fn uncovered(crops: Vec<Crop>, width: u32, height: u32) -> Vec<Crop> {
    let area: u64 = crops.iter().map(Crop::pixels).sum();
    if area == u64::from(width) * u64::from(height) {
        return Vec::new();
    }
    let edges = |of: fn(&Crop) -> [u32; 2], end: u32| {
        let mut e: Vec<u32> = crops.iter().flat_map(of).chain([0, end]).collect();
        e.sort_unstable();
        e.dedup();
        e
    };
    let xs = edges(|c| [c.x0, c.x1], width);
    let ys = edges(|c| [c.y0, c.y1], height);
    let mut holes = Vec::new();
    for y in ys.windows(2) {
        let mut run: Option<Crop> = None;
        for x in xs.windows(2) {
            let cell = Crop { x0: x[0], x1: x[1], y0: y[0], y1: y[1] };
            if crops.iter().any(|c| c.intersects(&cell)) {
                holes.extend(run.take());
            } else {
                run = Some(run.map_or(cell, |r| Crop { x1: cell.x1, ..r }));
            }
        }
        holes.extend(run);
    }
    holes
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

    #[test]
    fn the_holes_between_crops_are_listed_as_crops() {
        let crop = |s: &str| s.parse::<Crop>().unwrap();
        assert!(uncovered(vec![crop("0,4,0,2"), crop("0,4,2,3")], 4, 3).is_empty());
        assert_eq!(uncovered(vec![crop("0,2,0,2")], 4, 3), vec![crop("2,4,0,2"), crop("0,4,2,3")]);
        assert_eq!(uncovered(vec![], 4, 3), vec![crop("0,4,0,3")]);
    }
}
