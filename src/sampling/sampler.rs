//! Sample values as a pure function of (seed, pixel, sample index, dimension), so that an image
//! never depends on the thread count or on the order in which pixels are rendered.
//!
//! In the first `SOBOL_DIMENSIONS`, each 2-D request is a point of the Sobol (0,2)-sequence,
//! Owen-scrambled, with the sample index shuffled per dimension pair ("padding", Burley 2020,
//! "Practical Hash-based Owen Scrambling"): the first 2^k samples of a pixel are stratified in
//! every pair of these dimensions, and dimensions are decorrelated from each other and from
//! other pixels. Later dimensions are independent uniform values from a hash.

use glam::Vec2;

/// Dimensions drawn from the scrambled Sobol sequence: the camera's (2, or 4 with a lens) and
/// a path's first bounce (7: light choice, light position, lobe, direction, roulette). They
/// carry nearly all of the gain from stratification, at a quarter of the cost of Sobol points
/// in every dimension. Measured on S3 and S4 at 16 and 64 spp against 4096-spp references:
/// Sobol everywhere is 16% slower and lowers RMSE by only 0-5%; independent values
/// everywhere double S3's RMSE.
const SOBOL_DIMENSIONS: u32 = 11;

/// The random stream of one pixel sample; `next_1d` / `next_2d` read its dimensions in order.
/// Small (24 bytes), for it moves with its camera sample into the lane that traces it: with the
/// Sobol dimensions' seeds hashed once per pixel and carried in it (120 bytes, a36f035), S1 ran
/// 1 % fewer instructions but took 7–9 % more CPU time, the moved bytes read back by wider
/// loads that stalled on store forwarding (perf); each draw hashes its dimension's seeds again.
#[derive(Debug, Clone)]
pub struct Sampler {
    /// Hash of (seed, pixel): selects the scrambles, shared by all samples of the pixel.
    pixel_hash: u64,
    /// The sample index, bit-reversed: the form its Owen scrambling works on.
    index_reversed: u32,
    /// Hash of (seed, pixel, sample index): selects the independent values.
    sample_hash: u64,
    dimension: u32,
}

/// What the samples of one pixel share: the hash of (seed, pixel) that selects their
/// scrambles. Made once per pixel, it saves each of the pixel's samples one hash.
#[derive(Debug, Clone, Copy)]
pub struct PixelSampler {
    pixel_hash: u64,
}

impl PixelSampler {
    pub fn new(seed: u64, pixel: u64) -> Self {
        PixelSampler { pixel_hash: mix64(mix64(seed ^ 0x9e37_79b9_7f4a_7c15) ^ pixel) }
    }

    /// The random stream of the pixel's sample `sample_index`.
    #[inline]
    pub fn sample(&self, sample_index: u64) -> Sampler {
        Sampler {
            pixel_hash: self.pixel_hash,
            // More than 2^32 samples per pixel is beyond any limit the renderer accepts.
            index_reversed: (sample_index as u32).reverse_bits(),
            sample_hash: mix64(self.pixel_hash ^ sample_index),
            dimension: 0,
        }
    }
}

impl Sampler {
    pub fn new(seed: u64, pixel: u64, sample_index: u64) -> Self {
        PixelSampler::new(seed, pixel).sample(sample_index)
    }

    /// A value in [0, 1): a scrambled van der Corput point.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        if self.dimension >= SOBOL_DIMENSIONS {
            return to_unit(self.next_independent()[0]);
        }
        let [shuffle, scramble] = self.next_seeds();
        let index = self.shuffled_index(shuffle);
        // The van der Corput point is reverse(index); scrambling it reverses it back first.
        to_unit(laine_karras(index, scramble).reverse_bits())
    }

    /// `next_1d()` where the value will be used, else 0 at no cost: either way the later
    /// dimensions stay where they are, so a path's decisions keep their dimensions.
    #[inline]
    pub fn next_1d_if(&mut self, needed: bool) -> f32 {
        if needed {
            self.next_1d()
        } else {
            self.dimension += 1;
            0.0
        }
    }

    /// A point in [0, 1)^2: a scrambled Sobol (0,2)-sequence point. Always inlined: a path
    /// draws one per light sample and per BSDF sample, and out of line (as LLVM left it) each
    /// call cost its call and the return of the point (callgrind of S3).
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        if self.dimension >= SOBOL_DIMENSIONS {
            // One hash gives both values; the second dimension is skipped to stay aligned.
            let [x, y] = self.next_independent();
            self.dimension += 1;
            return Vec2::new(to_unit(x), to_unit(y));
        }
        let [shuffle, scramble_x] = self.next_seeds();
        let [scramble_y, _] = self.next_seeds();
        let index = self.shuffled_index(shuffle);
        let y_reversed = (0..4)
            .fold(0, |y, byte| y ^ SOBOL_1_REVERSED[byte][(index >> (8 * byte)) as usize & 0xff]);
        // Both coordinates' bits reversed by one 64-bit reversal, which swaps the halves too:
        // x's scrambled bits go in the low half and come out in the high one.
        let scrambled = (u64::from(laine_karras(y_reversed, scramble_y)) << 32)
            | u64::from(laine_karras(index, scramble_x));
        let reversed = scrambled.reverse_bits();
        Vec2::new(to_unit((reversed >> 32) as u32), to_unit(reversed as u32))
    }

    /// `next_2d()` where the point will be used, else (0, 0) at no cost, the point's two
    /// dimensions skipped: a point light reads no sample, a delta lobe no direction sample, and
    /// the later dimensions stay where they are. A Sobol point is about 140 instructions
    /// (callgrind, docs/benchmarks.md).
    #[inline(always)]
    pub fn next_2d_if(&mut self, needed: bool) -> Vec2 {
        if needed {
            self.next_2d()
        } else {
            self.dimension += 2;
            Vec2::ZERO
        }
    }

    /// The sample index under an Owen scramble of its bits (the most significant bit decides
    /// the first split): each bit is flipped by a hash of the bits above it, which is
    /// Laine–Karras on the reversed bits (Burley 2020). A different scramble per dimension pair
    /// decorrelates the pairs ("padding") while the first 2^k indices stay a block of 2^k.
    #[inline]
    fn shuffled_index(&self, seed: u32) -> u32 {
        laine_karras(self.index_reversed, seed).reverse_bits()
    }

    /// Two independent uniform 32-bit values for the current dimension, then the next one.
    #[inline]
    fn next_independent(&mut self) -> [u32; 2] {
        let bits = mix64(self.sample_hash ^ dimension_key(self.dimension));
        self.dimension += 1;
        [bits as u32, (bits >> 32) as u32]
    }

    /// The two 32-bit seeds of a Sobol dimension (or of the one after them), a hash of (seed,
    /// pixel, dimension); each call moves to the next dimension.
    #[inline]
    fn next_seeds(&mut self) -> [u32; 2] {
        let bits = mix64(self.pixel_hash ^ dimension_key(self.dimension));
        self.dimension += 1;
        [bits as u32, (bits >> 32) as u32]
    }
}

/// `SOBOL_1_REVERSED[k][b]`: the contribution of byte `k` (equal to `b`) of the index to the
/// second dimension of Sobol's sequence, bit-reversed. The generator matrix's columns are
/// v_1 = 2^31, v_k = v_(k-1) ^ (v_(k-1) >> 1); the first dimension is the reversed index itself.
static SOBOL_1_REVERSED: [[u32; 256]; 4] = sobol_1_tables();

const fn sobol_1_tables() -> [[u32; 256]; 4] {
    let mut columns = [0u32; 32];
    let mut v = 1u32 << 31;
    let mut bit = 0;
    while bit < 32 {
        columns[bit] = v.reverse_bits();
        v ^= v >> 1;
        bit += 1;
    }
    let mut tables = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut value = 0;
        while value < 256 {
            let mut y = 0;
            let mut b = 0;
            while b < 8 {
                if value & (1 << b) != 0 {
                    y ^= columns[8 * byte + b];
                }
                b += 1;
            }
            tables[byte][value] = y;
            value += 1;
        }
        byte += 1;
    }
    tables
}

/// The Laine–Karras hash, which flips each bit by a hash of the bits below it: Owen scrambling
/// of a bit-reversed value (with Vegdahl's improved constants).
#[inline]
fn laine_karras(x: u32, seed: u32) -> u32 {
    let mut v = x.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// The top 24 bits as a float in [0, 1): exactly representable, never 1.
#[inline]
fn to_unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Spreads a dimension's index over 64 bits before it is mixed into a hash.
#[inline]
fn dimension_key(dimension: u32) -> u64 {
    u64::from(dimension).wrapping_mul(0xa076_1d64_78bd_642f)
}

/// A 64-bit finaliser with full avalanche (splitmix64's, Stafford's variant 13).
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_pure_functions_of_their_coordinates() {
        // Values from the Sobol dimensions and from the independent ones after them.
        let take = |seed, pixel, index| {
            let mut s = Sampler::new(seed, pixel, index);
            let values: Vec<f32> = (0..2 * SOBOL_DIMENSIONS).map(|_| s.next_1d()).collect();
            [values[0], values[1], values[2 * SOBOL_DIMENSIONS as usize - 1]]
        };
        assert_eq!(take(1, 2, 3), take(1, 2, 3));
        assert_ne!(take(1, 2, 3), take(0, 2, 3));
        assert_ne!(take(1, 2, 3), take(1, 3, 3));
        assert_ne!(take(1, 2, 3), take(1, 2, 4));
    }

    #[test]
    fn a_skipped_value_keeps_the_later_dimensions_in_place() {
        for dimension in [0, SOBOL_DIMENSIONS - 1, SOBOL_DIMENSIONS + 3] {
            let (mut drawn, mut skipped) = (Sampler::new(1, 2, 3), Sampler::new(1, 2, 3));
            for _ in 0..dimension {
                drawn.next_1d();
                skipped.next_1d();
            }
            assert_eq!(drawn.next_1d_if(true), skipped.clone().next_1d());
            assert_eq!(skipped.next_1d_if(false), 0.0);
            assert_eq!(drawn.next_2d(), skipped.next_2d(), "after dimension {dimension}");
            assert_eq!(drawn.next_2d_if(true), skipped.clone().next_2d());
            assert_eq!(skipped.next_2d_if(false), Vec2::ZERO);
            assert_eq!(drawn.next_1d(), skipped.next_1d(), "after dimension {dimension}");
        }
    }

    #[test]
    fn a_points_first_coordinate_is_the_one_dimensional_value_of_its_dimension() {
        // Both are the scrambled van der Corput point of the dimension's seeds.
        for index in 0..64 {
            let mut s = Sampler::new(2, 11, index);
            for _ in 0..SOBOL_DIMENSIONS.div_ceil(2) {
                let x = s.clone().next_1d();
                assert_eq!(s.next_2d().x, x, "sample {index}, dimension {}", s.dimension);
            }
        }
    }

    #[test]
    fn values_are_uniform_across_pixels() {
        // Per kind of dimension (Sobol, independent), 10 bins of 10000 values each: a
        // chi-square with 9 degrees of freedom stays below 27.9 with probability 0.999.
        let mut bins = [[0u32; 10]; 2];
        for pixel in 0..1000 {
            for index in 0..10 {
                let mut s = Sampler::new(7, pixel, index);
                for dimension in 0..SOBOL_DIMENSIONS + 10 {
                    let u = s.next_1d();
                    assert!((0.0..1.0).contains(&u));
                    // The last 10 Sobol dimensions and the first 10 independent ones.
                    if dimension >= SOBOL_DIMENSIONS - 10 {
                        bins[usize::from(dimension >= SOBOL_DIMENSIONS)][(u * 10.0) as usize] += 1;
                    }
                }
            }
        }
        let expected = 10000.0;
        for bins in bins {
            let chi2: f64 = bins.iter().map(|&n| (n as f64 - expected).powi(2) / expected).sum();
            assert!(chi2 < 27.9, "chi2 = {chi2}, bins = {bins:?}");
        }
    }

    #[test]
    fn the_first_power_of_two_samples_are_a_net_in_every_sobol_dimension_pair() {
        // A (0,4,2)-net: each of the 16 elementary intervals of area 1/16 of every shape
        // (1 x 1/16, 1/2 x 1/8, ..., 1/16 x 1) holds exactly one of the first 16 points.
        for pixel in [0, 17, 12345] {
            for dimension in 0..SOBOL_DIMENSIONS.div_ceil(2) {
                let points: Vec<Vec2> = (0..16)
                    .map(|i| {
                        let mut s = Sampler::new(3, pixel, i);
                        (0..dimension).for_each(|_| {
                            s.next_2d();
                        });
                        s.next_2d()
                    })
                    .collect();
                for log_x in 0..=4 {
                    let (nx, ny) = (1 << log_x, 1 << (4 - log_x));
                    let mut cells = [0; 16];
                    for p in &points {
                        cells[(p.y * ny as f32) as usize * nx + (p.x * nx as f32) as usize] += 1;
                    }
                    assert!(
                        cells.iter().all(|&c| c == 1),
                        "pixel {pixel} dim {dimension} {nx}x{ny}"
                    );
                }
            }
        }
    }

    #[test]
    fn one_dimensional_values_are_stratified() {
        let mut values: Vec<f32> = (0..8).map(|i| Sampler::new(5, 9, i).next_1d()).collect();
        values.sort_by(f32::total_cmp);
        for (i, v) in values.iter().enumerate() {
            assert_eq!((v * 8.0) as usize, i, "{values:?}");
        }
    }
}
