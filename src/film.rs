//! The film: per-pixel sums of radiance samples and of their squares, so that the image and an
//! estimate of its variance exist after any number of passes. Sums are kept in f64: a radiance
//! near f32's largest value still has a finite mean, and a million samples add up without the
//! rounding of f32. It carries the render's AOVs when they were asked for (`aov`), as pbrt's
//! G-buffer film does.

use glam::{DVec3, Vec3};

use crate::aov::AovImage;
use crate::image::Image;

#[derive(Debug, Clone)]
pub struct Film {
    pub width: usize,
    pub height: usize,
    pub sum: Vec<DVec3>,
    pub sum_squares: Vec<DVec3>,
    /// Samples taken in every pixel so far.
    pub samples: u32,
    /// Samples that were NaN or infinite, dropped (counted as zero radiance).
    pub dropped: u64,
    /// The AOVs of the samples it holds (`aov::render`), when asked for.
    pub aovs: Option<AovImage>,
}

/// Bytes a film of one pixel holds while rendering: its sums, and the sums of the pass under
/// way (kept apart so that a pass stopped half-way can be dropped).
pub const BYTES_PER_PIXEL: u64 = 4 * std::mem::size_of::<DVec3>() as u64;

impl Film {
    pub fn new(width: usize, height: usize) -> Self {
        Film {
            width,
            height,
            sum: vec![DVec3::ZERO; width * height],
            sum_squares: vec![DVec3::ZERO; width * height],
            samples: 0,
            dropped: 0,
            aovs: None,
        }
    }

    /// Adds a completed pass of `samples` samples per pixel.
    pub fn add_pass(&mut self, pass: &Film) {
        let sums = self.sum.iter_mut().zip(&mut self.sum_squares);
        for ((sum, squares), (pass_sum, pass_squares)) in
            sums.zip(pass.sum.iter().zip(&pass.sum_squares))
        {
            *sum += *pass_sum;
            *squares += *pass_squares;
        }
        self.samples += pass.samples;
        self.dropped += pass.dropped;
    }

    /// The mean radiance per pixel.
    pub fn image(&self) -> Image {
        let scale = 1.0 / f64::from(self.samples.max(1));
        Image {
            width: self.width,
            height: self.height,
            pixels: self.sum.iter().map(|s| (*s * scale).as_vec3()).collect(),
        }
    }

    /// The estimated variance of each pixel's mean (sample variance / n).
    pub fn variance_of_mean(&self) -> Vec<Vec3> {
        let n = f64::from(self.samples);
        if n < 2.0 {
            return vec![Vec3::splat(f32::INFINITY); self.sum.len()];
        }
        self.sum
            .iter()
            .zip(&self.sum_squares)
            .map(|(s, s2)| {
                let mean = *s / n;
                (((*s2 / n - mean * mean) * (n / (n - 1.0))).max(DVec3::ZERO) / n).as_vec3()
            })
            .collect()
    }
}
