//! The preview's render loop: load the scene, recording the files it reads; render it, each
//! finished pass published; on a save of any of those files, stop and start again.

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

/// Renders the scene again after each change of a file it read, forever.
pub fn run(scene: &Path, request: &RenderRequest, shown: &Shown, watch: &Watch) -> ! {
    loop {
        let start = Instant::now();
        let render = shown.render_starts();
        let (loaded, reads) = crate::input::recording_reads(|| load(scene, request));
        watch.set(reads);
        match loaded {
            Ok(scene) => {
                let passes = Passes { shown, watch, render, start, settings: &scene.settings };
                crate::render::render(&scene, &passes);
            }
            Err(error) => shown.failed(error),
        }
        watch.wait_for_change();
    }
}

/// The scene ready to render, or the error the terminal would print.
fn load(path: &Path, request: &RenderRequest) -> Result<Scene, String> {
    let scene = crate::load(path, request).map_err(|e| e.to_string())?;
    check_film_memory(&scene.settings, MAX_BYTES).map_err(|e| e.to_string())?;
    check_render_memory(&scene, MAX_BYTES).map_err(|e| e.to_string())?;
    Ok(scene)
}

/// The render's progress as the page sees it: each pass published, and a save stops it.
struct Passes<'a> {
    shown: &'a Shown,
    watch: &'a Watch,
    render: u64,
    start: Instant,
    settings: &'a Settings,
}

impl Progress for Passes<'_> {
    fn advance(&self, _: u64) {}

    fn pass_done(&self, film: &Film) {
        let info = RenderInfo {
            samples_per_pixel: film.samples,
            integrator: self.settings.integrator.name().to_string(),
            seed: self.settings.seed,
            seconds: self.start.elapsed().as_secs_f64(),
            parameters: self.settings.parameters(),
        };
        self.shown.pass(self.render, film.image(), info, self.settings.samples);
    }

    fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
        self.watch.changed().then_some(0)
    }

    fn should_abandon(&self) -> bool {
        self.watch.changed()
    }
}
