//! The film: per-pixel sums of radiance samples and of their squares, so that the image and an
//! estimate of its variance exist after any number of passes.

use glam::Vec3;

use crate::image::Image;

#[derive(Debug, Clone)]
pub struct Film {
    pub width: usize,
    pub height: usize,
    pub sum: Vec<Vec3>,
    pub sum_squares: Vec<Vec3>,
    /// Samples taken in every pixel so far.
    pub samples: u32,
    /// Samples that were NaN or infinite, dropped (counted as zero radiance).
    pub dropped: u64,
}

impl Film {
    pub fn new(width: usize, height: usize) -> Self {
        Film {
            width,
            height,
            sum: vec![Vec3::ZERO; width * height],
            sum_squares: vec![Vec3::ZERO; width * height],
            samples: 0,
            dropped: 0,
        }
    }

    /// The mean radiance per pixel.
    pub fn image(&self) -> Image {
        let scale = 1.0 / self.samples.max(1) as f32;
        Image {
            width: self.width,
            height: self.height,
            pixels: self.sum.iter().map(|s| *s * scale).collect(),
        }
    }

    /// The estimated variance of each pixel's mean (sample variance / n).
    pub fn variance_of_mean(&self) -> Vec<Vec3> {
        let n = self.samples as f32;
        if n < 2.0 {
            return vec![Vec3::splat(f32::INFINITY); self.sum.len()];
        }
        self.sum
            .iter()
            .zip(&self.sum_squares)
            .map(|(s, s2)| {
                let mean = *s / n;
                ((*s2 / n - mean * mean) * (n / (n - 1.0))).max(Vec3::ZERO) / n
            })
            .collect()
    }
}
