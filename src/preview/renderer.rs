//! The preview's render loop: load the scene, recording the files it reads; show a glance of
//! it, then render it, each finished pass published, then denoised when raydiance denoises; on
//! a save of any of those files, stop and start again.

use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

use crate::RenderRequest;
use crate::aov::{self, Aov, AovImage, AovList};
use crate::denoise::Denoiser;
use crate::film::Film;
use crate::graph::Settings;
use crate::image::{Image, RenderInfo};
use crate::pipeline::{
    FilmTooLarge, LoadError, RenderTooLarge, check_film_memory, check_render_memory,
};
use crate::progress::Progress;
use crate::region::Region;
use crate::scene::Scene;

use super::shown::Shown;
use super::watch::Watch;

/// The most memory a preview's render may take, as `render --max-memory`'s default.
const MAX_BYTES: u64 = 8 << 30;

/// The longer side of the glance, the first image: one sample per pixel of the image scaled
/// down to it (a sixteenth of the work of the first full pass of a 512-pixel image).
pub const GLANCE_SIDE: u32 = 128;

/// The most samples per pixel of the AOVs that guide the denoiser: each pass takes them again
/// until then. Guides need not be free of noise (the filter is not told they are), and each of
/// their samples costs a camera ray and a lobe sample, where the beauty's costs a whole path.
const GUIDE_SAMPLES: u32 = 8;

/// Renders the scene again after each change of a file it read, forever; each pass is denoised
/// too when there is a `denoiser`.
pub fn run(
    scene: &Path,
    request: &RenderRequest,
    shown: &Shown,
    watch: &Watch,
    denoiser: Option<&Denoiser>,
) -> ! {
    loop {
        let start = Instant::now();
        let render = shown.render_starts();
        let (loaded, reads) = crate::input::recording_reads(|| load(scene, request));
        watch.set(reads);
        match loaded {
            Ok(mut scene) => {
                let full = scene.settings.clone();
                let job = Job { shown, watch, render, start, full: &full, denoiser };
                if let Some(glance) = glance_of(&full) {
                    scene.settings = glance;
                    crate::render::render(&scene, &Passes::new(&job, &scene, true));
                    scene.settings = full.clone();
                }
                if !watch.changed() {
                    crate::render::render(&scene, &Passes::new(&job, &scene, false));
                }
            }
            Err(error) => shown.failed(error.to_string()),
        }
        watch.wait_for_change();
    }
}

/// Why the preview has no scene to render: what the terminal would print.
#[derive(Debug, thiserror::Error)]
enum Unrenderable {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(transparent)]
    Film(#[from] FilmTooLarge),
    #[error(transparent)]
    Render(#[from] RenderTooLarge),
}

/// The scene ready to render.
fn load(path: &Path, request: &RenderRequest) -> Result<Scene, Unrenderable> {
    let scene = crate::load(path, request)?;
    check_film_memory(&scene.settings, &crate::aov::AovList::default(), MAX_BYTES)?;
    check_render_memory(&scene, MAX_BYTES)?;
    Ok(scene)
}

/// The settings of the glance: one sample per pixel, the longer side `GLANCE_SIDE`, the same
/// view (cameras map the image's unit square, whatever its pixels). None for an image no larger,
/// or an integrator that would trace its photons again for it.
pub fn glance_of(settings: &Settings) -> Option<Settings> {
    let longer = settings.width.max(settings.height);
    let independent = crate::integrator::of(settings).samples_are_independent();
    if longer <= GLANCE_SIDE || !independent {
        return None;
    }
    let scaled = |side: u32| (u64::from(side) * u64::from(GLANCE_SIDE) / u64::from(longer)) as u32;
    Some(Settings {
        width: scaled(settings.width).max(1),
        height: scaled(settings.height).max(1),
        samples: 1,
        ..settings.clone()
    })
}

/// One load's render, its glance and then the image at full size.
struct Job<'a> {
    shown: &'a Shown,
    watch: &'a Watch,
    render: u64,
    start: Instant,
    /// The settings of the render at full size.
    full: &'a Settings,
    denoiser: Option<&'a Denoiser>,
}

/// The render's progress as the page sees it: each pass published (and denoised), and a save
/// stops it.
struct Passes<'a> {
    job: &'a Job<'a>,
    /// The scene rendered (at the glance's size for the glance), for the guides' AOVs.
    scene: &'a Scene,
    glance: bool,
    /// The guides last taken, and their samples per pixel.
    guides: Mutex<Option<(u32, AovImage)>>,
}

impl<'a> Passes<'a> {
    fn new(job: &'a Job<'a>, scene: &'a Scene, glance: bool) -> Passes<'a> {
        Passes { job, scene, glance, guides: Mutex::default() }
    }

    /// Denoises the pass just shown and shows it denoised, guided by the albedo and normal of
    /// its first `GUIDE_SAMPLES` samples.
    fn denoise(&self, denoiser: &Denoiser, image: &Image, mut info: RenderInfo) {
        let guides = self.guides(info.samples_per_pixel.min(GUIDE_SAMPLES));
        match denoiser.denoise(image, &guides) {
            Ok(denoised) => {
                info.parameters.push(("denoised", crate::denoise::description(&guides)));
                self.job.shown.denoised(denoised, info);
            }
            Err(message) => eprintln!("warning: a pass was not denoised: {message}"),
        }
    }

    /// The albedo and normal of the first `taken` samples of each pixel.
    fn guides(&self, taken: u32) -> AovImage {
        let mut guides = self.guides.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        match &*guides {
            Some((samples, aovs)) if *samples == taken => aovs.clone(),
            _ => {
                let s = &self.scene.settings;
                let whole = Region::whole(s.width, s.height, s.samples);
                let list = AovList::new([Aov::Albedo, Aov::Normal]);
                let aovs = aov::render(self.scene, &whole, taken, &list);
                *guides = Some((taken, aovs.clone()));
                aovs
            }
        }
    }
}

impl Progress for Passes<'_> {
    fn advance(&self, _: u64) {}

    fn pass_done(&self, film: &Film) {
        let job = self.job;
        let info = RenderInfo {
            samples_per_pixel: film.samples,
            integrator: job.full.integrator.name().to_string(),
            seed: job.full.seed,
            seconds: job.start.elapsed().as_secs_f64(),
            parameters: job.full.parameters(),
        };
        let size = (job.full.width, job.full.height);
        let image = film.image();
        let (render, target) = (job.render, job.full.samples);
        job.shown.pass(render, image.clone(), info.clone(), target, size, self.glance);
        if let Some(denoiser) = job.denoiser.filter(|_| !job.watch.changed()) {
            self.denoise(denoiser, &image, info);
        }
    }

    fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
        self.job.watch.changed().then_some(0)
    }

    fn should_abandon(&self) -> bool {
        self.job.watch.changed()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::IntegratorKind;

    #[test]
    fn a_glance_is_one_sample_of_the_image_scaled_to_its_side() {
        let settings = |width, height, integrator| Settings {
            width,
            height,
            samples: 64,
            integrator,
            ..Settings::default()
        };
        let glance = glance_of(&settings(1920, 1080, IntegratorKind::Path)).unwrap();
        assert_eq!((glance.width, glance.height, glance.samples), (128, 72, 1));
        let thin = glance_of(&settings(4000, 10, IntegratorKind::Direct)).unwrap();
        assert_eq!((thin.width, thin.height), (128, 1));
        assert!(glance_of(&settings(128, 100, IntegratorKind::Path)).is_none());
        assert!(glance_of(&settings(1920, 1080, IntegratorKind::Sppm)).is_none());
        assert!(glance_of(&settings(1920, 1080, IntegratorKind::Photon)).is_none());
    }
}
