//! Sample values as a pure function of (seed, pixel, sample index, dimension), so that an image
//! never depends on the thread count or on the order in which pixels are rendered.

use glam::Vec2;

/// The random stream of one pixel sample: dimension `d` of sample `i` of pixel `p` is
/// `hash(seed, p, i, d)`, read in order by `next_1d`/`next_2d`.
#[derive(Debug, Clone)]
pub struct Sampler {
    stream: u64,
    dimension: u32,
}

impl Sampler {
    pub fn new(seed: u64, pixel: u64, sample_index: u64) -> Self {
        let stream = mix64(mix64(seed ^ 0x9e37_79b9_7f4a_7c15) ^ pixel);
        Sampler {
            stream: mix64(stream ^ sample_index.wrapping_mul(0xd1b5_4a32_d192_ed03)),
            dimension: 0,
        }
    }

    /// A value in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let bits =
            mix64(self.stream ^ u64::from(self.dimension).wrapping_mul(0xa076_1d64_78bd_642f));
        self.dimension += 1;
        // The top 24 bits make every value exactly representable and below 1.
        (bits >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }
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
            [s.next_1d(), s.next_1d(), s.next_1d()]
        };
        assert_eq!(take(1, 2, 3), take(1, 2, 3));
        assert_ne!(take(1, 2, 3), take(0, 2, 3));
        assert_ne!(take(1, 2, 3), take(1, 3, 3));
        assert_ne!(take(1, 2, 3), take(1, 2, 4));
    }

    #[test]
    fn values_are_uniform_in_unit_interval() {
        // 10 bins of 10000 values each: a chi-square with 9 degrees of freedom stays below
        // 27.9 with probability 0.999.
        let mut bins = [0u32; 10];
        for pixel in 0..1000 {
            let mut s = Sampler::new(7, pixel, 0);
            for _ in 0..100 {
                let u = s.next_1d();
                assert!((0.0..1.0).contains(&u));
                bins[(u * 10.0) as usize] += 1;
            }
        }
        let expected = 10000.0;
        let chi2: f64 = bins
            .iter()
            .map(|&n| (n as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 27.9, "chi2 = {chi2}, bins = {bins:?}");
    }
}
