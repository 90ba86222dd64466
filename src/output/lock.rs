//! One writer at a time for each set of outputs: an advisory lock (`flock`)
//! on a hidden lock file beside them, held from before the work starts until
//! the outputs are committed.
//!
//! A second command that would write the same outputs is refused at once,
//! with a message naming the folder and the process that holds them, rather
//! than made to wait for a solve that may take an hour. The lock file is
//! removed when the lock is released; a run killed outright leaves it, and
//! the kernel releases its lock with the process, so the next run takes it.

use super::pending;
use crate::error::{Error, Result};
use std::fs::File;
use std::path::{Path, PathBuf};

/// A held lock on the outputs named `name` in one folder. Released (and its
/// file removed) when dropped.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    // Kept open: closing the file would release the lock.
    _file: File,
}

impl OutputLock {
    /// Takes the lock on the outputs `name` in `folder` (which must exist):
    /// the file `folder/.name.lock`. The lock is advisory: it keeps out other
    /// runs of this library, not other programs.
    ///
    /// # Errors
    ///
    /// [`Error::Output`] naming the folder when another process holds the
    /// lock; [`Error::Io`] when the lock file cannot be created.
    pub fn acquire(folder: &Path, name: &str) -> Result<OutputLock> {
        let folder = if folder.as_os_str().is_empty() {
            Path::new(".")
        } else {
            folder
        };
        let path = folder.join(format!(".{name}.lock"));
        let file = take(&path, folder, name)?;
        Ok(OutputLock { path, _file: file })
    }

    /// The lock file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held, so that a process that opened the old
        // file and locks it after this sees that it is gone and tries again.
        let _ = std::fs::remove_file(&self.path);
        pending::forget(&self.path);
    }
}

/// Opens and locks the lock file, again if it was replaced in between.
/// The file is registered as unfinished while it is held (see
/// [`pending`]), so that a run stopped by a signal removes it.
#[cfg(unix)]
fn take(path: &Path, folder: &Path, name: &str) -> Result<File> {
    use std::io::{Read, Seek, Write};
    use std::os::unix::fs::MetadataExt;
    use std::os::unix::io::AsRawFd;
    loop {
        let opened = pending::create(path, |p| {
            std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(p)
        });
        let mut file = opened.map_err(|e| Error::io(path, e))?;
        // SAFETY: `flock` on a descriptor this function owns and keeps open.
        let held = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
        if held != 0 {
            let e = std::io::Error::last_os_error();
            pending::forget(path);
            if e.raw_os_error() != Some(libc::EWOULDBLOCK) {
                return Err(Error::io(path, e));
            }
            let mut holder = String::new();
            let _ = file.read_to_string(&mut holder);
            let holder = holder.trim();
            let by = if holder.is_empty() {
                String::new()
            } else {
                format!(" (process {holder})")
            };
            return Err(Error::Output {
                path: folder.to_path_buf(),
                message: format!(
                    "another run{by} is writing the outputs '{name}' in this folder; wait for \
                     it to finish or write elsewhere (two runs at once would mix their files)"
                ),
            });
        }
        // The holder before us may have removed the file after we opened it:
        // then we hold a lock on a file nobody else will see.
        let same = match (file.metadata(), std::fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        };
        if !same {
            pending::forget(path);
            continue;
        }
        let _ = file.set_len(0);
        let _ = file.rewind();
        let _ = write!(file, "{}", std::process::id());
        return Ok(file);
    }
}

/// Without `flock`, the lock file is created exclusively: a second run
/// finds it and is refused (a crashed run's file must then be removed by
/// hand, which the message says).
#[cfg(not(unix))]
fn take(path: &Path, folder: &Path, name: &str) -> Result<File> {
    pending::create(path, |p| {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(p)
    })
    .map_err(|e| {
        if e.kind() == std::io::ErrorKind::AlreadyExists {
            Error::Output {
                path: folder.to_path_buf(),
                message: format!(
                    "another run is writing the outputs '{name}' in this folder (or one \
                         stopped without removing {}); wait for it, or remove that file",
                    path.display()
                ),
            }
        } else {
            Error::io(path, e)
        }
    })
}
