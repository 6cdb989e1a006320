//! `raydiance render` without the command line: everything checked that can be before any work
//! (the outputs' types and folders, the film's memory, whether the integrator can render a
//! part), then the planned frames rendered one after another and written, as images or part
//! files. The caller draws the progress and prints what the job says (`Observer`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use crate::aov::{self, AovList};
use crate::graph::{IntegratorKind, Settings};
use crate::image::{self, ImageError, SignalError};
use crate::integrator::sppm;
use crate::pipeline::{
    FilmTooLarge, LoadError, OutputFormat, RenderRequest, RenderTooLarge, check_film_memory,
    check_render_memory,
};
use crate::progress::Progress;
use crate::region::{Crop, Region, RegionError, Share};
use crate::split::part_file::{self, PartHeader};
use crate::split::plan::{self, Choices, Job, Plan, PlanError};
use crate::{load_with_digest, render, tonemap, write_render};

/// The longest `--time` budget, in seconds (some 30 years; more cannot be a deadline).
pub const MAX_TIME: f64 = 1e9;

/// What `raydiance render` was asked.
#[derive(Debug, Clone, Default)]
pub struct RenderJob {
    pub scene: PathBuf,
    /// The image to write; `None`: the scene's name as a PNG in the current folder (POV-Ray's
    /// habit).
    pub output: Option<PathBuf>,
    pub request: RenderRequest,
    /// Time budget in seconds: as many samples as fit (up to the request's, if given).
    pub time: Option<f64>,
    /// The integer that MAX stands for in HDR `.ppm` output.
    pub ppm_res: u32,
    /// The most memory the film may take, in GiB.
    pub max_memory: f64,
    pub choices: Choices,
    /// The AOVs to write beside the beauty (`--aov`), into EXR files only.
    pub aovs: AovList,
}

/// Why a render job did not render, each with the message the command line prints.
#[derive(Debug, thiserror::Error)]
pub enum RenderJobError {
    #[error("error: --time {0} must be a positive number of seconds, at most {max:e}", max = MAX_TIME)]
    Time(f64),
    #[error("error: --max-memory {0} must be a positive number")]
    MaxMemory(f64),
    #[error(transparent)]
    Plan(#[from] PlanError),
    #[error("error: {}: a part (--part or --crop) is an OpenEXR file: name it .exr", .0.display())]
    PartNotExr(PathBuf),
    #[error(
        "error: {}: --aov writes its layers beside the image in an OpenEXR file, which a PPM or \
         PNG cannot hold: name it .exr (and tone-map it with `raydiance tonemap`)",
        .0.display()
    )]
    AovsNotExr(PathBuf),
    #[error("error: {0}")]
    Output(ImageError),
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(
        "error: --part and --crop do not work with integrator {} yet: its samples are not \
         independent of each other",
        .0.name()
    )]
    SamplesShared(IntegratorKind),
    #[error("error: {0}")]
    Region(RegionError),
    #[error(transparent)]
    FilmTooLarge(#[from] FilmTooLarge),
    #[error(transparent)]
    RenderTooLarge(#[from] RenderTooLarge),
    #[error(transparent)]
    Signals(#[from] SignalError),
    #[error("interrupted before the first pass: nothing written ({} left as it was)", .0.display())]
    InterruptedBeforeFirstPass(PathBuf),
    #[error("error: {0}")]
    Write(ImageError),
}

/// What a running job tells the one who runs it.
pub trait Observer {
    /// A frame's render starts, of `total` samples (`None` under a time budget): the progress
    /// to report them to (dropped when the render ends).
    fn frame_starts(&self, total: Option<u64>) -> Result<Box<dyn Progress + '_>, RenderJobError>;
    /// Something worth saying that is not an error.
    fn warning(&self, text: &str);
    /// A file was written: the line that says what it holds.
    fn written(&self, summary: &str);
    /// Whether the run was asked to stop (between frames, and cutting the frame under way short).
    fn interrupted(&self) -> bool;
}

/// How a job that did not fail ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    Complete,
    /// Stopped before its last frame or sample (`Observer::interrupted`); what was rendered is
    /// written.
    Interrupted,
}

impl RenderJob {
    /// Checks the command line's values and plans the frames and parts; `var` looks up the
    /// environment (for `--part auto`).
    pub fn plan(&self, var: impl Fn(&str) -> Option<String>) -> Result<PlannedJob, RenderJobError> {
        // The scene first: a missing one is named before any frame is planned.
        crate::lang::check_readable(&self.scene).map_err(LoadError::from)?;
        if let Some(t) = self.time.filter(|t| !(*t > 0.0 && *t <= MAX_TIME)) {
            return Err(RenderJobError::Time(t));
        }
        // With a time budget the sample count is only a ceiling.
        let samples = self.request.samples.or(self.time.map(|_| crate::MAX_SAMPLES));
        let request = RenderRequest { samples, ..self.request.clone() };
        if !(self.max_memory.is_finite() && self.max_memory > 0.0) {
            return Err(RenderJobError::MaxMemory(self.max_memory));
        }
        let max_bytes = (self.max_memory * f64::from(1u32 << 30)) as u64;
        let output = self.output.clone().unwrap_or_else(|| {
            PathBuf::from(self.scene.file_stem().unwrap_or_default()).with_extension("png")
        });
        let plan = plan::plan(&self.choices, &output, var)?;
        Ok(PlannedJob {
            scene: self.scene.clone(),
            aovs: self.aovs,
            plan,
            request,
            ppm_res: self.ppm_res,
            time: self.time,
            max_bytes,
        })
    }
}

/// A checked and planned job, ready to render.
#[derive(Debug, Clone)]
pub struct PlannedJob {
    scene: PathBuf,
    aovs: AovList,
    plan: Plan,
    request: RenderRequest,
    ppm_res: u32,
    time: Option<f64>,
    max_bytes: u64,
}

impl PlannedJob {
    /// Where a scheduler's task came from (`--part auto`), to say before rendering.
    pub fn task(&self) -> Option<&str> {
        self.plan.task.as_deref()
    }

    /// Renders the planned frames one after another; a stop asked during a frame ends the run
    /// once that frame is written.
    pub fn render(&self, observer: &dyn Observer) -> Result<Ended, RenderJobError> {
        // Everything that can be checked before rendering is: the outputs' types and folders first.
        let formats = self
            .plan
            .jobs
            .iter()
            .map(|job| {
                let exr = image::extension(&job.output).as_deref() == Some("exr");
                if job.is_part() && !exr {
                    return Err(RenderJobError::PartNotExr(job.output.clone()));
                }
                if !self.aovs.is_empty() && !exr {
                    return Err(RenderJobError::AovsNotExr(job.output.clone()));
                }
                OutputFormat::for_path(&job.output, self.ppm_res).map_err(RenderJobError::Output)
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (job, format) in self.plan.jobs.iter().zip(&formats) {
            if observer.interrupted() {
                return Ok(Ended::Interrupted);
            }
            if self.render_frame(job, format, observer)? == Ended::Interrupted {
                return Ok(Ended::Interrupted);
            }
        }
        Ok(Ended::Complete)
    }

    fn render_frame(
        &self,
        job: &Job,
        format: &OutputFormat,
        observer: &dyn Observer,
    ) -> Result<Ended, RenderJobError> {
        let output = &job.output;
        let request = RenderRequest { frame: job.frame, ..self.request.clone() };
        let (scene, digest) = load_with_digest(&self.scene, &request)?;
        let settings = &scene.settings;
        let region = Region {
            crop: job.crop.unwrap_or(Crop::whole(settings.width, settings.height)),
            share: job.share.unwrap_or(Share::WHOLE),
            samples: settings.samples,
        };
        if job.is_part() {
            if !crate::integrator::of(settings).samples_are_independent() {
                return Err(RenderJobError::SamplesShared(settings.integrator));
            }
            region.check(settings.width, settings.height).map_err(RenderJobError::Region)?;
        }
        let film_settings = Settings {
            width: region.crop.width(),
            height: region.crop.height(),
            ..settings.clone()
        };
        check_film_memory(&film_settings, &self.aovs, self.max_bytes)?;
        check_render_memory(&scene, self.max_bytes)?;
        for warning in &scene.warnings {
            observer.warning(warning);
        }
        if let Some(warning) = (settings.integrator == IntegratorKind::Sppm)
            .then(|| sppm::radius_warning(&scene))
            .flatten()
        {
            observer.warning(&warning);
        }
        let total = if self.time.is_some() { None } else { Some(region.samples_taken(u32::MAX)) };
        let (mut film, stats) = {
            let progress = Budget {
                progress: observer.frame_starts(total)?,
                deadline: self.time.map(|t| Instant::now() + Duration::from_secs_f64(t)),
            };
            render::render_region(&scene, &region, &progress)
        };
        if !self.aovs.is_empty() {
            film.aovs = Some(aov::render(&scene, &region, film.samples, &self.aovs));
        }
        // Nothing rendered: the file there (a render of before) is worth more than a black image.
        if stats.samples_per_pixel == 0 && observer.interrupted() {
            return Err(RenderJobError::InterruptedBeforeFirstPass(output.clone()));
        }
        let written = if job.is_part() {
            let header = PartHeader {
                path: output.clone(),
                width: settings.width,
                height: settings.height,
                region,
                taken: stats.samples_per_pixel,
                seed: settings.seed,
                integrator: settings.integrator.name().to_string(),
                max_depth: settings.max_depth,
                digest: digest.to_string(),
                frame: job.frame,
                seconds: stats.seconds,
                aovs: self.aovs,
            };
            part_file::write(output, &film, &header)
        } else {
            write_render(output, format, &film, &stats, settings)
        };
        written.map_err(RenderJobError::Write)?;
        if stats.dropped > 0 {
            observer.warning(&format!(
                "warning: {} samples were NaN or infinite and were dropped",
                stats.dropped
            ));
        }
        if let Some(warning) = tonemap::darkness_warning(&film.image()) {
            observer.warning(&warning);
        }
        // A time budget ends a render too; only a stop asked makes it "interrupted".
        let most = region.most_samples();
        let ended = if observer.interrupted() && stats.samples_per_pixel < most {
            observer.warning(&format!(
                "interrupted: wrote the {} of {} samples per pixel completed",
                stats.samples_per_pixel, most
            ));
            Ended::Interrupted
        } else {
            Ended::Complete
        };
        let what = if job.is_part() {
            format!(
                "share {} of crop {} of {}x{}",
                region.share, region.crop, settings.width, settings.height
            )
        } else {
            format!("{}x{}", film.width, film.height)
        };
        let samples =
            region.samples_taken(stats.samples_per_pixel) as f64 / stats.seconds.max(1e-9);
        observer.written(&format!(
            "{}: {what}, {} spp, {}, {:.3} s, {:.2} Msamples/s",
            output.display(),
            stats.samples_per_pixel,
            settings.integrator.name(),
            stats.seconds,
            samples / 1e6,
        ));
        Ok(ended)
    }
}

/// The observer's progress, with the time budget's deadline: the last pass is shortened to end
/// near it.
struct Budget<'a> {
    progress: Box<dyn Progress + 'a>,
    deadline: Option<Instant>,
}

impl Progress for Budget<'_> {
    fn advance(&self, samples: u64) {
        self.progress.advance(samples);
    }

    fn pass_limit(&self, seconds_per_sample: f64) -> Option<u32> {
        let asked = self.progress.pass_limit(seconds_per_sample);
        let by_time = self.deadline.map(|deadline| {
            let left = deadline.saturating_duration_since(Instant::now()).as_secs_f64();
            (left / seconds_per_sample.max(1e-9)).min(f64::from(u32::MAX)) as u32
        });
        match (asked, by_time) {
            (Some(asked), Some(by_time)) => Some(asked.min(by_time)),
            (asked, by_time) => asked.or(by_time),
        }
    }

    fn pass_done(&self, film: &crate::film::Film) {
        self.progress.pass_done(film);
    }

    fn should_abandon(&self) -> bool {
        self.progress.should_abandon()
    }
}
