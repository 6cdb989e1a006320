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

/// The file's bytes, if it is a regular file of at most `max_bytes`; otherwise a message (without
/// the path, which the caller puts in front) saying why not.
pub fn read(path: &Path, max_bytes: u64) -> Result<Vec<u8>, String> {
    // Asked before opening: opening a FIFO for reading waits for a writer.
    let metadata = std::fs::metadata(path).map_err(|e| e.to_string())?;
    check(&metadata, max_bytes)?;
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // Asked again of what was opened, in case the name now stands for another file.
    check(&file.metadata().map_err(|e| e.to_string())?, max_bytes)?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(max_bytes + 1).read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large(max_bytes));
    }
    Ok(bytes)
}

/// The file's text, as `read`, which must be UTF-8.
pub fn read_text(path: &Path, max_bytes: u64) -> Result<String, String> {
    String::from_utf8(read(path, max_bytes)?)
        .map_err(|e| format!("not a text file (no UTF-8 at byte {})", e.utf8_error().valid_up_to()))
}

fn check(metadata: &std::fs::Metadata, max_bytes: u64) -> Result<(), String> {
    let kind = metadata.file_type();
    if !kind.is_file() {
        return Err(format!("not a regular file ({})", describe(&kind)));
    }
    if metadata.len() > max_bytes {
        return Err(format!("{} bytes: {}", metadata.len(), too_large(max_bytes)));
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
        assert!(read(&file, 9).unwrap_err().contains("larger than raydiance reads"));
        assert_eq!(read(dir.path(), 10).unwrap_err(), "not a regular file (a folder)");
        assert_eq!(read(Path::new("/dev/zero"), 10).unwrap_err(), "not a regular file (a device)");
        assert!(read_text(&file, 10).is_ok());
        std::fs::write(&file, [b'a', 0xff]).unwrap();
        assert_eq!(read_text(&file, 10).unwrap_err(), "not a text file (no UTF-8 at byte 1)");
    }
}
