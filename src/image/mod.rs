//! Linear HDR images and their files: OpenEXR, HDR PPM with `#MAX`, PNG. Every file is written
//! to a temporary name in its folder and renamed into place, so a failure never leaves a partial
//! file nor replaces an existing one.

pub mod exr;
pub mod png;
pub mod ppm;

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use glam::Vec3;

/// The most pixels an image read may have, from its header: a corrupt or hostile header must not
/// make the decoder exhaust memory.
pub const MAX_PIXELS: usize = 1 << 25;

/// Linear RGB radiance, rows top to bottom, columns left to right.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Image { width, height, pixels: vec![Vec3::ZERO; width * height] }
    }

    pub fn get(&self, x: usize, y: usize) -> Vec3 {
        self.pixels[y * self.width + x]
    }

    /// The largest component of any pixel (0 for an empty image).
    pub fn max_component(&self) -> f32 {
        self.pixels.iter().map(|p| p.max_element()).fold(0.0, f32::max)
    }
}

/// What a render records in its output file's metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderInfo {
    pub samples_per_pixel: u32,
    pub integrator: String,
    pub seed: u64,
    pub seconds: f64,
    /// The integrator's parameters, as `raydiance:NAME` text attributes.
    pub parameters: Vec<(&'static str, String)>,
}

#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {source}")]
    Input { path: PathBuf, source: crate::input::InputError },
    #[error("{path}: {source}")]
    Ppm { path: PathBuf, source: ppm::PpmError },
    #[error("{path}: {source}")]
    Exr { path: PathBuf, source: exr::ExrError },
    #[error("{path}: {source}")]
    Png { path: PathBuf, source: ::image::ImageError },
}

impl ImageError {
    pub fn format(path: &Path, message: impl Into<String>) -> Self {
        ImageError::Format { path: path.to_path_buf(), message: message.into() }
    }

    pub fn io(path: &Path, source: std::io::Error) -> Self {
        ImageError::Io { path: path.to_path_buf(), source }
    }

    pub fn input(path: &Path, source: crate::input::InputError) -> Self {
        ImageError::Input { path: path.to_path_buf(), source }
    }

    pub fn ppm(path: &Path, source: ppm::PpmError) -> Self {
        ImageError::Ppm { path: path.to_path_buf(), source }
    }

    pub fn exr(path: &Path, source: exr::ExrError) -> Self {
        ImageError::Exr { path: path.to_path_buf(), source }
    }

    pub fn png(path: &Path, source: ::image::ImageError) -> Self {
        ImageError::Png { path: path.to_path_buf(), source }
    }
}

/// Reads an HDR image (`.exr`, or `.ppm` with or without `#MAX`) by its extension.
pub fn read_hdr(path: &Path) -> Result<Image, ImageError> {
    match extension(path).as_deref() {
        Some("exr") => exr::read(path),
        Some("ppm") => {
            // The size the header declares is refused before the rest is read (a sparse 1 GB
            // file declaring 18000 x 18000 pixels took 27 s and 953 MB to refuse).
            let start = crate::input::read_prefix(path, ppm::HEADER_BYTES)
                .map_err(|e| ImageError::input(path, e))?;
            ppm::check_size(&start).map_err(|e| ImageError::ppm(path, e))?;
            let bytes = crate::input::read(path, crate::input::MAX_HDR_BYTES)
                .map_err(|e| ImageError::input(path, e))?;
            ppm::parse(&bytes).map_err(|e| ImageError::ppm(path, e))
        }
        _ => Err(ImageError::format(path, "unknown image type (expected .exr or .ppm)")),
    }
}

pub fn extension(path: &Path) -> Option<String> {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase)
}

/// Checks, before any work, that `path` can be written: its folder exists and takes new files.
pub fn check_writable(path: &Path) -> Result<(), ImageError> {
    if path.is_dir() {
        return Err(ImageError::format(path, "is a folder, not a file to write"));
    }
    let folder = folder_of(path);
    if !folder.is_dir() {
        return Err(ImageError::format(
            path,
            format!("the folder `{}` does not exist", folder.display()),
        ));
    }
    // The error names `path`, not the temporary file tried (`.tmpXXXXXX`, unknown to the user).
    tempfile::NamedTempFile::new_in(folder)
        .map(drop)
        .map_err(|e| ImageError::io(path, std::io::Error::from(e.kind())))
}

/// Writes `path` through `write` into a temporary file in the same folder, renamed into place
/// only when everything succeeded.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut std::fs::File>) -> Result<(), ImageError>,
) -> Result<(), ImageError> {
    let mut builder = tempfile::Builder::new();
    // A temporary file is private (0600); the image gets the read and write permissions of the
    // file it replaces (never its setuid, setgid or sticky bits), or the usual 0644.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode() & 0o777);
        builder.permissions(std::fs::Permissions::from_mode(mode));
    }
    let mut temporary = builder
        .tempfile_in(folder_of(path))
        .map_err(|e| ImageError::io(path, std::io::Error::from(e.kind())))?;
    let _pending = Pending::register(temporary.path());
    {
        let mut writer = BufWriter::new(temporary.as_file_mut());
        write(&mut writer)?;
        writer.flush().map_err(|e| ImageError::io(path, e))?;
    }
    // Renamed under the lock, so that `remove_pending_files` never sees a name half-way (the lock
    // goes before `_pending`, which takes it again).
    let _lock = PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    temporary.persist(path).map_err(|e| ImageError::io(path, e.error))?;
    Ok(())
}

/// Temporary files being written by `write_atomic`, for a process that must end at once.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A temporary file's place in `PENDING`, given up when the write ends, however it ends.
struct Pending(PathBuf);

impl Pending {
    fn register(path: &Path) -> Pending {
        PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(path.to_path_buf());
        Pending(path.to_path_buf())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        let mut pending = PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        pending.retain(|p| *p != self.0);
    }
}

/// Removes the temporary files of writes under way and keeps any more from being renamed into
/// place: for a process about to exit without unwinding (a second Ctrl-C or SIGTERM), so that
/// it leaves no `.tmpXXXX` file behind. The returned guard must be held until the exit.
pub fn remove_pending_files() -> MutexGuard<'static, Vec<PathBuf>> {
    let pending = PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    for path in pending.iter() {
        let _ = std::fs::remove_file(path);
    }
    pending
}

/// For a command that only writes files, with nothing to keep when stopped (`merge`,
/// `tonemap`): Ctrl-C, SIGTERM and SIGHUP end the process at once with status 130, leaving no
/// temporary file (by default the process would die with its `.tmpXXXXXX` beside the output).
pub fn end_cleanly_on_signal() -> Result<(), SignalError> {
    ctrlc::set_handler(|| {
        let _no_more_renames = remove_pending_files();
        std::process::exit(130);
    })
    .map_err(|e| SignalError(e.to_string()))
}

/// The handler of Ctrl-C, SIGTERM and SIGHUP could not be installed: ctrlc's message (kept as
/// text, so that a handler installed once can give its outcome to each render that asks).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("error: cannot handle signals: {0}")]
pub struct SignalError(pub String);

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}
