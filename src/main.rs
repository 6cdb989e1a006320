//! The `raydiance` command line: render, merge, tonemap, denoise, check, snapshot, bench, preview.

use std::error::Error;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use raydiance::animation;
use raydiance::aov::AovList;
use raydiance::graph::IntegratorKind;
use raydiance::image::{SignalError, end_cleanly_on_signal};
use raydiance::job::{Ended, Observer, RenderJob, RenderJobError};
use raydiance::progress::Progress;
use raydiance::region::Crop;
use raydiance::split::plan::{Choices, PartChoice};
use raydiance::tonemap::{Operator, ToneMap};
use raydiance::{RenderRequest, bench, preview, snapshot};

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
        #[arg(long, allow_negative_numbers = true)]
        samples: Option<u32>,
        /// Image width in pixels, 1 to 65536 [default: the scene's `settings`, else 256]
        #[arg(long, allow_negative_numbers = true)]
        width: Option<u32>,
        /// Image height in pixels, 1 to 65536 [default: the scene's `settings`, else 256]
        #[arg(long, allow_negative_numbers = true)]
        height: Option<u32>,
        /// Seed of the random numbers: the same seed gives the same image [default: the scene's
        /// `settings`, else 0]
        #[arg(long, allow_negative_numbers = true)]
        seed: Option<u64>,
        /// Worker threads, 1 to 1024 [default: one per core]. The image does not depend on it.
        #[arg(long, allow_negative_numbers = true)]
        threads: Option<usize>,
        /// `direct` (the course's Lab 4: direct light, mirrors and glass followed), `path`
        /// (path tracing of the full rendering equation), `photon` (Jensen's photon mapping, one
        /// map), `final_gather` (photon mapping with a caustic map and final gathering) or
        /// `sppm` (stochastic progressive photon mapping) [default: the scene's `settings`,
        /// else path]
        #[arg(long, value_parser = parse_integrator)]
        integrator: Option<IntegratorKind>,
        /// Longest path in bounces, 0 to 1024 [default: the scene's `settings`, else 32]
        #[arg(long, allow_negative_numbers = true)]
        max_depth: Option<u32>,
        /// Time budget in seconds: render as many samples as fit, the last pass shortened to
        /// end near the budget (up to --samples if given).
        #[arg(long, allow_negative_numbers = true)]
        time: Option<f64>,
        /// The integer that MAX stands for in HDR .ppm output.
        #[arg(long, default_value_t = raydiance::image::ppm::HDR_RES, allow_negative_numbers = true)]
        ppm_res: u32,
        /// The most memory the film may take, in GiB (it takes 96 bytes a pixel).
        #[arg(long, default_value_t = 8.0, allow_negative_numbers = true)]
        max_memory: f64,
        /// Render share I (0-based) of N disjoint shares of the samples, into a part file
        /// (.exr) for `merge`; `auto` takes the share from a Slurm job array or a Kubernetes
        /// Indexed Job (with --parts).
        #[arg(long, value_name = "I/N|auto", allow_hyphen_values = true)]
        part: Option<PartChoice>,
        /// With --part auto under Kubernetes: the number of shares of each frame (the Job's
        /// completions divided by the frames).
        #[arg(long, value_name = "N", allow_negative_numbers = true)]
        parts: Option<u32>,
        /// Render only pixels X0 <= x < X1, Y0 <= y < Y1 of the image, into a part file (.exr).
        #[arg(long, value_name = "X0,X1,Y0,Y1", allow_hyphen_values = true)]
        crop: Option<Crop>,
        /// Render frames F0 to F1 (inclusive) of an animation; a run of `#` in the output's
        /// name becomes the frame number (else it is appended before the extension).
        #[arg(long, value_name = "F0..F1", value_parser = animation::parse_frames, allow_hyphen_values = true)]
        frames: Option<(u32, u32)>,
        /// Render only frame F of --frames.
        #[arg(long, value_name = "F", allow_negative_numbers = true)]
        frame: Option<u32>,
        /// `clock` runs from C0 at the first frame to C1 at the last [default: 0..1].
        #[arg(long, value_name = "C0..C1", value_parser = animation::parse_clock, allow_hyphen_values = true)]
        clock: Option<(f64, f64)>,
        /// A folder searched for `#include`d files after the including file's own, before
        /// RAYDIANCE_INCLUDE_PATH and the built-in library (may be repeated).
        #[arg(long, value_name = "DIR")]
        include_path: Vec<PathBuf>,
        /// Write AOVs beside the image, as layers of the EXR: any of albedo, normal, depth,
        /// position, separated by commas (seen through mirrors and glass).
        #[arg(long, value_name = "LIST")]
        aov: Option<AovList>,
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
        #[arg(long, default_value_t = raydiance::image::ppm::HDR_RES, allow_negative_numbers = true)]
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
    /// Denoise a render (.exr) with Intel Open Image Denoise, guided by its albedo and normal
    /// AOVs when it has them, into another .exr (built with the cargo feature `denoise`).
    Denoise {
        /// The render: an .exr written by `render` or `merge` (not a part).
        input: PathBuf,
        /// The denoised image to write (.exr); the render stays as it is.
        #[arg(short, long)]
        output: PathBuf,
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
        #[arg(long, allow_negative_numbers = true)]
        samples: Option<u32>,
        /// Image size WxH [default: the stored snapshot's, or the scene's scaled to 64 pixels
        /// on its longer side].
        #[arg(long, value_parser = parse_size, allow_hyphen_values = true)]
        size: Option<(u32, u32)>,
        /// Worker threads (default: one per core). The verdict does not depend on it.
        #[arg(long, allow_negative_numbers = true)]
        threads: Option<usize>,
    },
    /// Serve a page on this machine that shows the scene's render as it refines, and renders
    /// it again whenever the scene or a file it reads is saved.
    Preview {
        /// The scene file (.scn or .pov).
        scene: PathBuf,
        /// The address to listen on, IP:PORT (port 0: any free one). An address other than
        /// 127.0.0.1 or ::1 lets other machines see the page.
        #[arg(long, value_name = "IP:PORT", default_value = preview::DEFAULT_LISTEN)]
        listen: SocketAddr,
        /// Open the page in the desktop's browser (with `xdg-open`).
        #[arg(long)]
        open: bool,
        /// Worker threads, 1 to 1024 [default: one per core].
        #[arg(long, allow_negative_numbers = true)]
        threads: Option<usize>,
        /// A folder searched for `#include`d files, as `render --include-path`.
        #[arg(long, value_name = "DIR")]
        include_path: Vec<PathBuf>,
    },
    /// Render scenes and print samples per second and seconds per frame.
    Bench {
        /// Scenes to render (default: the benchmark scenes in scenes/).
        scenes: Vec<PathBuf>,
        /// Samples per pixel, one or more separated by commas (e.g. 16,64).
        #[arg(long, default_value = "16")]
        samples: String,
        /// Timed renders of each scene after one warm-up (1 to 1000).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=1000), allow_negative_numbers = true)]
        repeats: u16,
        /// Worker threads, 1 to 1024 [default: one per core].
        #[arg(long, allow_negative_numbers = true)]
        threads: Option<usize>,
    },
}

/// A command-line value that clap's own parsers cannot check.
#[derive(Debug, thiserror::Error)]
enum ValueError {
    #[error(
        "unknown integrator `{0}` (expected `direct`, `path`, `photon`, `final_gather` or `sppm`)"
    )]
    UnknownIntegrator(String),
    #[error("`{0}` is not a size WxH with sides from 1 to {max} (e.g. 64x48)", max = raydiance::MAX_RESOLUTION)]
    NotASize(String),
    #[error(
        "error: --samples {0} is out of range (2 to {max}): a snapshot needs a variance",
        max = raydiance::MAX_SAMPLES
    )]
    SnapshotSamples(u32),
}

fn parse_integrator(s: &str) -> Result<IntegratorKind, ValueError> {
    IntegratorKind::named(s).ok_or_else(|| ValueError::UnknownIntegrator(s.to_string()))
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

fn parse_size(s: &str) -> Result<(u32, u32), ValueError> {
    let max = raydiance::MAX_RESOLUTION;
    let side = |v: &str| v.trim().parse::<u32>().ok().filter(|v| (1..=max).contains(v));
    s.split_once(['x', 'X'])
        .and_then(|(w, h)| Some((side(w)?, side(h)?)))
        .ok_or_else(|| ValueError::NotASize(s.to_string()))
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
            include_path,
            aov,
        } => {
            let job = RenderJob {
                scene,
                output,
                request: RenderRequest {
                    samples,
                    width,
                    height,
                    seed,
                    integrator,
                    max_depth,
                    frame: Default::default(),
                    include_path,
                },
                time,
                ppm_res,
                max_memory,
                choices: Choices { part, parts, crop, frames, frame, clock },
                aovs: aov.unwrap_or_default(),
            };
            match job.plan(|name| std::env::var(name).ok()) {
                Ok(planned) => {
                    if let Some(task) = planned.task() {
                        tell!("{task}");
                    }
                    on_threads(threads, || planned.render(&Terminal))
                }
                Err(e) => Err(e.into()),
            }
        }
        Command::Merge { parts, output, allow_partial, ppm_res } => complete(
            end_cleanly_on_signal()
                .map_err(Failure::from)
                .and_then(|()| {
                    raydiance::merge_files(&parts, &output, allow_partial, ppm_res)
                        .map_err(Failure::from)
                })
                .map(|merged| {
                    for line in &merged.missing {
                        tell!("warning: {line}");
                    }
                    say!("{}", merged.summary);
                }),
        ),
        Command::Tonemap { input, output, op, v, gamma, exposure, white } => {
            let tone_map = ToneMap { op, v, gamma, exposure, white };
            complete(
                end_cleanly_on_signal()
                    .map_err(Failure::from)
                    .and_then(|()| {
                        raydiance::tonemap_file(&input, &output, &tone_map).map_err(Failure::from)
                    })
                    .map(|s| say!("{s}")),
            )
        }
        Command::Denoise { input, output } => complete(
            end_cleanly_on_signal()
                .map_err(Failure::from)
                .and_then(|()| {
                    raydiance::denoise::denoise_file(&input, &output).map_err(Failure::from)
                })
                .map(|s| say!("{s}")),
        ),
        Command::Check { scene } => {
            complete(raydiance::check(&scene).map(|summary| say!("{summary}")))
        }
        Command::Snapshot { paths, accept, samples, size, threads } => {
            let paths = if paths.is_empty() { vec![PathBuf::from(".")] } else { paths };
            if accept {
                complete(accept_snapshots(&paths))
            } else if let Some(n) = samples.filter(|&n| !(2..=raydiance::MAX_SAMPLES).contains(&n))
            {
                complete(Err(ValueError::SnapshotSamples(n)))
            } else {
                let options = snapshot::Options { samples, size };
                complete(on_threads(threads, || check_snapshots(&paths, &options)))
            }
        }
        Command::Preview { scene, listen, open, threads, include_path } => {
            let request = RenderRequest { include_path, ..RenderRequest::default() };
            complete(on_threads(threads, || serve_preview(scene, request, listen, open)))
        }
        Command::Bench { scenes, samples, repeats, threads } => {
            complete(on_threads(threads, || {
                bench::run(&scenes, &samples, repeats.into(), &mut std::io::stdout())
            }))
        }
    };
    match result {
        Ok(Ended::Interrupted) => ExitCode::from(130),
        Ok(Ended::Complete) => ExitCode::SUCCESS,
        Err(error) => fail(error),
    }
}

/// Any error of a command, to print.
type Failure = Box<dyn Error + Send + Sync>;

fn fail(error: impl std::fmt::Display) -> ExitCode {
    tell!("{error}");
    ExitCode::FAILURE
}

/// Runs `f` on a pool of `threads` workers (rayon's default pool when `None`).
fn on_threads<T: Send, E: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<T, E> + Send,
) -> Result<T, Failure>
where
    Failure: From<E>,
{
    Ok(raydiance::threads::with_threads(threads, f)??)
}

/// The end of a command that has no other way to end than doing all its work.
fn complete<E>(result: Result<(), E>) -> Result<Ended, Failure>
where
    Failure: From<E>,
{
    result?;
    Ok(Ended::Complete)
}

/// Set by Ctrl-C, SIGTERM or SIGHUP: the render drops the pass under way and writes the passes
/// it completed.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Ctrl-C, SIGTERM and SIGHUP stop the render within a task; a second one ends the process at
/// once, leaving no temporary file. Installed when the first render starts: one before it ends
/// the process as usual.
fn handle_signals() -> Result<(), SignalError> {
    static INSTALLED: OnceLock<Result<(), SignalError>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                if INTERRUPTED.swap(true, Ordering::SeqCst) {
                    let _no_more_renames = raydiance::image::remove_pending_files();
                    std::process::exit(130);
                }
            })
            .map_err(|e| SignalError(e.to_string()))
        })
        .clone()
}

/// `raydiance snapshot`: checks every scene, printing a line for each that does not match and
/// one summary line; an error in one scene does not stop the others.
fn check_snapshots(paths: &[PathBuf], options: &snapshot::Options) -> Result<(), Failure> {
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
        n => {
            Err(format!("error: {n} of {} scenes do not match their snapshots", scenes.len())
                .into())
        }
    }
}

/// `raydiance preview`: says where the page is, opens it if asked, and serves it until the
/// process is ended.
fn serve_preview(
    scene: PathBuf,
    request: RenderRequest,
    listen: SocketAddr,
    open: bool,
) -> Result<(), Failure> {
    let server = preview::listen(preview::Preview { scene: scene.clone(), request }, listen)?;
    let url = server.url();
    if !server.address().ip().is_loopback() {
        tell!("warning: listening on {}: other machines can see the page", server.address());
    }
    say!("preview of {} at {url} (Ctrl-C ends it)", scene.display());
    if open {
        // The page works without it: a desktop without a browser is only told.
        if let Err(e) = std::process::Command::new("xdg-open").arg(&url).spawn() {
            tell!("warning: cannot open a browser (xdg-open: {e}): open {url}");
        }
    }
    server.serve()
}

/// `raydiance snapshot --accept`: promotes the `.new` snapshots.
fn accept_snapshots(paths: &[PathBuf]) -> Result<(), snapshot::SnapshotError> {
    let accepted = snapshot::accept(paths)?;
    for path in &accepted {
        say!("accepted {}", path.display());
    }
    say!("snapshot: accepted {} new snapshots", accepted.len());
    Ok(())
}

/// The command line's observer of a render job: a progress bar for each frame, what the job
/// says on stdout and stderr, and Ctrl-C.
struct Terminal;

impl Observer for Terminal {
    fn frame_starts(&self, total: Option<u64>) -> Result<Box<dyn Progress + '_>, RenderJobError> {
        handle_signals().map_err(RenderJobError::Signals)?;
        Ok(Box::new(Bar::new(total)))
    }

    fn warning(&self, text: &str) {
        tell!("{text}");
    }

    fn written(&self, summary: &str) {
        say!("{summary}");
    }

    fn interrupted(&self) -> bool {
        INTERRUPTED.load(Ordering::SeqCst)
    }
}

/// A progress bar on stderr with elapsed time and ETA (hidden when stderr is not a terminal),
/// cleared when the render ends; Ctrl-C stops the render.
struct Bar {
    bar: ProgressBar,
}

impl Bar {
    /// `total` samples, or a spinner when the total is not known (a time budget).
    fn new(total: Option<u64>) -> Self {
        let (bar, template) = match total {
            Some(total) => (
                ProgressBar::new(total),
                "{spinner} [{elapsed_precise}] {wide_bar} {percent}% ETA {eta}",
            ),
            None => (ProgressBar::no_length(), "{spinner} [{elapsed_precise}] {human_pos} samples"),
        };
        bar.set_style(ProgressStyle::with_template(template).expect("the template is valid"));
        bar.enable_steady_tick(Duration::from_millis(200));
        Bar { bar }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Bar {
    fn advance(&self, samples: u64) {
        self.bar.inc(samples);
    }

    fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
        INTERRUPTED.load(Ordering::SeqCst).then_some(0)
    }

    fn should_abandon(&self) -> bool {
        INTERRUPTED.load(Ordering::SeqCst)
    }
}
