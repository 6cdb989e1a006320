//! The per-sample rung of the integrator ladder: an integrator that estimates the radiance of
//! each camera sample on its own (`SampleIntegrator`) renders a region in passes of samples
//! over the image, rows in parallel on rayon, into a `Film`.
//!
//! Each pixel sample draws from `Sampler::new(seed, pixel, sample index)`, and a pixel's samples
//! are summed in index order, so the film is the same bit for bit whatever the thread count and
//! however the samples are split into passes.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::film::Film;
use crate::progress::{Progress, RenderStats};
use crate::ray::Ray;
use crate::region::Region;
use crate::sampling::Sampler;
use crate::scene::{Scene, camera_samples};

/// The most samples one task of a pass traces (and holds the radiance of) between two looks at
/// `Progress::should_abandon`: a few milliseconds of work, whatever the image or pass size.
pub const TASK_SAMPLES: usize = 4096;

/// A camera sample whose ray leaves the camera: where its radiance goes among a task's
/// samples (`slot`), the ray, and the sampler that drew it, to draw the rest of its path.
#[derive(Clone)]
pub struct CameraSample {
    pub slot: usize,
    pub ray: Ray,
    pub sampler: Sampler,
}

/// An estimator of the radiance arriving along camera rays, one camera sample at a time.
pub trait SampleIntegrator: Sync {
    /// An estimate of the radiance arriving at the ray's origin from along `-ray.dir`.
    fn radiance(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Vec3;

    /// The radiance of each camera sample into `radiance[sample.slot]`; the slots of samples
    /// without a ray (where the film is dark) are not among them and stay as they are.
    /// Integrators that trace several paths at once override this.
    fn radiance_of_all(&self, scene: &Scene, samples: &[CameraSample], radiance: &mut [Vec3]) {
        for CameraSample { slot, ray, sampler } in samples {
            radiance[*slot] = self.radiance(scene, *ray, &mut sampler.clone());
        }
    }
}

/// The black film of a render stopped before its first pass.
pub fn stopped_before_a_pass(scene: &Scene, start: Instant) -> (Film, RenderStats) {
    let film = Film::new(scene.settings.width as usize, scene.settings.height as usize);
    (film, RenderStats { seconds: start.elapsed().as_secs_f64(), samples_per_pixel: 0, dropped: 0 })
}

/// Renders a region with `integrator` in passes whose sample counts double (1, 1, 2, 4, ...,
/// the last one shortened to end at the sample count or where `Progress::pass_limit` says), so
/// that a render stopped between passes is still an unbiased image.
pub fn render_samples(
    scene: &Scene,
    integrator: &impl SampleIntegrator,
    region: &Region,
    progress: &dyn Progress,
) -> (Film, RenderStats) {
    let start = Instant::now();
    let (width, height) = (region.crop.width() as usize, region.crop.height() as usize);
    let mut film = Film::new(width, height);
    let mut pass_film = Film::new(width, height);
    let mut seconds_per_sample = 0.0;
    let most = region.most_samples();
    while film.samples < most {
        let mut pass = film.samples.max(1).min(most - film.samples);
        if film.samples > 0 {
            match progress.pass_limit(seconds_per_sample) {
                Some(0) => break,
                Some(limit) => pass = pass.min(limit),
                None => {}
            }
        }
        let pass_start = Instant::now();
        if !render_pass(
            scene,
            integrator,
            progress,
            region,
            film.samples..film.samples + pass,
            &mut pass_film,
        ) {
            break;
        }
        film.add_pass(&pass_film);
        progress.pass_done(&film);
        seconds_per_sample = pass_start.elapsed().as_secs_f64() / f64::from(pass);
    }
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        samples_per_pixel: film.samples,
        dropped: film.dropped,
    };
    (film, stats)
}

/// Renders the samples `offsets` of each pixel's share (its sample indices
/// `Region::samples_of(pixel)`, from the first) into `pass` (overwritten), rows in parallel, each
/// row in tasks of at most `TASK_SAMPLES` samples: several pixels' samples together (so that
/// integrators tracing paths in lanes have enough of them), or a part of one pixel's. A pixel's
/// samples are summed in index order. False when the pass was abandoned.
fn render_pass(
    scene: &Scene,
    integrator: &impl SampleIntegrator,
    progress: &dyn Progress,
    region: &Region,
    offsets: Range<u32>,
    pass: &mut Film,
) -> bool {
    let (x0, y0) = (region.crop.x0 as usize, region.crop.y0 as usize);
    let width = pass.width;
    let count = (offsets.end - offsets.start) as usize;
    let pixels_per_task = (TASK_SAMPLES / count).clamp(1, width);
    let samples_per_task = count.min(TASK_SAMPLES) as u32;
    let abandoned = AtomicBool::new(false);
    let dropped = AtomicU64::new(0);
    let layout = region.layout();
    pass.sum
        .par_chunks_mut(width)
        .zip(pass.sum_squares.par_chunks_mut(width))
        .enumerate()
        .for_each(|(row, (sum_row, squares_row))| {
            sum_row.fill(DVec3::ZERO);
            squares_row.fill(DVec3::ZERO);
            let y = y0 + row;
            let mut radiance = vec![Vec3::ZERO; pixels_per_task * samples_per_task as usize];
            // A task's camera samples, made before they are traced: taken one at a time from
            // an iterator behind `dyn`, each was returned through memory and its copy into a
            // lane waited on the narrower stores that wrote it (perf of S1: 11 % of
            // `Direct::radiance_of_all`'s samples).
            let mut camera = Vec::with_capacity(radiance.len());
            let mut task: Vec<(usize, Range<u32>)> = Vec::with_capacity(pixels_per_task);
            for first_x in (0..width).step_by(pixels_per_task) {
                let columns = first_x..(first_x + pixels_per_task).min(width);
                for first in offsets.clone().step_by(samples_per_task as usize) {
                    if abandoned.load(Ordering::Relaxed) || progress.should_abandon() {
                        abandoned.store(true, Ordering::Relaxed);
                        return;
                    }
                    let last = (first + samples_per_task).min(offsets.end);
                    // Each pixel's sample indices in this task: offsets first..last of its share.
                    task.clear();
                    task.extend(columns.clone().map(|column| {
                        let share = layout.samples_of((row * width + column) as u64);
                        let start = (share.start + first).min(share.end);
                        (column, start..(share.start + last).min(share.end))
                    }));
                    // The task's camera samples, pixel by pixel, each pixel's in index order;
                    // those without a ray (where the film is dark) are traced by no integrator
                    // and stay black.
                    camera.clear();
                    let mut slot = 0;
                    for (column, indices) in &task {
                        let pixel = camera_samples(scene, x0 + column, y);
                        for index in indices.clone() {
                            if let (Some(ray), sampler) = pixel.sample(index) {
                                camera.push(CameraSample { slot, ray, sampler });
                            }
                            slot += 1;
                        }
                    }
                    let taken = slot; // every sample index took a slot, with a ray or not
                    let radiance = &mut radiance[..taken];
                    radiance.fill(Vec3::ZERO);
                    integrator.radiance_of_all(scene, &camera, radiance);
                    let mut task_dropped = 0;
                    let mut samples = radiance.iter();
                    for (column, indices) in &task {
                        let (sum, squares) = (&mut sum_row[*column], &mut squares_row[*column]);
                        for radiance in samples.by_ref().take(indices.len()) {
                            if radiance.is_finite() {
                                let radiance = radiance.as_dvec3();
                                *sum += radiance;
                                *squares += radiance * radiance;
                            } else {
                                task_dropped += 1;
                            }
                        }
                    }
                    dropped.fetch_add(task_dropped, Ordering::Relaxed);
                    progress.advance(taken as u64);
                }
            }
        });
    pass.samples = offsets.end - offsets.start;
    pass.dropped = dropped.into_inner();
    !abandoned.into_inner()
}
