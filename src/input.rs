//! Reading the files a render names (scenes, includes, meshes, images, tone-mapping inputs):
//! only regular files, and no more bytes than a stated cap, so that a FIFO, a device, a folder or
//! a huge file is an error that names it, not a hang or the machine's memory.

use std::io::Read;
use std::path::Path;

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

/// The file's bytes, if it is a regular file of at most `max_bytes`.
pub fn read(path: &Path, max_bytes: u64) -> Result<Vec<u8>, InputError> {
    // Asked before opening: opening a FIFO for reading waits for a writer.
    let metadata = std::fs::metadata(path)?;
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
    let metadata = std::fs::metadata(path)?;
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
}
