//! Reading the files a render names (scenes, includes, meshes, images, tone-mapping inputs):
//! only regular files, and no more bytes than a stated cap, so that a FIFO, a device, a folder or
//! a huge file is an error that names it, not a hang or the machine's memory.

use std::cell::RefCell;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The largest file of each kind that raydiance reads.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;
pub const MAX_MESH_BYTES: u64 = 2 << 30;
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;
pub const MAX_HDR_BYTES: u64 = 4 << 30;

/// Why a file was not read; the message leaves out the path, which the caller puts in front.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("not a regular file ({0})")]
    NotRegular(&'static str),
    #[error("{bytes} bytes: {}", too_large(*max_bytes))]
    TooLarge { bytes: u64, max_bytes: u64 },
    /// Larger when read than its size said (it grew while being read).
    #[error("{}", too_large(*max_bytes))]
    GrewTooLarge { max_bytes: u64 },
    #[error("not a text file (no UTF-8 at byte {valid_up_to})")]
    NotText { valid_up_to: usize },
}

/// A file as it was when asked for: its modification time and length, `None` when it could not
/// be found. A later stamp that differs says the file changed (what `preview` watches).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Stamp {
    pub path: PathBuf,
    pub version: Option<(SystemTime, u64)>,
}

impl Stamp {
    pub fn of(path: &Path, metadata: Option<&std::fs::Metadata>) -> Stamp {
        let version = metadata.and_then(|m| Some((m.modified().ok()?, m.len())));
        Stamp { path: path.to_path_buf(), version }
    }

    /// The file's stamp now.
    pub fn now(path: &Path) -> Stamp {
        Stamp::of(path, std::fs::metadata(path).ok().as_ref())
    }

    pub fn changed(&self) -> bool {
        Stamp::now(&self.path) != *self
    }
}

thread_local! {
    /// The files asked for on this thread while `recording_reads` runs.
    static READS: RefCell<Option<Vec<Stamp>>> = const { RefCell::new(None) };
}

/// Runs `f` (on this thread), and returns with its result every file it asked this module for,
/// found or not, stamped as it was when asked (before reading, so a change while it read is
/// still a change).
pub fn recording_reads<T>(f: impl FnOnce() -> T) -> (T, Vec<Stamp>) {
    let outer = READS.replace(Some(Vec::new()));
    let result = f();
    let reads = READS.replace(outer).unwrap_or_default();
    (result, reads)
}

/// The metadata of a file about to be read, noted if reads are being recorded.
fn metadata_of(path: &Path) -> std::io::Result<std::fs::Metadata> {
    let metadata = std::fs::metadata(path);
    READS.with_borrow_mut(|reads| {
        if let Some(reads) = reads {
            reads.push(Stamp::of(path, metadata.as_ref().ok()));
        }
    });
    metadata
}

/// The file's bytes, if it is a regular file of at most `max_bytes`.
pub fn read(path: &Path, max_bytes: u64) -> Result<Vec<u8>, InputError> {
    // Asked before opening: opening a FIFO for reading waits for a writer.
    let metadata = metadata_of(path)?;
    check(&metadata, max_bytes)?;
    let file = std::fs::File::open(path)?;
    // Asked again of what was opened, in case the name now stands for another file.
    check(&file.metadata()?, max_bytes)?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(InputError::GrewTooLarge { max_bytes });
    }
    Ok(bytes)
}

/// At most the first `max_bytes` of a regular file (what a header needs, read before the rest).
pub fn read_prefix(path: &Path, max_bytes: u64) -> Result<Vec<u8>, InputError> {
    let metadata = metadata_of(path)?;
    check(&metadata, u64::MAX)?;
    let mut bytes = Vec::new();
    std::fs::File::open(path)?.take(max_bytes).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The file's text, as `read`, which must be UTF-8.
pub fn read_text(path: &Path, max_bytes: u64) -> Result<String, InputError> {
    String::from_utf8(read(path, max_bytes)?)
        .map_err(|e| InputError::NotText { valid_up_to: e.utf8_error().valid_up_to() })
}

fn check(metadata: &std::fs::Metadata, max_bytes: u64) -> Result<(), InputError> {
    let kind = metadata.file_type();
    if !kind.is_file() {
        return Err(InputError::NotRegular(describe(&kind)));
    }
    if metadata.len() > max_bytes {
        return Err(InputError::TooLarge { bytes: metadata.len(), max_bytes });
    }
    Ok(())
}

fn too_large(max_bytes: u64) -> String {
    format!("larger than raydiance reads for a file of this kind ({} MiB)", max_bytes >> 20)
}

fn describe(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() { "a folder" } else { "not a file" }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_cap_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("small.txt");
        std::fs::write(&file, "0123456789").unwrap();
        assert_eq!(read(&file, 10).unwrap(), b"0123456789");
        let message = |error: InputError| error.to_string();
        assert!(message(read(&file, 9).unwrap_err()).contains("larger than raydiance reads"));
        assert_eq!(message(read(dir.path(), 10).unwrap_err()), "not a regular file (a folder)");
        let device = read(Path::new("/dev/zero"), 10).unwrap_err();
        assert_eq!(message(device), "not a regular file (a device)");
        assert!(read_text(&file, 10).is_ok());
        std::fs::write(&file, [b'a', 0xff]).unwrap();
        let binary = read_text(&file, 10).unwrap_err();
        assert!(matches!(binary, InputError::NotText { valid_up_to: 1 }), "{binary:?}");
    }

    #[test]
    fn reads_are_recorded_with_their_stamps_missing_files_too() {
        let dir = tempfile::tempdir().unwrap();
        let (file, missing) = (dir.path().join("a.txt"), dir.path().join("missing.txt"));
        std::fs::write(&file, "abc").unwrap();
        let ((), reads) = recording_reads(|| {
            read(&file, 10).unwrap();
            assert!(read_text(&missing, 10).is_err());
        });
        let paths: Vec<&Path> = reads.iter().map(|r| r.path.as_path()).collect();
        assert_eq!(paths, [file.as_path(), missing.as_path()]);
        assert!(reads[0].version.is_some() && reads[1].version.is_none());
        assert!(!reads[0].changed() && !reads[1].changed());
        std::fs::write(&file, "abcd").unwrap();
        std::fs::write(&missing, "").unwrap();
        assert!(reads[0].changed() && reads[1].changed());
        // Nothing is recorded outside `recording_reads`.
        let (_, none) = recording_reads(|| ());
        assert!(none.is_empty());
    }
}
