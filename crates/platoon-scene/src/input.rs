//! Reading the files a user names: only regular files, and never more bytes than they hold, so
//! that `/dev/zero`, a named pipe or a folder is refused by name instead of read forever.

use std::io::Read as _;
use std::path::Path;

/// What a non-regular file is, for the message that refuses it.
fn kind(m: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt as _;
    let t = m.file_type();
    if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a named pipe"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a plain file"
    }
}

/// `Ok` when `path` (symlinks followed) is a regular file.
pub fn regular_file(path: &Path) -> Result<(), String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_file() {
        Ok(())
    } else {
        Err(format!("not a regular file ({})", kind(&meta)))
    }
}

/// The bytes of a regular file, at most `limit` of them and never more than its length when
/// opened.
pub fn read_regular_file(path: &Path, limit: Option<u64>) -> Result<Vec<u8>, String> {
    regular_file(path)?;
    // O_NONBLOCK: should the path become a pipe between the check and the open, opening it
    // does not wait for a writer; the handle is checked again below.
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    #[cfg(target_os = "linux")]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut open, libc::O_NONBLOCK);
    let file = open.open(path).map_err(|e| e.to_string())?;
    let meta = file.metadata().map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err(format!("not a regular file ({})", kind(&meta)));
    }
    let bound = limit.unwrap_or(u64::MAX).min(meta.len());
    let mut bytes = Vec::with_capacity(bound as usize);
    file.take(bound)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}
