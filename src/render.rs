//! Rendering: the integrator a scene's settings name renders the image, or a region of it.

use crate::film::Film;
use crate::integrator::{self, SampleIntegrator, render_samples};
use crate::progress::{Progress, RenderStats};
use crate::region::Region;
use crate::scene::Scene;

/// Renders `scene` with its settings.
pub fn render(scene: &Scene, progress: &dyn Progress) -> (Film, RenderStats) {
    let s = &scene.settings;
    render_region(scene, &Region::whole(s.width, s.height, s.samples), progress)
}

/// Renders a crop of the image and a share of its samples (see `region`): the film is the
/// crop's, and its `samples` counts the passes' samples per pixel, of which each pixel holds
/// at most its share (`Region::samples_of`).
pub fn render_region(
    scene: &Scene,
    region: &Region,
    progress: &dyn Progress,
) -> (Film, RenderStats) {
    integrator::of(&scene.settings).render(scene, region, progress)
}

/// Renders the whole image with a given per-sample integrator (e.g. a `Path` with one sampling
/// strategy, for tests).
pub fn render_with(
    scene: &Scene,
    integrator: &impl SampleIntegrator,
    progress: &dyn Progress,
) -> (Film, RenderStats) {
    let s = &scene.settings;
    render_samples(scene, integrator, &Region::whole(s.width, s.height, s.samples), progress)
}
