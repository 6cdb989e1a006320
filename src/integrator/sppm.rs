//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009; `docs/language.md`'s `sppm`).
//! Each iteration j traces one camera path per pixel through delta lobes to its visible point,
//! adding emission on the way and next-event estimation there; then `photons` photons of pass j,
//! whose deposits after one bounce or more within a pixel's radius add to its flux. Per pixel,
//! with M photons found this iteration and alpha = 2/3 (pbrt-v4's SPPMIntegrator, 13.5):
//!   N' = N + alpha M,   R' = R sqrt(N' / (N + M)),   tau' = (tau + Phi) (R' / R)^2,
//! and after n iterations L = (sum of direct) / n + tau / (n pi R^2) (each pass's photons carry
//! the lights' whole power, so n passes divide by n).
//!
//! Memory is bounded by the image, whatever the radius or the photon count: each photon task
//! adds what it finds into its own per-pixel sums (not a list of deposits), and as many tasks
//! run together as there are threads (`bytes_per_pixel` counts it all before the render).

use std::f32::consts::PI;
use std::time::Instant;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::direct::{
    Vertex, WhittedPath, arrive, direct_from_environment, follow, lit_one_at_a_time,
};
use super::missed_light::MissedLight;
use super::{Integrator, PHOTON_TASK};
use crate::film::{BYTES_PER_PIXEL, Film};
use crate::photon::{Arrival, Emission, HashGrid, trace_photon};
use crate::progress::{Progress, RenderStats};
use crate::region::Region;
use crate::scene::{Scene, camera_sample};

/// alpha: the fraction of each iteration's photons a pixel keeps as its radius shrinks.
const ALPHA: f32 = 2.0 / 3.0;

/// The flux Phi and photon count M a pixel gathers from some photons.
#[derive(Clone, Copy, Default)]
struct Gathered {
    flux: Vec3,
    found: u32,
}

/// Photon tasks traced together before their sums are added up in task order: one a thread, so
/// that their per-pixel sums take threads x pixels, and the image does not depend on the threads.
fn tasks_per_wave() -> usize {
    rayon::current_num_threads().max(1)
}

/// The most memory an `sppm` render takes per pixel on this thread pool: the film, each
/// pixel's state, camera path and visible point (twice: by rows, then flattened), its sphere
/// in the hash grid, and the sums of the iteration and of each task under way.
pub fn bytes_per_pixel() -> u64 {
    let per_pixel = size_of::<PixelState>()
        + 2 * size_of::<CameraPath>()
        + size_of::<(u32, Vec3, f32)>()
        + HashGrid::BYTES_PER_SPHERE
        + (1 + tasks_per_wave()) * size_of::<Gathered>();
    BYTES_PER_PIXEL + per_pixel as u64
}

/// Camera rays across the image whose hits measure the scene's extent for `radius_warning`.
const EXTENT_RAYS: usize = 32;

/// A warning when `photon_radius` is large against the scene the camera sees (the diagonal of
/// the box holding the first hits of a 32 x 32 grid of camera rays): above a tenth of it, the
/// image blurs and each photon is gathered by a large share of the pixels; usually the scene's
/// scale is not what the radius assumed.
pub fn radius_warning(scene: &Scene) -> Option<String> {
    let (width, height) = (scene.settings.width as usize, scene.settings.height as usize);
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for j in 0..EXTENT_RAYS {
        for i in 0..EXTENT_RAYS {
            let (x, y) =
                ((2 * i + 1) * width / (2 * EXTENT_RAYS), (2 * j + 1) * height / (2 * EXTENT_RAYS));
            let (ray, _) = camera_sample(scene, x, y, 0);
            if let Some(hit) = ray.and_then(|ray| scene.intersect(&ray)) {
                (lo, hi) = (lo.min(hit.point), hi.max(hit.point));
            }
        }
    }
    let extent = (hi - lo).length();
    let radius = scene.settings.photon_radius;
    (extent.is_finite() && radius > extent / 10.0).then(|| {
        format!(
            "warning: photon_radius {radius} is large against the scene: the camera sees \
             surfaces across {extent:.3} scene units, and every pixel gathers photons within \
             {radius} of what it sees, so the image blurs and takes long. Is the scene's scale \
             right? A radius of about a hundredth of it ({:.3}) is a usual start",
            extent / 100.0
        )
    })
}

/// Where a camera path stopped on a gathered lobe, the BSDF there, and the throughput it
/// brought there.
struct VisiblePoint {
    vertex: Vertex,
    beta: Vec3,
}

impl VisiblePoint {
    /// Light a photon arriving from `wi` with `power` sends along the camera path.
    fn flux(&self, wi: Vec3, power: Vec3) -> Vec3 {
        let Vertex { bsdf, wo, gathered, .. } = &self.vertex;
        self.beta * bsdf.eval_lobes(*wo, wi, *gathered) * power
    }
}

/// A pixel's camera path of one iteration: emission and direct light it found, and its visible
/// point if it reached one.
type CameraPath = (Vec3, Option<VisiblePoint>);

/// A pixel's progressive state.
#[derive(Clone, Copy)]
struct PixelState {
    radius: f32,
    /// N: photons kept so far.
    photons: f32,
    /// tau: flux gathered within the current radius.
    flux: DVec3,
    /// The sum over iterations of emission seen and direct light.
    direct: DVec3,
}

/// Stochastic progressive photon mapping: it renders whole images (every pixel reads the
/// same photons), by iterations of its own.
pub struct Sppm;

impl Integrator for Sppm {
    fn render(
        &self,
        scene: &Scene,
        region: &Region,
        progress: &dyn Progress,
    ) -> (Film, RenderStats) {
        let s = &scene.settings;
        assert!(
            *region == Region::whole(s.width, s.height, s.samples),
            "sppm renders whole images"
        );
        render(scene, progress)
    }

    fn samples_are_independent(&self) -> bool {
        false
    }
}

fn render(scene: &Scene, progress: &dyn Progress) -> (Film, RenderStats) {
    let start = Instant::now();
    let settings = &scene.settings;
    let (width, height) = (settings.width as usize, settings.height as usize);
    let emission = Emission::new(&scene.lights, settings.photons());
    let initial = PixelState {
        radius: settings.photon_radius,
        photons: 0.0,
        flux: DVec3::ZERO,
        direct: DVec3::ZERO,
    };
    let mut pixels = vec![initial; width * height];
    let missed = MissedLight::of(scene);
    let mut iterations = 0;
    while iterations < settings.samples {
        let iteration_start = Instant::now();
        if !iterate(scene, &emission, missed.as_ref(), iterations, &mut pixels, progress) {
            break;
        }
        iterations += 1;
        // Shown at the same doubling counts as the passes of the other integrators.
        if iterations.is_power_of_two() {
            progress.pass_done(&film_of(&pixels, iterations, width, height));
        }
        let seconds = iteration_start.elapsed().as_secs_f64();
        if iterations < settings.samples && progress.pass_limit(seconds) == Some(0) {
            break;
        }
    }
    let film = film_of(&pixels, iterations, width, height);
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        samples_per_pixel: iterations,
        dropped: 0,
    };
    (film, stats)
}

/// The image of `iterations` iterations' pixel states.
fn film_of(pixels: &[PixelState], iterations: u32, width: usize, height: usize) -> Film {
    let mut film = Film::new(width, height);
    let n = f64::from(iterations.max(1));
    for (i, pixel) in pixels.iter().enumerate() {
        let area = f64::from(PI) * f64::from(pixel.radius).powi(2);
        let radiance = pixel.direct / n + pixel.flux / (n * area);
        // The film holds the estimate as n equal samples (progressive estimates have no
        // per-sample variance).
        film.sum[i] = radiance * f64::from(iterations);
        film.sum_squares[i] = radiance * radiance * f64::from(iterations);
    }
    film.samples = iterations;
    film
}

/// One iteration into `pixels`; false (and `pixels` untouched) if `progress` asked to stop.
fn iterate(
    scene: &Scene,
    emission: &Emission,
    missed: Option<&MissedLight>,
    iteration: u32,
    pixels: &mut [PixelState],
    progress: &dyn Progress,
) -> bool {
    let width = scene.settings.width as usize;
    let rows: Vec<Option<Vec<CameraPath>>> = (0..scene.settings.height as usize)
        .into_par_iter()
        .map(|y| {
            if progress.should_abandon() {
                return None;
            }
            let row = (0..width).map(|x| visible_point(scene, missed, x, y, iteration)).collect();
            progress.advance(width as u64);
            Some(row)
        })
        .collect();
    let Some(rows) = rows.into_iter().collect::<Option<Vec<_>>>() else { return false };
    let points: Vec<CameraPath> = rows.into_iter().flatten().collect();
    let spheres: Vec<(u32, Vec3, f32)> = points
        .iter()
        .enumerate()
        .filter_map(|(i, (_, vp))| {
            Some((i as u32, vp.as_ref()?.vertex.hit.point, pixels[i].radius))
        })
        .collect();
    let grid = HashGrid::build(&spheres);

    // Phi and M of each pixel: per task in photon order, then the tasks in task order.
    let mut gathered = vec![Gathered::default(); pixels.len()];
    let tasks: Vec<u32> = (0..emission.total().div_ceil(PHOTON_TASK)).collect();
    for wave in tasks.chunks(tasks_per_wave()) {
        let sums: Vec<Option<Vec<Gathered>>> = wave
            .par_iter()
            .map(|&task| {
                if progress.should_abandon() {
                    return None;
                }
                let mut sums = vec![Gathered::default(); pixels.len()];
                let first = task * PHOTON_TASK;
                for index in first..(first + PHOTON_TASK).min(emission.total()) {
                    let max_depth = scene.settings.max_depth;
                    trace_photon(scene, emission, max_depth, u64::from(iteration), index, |d| {
                        // Direct light comes from next-event estimation.
                        if d.arrival == Arrival::Direct {
                            return;
                        }
                        for pixel in grid.holding(d.hit.point) {
                            let Some(vp) = &points[pixel as usize].1 else { continue };
                            let sum = &mut sums[pixel as usize];
                            sum.flux += vp.flux(d.wi, d.power);
                            sum.found += 1;
                        }
                    });
                }
                Some(sums)
            })
            .collect();
        for sums in sums {
            let Some(sums) = sums else { return false };
            gathered.par_iter_mut().zip(&sums).for_each(|(total, sum)| {
                total.flux += sum.flux;
                total.found += sum.found;
            });
        }
    }

    pixels.par_iter_mut().zip(points.par_iter()).zip(&gathered).for_each(
        |((pixel, (direct, _)), &Gathered { flux: phi, found: m })| {
            pixel.direct += direct.as_dvec3();
            if m > 0 {
                let m = m as f32;
                let photons = pixel.photons + ALPHA * m;
                let radius = pixel.radius * (photons / (pixel.photons + m)).sqrt();
                let shrink = f64::from(radius / pixel.radius).powi(2);
                pixel.flux = (pixel.flux + phi.as_dvec3()) * shrink;
                pixel.photons = photons;
                pixel.radius = radius;
            }
        },
    );
    true
}

/// Iteration `iteration`'s camera path of pixel (x, y): the emission it saw, the direct light
/// at its visible point and the light photons miss there (`missed`'s), weighted by the path's
/// throughput; and the visible point if any.
fn visible_point(
    scene: &Scene,
    missed: Option<&MissedLight>,
    x: usize,
    y: usize,
    iteration: u32,
) -> CameraPath {
    let (Some(ray), mut sampler) = camera_sample(scene, x, y, iteration) else {
        return (Vec3::ZERO, None); // the film is dark there
    };
    let mut path = WhittedPath::photon_mapping(ray);
    loop {
        let hit = scene.intersect(&path.ray);
        let Some(vertex) = arrive(scene, &mut path, hit, scene.settings.max_depth) else { break };
        let (gathered, followed) = (vertex.gathered, vertex.followed());
        if followed.is_non_delta() {
            // Lights seen in a near-specular lobe, whichever way the path goes on: a point
            // light's sample whole, the others' weighted against the ray the lobe samples.
            path.radiance += path.beta * lit_one_at_a_time(scene, &vertex, followed, &mut sampler);
        }
        if !gathered.is_empty() {
            // With followed lobes too, the path stops here with the gathered lobes'
            // probability p and goes on through a followed lobe otherwise, each divided by its
            // probability.
            let p = if followed.is_empty() {
                1.0
            } else {
                vertex.bsdf.probability_of(vertex.wo, gathered)
            };
            if sampler.next_1d_if(!followed.is_empty()) < p {
                path.beta /= p;
                let lit = lit_one_at_a_time(scene, &vertex, gathered, &mut sampler);
                path.radiance += path.beta * lit;
                let Vertex { hit, wo, bsdf, .. } = &vertex;
                let environment =
                    direct_from_environment(scene, hit, *wo, bsdf, gathered, &mut sampler);
                path.radiance += path.beta * environment;
                if let Some(missed) = missed {
                    let max_depth = scene.settings.max_depth;
                    path.radiance += path.beta * missed.at(scene, &vertex, max_depth, &mut sampler);
                }
                return (path.radiance, Some(VisiblePoint { vertex, beta: path.beta }));
            }
            path.beta /= 1.0 - p;
        }
        if !follow(&mut path, &vertex, &mut sampler) {
            break;
        }
    }
    (path.radiance, None)
}
