//! The `raydiance` command line: render, tonemap, check, snapshot, bench.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use raydiance::animation;
use raydiance::region::{Crop, Region};
use raydiance::render::Progress;
use raydiance::scene::graph::IntegratorKind;
use raydiance::split::part_file::{self, PartHeader};
use raydiance::split::plan::{self, Choices, Job, PartChoice};
use raydiance::tonemap::{Operator, ToneMap};
use raydiance::{RenderRequest, bench, snapshot};

#[derive(Parser)]
#[command(name = "raydiance", version, about = "A physically based renderer for .scn scenes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to .exr (linear HDR), .ppm (HDR with #MAX) or .png (tone-mapped).
    Render {
        /// The scene file (.scn).
        scene: PathBuf,
        /// The image to write, by its extension: .exr (linear HDR), .ppm (HDR with #MAX) or .png
        /// (tone-mapped with clamp-gamma) [default: SCENE.png in the current folder, as POV-Ray]
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Samples per pixel (`sppm`: iterations), 1 to 1000000 [default: the scene's
        /// `settings`, else 16]
        #[arg(long)]
        samples: Option<u32>,
        /// Image width in pixels, 1 to 65536 [default: the scene's `settings`, else 256]
        #[arg(long)]
        width: Option<u32>,
        /// Image height in pixels, 1 to 65536 [default: the scene's `settings`, else 256]
        #[arg(long)]
        height: Option<u32>,
        /// Seed of the random numbers: the same seed gives the same image [default: the scene's
        /// `settings`, else 0]
        #[arg(long)]
        seed: Option<u64>,
        /// Worker threads, 1 to 1024 [default: one per core]. The image does not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// `direct` (the course's Lab 4: direct light, mirrors and glass followed), `path`
        /// (path tracing of the full rendering equation), `photon` (Jensen's photon mapping) or
        /// `sppm` (stochastic progressive photon mapping) [default: the scene's `settings`,
        /// else path]
        #[arg(long, value_parser = parse_integrator)]
        integrator: Option<IntegratorKind>,
        /// Longest path in bounces, 0 to 1024 [default: the scene's `settings`, else 32]
        #[arg(long)]
        max_depth: Option<u32>,
        /// Time budget in seconds: render as many samples as fit, the last pass shortened to
        /// end near the budget (up to --samples if given).
        #[arg(long, allow_negative_numbers = true)]
        time: Option<f64>,
        /// The integer that MAX stands for in HDR .ppm output.
        #[arg(long, default_value_t = raydiance::image::ppm::HDR_RES)]
        ppm_res: u32,
        /// The most memory the film may take, in GiB (it takes 96 bytes a pixel).
        #[arg(long, default_value_t = 8.0)]
        max_memory: f64,
        /// Render share I (0-based) of N disjoint shares of the samples, into a part file
        /// (.exr) for `merge`; `auto` takes the share from a Slurm job array or a Kubernetes
        /// Indexed Job (with --parts).
        #[arg(long, value_name = "I/N|auto")]
        part: Option<PartChoice>,
        /// With --part auto under Kubernetes: the number of shares of each frame (the Job's
        /// completions divided by the frames).
        #[arg(long, value_name = "N")]
        parts: Option<u32>,
        /// Render only pixels X0 <= x < X1, Y0 <= y < Y1 of the image, into a part file (.exr).
        #[arg(long, value_name = "X0,X1,Y0,Y1")]
        crop: Option<Crop>,
        /// Render frames F0 to F1 (inclusive) of an animation; a run of `#` in the output's
        /// name becomes the frame number (else it is appended before the extension).
        #[arg(long, value_name = "F0..F1", value_parser = animation::parse_frames)]
        frames: Option<(u32, u32)>,
        /// Render only frame F of --frames.
        #[arg(long, value_name = "F")]
        frame: Option<u32>,
        /// `clock` runs from C0 at the first frame to C1 at the last [default: 0..1].
        #[arg(long, value_name = "C0..C1", value_parser = animation::parse_clock, allow_hyphen_values = true)]
        clock: Option<(f64, f64)>,
    },
    /// Merge part files (render --part / --crop) into the image one render would have made.
    Merge {
        /// The part files (.exr), in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// The image to write: .exr, .ppm (HDR with #MAX) or .png (tone-mapped).
        #[arg(short, long)]
        output: PathBuf,
        /// Merge the parts there are even when shares or tiles are missing: the image is the
        /// mean of the samples there are, and records the fewest a pixel holds.
        #[arg(long)]
        allow_partial: bool,
        /// The integer that MAX stands for in HDR .ppm output.
        #[arg(long, default_value_t = raydiance::image::ppm::HDR_RES)]
        ppm_res: u32,
    },
    /// Tone-map an HDR image (.exr or .ppm) to LDR .ppm (#MAX=1) or .png.
    Tonemap {
        /// The HDR image: .exr, or .ppm (P3 or P6, with or without #MAX).
        input: PathBuf,
        /// The image to write: .ppm (P3, #MAX=1, res 255) or .png.
        #[arg(short, long)]
        output: PathBuf,
        /// The operator: clamp, equalize, equalize-clamp, gamma, clamp-gamma, reinhard or aces.
        #[arg(long, default_value = "clamp-gamma")]
        op: Operator,
        /// Threshold V of equalize-clamp and clamp-gamma.
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        v: f32,
        /// Gamma γ of the gamma operators: c' = c^(1/γ).
        #[arg(long, default_value_t = 2.2, allow_negative_numbers = true)]
        gamma: f32,
        /// Exposure in stops: values are multiplied by 2^EV first.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        exposure: f32,
        /// Reinhard's white point (default: the largest scaled luminance).
        #[arg(long, allow_negative_numbers = true)]
        white: Option<f32>,
    },
    /// Parse and validate a scene; print a short summary.
    Check {
        /// The scene file (.scn).
        scene: PathBuf,
    },
    /// Snapshot-test scenes: render each .scn small and compare it, statistically, with its
    /// snapshot `__snapshots__/NAME.exr` beside it; exit status 0 only when all match.
    Snapshot {
        /// Scenes, or folders searched below for .scn files (default: the current folder).
        paths: Vec<PathBuf>,
        /// Make every `.new` snapshot (written by an earlier run) the snapshot; renders nothing.
        #[arg(long)]
        accept: bool,
        /// Samples per pixel of each render (at least 2) [default: 64].
        #[arg(long)]
        samples: Option<u32>,
        /// Image size WxH [default: the stored snapshot's, or the scene's scaled to 64 pixels
        /// on its longer side].
        #[arg(long, value_parser = parse_size)]
        size: Option<(u32, u32)>,
        /// Worker threads (default: one per core). The verdict does not depend on it.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Render scenes and print samples per second and seconds per frame.
    Bench {
        /// Scenes to render (default: the benchmark scenes in scenes/).
        scenes: Vec<PathBuf>,
        /// Samples per pixel, one or more separated by commas (e.g. 16,64).
        #[arg(long, default_value = "16")]
        samples: String,
        /// Timed renders of each scene after one warm-up (1 to 1000).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=1000))]
        repeats: u16,
        /// Worker threads, 1 to 1024 [default: one per core].
        #[arg(long)]
        threads: Option<usize>,
    },
}

fn parse_integrator(s: &str) -> Result<IntegratorKind, String> {
    IntegratorKind::named(s).ok_or_else(|| {
        format!("unknown integrator `{s}` (expected `direct`, `path`, `photon` or `sppm`)")
    })
}

/// `println!` and `eprintln!` panic when their stream is closed (`raydiance ... | head`); these
/// drop the line instead: the work is done, and only the words are lost.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

macro_rules! tell {
    ($($arg:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let max = raydiance::MAX_RESOLUTION;
    let side = |v: &str| v.trim().parse::<u32>().ok().filter(|v| (1..=max).contains(v));
    s.split_once(['x', 'X'])
        .and_then(|(w, h)| Some((side(w)?, side(h)?)))
        .ok_or_else(|| format!("`{s}` is not a size WxH with sides from 1 to {max} (e.g. 64x48)"))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render {
            scene,
            output,
            samples,
            width,
            height,
            seed,
            threads,
            integrator,
            max_depth,
            time,
            ppm_res,
            max_memory,
            part,
            parts,
            crop,
            frames,
            frame,
            clock,
        } => {
            if let Some(t) = time.filter(|t| !(*t > 0.0 && *t <= MAX_TIME)) {
                return fail(format!(
                    "error: --time {t} must be a positive number of seconds, at most {MAX_TIME:e}"
                ));
            }
            // With a time budget the sample count is only a ceiling.
            let samples = samples.or(time.map(|_| raydiance::MAX_SAMPLES));
            let request = RenderRequest {
                samples,
                width,
                height,
                seed,
                integrator,
                max_depth,
                frame: Default::default(),
            };
            if !(max_memory.is_finite() && max_memory > 0.0) {
                return fail(format!("error: --max-memory {max_memory} must be a positive number"));
            }
            let max_bytes = (max_memory * f64::from(1u32 << 30)) as u64;
            // POV-Ray's habit: without -o, the scene's name as a PNG in the current folder.
            let output = output.unwrap_or_else(|| {
                PathBuf::from(scene.file_stem().unwrap_or_default()).with_extension("png")
            });
            let choices = Choices { part, parts, crop, frames, frame, clock };
            let plan = match plan::plan(&choices, &output, |name| std::env::var(name).ok()) {
                Ok(plan) => plan,
                Err(message) => return fail(message),
            };
            if let Some(task) = &plan.task {
                tell!("{task}");
            }
            let options = RenderOptions { ppm_res, time, max_bytes };
            with_threads(threads, || render_all(&scene, &plan.jobs, &request, &options))
        }
        Command::Merge { parts, output, allow_partial, ppm_res } => {
            raydiance::image::end_cleanly_on_signal()
                .and_then(|()| merge(&parts, &output, allow_partial, ppm_res))
        }
        Command::Tonemap { input, output, op, v, gamma, exposure, white } => {
            let tone_map = ToneMap { op, v, gamma, exposure, white };
            raydiance::image::end_cleanly_on_signal()
                .and_then(|()| raydiance::tonemap_file(&input, &output, &tone_map))
                .map(|summary| say!("{summary}"))
        }
        Command::Check { scene } => {
            raydiance::check(&scene).map(|summary| say!("{summary}")).map_err(|e| e.to_string())
        }
        Command::Snapshot { paths, accept, samples, size, threads } => {
            let paths = if paths.is_empty() { vec![PathBuf::from(".")] } else { paths };
            if accept {
                accept_snapshots(&paths)
            } else if let Some(n) = samples.filter(|&n| !(2..=raydiance::MAX_SAMPLES).contains(&n))
            {
                Err(format!(
                    "error: --samples {n} is out of range (2 to {}): a snapshot needs a variance",
                    raydiance::MAX_SAMPLES
                ))
            } else {
                let options = snapshot::Options { samples, size };
                with_threads(threads, || check_snapshots(&paths, &options))
            }
        }
        Command::Bench { scenes, samples, repeats, threads } => with_threads(threads, || {
            bench::run(&scenes, &samples, repeats.into(), &mut std::io::stdout())
                .map_err(|e| e.to_string())
        }),
    };
    match result {
        Ok(()) if STOPPED.load(Ordering::SeqCst) => ExitCode::from(130),
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => fail(message),
    }
}

fn fail(message: String) -> ExitCode {
    tell!("{message}");
    ExitCode::FAILURE
}

/// Set by Ctrl-C, SIGTERM or SIGHUP: the render drops the pass under way and writes the passes
/// it completed.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Set when a render was stopped before its last sample: the exit status is then 130.
static STOPPED: AtomicBool = AtomicBool::new(false);

/// The longest `--time` budget, in seconds (some 30 years; more cannot be a deadline).
const MAX_TIME: f64 = 1e9;

/// The most worker threads `--threads` starts.
const MAX_THREADS: usize = 1024;

/// Runs `f` on a pool of `threads` workers (rayon's default pool when `None`).
fn with_threads(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<(), String> + Send,
) -> Result<(), String> {
    match threads {
        None => f(),
        Some(n) if !(1..=MAX_THREADS).contains(&n) => {
            Err(format!("error: --threads {n} is out of range (1 to {MAX_THREADS})"))
        }
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| format!("error: cannot start {n} threads: {e}"))?
            .install(f),
    }
}

/// What every render of a command shares.
struct RenderOptions {
    ppm_res: u32,
    time: Option<f64>,
    max_bytes: u64,
}

/// Renders the planned jobs (frames) one after another; a signal ends the run after the
/// frame under way is written.
fn render_all(
    scene_path: &Path,
    jobs: &[Job],
    request: &RenderRequest,
    options: &RenderOptions,
) -> Result<(), String> {
    // Everything that can be checked before rendering is: the outputs' types and folders first.
    let formats = jobs
        .iter()
        .map(|job| {
            if job.is_part() && raydiance::image::extension(&job.output).as_deref() != Some("exr") {
                return Err(format!(
                    "error: {}: a part (--part or --crop) is an OpenEXR file: name it .exr",
                    job.output.display()
                ));
            }
            raydiance::OutputFormat::for_path(&job.output, options.ppm_res)
                .map_err(|e| format!("error: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    for (job, format) in jobs.iter().zip(&formats) {
        // A signal during a frame ends the run once that frame is written.
        if INTERRUPTED.load(Ordering::SeqCst) {
            STOPPED.store(true, Ordering::SeqCst);
            break;
        }
        let request = RenderRequest { frame: job.frame, ..request.clone() };
        render(scene_path, job, format, &request, options)?;
    }
    Ok(())
}

/// Ctrl-C, SIGTERM and SIGHUP stop the render within a task; a second one ends the process at
/// once, leaving no temporary file. Installed when the first render starts: one before it ends
/// the process as usual.
fn handle_signals() -> Result<(), String> {
    static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                if INTERRUPTED.swap(true, Ordering::SeqCst) {
                    let _no_more_renames = raydiance::image::remove_pending_files();
                    std::process::exit(130);
                }
            })
            .map_err(|e| format!("error: cannot handle signals: {e}"))
        })
        .clone()
}

fn render(
    scene_path: &Path,
    job: &Job,
    format: &raydiance::OutputFormat,
    request: &RenderRequest,
    options: &RenderOptions,
) -> Result<(), String> {
    let output = &job.output;
    let (scene, digest) =
        raydiance::load_with_digest(scene_path, request).map_err(|e| e.to_string())?;
    let settings = &scene.settings;
    let region = Region {
        crop: job.crop.unwrap_or(Crop::whole(settings.width, settings.height)),
        share: job.share.unwrap_or(raydiance::region::Share::WHOLE),
        samples: settings.samples,
    };
    if job.is_part() {
        if !settings.integrator.samples_are_independent() {
            return Err(format!(
                "error: --part and --crop do not work with integrator {} yet: its samples are \
                 not independent of each other",
                settings.integrator.name()
            ));
        }
        region.check(settings.width, settings.height).map_err(|e| format!("error: {e}"))?;
    }
    let film_settings = raydiance::scene::graph::Settings {
        width: region.crop.width(),
        height: region.crop.height(),
        ..settings.clone()
    };
    raydiance::check_film_memory(&film_settings, options.max_bytes)?;
    for warning in &scene.warnings {
        tell!("{warning}");
    }
    handle_signals()?;
    let deadline = options.time.map(|t| Instant::now() + Duration::from_secs_f64(t));
    let progress = Bar::new(
        if deadline.is_some() { None } else { Some(region.samples_taken(u32::MAX)) },
        deadline,
    );
    let (film, stats) = raydiance::render::render_region(&scene, &region, &progress);
    progress.bar.finish_and_clear();
    // Nothing rendered: the file there (a render of before) is worth more than a black image.
    if stats.samples_per_pixel == 0 && INTERRUPTED.load(Ordering::SeqCst) {
        STOPPED.store(true, Ordering::SeqCst);
        return Err(format!(
            "interrupted before the first pass: nothing written ({} left as it was)",
            output.display()
        ));
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
        };
        part_file::write(output, &film, &header)
    } else {
        raydiance::write_render(output, format, &film, &stats, settings)
    };
    written.map_err(|e| format!("error: {e}"))?;
    if stats.dropped > 0 {
        tell!("warning: {} samples were NaN or infinite and were dropped", stats.dropped);
    }
    if let Some(warning) = raydiance::tonemap::darkness_warning(&film.image()) {
        tell!("{warning}");
    }
    // A time budget ends a render too; only a signal makes it "interrupted".
    let most = region.most_samples();
    if INTERRUPTED.load(Ordering::SeqCst) && stats.samples_per_pixel < most {
        STOPPED.store(true, Ordering::SeqCst);
        tell!(
            "interrupted: wrote the {} of {} samples per pixel completed",
            stats.samples_per_pixel,
            most
        );
    }
    let what = if job.is_part() {
        format!(
            "share {} of crop {} of {}x{}",
            region.share, region.crop, settings.width, settings.height
        )
    } else {
        format!("{}x{}", film.width, film.height)
    };
    let samples = region.samples_taken(stats.samples_per_pixel) as f64 / stats.seconds.max(1e-9);
    say!(
        "{}: {what}, {} spp, {}, {:.3} s, {:.2} Msamples/s",
        output.display(),
        stats.samples_per_pixel,
        settings.integrator.name(),
        stats.seconds,
        samples / 1e6,
    );
    Ok(())
}

/// `raydiance merge`: checks the parts together, adds them, writes the image.
fn merge(
    parts: &[PathBuf],
    output: &Path,
    allow_partial: bool,
    ppm_res: u32,
) -> Result<(), String> {
    let start = Instant::now();
    let format =
        raydiance::OutputFormat::for_path(output, ppm_res).map_err(|e| format!("error: {e}"))?;
    if let Ok(out) = std::fs::canonicalize(output) {
        if let Some(part) = parts.iter().find(|p| std::fs::canonicalize(p).is_ok_and(|p| p == out))
        {
            return Err(format!(
                "error: {}: is one of the parts; merging would replace it",
                part.display()
            ));
        }
    }
    let merged = raydiance::split::merge::merge(parts, allow_partial)?;
    raydiance::write_image(output, &format, &merged.image, &merged.info)
        .map_err(|e| format!("error: {e}"))?;
    for line in &merged.missing {
        tell!("warning: {line}");
    }
    let (least, most) = merged.samples;
    let spp = if least == most { least.to_string() } else { format!("{least} to {most}") };
    say!(
        "{}: {}x{}, {spp} spp, {}, merged from {} parts in {:.3} s ({:.3} s of rendering)",
        output.display(),
        merged.image.width,
        merged.image.height,
        merged.info.integrator,
        merged.parts,
        start.elapsed().as_secs_f64(),
        merged.info.seconds,
    );
    Ok(())
}

/// `raydiance snapshot`: checks every scene, printing a line for each that does not match and
/// one summary line; an error in one scene does not stop the others.
fn check_snapshots(paths: &[PathBuf], options: &snapshot::Options) -> Result<(), String> {
    let start = Instant::now();
    let scenes = snapshot::scenes(paths)?;
    let bar = ProgressBar::new(scenes.len() as u64);
    let style =
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} {msg}");
    bar.set_style(style.expect("the template is valid"));
    let (mut matched, mut differ, mut new, mut unsupported, mut errors) = (0, 0, 0, 0, 0);
    for scene in &scenes {
        bar.set_message(scene.display().to_string());
        match snapshot::check(scene, options) {
            Ok(outcome) => {
                match outcome.verdict {
                    snapshot::Verdict::Matches => matched += 1,
                    snapshot::Verdict::Differs { .. } => differ += 1,
                    snapshot::Verdict::New => new += 1,
                    snapshot::Verdict::Unsupported { .. } => unsupported += 1,
                }
                if outcome.verdict != snapshot::Verdict::Matches {
                    bar.suspend(|| say!("{}", outcome.summary()));
                }
            }
            Err(message) => {
                errors += 1;
                bar.suspend(|| tell!("{message}"));
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    say!(
        "snapshot: {} scenes: {matched} match, {differ} differ, {new} new, {unsupported} not \
         snapshotted, {errors} failed to render ({:.2} s)",
        scenes.len(),
        start.elapsed().as_secs_f64()
    );
    match scenes.len() - matched - unsupported {
        0 => Ok(()),
        n => Err(format!("error: {n} of {} scenes do not match their snapshots", scenes.len())),
    }
}

/// `raydiance snapshot --accept`: promotes the `.new` snapshots.
fn accept_snapshots(paths: &[PathBuf]) -> Result<(), String> {
    let accepted = snapshot::accept(paths)?;
    for path in &accepted {
        say!("accepted {}", path.display());
    }
    say!("snapshot: accepted {} new snapshots", accepted.len());
    Ok(())
}

/// A progress bar on stderr with elapsed time and ETA (hidden when stderr is not a terminal),
/// and the reasons to stop early: Ctrl-C and the time budget.
struct Bar {
    bar: ProgressBar,
    deadline: Option<Instant>,
}

impl Bar {
    /// `total` samples, or a spinner when the total is not known (a time budget).
    fn new(total: Option<u64>, deadline: Option<Instant>) -> Self {
        let (bar, template) = match total {
            Some(total) => (
                ProgressBar::new(total),
                "{spinner} [{elapsed_precise}] {wide_bar} {percent}% ETA {eta}",
            ),
            None => (ProgressBar::no_length(), "{spinner} [{elapsed_precise}] {human_pos} samples"),
        };
        bar.set_style(ProgressStyle::with_template(template).expect("the template is valid"));
        bar.enable_steady_tick(Duration::from_millis(200));
        Bar { bar, deadline }
    }
}

impl Progress for Bar {
    fn advance(&self, samples: u64) {
        self.bar.inc(samples);
    }

    fn pass_limit(&self, seconds_per_sample: f64) -> Option<u32> {
        if INTERRUPTED.load(Ordering::SeqCst) {
            return Some(0);
        }
        let deadline = self.deadline?;
        let left = deadline.saturating_duration_since(Instant::now()).as_secs_f64();
        Some((left / seconds_per_sample.max(1e-9)).min(f64::from(u32::MAX)) as u32)
    }

    fn should_abandon(&self) -> bool {
        INTERRUPTED.load(Ordering::SeqCst)
    }
}
