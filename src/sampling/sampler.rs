//! Sample values as a pure function of (seed, pixel, sample index, dimension), so that an image
//! never depends on the thread count or on the order in which pixels are rendered.
//!
//! Each 2-D request is a point of the Sobol (0,2)-sequence, Owen-scrambled, with the sample index
//! shuffled per dimension pair ("padding", Burley 2020, "Practical Hash-based Owen Scrambling"):
//! the first 2^k samples of a pixel are stratified in every pair of dimensions, and dimensions
//! are decorrelated from each other and from other pixels.

use glam::Vec2;

/// The random stream of one pixel sample; `next_1d` / `next_2d` read its dimensions in order.
#[derive(Debug, Clone)]
pub struct Sampler {
    /// Hash of (seed, pixel): selects the scrambles, shared by all samples of the pixel.
    pixel_hash: u64,
    /// The sample index, bit-reversed: the form its Owen scrambling works on.
    index_reversed: u32,
    dimension: u32,
}

impl Sampler {
    pub fn new(seed: u64, pixel: u64, sample_index: u64) -> Self {
        Sampler {
            pixel_hash: mix64(mix64(seed ^ 0x9e37_79b9_7f4a_7c15) ^ pixel),
            // More than 2^32 samples per pixel is beyond any limit the renderer accepts.
            index_reversed: (sample_index as u32).reverse_bits(),
            dimension: 0,
        }
    }

    /// A value in [0, 1): a scrambled van der Corput point.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let [shuffle, scramble] = self.next_seeds();
        let index = self.shuffled_index(shuffle);
        // The van der Corput point is reverse(index); scrambling it reverses it back first.
        to_unit(laine_karras(index, scramble).reverse_bits())
    }

    /// A point in [0, 1)^2: a scrambled Sobol (0,2)-sequence point.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let [shuffle, scramble_x] = self.next_seeds();
        let [scramble_y, _] = self.next_seeds();
        let index = self.shuffled_index(shuffle);
        let y_reversed = (0..4)
            .fold(0, |y, byte| y ^ SOBOL_1_REVERSED[byte][(index >> (8 * byte)) as usize & 0xff]);
        Vec2::new(
            to_unit(laine_karras(index, scramble_x).reverse_bits()),
            to_unit(laine_karras(y_reversed, scramble_y).reverse_bits()),
        )
    }

    /// The sample index under an Owen scramble of its bits (the most significant bit decides
    /// the first split): each bit is flipped by a hash of the bits above it, which is
    /// Laine–Karras on the reversed bits (Burley 2020). A different scramble per dimension pair
    /// decorrelates the pairs ("padding") while the first 2^k indices stay a block of 2^k.
    #[inline]
    fn shuffled_index(&self, seed: u32) -> u32 {
        laine_karras(self.index_reversed, seed).reverse_bits()
    }

    /// Two independent 32-bit seeds; each call moves to the next dimension.
    #[inline]
    fn next_seeds(&mut self) -> [u32; 2] {
        let bits =
            mix64(self.pixel_hash ^ u64::from(self.dimension).wrapping_mul(0xa076_1d64_78bd_642f));
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
        let take = |seed, pixel, index| {
            let mut s = Sampler::new(seed, pixel, index);
            [s.next_1d(), s.next_1d(), s.next_2d().x]
        };
        assert_eq!(take(1, 2, 3), take(1, 2, 3));
        assert_ne!(take(1, 2, 3), take(0, 2, 3));
        assert_ne!(take(1, 2, 3), take(1, 3, 3));
        assert_ne!(take(1, 2, 3), take(1, 2, 4));
    }

    #[test]
    fn values_are_uniform_across_pixels() {
        // 10 bins of 10000 values each: a chi-square with 9 degrees of freedom stays below
        // 27.9 with probability 0.999.
        let mut bins = [0u32; 10];
        for pixel in 0..1000 {
            for index in 0..10 {
                let mut s = Sampler::new(7, pixel, index);
                for _ in 0..10 {
                    let u = s.next_1d();
                    assert!((0.0..1.0).contains(&u));
                    bins[(u * 10.0) as usize] += 1;
                }
            }
        }
        let expected = 10000.0;
        let chi2: f64 = bins.iter().map(|&n| (n as f64 - expected).powi(2) / expected).sum();
        assert!(chi2 < 27.9, "chi2 = {chi2}, bins = {bins:?}");
    }

    #[test]
    fn the_first_power_of_two_samples_are_a_net_in_every_dimension_pair() {
        // A (0,4,2)-net: each of the 16 elementary intervals of area 1/16 of every shape
        // (1 x 1/16, 1/2 x 1/8, ..., 1/16 x 1) holds exactly one of the first 16 points.
        for pixel in [0, 17, 12345] {
            for dimension in 0..6 {
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
