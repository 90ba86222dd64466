//! [`Outputs`]: files staged as temporaries beside their targets, renamed into
//! place together.

use crate::error::{Error, Result};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// What a staged file is written through: a buffered temporary file, which can
/// seek (the OpenEXR encoder writes its offset table last).
pub trait WriteSeek: Write + Seek {}

impl<T: Write + Seek + ?Sized> WriteSeek for T {}

/// One file written to its temporary, waiting for the rename.
#[derive(Debug)]
struct Staged {
    /// The path as the caller named it, for messages and the list of outputs.
    shown: PathBuf,
    /// Where the file goes: `shown`, or what it links to if it is a symbolic
    /// link (so that the link keeps pointing at the new file).
    target: PathBuf,
    /// The temporary holding the new contents.
    temp: PathBuf,
}

/// The files of one run. [`stage`](Outputs::stage) writes each where it
/// waits for the commit; [`commit`](Outputs::commit) makes them all visible.
/// Dropping the set without committing removes what it staged and leaves
/// every target as it was.
///
/// [`Outputs::new`] stages each file beside its target and renames them one
/// by one: each file is replaced whole, and a failure before the commit
/// changes none. [`Outputs::set`] (on Unix) stages them into a version
/// folder and swaps the whole set in one rename, so that even a process
/// killed during the commit leaves the previous set or the new one, never a
/// mix (see [`crate::output`]).
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
    #[cfg(unix)]
    set: Option<super::set::VersionedSet>,
    hook: Option<StepHook>,
}

/// Called before each step of a commit, with what the step does.
pub(crate) type StepHook = Box<dyn FnMut(&str) + Send>;

impl std::fmt::Debug for Outputs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("Outputs");
        d.field("staged", &self.staged);
        #[cfg(unix)]
        d.field("set", &self.set);
        d.finish_non_exhaustive()
    }
}

impl Outputs {
    /// An empty set whose files are staged beside their targets.
    #[must_use]
    pub fn new() -> Self {
        Outputs::default()
    }

    /// An empty set of outputs called `name` (a scene's name, say), anchored
    /// in `folder` (created if missing): its files are staged in a hidden
    /// version folder there, and the names the caller gives become links
    /// into it, all swapped at once by the commit. Hold an
    /// [`OutputLock`](super::OutputLock) on the same folder and name from
    /// before the work until the commit, so that no other run writes the
    /// set meanwhile. Elsewhere than on Unix, the same as [`Outputs::new`].
    ///
    /// # Errors
    ///
    /// [`Error::Io`] when the folder or the version folder cannot be made;
    /// [`Error::Output`] for a name that cannot name files.
    pub fn set(folder: &Path, name: &str) -> Result<Self> {
        #[cfg(unix)]
        {
            Ok(Outputs {
                staged: Vec::new(),
                set: Some(super::set::VersionedSet::new(folder, name)?),
                hook: None,
            })
        }
        #[cfg(not(unix))]
        {
            let _ = (folder, name);
            Ok(Outputs::default())
        }
    }

    /// Calls `hook` before each step of the commit with what the step does
    /// (for tests that stop a commit at every step; not needed otherwise).
    #[doc(hidden)]
    pub fn on_commit_step(&mut self, hook: impl FnMut(&str) + Send + 'static) {
        #[cfg(unix)]
        if let Some(set) = &mut self.set {
            set.hook = Some(Box::new(hook));
            return;
        }
        self.hook = Some(Box::new(hook));
    }

    /// Writes the file `path` through `write` into a temporary file in the same
    /// folder (created if missing), flushed and synced to the disk. Nothing
    /// at `path` changes until [`commit`](Outputs::commit).
    ///
    /// # Errors
    ///
    /// [`Error::Output`] when `path` is a folder or another non-regular file,
    /// or is already staged in this set; [`Error::Io`] naming `path` when the
    /// temporary cannot be created, written or synced; whatever `write` returns.
    /// On any error the temporary is removed.
    pub fn stage(
        &mut self,
        path: &Path,
        write: impl FnOnce(&mut dyn WriteSeek) -> Result<()>,
    ) -> Result<()> {
        #[cfg(unix)]
        if let Some(set) = &mut self.set {
            return set.stage(path, write);
        }
        let target = writable_target(path)?;
        if self.staged.iter().any(|s| s.target == target) {
            return Err(Error::Output {
                path: path.to_path_buf(),
                message: "the same file is written twice in one run".to_string(),
            });
        }
        if let Some(folder) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))?;
        }
        let temp = Temporary::create(&target).map_err(|e| Error::io(path, e))?;
        let mut writer = BufWriter::new(&temp.file);
        write(&mut writer)?;
        let file = writer
            .into_inner()
            .map_err(|e| Error::io(path, e.into_error()))?;
        file.sync_all().map_err(|e| Error::io(path, e))?;
        keep_permissions(&target, &temp.path);
        self.staged.push(Staged {
            shown: path.to_path_buf(),
            target,
            temp: temp.keep(),
        });
        Ok(())
    }

    /// [`stage`](Outputs::stage) for contents already in memory.
    ///
    /// # Errors
    ///
    /// As for [`stage`](Outputs::stage).
    pub fn stage_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        self.stage(path, |w| w.write_all(bytes).map_err(|e| Error::io(path, e)))
    }

    /// The files staged so far, as their callers named them.
    pub fn paths(&self) -> Vec<&Path> {
        #[cfg(unix)]
        if let Some(set) = &self.set {
            return set.paths().collect();
        }
        self.staged.iter().map(|s| s.shown.as_path()).collect()
    }

    /// Renames every staged file over its target, in the order staged, and
    /// returns their paths. Every target is checked again first, so that a
    /// target that became a folder in the meantime fails the whole set before
    /// anything is replaced.
    ///
    /// # Errors
    ///
    /// [`Error::Output`] when a target can no longer be replaced (nothing has
    /// been renamed then); [`Error::Io`] when a rename itself fails, which
    /// after those checks only a concurrent change of the folder can cause:
    /// the message then lists the files already replaced. The remaining
    /// temporaries are removed.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        #[cfg(unix)]
        if let Some(set) = self.set.take() {
            return set.commit();
        }
        let _guard = super::pending::commit_guard();
        for s in &self.staged {
            writable_target(&s.shown)?;
        }
        let mut done: Vec<PathBuf> = Vec::with_capacity(self.staged.len());
        let staged = std::mem::take(&mut self.staged);
        let mut rest = staged.into_iter();
        while let Some(s) = rest.next() {
            if let Some(hook) = &mut self.hook {
                hook(&format!("rename {}", s.shown.display()));
            }
            let renamed = std::fs::rename(&s.temp, &s.target);
            super::pending::forget(&s.temp);
            if let Err(e) = renamed {
                let _ = std::fs::remove_file(&s.temp);
                for later in rest {
                    let _ = std::fs::remove_file(&later.temp);
                    super::pending::forget(&later.temp);
                }
                let replaced = if done.is_empty() {
                    "no file was replaced".to_string()
                } else {
                    let names: Vec<String> = done.iter().map(|p| p.display().to_string()).collect();
                    format!("already replaced: {}", names.join(", "))
                };
                let error = std::io::Error::new(e.kind(), format!("{e} ({replaced})"));
                return Err(Error::io(&s.shown, error));
            }
            sync_folder(&s.target);
            done.push(s.shown);
        }
        Ok(done)
    }
}

impl Drop for Outputs {
    /// Removes the temporaries of a set that was never committed.
    fn drop(&mut self) {
        for s in &self.staged {
            let _ = std::fs::remove_file(&s.temp);
            super::pending::forget(&s.temp);
        }
    }
}

/// Writes one file whole or not at all: [`Outputs::stage`] and
/// [`Outputs::commit`] for a single file.
///
/// # Errors
///
/// As for [`Outputs::stage`] and [`Outputs::commit`]; on any error the file at
/// `path` is left as it was.
pub fn write_file(path: &Path, write: impl FnOnce(&mut dyn WriteSeek) -> Result<()>) -> Result<()> {
    let mut outputs = Outputs::new();
    outputs.stage(path, write)?;
    outputs.commit().map(|_| ())
}

/// [`write_file`] for contents already in memory.
///
/// # Errors
///
/// As for [`write_file`].
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut outputs = Outputs::new();
    outputs.stage_bytes(path, bytes)?;
    outputs.commit().map(|_| ())
}

/// Where a file written to `path` must go: `path` itself, or the file a
/// symbolic link at `path` points to. Refuses a folder and anything else that
/// is not a regular file (renaming over a device such as `/dev/null` would
/// replace the device itself).
pub(super) fn writable_target(path: &Path) -> Result<PathBuf> {
    let refuse = |what: &str| {
        Err(Error::Output {
            path: path.to_path_buf(),
            message: format!(
                "{what}; an output is written to a temporary file and renamed over its target, \
                 which must be a regular file or not exist yet"
            ),
        })
    };
    if path.file_name().is_none() {
        return refuse("this names no file");
    }
    let is_link = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    let target = if is_link {
        std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
    } else {
        path.to_path_buf()
    };
    match std::fs::metadata(&target) {
        Ok(m) if m.is_dir() => refuse("this is a folder"),
        Ok(m) if !m.is_file() => refuse("this is a device, FIFO or socket, not a regular file"),
        _ => Ok(target),
    }
}

/// A temporary file beside a target, removed when dropped unless kept.
pub(super) struct Temporary {
    pub(super) path: PathBuf,
    pub(super) file: File,
    kept: bool,
}

impl Temporary {
    /// Creates a new, empty temporary in `target`'s folder: a hidden name made
    /// of the target's name, the process id and a counter, created exclusively
    /// so that two runs (or two files of one run) never share one.
    pub(super) fn create(target: &Path) -> std::io::Result<Temporary> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let name = target
            .file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        // Room for the prefix and suffix within the usual 255-byte name limit.
        let mut short: String = name.chars().take(96).collect();
        while short.len() > 200 {
            short.pop();
        }
        let folder = target.parent().unwrap_or(Path::new(""));
        loop {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = folder.join(format!(".{short}.{}-{n}.tmp", std::process::id()));
            let opened = super::pending::create(&path, |p| {
                OpenOptions::new().write(true).create_new(true).open(p)
            });
            match opened {
                Ok(file) => {
                    return Ok(Temporary {
                        path,
                        file,
                        kept: false,
                    })
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(e),
            }
        }
    }

    /// Leaves the file in place and returns its path.
    pub(super) fn keep(mut self) -> PathBuf {
        self.kept = true;
        std::mem::take(&mut self.path)
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.kept {
            let _ = std::fs::remove_file(&self.path);
            super::pending::forget(&self.path);
        }
    }
}

/// Gives the temporary the permissions of the file it replaces, so that
/// writing a file anew does not change who may read it (best effort).
fn keep_permissions(target: &Path, temp: &Path) {
    if let Ok(m) = std::fs::metadata(target) {
        let _ = std::fs::set_permissions(temp, m.permissions());
    }
}

/// Syncs the folder of `target` so that the rename itself survives a crash
/// (best effort; only Unix can open a folder for this).
fn sync_folder(target: &Path) {
    #[cfg(unix)]
    {
        let folder = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if let Ok(f) = File::open(folder) {
            let _ = f.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = target;
}
