//! The preview's render loop: load the scene, recording the files it reads; show a glance of
//! it, then render it, each finished pass published; on a save of any of those files, stop and
//! start again.

use std::path::Path;
use std::time::Instant;

use crate::RenderRequest;
use crate::film::Film;
use crate::graph::Settings;
use crate::image::RenderInfo;
use crate::pipeline::{check_film_memory, check_render_memory};
use crate::progress::Progress;
use crate::scene::Scene;

use super::shown::Shown;
use super::watch::Watch;

/// The most memory a preview's render may take, as `render --max-memory`'s default.
const MAX_BYTES: u64 = 8 << 30;

/// The longer side of the glance, the first image: one sample per pixel of the image scaled
/// down to it (a sixteenth of the work of the first full pass of a 512-pixel image).
pub const GLANCE_SIDE: u32 = 128;

/// Renders the scene again after each change of a file it read, forever.
pub fn run(scene: &Path, request: &RenderRequest, shown: &Shown, watch: &Watch) -> ! {
    loop {
        let start = Instant::now();
        let render = shown.render_starts();
        let (loaded, reads) = crate::input::recording_reads(|| load(scene, request));
        watch.set(reads);
        match loaded {
            Ok(mut scene) => {
                let full = scene.settings.clone();
                let passes = |glance| Passes { shown, watch, render, start, full: &full, glance };
                if let Some(glance) = glance_of(&full) {
                    scene.settings = glance;
                    crate::render::render(&scene, &passes(true));
                    scene.settings = full.clone();
                }
                if !watch.changed() {
                    crate::render::render(&scene, &passes(false));
                }
            }
            Err(error) => shown.failed(error),
        }
        watch.wait_for_change();
    }
}

/// The scene ready to render, or the error the terminal would print.
fn load(path: &Path, request: &RenderRequest) -> Result<Scene, String> {
    let scene = crate::load(path, request).map_err(|e| e.to_string())?;
    check_film_memory(&scene.settings, &crate::aov::AovList::default(), MAX_BYTES)
        .map_err(|e| e.to_string())?;
    check_render_memory(&scene, MAX_BYTES).map_err(|e| e.to_string())?;
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

/// The render's progress as the page sees it: each pass published, and a save stops it.
struct Passes<'a> {
    shown: &'a Shown,
    watch: &'a Watch,
    render: u64,
    start: Instant,
    /// The settings of the render at full size.
    full: &'a Settings,
    glance: bool,
}

impl Progress for Passes<'_> {
    fn advance(&self, _: u64) {}

    fn pass_done(&self, film: &Film) {
        let info = RenderInfo {
            samples_per_pixel: film.samples,
            integrator: self.full.integrator.name().to_string(),
            seed: self.full.seed,
            seconds: self.start.elapsed().as_secs_f64(),
            parameters: self.full.parameters(),
        };
        let size = (self.full.width, self.full.height);
        self.shown.pass(self.render, film.image(), info, self.full.samples, size, self.glance);
    }

    fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
        self.watch.changed().then_some(0)
    }

    fn should_abandon(&self) -> bool {
        self.watch.changed()
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
