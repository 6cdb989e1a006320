//! `raydiance denoise`: Intel Open Image Denoise's `RT` filter over a finished render, guided
//! by its `albedo` and `normal` AOVs when the file has them (`render --aov albedo,normal`); the
//! preview's denoised view uses the same `Denoiser`. Built with the cargo feature `denoise` only
//! (the libraries come from `scripts/fetch-oidn`). The denoised image is another file: the
//! unbiased render stays as it was, and a part of a split render is refused (denoising is not
//! linear: the merge of denoised parts is not the denoised merge).

use std::path::{Path, PathBuf};
use std::time::Instant;

use ::exr::prelude::{AttributeValue, Text};

use crate::aov::{Aov, AovImage};
use crate::image::{self, Image, ImageError};

/// The version of Open Image Denoise the feature builds against.
pub const OIDN_VERSION: &str = "2.5.1";

/// Why `raydiance denoise` wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    #[error(
        "error: this raydiance was built without denoising (Intel Open Image Denoise): build it \
         with `scripts/fetch-oidn && OIDN_DIR=$PWD/.oidn cargo build --release --features \
         denoise`"
    )]
    NotBuilt,
    #[error(
        "error: {}: is a part of a split render: merge the parts first (`raydiance merge`), then \
         denoise the merged image",
        .0.display()
    )]
    Part(PathBuf),
    #[error("error: {}: unknown output type (expected .exr)", .0.display())]
    OutputType(PathBuf),
    #[error(
        "error: {}: is the input; the denoised image is written beside the render, never over it",
        .0.display()
    )]
    OutputIsInput(PathBuf),
    #[error("error: {0}")]
    Image(#[from] ImageError),
    #[error("error: Open Image Denoise cannot run on this machine: {0}")]
    Device(String),
    #[error("error: {}: Open Image Denoise failed: {source}", path.display())]
    Filter { path: PathBuf, source: FilterFailed },
}

/// Open Image Denoise's own word for why its filter failed.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct FilterFailed(String);

/// The guides of the filter a file's AOVs give, interleaved RGB / XYZ as the filter reads them.
struct Guides {
    albedo: Option<Vec<f32>>,
    normal: Option<Vec<f32>>,
}

impl Guides {
    fn of(aovs: &AovImage) -> Guides {
        let interleaved = |aov: Aov| {
            let planes: Vec<&[f32]> =
                aov.channels().iter().map(|name| aovs.plane(name)).collect::<Option<_>>()?;
            let pixels = aovs.width * aovs.height;
            Some((0..pixels).flat_map(|i| planes.iter().map(move |p| p[i])).collect())
        };
        Guides { albedo: interleaved(Aov::Albedo), normal: interleaved(Aov::Normal) }
    }

    /// What they are, for the summary and the header.
    fn describe(&self) -> &'static str {
        match (&self.albedo, &self.normal) {
            (Some(_), Some(_)) => "the beauty, albedo and normal",
            (Some(_), None) => "the beauty and albedo",
            // The filter takes a normal only with an albedo.
            (None, _) => "the beauty alone",
        }
    }
}

/// `raydiance denoise`: reads a render (`.exr`), writes its denoised beauty to `output`
/// (`.exr`, with the render's `raydiance:` attributes and `raydiance:denoised`); returns the
/// summary line.
pub fn denoise_file(input: &Path, output: &Path) -> Result<String, DenoiseError> {
    let start = Instant::now();
    let denoiser = Denoiser::new()?;
    if image::extension(output).as_deref() != Some("exr") {
        return Err(DenoiseError::OutputType(output.to_path_buf()));
    }
    image::check_writable(output)?;
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(input), std::fs::canonicalize(output))
        && a == b
    {
        return Err(DenoiseError::OutputIsInput(output.to_path_buf()));
    }
    let beauty = image::exr::read(input)?;
    let mut attributes = image::exr::read_attributes(input)?;
    if attributes.iter().any(|(name, _)| name == "part") {
        return Err(DenoiseError::Part(input.to_path_buf()));
    }
    let aovs = image::exr::read_aovs(input)?;
    let denoised = denoiser
        .denoise(&beauty, &aovs)
        .map_err(|source| DenoiseError::Filter { path: input.to_path_buf(), source })?;
    let what = description(&aovs);
    attributes.push(("denoised".to_string(), AttributeValue::Text(Text::from(what.as_str()))));
    image::exr::write_with_attributes(output, &denoised, None, attributes)?;
    Ok(format!(
        "{}: {}x{}, denoised from {} in {:.3} s",
        output.display(),
        denoised.width,
        denoised.height,
        Guides::of(&aovs).describe(),
        start.elapsed().as_secs_f64()
    ))
}

/// What denoised an image guided by `aovs`: the `raydiance:denoised` attribute of its file.
pub fn description(aovs: &AovImage) -> String {
    format!("Open Image Denoise {OIDN_VERSION} RT filter, from {}", Guides::of(aovs).describe())
}

/// Open Image Denoise's CPU device, made once and used for every image (making it is costly),
/// by one thread at a time. Without the feature there is none: the field's type has no value.
pub struct Denoiser {
    #[cfg(feature = "denoise")]
    device: std::sync::Mutex<oidn::Device>,
    #[cfg(not(feature = "denoise"))]
    never: std::convert::Infallible,
}

impl Denoiser {
    /// The device, or why there is none: the feature is off, or the machine cannot run it.
    #[cfg(feature = "denoise")]
    pub fn new() -> Result<Denoiser, DenoiseError> {
        let device = oidn::Device::cpu().map_err(|e| DenoiseError::Device(e.to_string()))?;
        Ok(Denoiser { device: std::sync::Mutex::new(device) })
    }

    #[cfg(not(feature = "denoise"))]
    pub fn new() -> Result<Denoiser, DenoiseError> {
        Err(DenoiseError::NotBuilt)
    }

    /// The `RT` filter over linear HDR radiance, guided by the albedo and normal of `aovs`
    /// when it has them (any other AOV is not a guide).
    #[cfg(feature = "denoise")]
    pub fn denoise(&self, beauty: &Image, aovs: &AovImage) -> Result<Image, FilterFailed> {
        let guides = Guides::of(aovs);
        // A panic while denoising leaves a device that can still be used.
        let device = self.device.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let color: Vec<f32> = beauty.pixels.iter().flat_map(|p| p.to_array()).collect();
        let mut filter =
            oidn::RayTracing::try_new(&device).map_err(|e| FilterFailed(e.to_string()))?;
        filter.hdr(true).srgb(false).image_dimensions(beauty.width, beauty.height);
        match (&guides.albedo, &guides.normal) {
            (Some(albedo), Some(normal)) => filter.albedo_normal(albedo, normal),
            (Some(albedo), None) => filter.albedo(albedo),
            (None, _) => &mut filter,
        };
        let mut output = vec![0.0; color.len()];
        filter.filter(&color, &mut output).map_err(|e| FilterFailed(e.to_string()))?;
        device.get_error().map_err(|e| FilterFailed(e.to_string()))?;
        let pixels = output.chunks_exact(3).map(glam::Vec3::from_slice).collect();
        Ok(Image { width: beauty.width, height: beauty.height, pixels })
    }

    #[cfg(not(feature = "denoise"))]
    pub fn denoise(&self, _: &Image, _: &AovImage) -> Result<Image, FilterFailed> {
        match self.never {}
    }
}
