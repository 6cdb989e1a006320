//! Snapshot tests of scenes (`raydiance snapshot`; hdr-pipeline.md, "Snapshot tests of scenes"):
//! each scene is rendered small and fast and compared with its stored snapshot,
//! `__snapshots__/NAME.exr` beside it, statistically and tile by tile (`compare`), so that noise
//! passes and a changed picture fails.

mod compare;
mod estimate;
mod file;
mod heatmap;

use std::path::{Path, PathBuf};

pub use compare::{Comparison, FINEST_TILE, Rect, SizesDiffer, TileTest, Z_BOUND, compare};
pub use estimate::{Estimate, TooFewSamples};
pub use file::{read, write};

use crate::image::ImageError;
use crate::pipeline::{LoadError, RenderRequest, build, load_graph};
use crate::progress::Silent;
use crate::render::render;

/// Why a scene could not be snapshot-tested, or snapshots not found or accepted.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error("error: {0}")]
    Image(#[from] ImageError),
    #[error("error: {}: {source}", scene.display())]
    TooFewSamples { scene: PathBuf, source: TooFewSamples },
    #[error("error: {}: {source} (`--size` sets the size)", snapshot.display())]
    SizesDiffer { snapshot: PathBuf, source: SizesDiffer },
    #[error("error: {}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A scene named `NAME.new.scn` or `NAME.diff.scn`: its snapshot's name would be the new
    /// render or the heat map of `NAME.scn`.
    #[error(
        "error: {}: a scene named NAME.{suffix}.scn cannot be snapshotted: its snapshot would \
         be the file NAME.scn's comparison writes (rename the scene)",
        scene.display()
    )]
    NameTaken { scene: PathBuf, suffix: &'static str },
    #[error("error: --size {0}")]
    Size(TooLarge),
}

/// A snapshot, stored or asked for, of more than `MAX_SNAPSHOT_PIXELS`.
#[derive(Debug, thiserror::Error)]
#[error("{width}x{height}: more pixels than a snapshot may have ({MAX_SNAPSHOT_PIXELS})")]
pub struct TooLarge {
    pub width: usize,
    pub height: usize,
}

impl SnapshotError {
    fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SnapshotError + '_ {
        move |source| SnapshotError::Io { path: path.to_path_buf(), source }
    }
}

/// Samples per pixel of a snapshot render unless `--samples` says otherwise.
pub const DEFAULT_SAMPLES: u32 = 64;
/// The longer side of a snapshot render unless `--size` or the stored snapshot says otherwise;
/// the other side keeps the scene's aspect ratio.
pub const DEFAULT_LONGER_SIDE: u32 = 64;

/// The most pixels a snapshot may have, stored or asked for with `--size`: snapshots are small
/// renders (a stored size is adopted, so a crafted one must not start a render of hours).
pub const MAX_SNAPSHOT_PIXELS: u64 = 1 << 22;

#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Options {
    /// Samples per pixel (default `DEFAULT_SAMPLES`).
    pub samples: Option<u32>,
    /// Width and height (default: the stored snapshot's, or the scene's scaled down).
    pub size: Option<(u32, u32)>,
}

/// Where a scene's snapshot and the files of a failed comparison live.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapshotFiles {
    pub snapshot: PathBuf,
    pub new: PathBuf,
    pub diff: PathBuf,
}

impl SnapshotFiles {
    /// The files of `scene`; refused for a scene named `NAME.new.scn` or `NAME.diff.scn`, whose
    /// snapshot would be the new render or heat map of `NAME.scn`.
    pub fn checked(scene: &Path) -> Result<SnapshotFiles, SnapshotError> {
        let stem = Path::new(scene.file_stem().unwrap_or_default());
        match ["new", "diff"].into_iter().find(|suffix| stem.extension() == Some(suffix.as_ref())) {
            Some(suffix) => Err(SnapshotError::NameTaken { scene: scene.to_path_buf(), suffix }),
            None => Ok(SnapshotFiles::of(scene)),
        }
    }

    /// The files of `scene`, named from its name as the system gives it: two names that are
    /// not UTF-8 do not become one name by the replacement character.
    pub fn of(scene: &Path) -> SnapshotFiles {
        let folder = scene.parent().unwrap_or(Path::new("")).join("__snapshots__");
        let name = scene.file_stem().unwrap_or_default();
        let file = |suffix: &str| {
            let mut file = name.to_os_string();
            file.push(suffix);
            folder.join(file)
        };
        SnapshotFiles { snapshot: file(".exr"), new: file(".new.exr"), diff: file(".diff.png") }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    Matches,
    /// Some tiles failed; the new render and the heat map were written.
    Differs {
        failing: usize,
        worst: TileTest,
    },
    /// There was no snapshot; the new render was written as `.new`.
    New,
    /// Not rendered: the scene's integrator's pixel samples are not independent (photons shared
    /// by every pixel's samples), so a render has no per-pixel variance to test with.
    Unsupported {
        integrator: &'static str,
    },
}

/// The result of checking one scene against its snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub scene: PathBuf,
    pub width: usize,
    pub height: usize,
    /// Tiles compared (0 for a new snapshot).
    pub tiles: usize,
    pub verdict: Verdict,
}

impl Outcome {
    /// One line. A match prints no figure that varies with the noise, so `insta` can hold it.
    pub fn summary(&self) -> String {
        let scene = self.scene.display();
        let files = SnapshotFiles::of(&self.scene);
        match &self.verdict {
            Verdict::Matches => format!(
                "{scene}: matches its snapshot ({}x{}, {} tiles)",
                self.width, self.height, self.tiles
            ),
            Verdict::Differs { failing, worst } => {
                let Rect { x0, x1, y0, y1 } = worst.rect;
                let z = worst.worst_z();
                format!(
                    "{scene}: differs from its snapshot in {failing} of {} tiles (largest: z = \
                     {z:.1}, {} in pixels x {x0}..{x1}, y {y0}..{y1}); see {} and {}",
                    self.tiles,
                    if z > 0.0 { "brighter" } else { "darker" },
                    files.new.display(),
                    files.diff.display(),
                )
            }
            Verdict::Unsupported { integrator } => format!(
                "{scene}: not snapshotted: integrator {integrator} shares its photons among all \
                 samples, so a render has no per-pixel variance to compare"
            ),
            Verdict::New => format!(
                "{scene}: no snapshot; wrote {} (accept it with `raydiance snapshot --accept`)",
                files.new.display()
            ),
        }
    }
}

/// Renders `scene` small and compares it with its snapshot. A differing or new render is
/// written beside the snapshot as `.new` (with a heat map of the z-scores when it differs); a
/// match removes any `.new` and heat map left from before.
pub fn check(scene_path: &Path, options: &Options) -> Result<Outcome, SnapshotError> {
    let files = SnapshotFiles::checked(scene_path)?;
    if let Some((width, height)) = options.size {
        check_size(width as usize, height as usize).map_err(SnapshotError::Size)?;
    }
    // A symbolic link to a missing file is a snapshot that cannot be read, not no snapshot.
    let reference = match std::fs::symlink_metadata(&files.snapshot).is_ok() {
        true => Some(read(&files.snapshot)?),
        false => None,
    };
    let graph = load_graph(scene_path)?;
    let integrator = graph.settings.integrator;
    if !crate::integrator::of(&graph.settings).samples_are_independent() {
        let verdict = Verdict::Unsupported { integrator: integrator.name() };
        return Ok(Outcome {
            scene: scene_path.to_path_buf(),
            width: 0,
            height: 0,
            tiles: 0,
            verdict,
        });
    }
    let (width, height) = match (options.size, &reference) {
        (Some(size), _) => size,
        (None, Some(r)) => (r.width as u32, r.height as u32),
        (None, None) => default_size(graph.settings.width, graph.settings.height),
    };
    let request = RenderRequest {
        samples: Some(options.samples.unwrap_or(DEFAULT_SAMPLES)),
        width: Some(width),
        height: Some(height),
        ..Default::default()
    };
    let scene = build(graph, &request)?;
    let (film, _) = render(&scene, &Silent);
    let new = Estimate::from_film(&film).map_err(|source| SnapshotError::TooFewSamples {
        scene: scene_path.to_path_buf(),
        source,
    })?;
    let outcome = |tiles, verdict| Outcome {
        scene: scene_path.to_path_buf(),
        width: new.width,
        height: new.height,
        tiles,
        verdict,
    };
    let Some(reference) = reference else {
        create_folder(&files.new)?;
        write(&files.new, &new)?;
        return Ok(outcome(0, Verdict::New));
    };
    let comparison = compare(&reference, &new).map_err(|source| SnapshotError::SizesDiffer {
        snapshot: files.snapshot.clone(),
        source,
    })?;
    let tiles = comparison.tiles.len();
    match comparison.worst().filter(|_| !comparison.matches()) {
        None => {
            remove_if_present(&files.new)?;
            remove_if_present(&files.diff)?;
            Ok(outcome(tiles, Verdict::Matches))
        }
        Some(&worst) => {
            write(&files.new, &new)?;
            heatmap::write(&files.diff, &comparison, &new)?;
            let failing = comparison.failing().count();
            Ok(outcome(tiles, Verdict::Differs { failing, worst }))
        }
    }
}

/// Refuses a snapshot of more than `MAX_SNAPSHOT_PIXELS`.
fn check_size(width: usize, height: usize) -> Result<(), TooLarge> {
    match (width as u64).saturating_mul(height as u64) > MAX_SNAPSHOT_PIXELS {
        true => Err(TooLarge { width, height }),
        false => Ok(()),
    }
}

/// The scene's resolution scaled so that its longer side is `DEFAULT_LONGER_SIDE`.
fn default_size(width: u32, height: u32) -> (u32, u32) {
    let longer = width.max(height).max(1) as f64;
    let scale = |side: u32| {
        ((f64::from(side) * f64::from(DEFAULT_LONGER_SIDE) / longer).round() as u32).max(1)
    };
    (scale(width), scale(height))
}

/// Every `.scn` file among `paths` and in the folders below them, sorted; folders named
/// `target`, and hidden ones, are passed over.
pub fn scenes(paths: &[PathBuf]) -> Result<Vec<PathBuf>, SnapshotError> {
    let mut found = Vec::new();
    for path in paths {
        let metadata = std::fs::metadata(path).map_err(SnapshotError::io(path))?;
        if metadata.is_dir() {
            walk(path, &mut |file| {
                if file.extension().is_some_and(|e| e == "scn") {
                    found.push(file.to_path_buf());
                }
            })?;
        } else {
            found.push(path.clone());
        }
    }
    found.sort();
    found.dedup();
    Ok(found)
}

/// `--accept`: every `.new` snapshot among `paths` (scenes, or folders searched below) becomes
/// the snapshot, and its heat map is removed. Returns the snapshots written.
pub fn accept(paths: &[PathBuf]) -> Result<Vec<PathBuf>, SnapshotError> {
    let mut pending = Vec::new();
    for path in paths {
        if path.is_dir() {
            walk(path, &mut |file| {
                let folder = file.parent().filter(|p| p.ends_with("__snapshots__"));
                // `NAME.new.exr`, NAME as the system gives it (perhaps not UTF-8).
                let new = Path::new(file.file_stem().unwrap_or_default());
                let is_new = file.extension() == Some("exr".as_ref())
                    && new.extension() == Some("new".as_ref());
                if let (Some(folder), Some(scene), true) = (folder, new.file_stem(), is_new) {
                    let scenes = folder.parent().unwrap_or(Path::new(""));
                    let mut scene = scene.to_os_string();
                    scene.push(".scn");
                    pending.push(SnapshotFiles::of(&scenes.join(scene)));
                }
            })?;
        } else if SnapshotFiles::of(path).new.exists() {
            pending.push(SnapshotFiles::of(path));
        }
    }
    pending
        .into_iter()
        .map(|files| {
            // A damaged `.new` is refused rather than made the snapshot.
            read(&files.new)?;
            std::fs::rename(&files.new, &files.snapshot)
                .map_err(SnapshotError::io(&files.snapshot))?;
            remove_if_present(&files.diff)?;
            Ok(files.snapshot)
        })
        .collect()
}

/// Calls `visit` on every file below `folder`, passing over snapshot, build and hidden folders.
/// A symbolic link is visited as the file it names (one naming no file too, so that reading it
/// is the error); links to folders are not followed, as a link may lead back up the tree.
fn walk(folder: &Path, visit: &mut dyn FnMut(&Path)) -> Result<(), SnapshotError> {
    let error = |e: std::io::Error| SnapshotError::io(folder)(e);
    let mut entries: Vec<_> =
        std::fs::read_dir(folder).map_err(error)?.collect::<Result<_, _>>().map_err(error)?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let path = entry.path();
        let name = entry.file_name();
        let file_type = entry.file_type().map_err(error)?;
        if file_type.is_dir() {
            let name = name.to_string_lossy();
            if !(name.starts_with('.') || name == "target") {
                walk(&path, visit)?;
            }
        } else if file_type.is_file() || (file_type.is_symlink() && !path.is_dir()) {
            visit(&path);
        }
    }
    Ok(())
}

fn create_folder(file: &Path) -> Result<(), SnapshotError> {
    let folder = file.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(folder).map_err(SnapshotError::io(folder))
}

fn remove_if_present(file: &Path) -> Result<(), SnapshotError> {
    match std::fs::remove_file(file) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(SnapshotError::io(file)(e)),
        _ => Ok(()),
    }
}
