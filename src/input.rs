//! Opening input files: regular files only.
//!
//! A scene, buffer or image path can name a FIFO, a device, a socket or a
//! folder. Reading a FIFO blocks until some other process writes to it (for
//! ever, if none does), a device such as `/dev/zero` never ends, and a folder
//! cannot be read at all. Every file the library reads is opened here, which
//! refuses all of them with an error naming the path, and never blocks.

use crate::error::{Error, Result};
use std::fs::{File, Metadata};
use std::path::Path;

/// Opens `path` for reading if it is a regular file (or a symbolic link to
/// one). On Unix the file is opened without blocking and its type checked on
/// the open handle, so that a FIFO cannot stall the open itself and the check
/// cannot be raced by swapping the file.
///
/// # Errors
///
/// [`Error::Io`] naming `path`: the operating system's reason if it cannot be
/// opened, else what kind of file it is when that is not a regular file.
pub fn open_regular(path: &Path) -> Result<File> {
    let file = open_without_blocking(path).map_err(|e| Error::io(path, e))?;
    let metadata = file.metadata().map_err(|e| Error::io(path, e))?;
    refuse_unless_regular(path, &metadata)?;
    Ok(file)
}

#[cfg(unix)]
fn open_without_blocking(path: &Path) -> std::io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    // O_NONBLOCK makes opening a FIFO return at once instead of waiting for a
    // writer; for a regular file it changes nothing.
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_without_blocking(path: &Path) -> std::io::Result<File> {
    // Without O_NONBLOCK, look before opening (a pipe could still be swapped in
    // between, which Unix's check on the open handle rules out).
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(not_regular(kind_of(&metadata)));
    }
    File::open(path)
}

/// The reason [`open_regular`] gives for a file that is not a regular file,
/// so that callers can tell it from the file's absence or unreadability.
#[derive(Debug)]
struct NotRegular(&'static str);

impl std::fmt::Display for NotRegular {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}, not a regular file (only regular files are read)",
            self.0
        )
    }
}

impl std::error::Error for NotRegular {}

/// True when `error` is [`open_regular`]'s refusal of a file that exists but
/// is not a regular file (a FIFO, device, socket or folder).
#[must_use]
pub(crate) fn is_not_regular(error: &Error) -> bool {
    match error {
        Error::Io { error, .. } => error
            .get_ref()
            .is_some_and(|inner| inner.is::<NotRegular>()),
        _ => false,
    }
}

fn not_regular(kind: &'static str) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidInput, NotRegular(kind))
}

fn refuse_unless_regular(path: &Path, metadata: &Metadata) -> Result<()> {
    if metadata.is_file() {
        return Ok(());
    }
    Err(Error::io(path, not_regular(kind_of(metadata))))
}

/// What kind of file `metadata` describes, in words.
fn kind_of(metadata: &Metadata) -> &'static str {
    let t = metadata.file_type();
    if t.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
    }
    "a special file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_is_refused_by_name() {
        let e = open_regular(Path::new(".")).unwrap_err();
        assert!(
            e.to_string().contains("a folder, not a regular file"),
            "{e}"
        );
        assert!(is_not_regular(&e));
        let missing = open_regular(Path::new("no such file here")).unwrap_err();
        assert!(!is_not_regular(&missing), "{missing}");
    }
}
