//! The files and folders a run has under way, so that a program stopped by a
//! signal can remove them, and a guard that keeps it from stopping half way
//! through a commit.
//!
//! Every temporary file, staging folder and lock file of [`crate::output`]
//! is registered here while it exists. A program that handles SIGINT or
//! SIGTERM calls [`remove_unfinished`] before it exits: that waits for a
//! commit in progress to end (a commit takes milliseconds: renames and a
//! folder sync), removes everything still registered, and refuses new
//! temporaries from then on, so that nothing is half replaced and nothing is
//! left behind.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// What is registered, and whether the process is shutting down.
struct Registry {
    paths: Vec<PathBuf>,
    closed: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    paths: Vec::new(),
    closed: false,
});

/// Held for the whole of a commit; [`remove_unfinished`] takes it too.
static COMMIT: Mutex<()> = Mutex::new(());

fn registry() -> MutexGuard<'static, Registry> {
    // A panic elsewhere while the list was held leaves it usable.
    REGISTRY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Creates `path` through `make` and records it as unfinished, both while
/// the list is held, so that [`remove_unfinished`] either finds it or keeps
/// it from being made: a file made in between would outlive the clean-up.
///
/// # Errors
///
/// What `make` returns; an [`std::io::ErrorKind::Interrupted`] error once
/// [`remove_unfinished`] has run (the process is stopping and must not
/// create anything more).
pub(super) fn create<T>(
    path: &Path,
    make: impl FnOnce(&Path) -> std::io::Result<T>,
) -> std::io::Result<T> {
    let mut r = registry();
    if r.closed {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "the run is stopping (interrupted)",
        ));
    }
    let made = make(path)?;
    r.paths.push(path.to_path_buf());
    Ok(made)
}

/// Runs `make` (which creates something inside a registered folder) while
/// the list is held, unless the run is stopping: a file made in a staging
/// folder while the clean-up empties it would keep the folder from going.
///
/// # Errors
///
/// What `make` returns, or [`std::io::ErrorKind::Interrupted`] once
/// [`remove_unfinished`] has run.
pub(super) fn inside<T>(make: impl FnOnce() -> std::io::Result<T>) -> std::io::Result<T> {
    let r = registry();
    if r.closed {
        return Err(std::io::Error::new(
            std::io::ErrorKind::Interrupted,
            "the run is stopping (interrupted)",
        ));
    }
    make()
}

/// Forgets `path`: it was renamed into place or removed.
pub(super) fn forget(path: &Path) {
    let mut r = registry();
    if let Some(i) = r.paths.iter().rposition(|p| p == path) {
        r.paths.swap_remove(i);
    }
}

/// Holds off [`remove_unfinished`] while a commit renames files into place.
pub(super) fn commit_guard() -> MutexGuard<'static, ()> {
    COMMIT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Whether [`remove_unfinished`] has run: the process is stopping, and an
/// error the work met since (a refused temporary) is a consequence, not a
/// fault to report.
#[must_use]
pub fn stopping() -> bool {
    registry().closed
}

/// Proof that the unfinished outputs are gone; while it is held no commit
/// can start. Meant to be held until the process exits.
#[must_use = "hold it until the process exits, so that no commit starts"]
pub struct Stopped {
    _commit: MutexGuard<'static, ()>,
    /// How many files and folders were removed.
    pub removed: usize,
}

/// For a program stopping on a signal: waits for a commit in progress to
/// finish (so that the outputs are the previous set or the new one, never a
/// mix), removes every temporary, staging folder and lock file still
/// registered, and refuses new ones. Hold the result until the process exits.
pub fn remove_unfinished() -> Stopped {
    let commit = commit_guard();
    let paths = {
        let mut r = registry();
        r.closed = true;
        std::mem::take(&mut r.paths)
    };
    let mut removed = 0;
    for p in paths.iter().rev() {
        let gone = match std::fs::symlink_metadata(p) {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(p).is_ok(),
            Ok(_) => std::fs::remove_file(p).is_ok(),
            Err(_) => false,
        };
        removed += usize::from(gone);
    }
    Stopped {
        _commit: commit,
        removed,
    }
}
