//! Reading input files (model files, body sources, decks, results) that are refused when they
//! are not regular files: opening a FIFO (named pipe) waits for a writer, so a model or body
//! source that is a FIFO, socket or device would hang the program instead of failing.

use std::io::{Error, ErrorKind};
use std::path::Path;

/// What `path` is when it is a special file (FIFO, socket, character or block device), else
/// `None` (a regular file, a folder, or a path that does not exist: the read reports those).
pub fn special_file_kind(path: &Path) -> Option<&'static str> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = std::fs::metadata(path).ok()?.file_type();
        if t.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
    }
    #[cfg(not(unix))]
    let _ = path;
    None
}

/// The error of a special file: `InvalidInput`, naming what the path is.
fn refused(kind: &str) -> Error {
    Error::new(
        ErrorKind::InvalidInput,
        format!("{kind}, not a regular file: refused (reading it could wait forever)"),
    )
}

/// [`std::fs::read`], refusing a special file ([`special_file_kind`]) before opening it.
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    match special_file_kind(path) {
        Some(kind) => Err(refused(kind)),
        None => std::fs::read(path),
    }
}

/// [`std::fs::read_to_string`], refusing a special file ([`special_file_kind`]) before opening
/// it.
pub fn read_to_string(path: &Path) -> std::io::Result<String> {
    match special_file_kind(path) {
        Some(kind) => Err(refused(kind)),
        None => std::fs::read_to_string(path),
    }
}
