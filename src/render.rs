//! Rendering: passes of samples over the image, rows in parallel on rayon, into a `Film`.
//!
//! Each pixel sample draws from `Sampler::new(seed, pixel, sample index)`, and a pixel's samples
//! are summed in index order, so the film is the same bit for bit whatever the thread count and
//! however the samples are split into passes.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::film::Film;
use crate::integrator::{Direct, Integrator, Path, Strategy};
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::scene::graph::IntegratorKind;

/// Receives progress from a render running on other threads; only the command line draws.
pub trait Progress: Sync {
    /// `samples` more pixel samples are done.
    fn advance(&self, samples: u64);
    /// Checked between passes, with an estimate of how long the next pass would take: true
    /// ends the render with the passes done so far.
    fn should_stop(&self, _next_pass_seconds: f64) -> bool {
        false
    }
}

/// Progress that nobody watches.
pub struct Silent;

impl Progress for Silent {
    fn advance(&self, _: u64) {}
}

#[derive(Debug, Clone, PartialEq)]
pub struct RenderStats {
    pub seconds: f64,
    /// Samples per pixel actually taken (fewer than asked if the render was stopped).
    pub samples_per_pixel: u32,
    pub dropped: u64,
}

impl RenderStats {
    pub fn samples_per_second(&self, film: &Film) -> f64 {
        (film.width * film.height) as f64 * f64::from(self.samples_per_pixel)
            / self.seconds.max(1e-9)
    }
}

/// Renders `scene` with its settings, in passes whose sample counts double (1, 1, 2, 4, ...), so
/// that a render stopped between passes is still an unbiased image.
pub fn render(scene: &Scene, progress: &dyn Progress) -> (Film, RenderStats) {
    match scene.settings.integrator {
        IntegratorKind::Direct => {
            render_with(scene, &Direct { max_depth: scene.settings.max_depth }, progress)
        }
        IntegratorKind::Path => render_with(
            scene,
            &Path { max_depth: scene.settings.max_depth, strategy: Strategy::Mis },
            progress,
        ),
    }
}

/// Renders with a given integrator (e.g. a `Path` with one sampling strategy, for tests).
pub fn render_with(
    scene: &Scene,
    integrator: &impl Integrator,
    progress: &dyn Progress,
) -> (Film, RenderStats) {
    let start = Instant::now();
    let settings = &scene.settings;
    let (width, height) = (settings.width as usize, settings.height as usize);
    let mut film = Film::new(width, height);
    let dropped = AtomicU64::new(0);
    let mut seconds_per_sample = 0.0;
    while film.samples < settings.samples {
        let pass = film.samples.max(1).min(settings.samples - film.samples);
        if film.samples > 0 && progress.should_stop(seconds_per_sample * f64::from(pass)) {
            break;
        }
        let pass_start = Instant::now();
        let samples = film.samples..film.samples + pass;
        film.sum
            .par_chunks_mut(width)
            .zip(film.sum_squares.par_chunks_mut(width))
            .enumerate()
            .for_each(|(y, (sum_row, squares_row))| {
                // The row's camera samples, pixel by pixel, each pixel's in index order.
                let mut camera_samples = (0..width).flat_map(|x| {
                    samples.clone().map(move |index| {
                        let pixel = (y * width + x) as u64;
                        let mut sampler = Sampler::new(settings.seed, pixel, u64::from(index));
                        let jitter = sampler.next_2d();
                        // A pinhole camera needs no lens sample.
                        let lens = if scene.camera.aperture > 0.0 {
                            sampler.next_2d()
                        } else {
                            glam::Vec2::ZERO
                        };
                        let ray = scene.camera.ray(
                            (x as f32 + jitter.x) / width as f32,
                            (y as f32 + jitter.y) / height as f32,
                            lens,
                        );
                        (ray, sampler)
                    })
                });
                let mut radiance = vec![glam::Vec3::ZERO; width * pass as usize];
                integrator.radiance_of_all(scene, &mut camera_samples, &mut radiance);
                let mut row_dropped = 0;
                let pixels = sum_row.iter_mut().zip(squares_row.iter_mut());
                for ((sum, squares), samples) in pixels.zip(radiance.chunks(pass as usize)) {
                    for radiance in samples {
                        if radiance.is_finite() {
                            *sum += *radiance;
                            *squares += *radiance * *radiance;
                        } else {
                            row_dropped += 1;
                        }
                    }
                }
                dropped.fetch_add(row_dropped, Ordering::Relaxed);
                progress.advance(width as u64 * u64::from(pass));
            });
        film.samples += pass;
        seconds_per_sample = pass_start.elapsed().as_secs_f64() / f64::from(pass);
    }
    film.dropped = dropped.into_inner();
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        samples_per_pixel: film.samples,
        dropped: film.dropped,
    };
    (film, stats)
}
