//! The statistical comparison of two renders of a scene, tile by tile.
//!
//! For a tile of P pixels the mean of pixel means m has variance Σ var(pixel mean) / P², so the
//! difference of two independent renders' tile means, d = m_new − m_ref, has standard error
//! se = √(var_ref + var_new). Under "same picture", z = d / se is close to standard normal (the
//! central limit theorem over the tile's samples), and |z| > `Z_BOUND` fails the tile. This is
//! the z-test of Mitsuba 3's render tests, applied to tiles rather than pixels so that each test
//! sees thousands of samples. Owen-scrambled samples make a render's real error smaller than
//! its sample variance says, which only makes the test more cautious.
//!
//! Tiles come in a pyramid: squares of `FINEST_TILE` pixels, then twice, four times as wide, up
//! to one tile over the whole image, so a small local change and a faint global one (a light
//! 5 % brighter) are both found.

use glam::Vec3;

use super::Estimate;

/// Side of the smallest tiles, in pixels.
pub const FINEST_TILE: usize = 8;

/// The bound on |z|: a tile's three channel tests together fail a matching tile with
/// probability 1e-4. Per channel α = 1 − (1 − 1e-4)^(1/3) = 3.3334e-5 (Šidák), two-sided:
/// Φ⁻¹(1 − α/2) = 4.1494.
pub const Z_BOUND: f32 = 4.1494;

/// A floor on the standard error, relative to the tile's mean: it stands for the rounding of
/// the sums, so a region without noise (a flat background, an emitter seen directly) rendered on
/// another CPU still matches.
const ROUNDING: f32 = 1e-4;

/// A rectangle of pixels, `x0 <= x < x1`, `y0 <= y < y1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub x0: usize,
    pub x1: usize,
    pub y0: usize,
    pub y1: usize,
}

impl Rect {
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }

    pub fn contains(&self, x: usize, y: usize) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }
}

/// One tile's test: its z-score per channel (new minus reference, in standard errors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TileTest {
    pub rect: Rect,
    /// The tile's level in the pyramid: its side is `FINEST_TILE` · 2^level.
    pub level: u32,
    pub z: Vec3,
}

impl TileTest {
    pub fn fails(&self) -> bool {
        self.z.abs().max_element() > Z_BOUND
    }

    /// The z-score of the channel farthest from zero, with its sign.
    pub fn worst_z(&self) -> f32 {
        let z = self.z.to_array();
        z.into_iter().fold(0.0, |worst, z| if z.abs() > worst.abs() { z } else { worst })
    }
}

/// Every tile of the pyramid, finest first.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    pub width: usize,
    pub height: usize,
    pub tiles: Vec<TileTest>,
}

impl Comparison {
    pub fn failing(&self) -> impl Iterator<Item = &TileTest> {
        self.tiles.iter().filter(|t| t.fails())
    }

    pub fn matches(&self) -> bool {
        self.failing().next().is_none()
    }

    /// The tile with the largest |z|.
    pub fn worst(&self) -> Option<&TileTest> {
        self.tiles.iter().max_by(|a, b| a.worst_z().abs().total_cmp(&b.worst_z().abs()))
    }

    /// Per pixel, the z-score of the finest tile that holds it divided by `Z_BOUND` (the channel
    /// farthest from zero, with its sign): above 1 in magnitude where that tile fails.
    pub fn pixel_scores(&self) -> Vec<f32> {
        let mut scores = vec![0.0f32; self.width * self.height];
        for tile in self.tiles.iter().filter(|t| t.level == 0) {
            let Rect { x0, x1, y0, y1 } = tile.rect;
            for y in y0..y1 {
                scores[y * self.width + x0..y * self.width + x1].fill(tile.worst_z() / Z_BOUND);
            }
        }
        scores
    }
}

/// A snapshot and a render of other sizes, which cannot be compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the snapshot is {}x{} and the render {}x{}", snapshot.0, snapshot.1, render.0, render.1)]
pub struct SizesDiffer {
    pub snapshot: (usize, usize),
    pub render: (usize, usize),
}

/// Compares a new render with the reference, tile by tile; the sizes must agree.
pub fn compare(reference: &Estimate, new: &Estimate) -> Result<Comparison, SizesDiffer> {
    if (reference.width, reference.height) != (new.width, new.height) {
        return Err(SizesDiffer {
            snapshot: (reference.width, reference.height),
            render: (new.width, new.height),
        });
    }
    let (width, height) = (new.width, new.height);
    let mut tiles = Vec::new();
    let mut level = 0;
    loop {
        let side = FINEST_TILE << level;
        for y0 in (0..height).step_by(side) {
            for x0 in (0..width).step_by(side) {
                let rect = Rect { x0, x1: (x0 + side).min(width), y0, y1: (y0 + side).min(height) };
                tiles.push(TileTest { rect, level, z: z_score(reference, new, &rect) });
            }
        }
        if side >= width && side >= height {
            break;
        }
        level += 1;
    }
    Ok(Comparison { width, height, tiles })
}

/// The z-score of the difference of the two renders' means over `rect`, per channel.
fn z_score(reference: &Estimate, new: &Estimate, rect: &Rect) -> Vec3 {
    // Sums in f64: a tile may hold many pixels, and its variance is a sum of small terms.
    let mut sums = [[0.0f64; 3]; 4];
    for y in rect.y0..rect.y1 {
        for i in y * new.width + rect.x0..y * new.width + rect.x1 {
            for (sum, value) in sums.iter_mut().zip([
                reference.mean[i],
                reference.variance[i],
                new.mean[i],
                new.variance[i],
            ]) {
                for (s, v) in sum.iter_mut().zip(value.to_array()) {
                    *s += f64::from(v);
                }
            }
        }
    }
    let pixels = ((rect.x1 - rect.x0) * (rect.y1 - rect.y0)) as f64;
    let [mean_ref, var_ref, mean_new, var_new] = sums;
    let z = std::array::from_fn(|c| {
        let (a, b) = (mean_ref[c] / pixels, mean_new[c] / pixels);
        let rounding = f64::from(ROUNDING) * a.abs().max(b.abs());
        let variance = (var_ref[c] + var_new[c]) / (pixels * pixels) + rounding * rounding;
        if variance > 0.0 { ((b - a) / variance.sqrt()) as f32 } else { 0.0 }
    });
    Vec3::from_array(z)
}
