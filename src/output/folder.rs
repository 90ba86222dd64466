//! Checks, before any expensive work, that outputs can be written where asked.

use super::staged::{writable_target, Temporary};
use crate::error::{Error, Result};
use std::path::Path;

/// Makes sure that files can be written into `folder`: creates it (and its
/// parents) if missing, then creates and removes one temporary file in it, the
/// same way [`Outputs`](super::Outputs) will. So a read-only or full file
/// system, a missing permission, or a path through a regular file is found out
/// before a solve rather than after it.
///
/// # Errors
///
/// [`Error::Io`] naming `folder` with the operating system's reason.
pub fn prepare_folder(folder: &Path) -> Result<()> {
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    if let Some(file) = folder.ancestors().find(|a| a.is_file()) {
        return Err(Error::Output {
            path: folder.to_path_buf(),
            message: format!("cannot be a folder: {} is a file", file.display()),
        });
    }
    std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))?;
    // The probe's own name stands for any output file in the folder.
    Temporary::create(&folder.join("write-check"))
        .map(drop)
        .map_err(|e| Error::io(folder, e))
}

/// Checks that the file `path` can be written: it is not a folder or another
/// non-regular file, and its folder exists (or can be created) and accepts new
/// files (see [`prepare_folder`]).
///
/// # Errors
///
/// [`Error::Output`] for a target that cannot be replaced by a file;
/// [`Error::Io`] for a folder that cannot hold it.
pub fn check_target(path: &Path) -> Result<()> {
    let target = writable_target(path)?;
    prepare_folder(target.parent().unwrap_or(Path::new("")))
}
