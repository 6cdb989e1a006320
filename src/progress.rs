//! What a render reports: its progress while it runs (to the command line, which draws it, or to
//! a test's budget), and its stats when it ends. Below the integrators and the render loop, which
//! both report.

use crate::film::Film;

/// Receives progress from a render running on other threads; only the command line draws.
pub trait Progress: Sync {
    /// `samples` more pixel samples are done.
    fn advance(&self, samples: u64);
    /// Asked between passes, with the seconds one sample per pixel took in the last pass: the
    /// most samples per pixel the next pass may take (0 ends the render with the passes done
    /// so far), or `None` for no bound.
    fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
        None
    }
    /// A pass is done: `film` holds every pass so far, a valid image of `film.samples` samples
    /// per pixel (what a preview shows while the render refines).
    fn pass_done(&self, _film: &Film) {}
    /// Checked between the small tasks of a pass (at most `render::TASK_SAMPLES` samples each): true
    /// drops the pass under way and ends the render with the passes done before it.
    fn should_abandon(&self) -> bool {
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
