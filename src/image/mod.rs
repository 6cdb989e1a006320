//! Linear HDR images and their files: OpenEXR, HDR PPM with `#MAX`, PNG.

use glam::Vec3;

/// Linear RGB radiance, rows top to bottom, columns left to right.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Image { width, height, pixels: vec![Vec3::ZERO; width * height] }
    }

    pub fn get(&self, x: usize, y: usize) -> Vec3 {
        self.pixels[y * self.width + x]
    }
}

/// What a render records in its output file's metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderInfo {
    pub samples_per_pixel: u32,
    pub integrator: String,
    pub seed: u64,
    pub seconds: f64,
}
