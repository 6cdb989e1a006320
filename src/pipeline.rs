//! The stages joined for the command line: load a scene with overrides, write a render, check a
//! scene, tone-map a file.

use std::fmt;
use std::path::Path;

use crate::animation::Frame;
use crate::diagnostic::SceneError;
use crate::digest::Digest;
use crate::film::Film;
use crate::image::{self, Image, ImageError, RenderInfo};
use crate::render::RenderStats;
use crate::scene::graph::{IntegratorKind, SceneGraph, Settings};
use crate::scene::{self, Scene};
use crate::tonemap::{self, ToneMap};

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
}

/// Largest image side and sample count accepted from the command line, as from `settings`.
pub const MAX_RESOLUTION: u32 = 65536;
pub const MAX_SAMPLES: u32 = 1_000_000;

impl RenderRequest {
    /// The scene's settings with these overrides applied; values out of range are errors.
    pub fn apply(&self, settings: &Settings) -> Result<Settings, String> {
        let check = |name: &str, value: Option<u32>, max: u32| match value {
            Some(v) if v == 0 || v > max => {
                Err(format!("error: --{name} {v} is out of range (1 to {max})"))
            }
            _ => Ok(()),
        };
        check("samples", self.samples, MAX_SAMPLES)?;
        check("width", self.width, MAX_RESOLUTION)?;
        check("height", self.height, MAX_RESOLUTION)?;
        if let Some(depth) = self.max_depth.filter(|&d| d > 1024) {
            return Err(format!("error: --max-depth {depth} is out of range (0 to 1024)"));
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
#[derive(Debug)]
pub enum LoadError {
    Scene(SceneError),
    Request(String),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Scene(e) => write!(f, "{e}"),
            LoadError::Request(e) => write!(f, "{e}"),
        }
    }
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
    let (mut graph, sources) =
        crate::lang::load_scene_for_image(path, request.frame, request.width.zip(request.height))
            .map_err(LoadError::Scene)?;
    graph.settings = request.apply(&graph.settings).map_err(LoadError::Request)?;
    let frame = request.frame;
    let digest = sources
        .with(format!("{:?}", graph.settings).as_bytes())
        .with(&frame.number.to_le_bytes())
        .with(&frame.clock.to_le_bytes());
    let scene = scene::build(&graph).map_err(LoadError::Scene)?;
    Ok((scene, digest))
}

/// Parses and evaluates the scene file.
pub fn load_graph(path: &Path) -> Result<SceneGraph, LoadError> {
    crate::lang::load_scene(path).map_err(LoadError::Scene)
}

/// Applies the overrides to the graph's settings and builds the render-ready scene.
pub fn build(mut graph: SceneGraph, request: &RenderRequest) -> Result<Scene, LoadError> {
    graph.settings = request.apply(&graph.settings).map_err(LoadError::Request)?;
    scene::build(&graph).map_err(LoadError::Scene)
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

/// Refuses, before any work, a film larger than `max_bytes` (`render --max-memory`).
pub fn check_film_memory(settings: &Settings, max_bytes: u64) -> Result<(), String> {
    let pixels = u64::from(settings.width) * u64::from(settings.height);
    let needed = pixels * crate::film::BYTES_PER_PIXEL;
    if needed <= max_bytes {
        return Ok(());
    }
    let gib = |bytes: u64| bytes as f64 / f64::from(1u32 << 30);
    Err(format!(
        "error: a {}x{} film needs {:.1} GiB ({} bytes a pixel while rendering), more than \
         --max-memory {:.1} GiB allows: render it in tiles with `--crop X0,X1,Y0,Y1` and join \
         them with `raydiance merge`, lower the resolution, or raise --max-memory if the machine \
         has the memory",
        settings.width,
        settings.height,
        gib(needed),
        crate::film::BYTES_PER_PIXEL,
        gib(max_bytes)
    ))
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
    write_image(path, format, &film.image(), &info)
}

/// Writes an image to `path` in `format` (`info` goes into an EXR's header).
pub fn write_image(
    path: &Path,
    format: &OutputFormat,
    image: &Image,
    info: &RenderInfo,
) -> Result<(), ImageError> {
    match *format {
        OutputFormat::Exr => image::exr::write(path, image, info),
        OutputFormat::Ppm { res } => image::ppm::write_hdr(path, image, res),
        OutputFormat::Png => {
            let pixels = tonemap::quantise(&tonemap::tonemap(image, &ToneMap::default()));
            image::png::write(path, image.width, image.height, &pixels)
        }
    }
}

/// `raydiance tonemap`: reads an HDR file, writes LDR `.ppm` (`#MAX=1`) or `.png`; returns
/// the summary line.
pub fn tonemap_file(input: &Path, output: &Path, params: &ToneMap) -> Result<String, String> {
    params.validate().map_err(|e| format!("error: {e}"))?;
    let ldr_ppm = match image::extension(output).as_deref() {
        Some("ppm") => true,
        Some("png") => false,
        _ => {
            return Err(format!(
                "error: {}: unknown output type (expected .ppm or .png)",
                output.display()
            ));
        }
    };
    image::check_writable(output).map_err(|e| format!("error: {e}"))?;
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(input), std::fs::canonicalize(output)) {
        if a == b {
            return Err(format!(
                "error: {}: is the input; tone mapping would replace it",
                output.display()
            ));
        }
    }
    let hdr = image::read_hdr(input).map_err(|e| format!("error: {e}"))?;
    let pixels = tonemap::quantise(&tonemap::tonemap(&hdr, params));
    let written = if ldr_ppm {
        image::ppm::write_ldr(output, hdr.width, hdr.height, &pixels)
    } else {
        image::png::write(output, hdr.width, hdr.height, &pixels)
    };
    written.map_err(|e| format!("error: {e}"))?;
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
