//! What a snapshot stores of a render: each pixel's mean radiance and the variance of that mean.

use glam::Vec3;

use crate::film::Film;

/// A render as an estimate: per pixel, the mean of its samples and the estimated variance of
/// that mean (sample variance / n), rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    pub width: usize,
    pub height: usize,
    pub mean: Vec<Vec3>,
    pub variance: Vec<Vec3>,
    pub samples_per_pixel: u32,
}

/// A render of fewer than two samples per pixel, which has no variance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("a snapshot needs at least 2 samples per pixel for its variance (the render has {0})")]
pub struct TooFewSamples(pub u32);

impl Estimate {
    /// The film's estimate; it needs at least two samples per pixel for a variance.
    pub fn from_film(film: &Film) -> Result<Estimate, TooFewSamples> {
        if film.samples < 2 {
            return Err(TooFewSamples(film.samples));
        }
        Ok(Estimate {
            width: film.width,
            height: film.height,
            mean: film.image().pixels,
            variance: film.variance_of_mean(),
            samples_per_pixel: film.samples,
        })
    }
}
