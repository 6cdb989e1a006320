//! The stages joined for the command line: load a scene with overrides, write a render, check a
//! scene, tone-map a file.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::animation::Frame;
use crate::aov::{self, AovImage, AovList};
use crate::diagnostic::SceneError;
use crate::digest::Digest;
use crate::film::{BYTES_PER_PIXEL, Film};
use crate::graph::{IntegratorKind, SceneGraph, Settings};
use crate::image::{self, Image, ImageError, RenderInfo};
use crate::integrator::{self, sppm};
use crate::progress::RenderStats;
use crate::scene::{self, Scene};
use crate::split::merge::{self, MergeError};
use crate::tonemap::{self, ToneMap, ToneMapError};

/// Command-line values that override a scene's `settings`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RenderRequest {
    pub samples: Option<u32>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub seed: Option<u64>,
    pub integrator: Option<IntegratorKind>,
    pub max_depth: Option<u32>,
    /// The animation frame to evaluate the scene at (`clock`, `frame_number`).
    pub frame: Frame,
    /// Folders searched for included files (`--include-path`), after the including file's.
    pub include_path: Vec<std::path::PathBuf>,
}

pub use crate::region::MAX_RESOLUTION;
/// Largest sample count accepted from the command line, as from `settings`.
pub const MAX_SAMPLES: u32 = 1_000_000;
/// Longest path accepted from the command line, in bounces.
pub const MAX_DEPTH: u32 = 1024;

/// A command-line value out of its range.
#[derive(Debug, thiserror::Error)]
pub enum RequestError {
    #[error("error: --{name} {value} is out of range (1 to {max})")]
    OutOfRange { name: &'static str, value: u32, max: u32 },
    #[error("error: --max-depth {0} is out of range (0 to {max})", max = MAX_DEPTH)]
    MaxDepth(u32),
}

impl RenderRequest {
    /// The scene's settings with these overrides applied; values out of range are errors.
    pub fn apply(&self, settings: &Settings) -> Result<Settings, RequestError> {
        let check = |name: &'static str, value: Option<u32>, max: u32| match value {
            Some(value) if value == 0 || value > max => {
                Err(RequestError::OutOfRange { name, value, max })
            }
            _ => Ok(()),
        };
        check("samples", self.samples, MAX_SAMPLES)?;
        check("width", self.width, MAX_RESOLUTION)?;
        check("height", self.height, MAX_RESOLUTION)?;
        if let Some(depth) = self.max_depth.filter(|&d| d > MAX_DEPTH) {
            return Err(RequestError::MaxDepth(depth));
        }
        Ok(Settings {
            width: self.width.unwrap_or(settings.width),
            height: self.height.unwrap_or(settings.height),
            samples: self.samples.unwrap_or(settings.samples),
            integrator: self.integrator.unwrap_or(settings.integrator),
            max_depth: self.max_depth.unwrap_or(settings.max_depth),
            seed: self.seed.unwrap_or(settings.seed),
            ..settings.clone()
        })
    }
}

/// Why loading failed: the scene's text, or a command-line value.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Request(#[from] RequestError),
}

/// Parses the scene file, applies the overrides and builds the render-ready scene.
pub fn load(path: &Path, request: &RenderRequest) -> Result<Scene, LoadError> {
    load_with_digest(path, request).map(|(scene, _)| scene)
}

/// As `load`, with a digest of what decides the image: the text of the scene and its includes,
/// the settings after the overrides, and the animation frame.
pub fn load_with_digest(
    path: &Path,
    request: &RenderRequest,
) -> Result<(Scene, Digest), LoadError> {
    let image = request.width.zip(request.height);
    let (mut graph, sources) =
        crate::lang::load_scene_with(path, request.frame, image, &request.include_path)?;
    graph.settings = request.apply(&graph.settings)?;
    let frame = request.frame;
    let digest = sources
        .with(format!("{:?}", graph.settings).as_bytes())
        .with(&frame.number.to_le_bytes())
        .with(&frame.clock.to_le_bytes());
    let scene = scene::build(&graph)?;
    Ok((scene, digest))
}

/// Parses and evaluates the scene file.
pub fn load_graph(path: &Path) -> Result<SceneGraph, LoadError> {
    crate::lang::load_scene(path).map_err(LoadError::from)
}

/// Applies the overrides to the graph's settings and builds the render-ready scene.
pub fn build(mut graph: SceneGraph, request: &RenderRequest) -> Result<Scene, LoadError> {
    graph.settings = request.apply(&graph.settings)?;
    scene::build(&graph).map_err(LoadError::from)
}

/// `raydiance check`: a short summary of a valid scene, or its first error.
pub fn check(path: &Path) -> Result<String, LoadError> {
    let scene = load(path, &RenderRequest::default())?;
    let s = &scene.settings;
    let mut summary = format!(
        "{}: ok: {}x{}, {} spp, integrator {}, max_depth {}, {} primitives, {} materials, {} lights",
        path.display(),
        s.width,
        s.height,
        s.samples,
        s.integrator.name(),
        s.max_depth,
        scene.traced_primitives(),
        scene.materials.len(),
        scene.lights.len(),
    );
    for warning in &scene.warnings {
        summary.push('\n');
        summary.push_str(warning);
    }
    Ok(summary)
}

/// A film larger than `render --max-memory` allows.
#[derive(Debug, thiserror::Error)]
#[error(
    "error: a {width}x{height} film needs {needed:.1} GiB ({per_pixel} bytes a pixel while \
     rendering), more than --max-memory {allowed:.1} GiB allows: render it in tiles with `--crop \
     X0,X1,Y0,Y1` and join them with `raydiance merge`, lower the resolution, or raise \
     --max-memory if the machine has the memory",
    needed = gib(*needed_bytes),
    allowed = gib(*max_bytes)
)]
pub struct FilmTooLarge {
    pub width: u32,
    pub height: u32,
    /// The film's bytes a pixel, with its AOVs'.
    pub per_pixel: u64,
    pub needed_bytes: u64,
    pub max_bytes: u64,
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 30)
}

/// Refuses, before any work, a film (with the AOVs of `aovs`) larger than `max_bytes`
/// (`render --max-memory`).
pub fn check_film_memory(
    settings: &Settings,
    aovs: &AovList,
    max_bytes: u64,
) -> Result<(), FilmTooLarge> {
    let pixels = u64::from(settings.width) * u64::from(settings.height);
    let per_pixel = BYTES_PER_PIXEL + aovs.channels().count() as u64 * aov::BYTES_PER_CHANNEL;
    let needed_bytes = pixels * per_pixel;
    if needed_bytes <= max_bytes {
        return Ok(());
    }
    let (width, height) = (settings.width, settings.height);
    Err(FilmTooLarge { width, height, per_pixel, needed_bytes, max_bytes })
}

/// A photon integrator's render larger than `render --max-memory` allows, counted before any
/// photon is traced.
#[derive(Debug, thiserror::Error)]
pub enum RenderTooLarge {
    #[error(
        "error: photon: `photons` {photons} with `max_depth` {max_depth} may store {stored} \
         photons (one at each bounce, up to max_depth per photon: all of them in a closed room \
         of white walls), {needed:.1} GiB with the film, more than --max-memory {allowed:.1} GiB \
         allows: lower `photons` or `max_depth`, or raise --max-memory if the machine has the \
         memory",
        needed = gib(*needed_bytes),
        allowed = gib(*max_bytes)
    )]
    Photons { photons: u32, max_depth: u32, stored: u64, needed_bytes: u64, max_bytes: u64 },
    #[error(
        "error: sppm: a {width}x{height} image needs {needed:.1} GiB ({per_pixel} bytes a pixel: \
         the film, the visible points, their grid and the photons' sums), more than --max-memory \
         {allowed:.1} GiB allows: lower the resolution, or raise --max-memory if the machine has \
         the memory",
        needed = gib(*needed_bytes),
        allowed = gib(*max_bytes)
    )]
    Sppm { width: u32, height: u32, per_pixel: u64, needed_bytes: u64, max_bytes: u64 },
}

/// Refuses, before any work, a photon integrator's render that would take more than
/// `max_bytes` (`render --max-memory`); the others take their film only (`check_film_memory`).
pub fn check_render_memory(scene: &Scene, max_bytes: u64) -> Result<(), RenderTooLarge> {
    let s = &scene.settings;
    let pixels = u64::from(s.width) * u64::from(s.height);
    match s.integrator {
        IntegratorKind::Direct | IntegratorKind::Path => Ok(()),
        IntegratorKind::Photon | IntegratorKind::FinalGather => {
            let stored = integrator::most_stored(scene);
            let needed_bytes = pixels * BYTES_PER_PIXEL + stored * integrator::STORED_PHOTON_BYTES;
            if needed_bytes <= max_bytes {
                return Ok(());
            }
            let (photons, max_depth) = (s.photons(), s.max_depth);
            Err(RenderTooLarge::Photons { photons, max_depth, stored, needed_bytes, max_bytes })
        }
        IntegratorKind::Sppm => {
            let per_pixel = sppm::bytes_per_pixel();
            let needed_bytes = pixels * per_pixel;
            if needed_bytes <= max_bytes {
                return Ok(());
            }
            let (width, height) = (s.width, s.height);
            Err(RenderTooLarge::Sppm { width, height, per_pixel, needed_bytes, max_bytes })
        }
    }
}

/// What `render` writes, chosen by the output's extension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutputFormat {
    Exr,
    /// HDR PPM with `#MAX`, the given integer standing for MAX.
    Ppm {
        res: u32,
    },
    /// 8-bit PNG, tone-mapped with the default operator.
    Png,
}

impl OutputFormat {
    /// The format for `path`, after checking that it can be written (before any rendering).
    pub fn for_path(path: &Path, ppm_res: u32) -> Result<OutputFormat, ImageError> {
        let format = match image::extension(path).as_deref() {
            Some("exr") => OutputFormat::Exr,
            Some("ppm") if ppm_res > 0 => OutputFormat::Ppm { res: ppm_res },
            Some("ppm") => return Err(ImageError::format(path, "--ppm-res must be at least 1")),
            Some("png") => OutputFormat::Png,
            _ => {
                return Err(ImageError::format(
                    path,
                    "unknown output type (expected .exr, .ppm or .png)",
                ));
            }
        };
        image::check_writable(path)?;
        Ok(format)
    }
}

/// Writes a finished render to `path`.
pub fn write_render(
    path: &Path,
    format: &OutputFormat,
    film: &Film,
    stats: &RenderStats,
    settings: &Settings,
) -> Result<(), ImageError> {
    let info = RenderInfo {
        samples_per_pixel: stats.samples_per_pixel,
        integrator: settings.integrator.name().to_string(),
        seed: settings.seed,
        seconds: stats.seconds,
        parameters: settings.parameters(),
    };
    write_image(path, format, &film.image(), film.aovs.as_ref(), &info)
}

/// Writes an image to `path` in `format` (`info` goes into an EXR's header, and so do the
/// AOVs; a PPM or PNG holds the beauty alone).
pub fn write_image(
    path: &Path,
    format: &OutputFormat,
    image: &Image,
    aovs: Option<&AovImage>,
    info: &RenderInfo,
) -> Result<(), ImageError> {
    match *format {
        OutputFormat::Exr => image::exr::write_with_aovs(path, image, aovs, info),
        OutputFormat::Ppm { res } => image::ppm::write_hdr(path, image, res),
        OutputFormat::Png => {
            let pixels = tonemap::quantise(&tonemap::tonemap(image, &ToneMap::default()));
            image::png::write(path, image.width, image.height, &pixels)
        }
    }
}

/// Why `raydiance tonemap` wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum ToneMapFileError {
    #[error("error: {0}")]
    Parameters(#[from] ToneMapError),
    #[error("error: {}: unknown output type (expected .ppm or .png)", .0.display())]
    OutputType(PathBuf),
    #[error("error: {}: is the input; tone mapping would replace it", .0.display())]
    OutputIsInput(PathBuf),
    #[error("error: {0}")]
    Image(#[from] ImageError),
}

/// `raydiance tonemap`: reads an HDR file, writes LDR `.ppm` (`#MAX=1`) or `.png`; returns
/// the summary line.
pub fn tonemap_file(
    input: &Path,
    output: &Path,
    params: &ToneMap,
) -> Result<String, ToneMapFileError> {
    params.validate()?;
    let ldr_ppm = match image::extension(output).as_deref() {
        Some("ppm") => true,
        Some("png") => false,
        _ => return Err(ToneMapFileError::OutputType(output.to_path_buf())),
    };
    image::check_writable(output)?;
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(input), std::fs::canonicalize(output))
        && a == b
    {
        return Err(ToneMapFileError::OutputIsInput(output.to_path_buf()));
    }
    let hdr = image::read_hdr(input)?;
    let pixels = tonemap::quantise(&tonemap::tonemap(&hdr, params));
    if ldr_ppm {
        image::ppm::write_ldr(output, hdr.width, hdr.height, &pixels)?;
    } else {
        image::png::write(output, hdr.width, hdr.height, &pixels)?;
    }
    let mut summary = format!(
        "{}: {}x{}, {} ({}), largest input value {}",
        output.display(),
        hdr.width,
        hdr.height,
        params.op,
        params.used(),
        hdr.max_component()
    );
    match tonemap::non_finite_pixels(&hdr) {
        0 => {}
        n => summary.push_str(&format!("; {n} pixels not finite, clamped (+inf to the largest)")),
    }
    Ok(summary)
}

/// What `raydiance merge` says when it has written the image.
#[derive(Debug, Clone, PartialEq)]
pub struct MergeReport {
    /// What was missing (with `allow_partial`), one line each.
    pub missing: Vec<String>,
    /// What was written, on one line.
    pub summary: String,
}

/// `raydiance merge`: checks the parts together, adds them, writes the image.
pub fn merge_files(
    parts: &[PathBuf],
    output: &Path,
    allow_partial: bool,
    ppm_res: u32,
) -> Result<MergeReport, MergeError> {
    let start = Instant::now();
    let format = OutputFormat::for_path(output, ppm_res)?;
    if let Ok(out) = std::fs::canonicalize(output)
        && let Some(part) = parts.iter().find(|p| std::fs::canonicalize(p).is_ok_and(|p| p == out))
    {
        return Err(MergeError::OutputIsAPart(part.clone()));
    }
    let merged = merge::merge(parts, allow_partial)?;
    write_image(output, &format, &merged.image, merged.aovs.as_ref(), &merged.info)?;
    let (least, most) = merged.samples;
    let spp = if least == most { least.to_string() } else { format!("{least} to {most}") };
    let summary = format!(
        "{}: {}x{}, {spp} spp, {}, merged from {} parts in {:.3} s ({:.3} s of rendering)",
        output.display(),
        merged.image.width,
        merged.image.height,
        merged.info.integrator,
        merged.parts,
        start.elapsed().as_secs_f64(),
        merged.info.seconds,
    );
    Ok(MergeReport { missing: merged.missing, summary })
}
