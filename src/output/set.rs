//! A set of outputs replaced in one step: the files live in a hidden version
//! folder, and the names a reader opens are symbolic links through one
//! pointer, so that a single `rename` of the pointer swaps every file at once.
//!
//! For the outputs `NAME` in folder `out` (the anchor):
//!
//! ```text
//! out/NAME.png            -> .NAME.outputs/NAME.png     (one link per file, made once)
//! out/.NAME.outputs       -> .NAME.outputs-7211-0       (the pointer)
//! out/.NAME.outputs-7211-0/NAME.png, NAME.exr, NAME.json (the files of one run)
//! ```
//!
//! A run writes its files into a fresh version folder, makes the links its
//! set needs that are missing, then renames a new pointer over the old one:
//! the commit point. A run killed at any moment (SIGKILL, a power cut) leaves
//! every name showing the previous set or every name showing the new one: a
//! link made before the swap points through the pointer into the previous
//! version, where a file the previous run did not write is simply absent.
//! Names that are still regular files (written before this scheme, or by
//! hand) are first taken into the previous version (hard-linked, else
//! copied) and only then replaced by links to the same contents. After the
//! swap, links to files the new set lacks, the previous version, and what
//! runs killed earlier left behind are removed.
//!
//! A file outside the anchor folder (an overlay PNG named by the user) gets
//! an absolute link into the anchor's version folder under a key made from
//! its folder, and is listed in the version's manifest so that a later set
//! that drops it can remove its link.

use super::pending;
use super::staged::{writable_target, WriteSeek};
use crate::error::{Error, Result};
use std::ffi::{OsStr, OsString};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The manifest's name inside a version folder.
const MANIFEST: &str = ".manifest";

/// One file of the set.
#[derive(Debug)]
struct Entry {
    /// The path as the caller named it.
    shown: PathBuf,
    /// Its file name inside the version folder.
    key: OsString,
    /// What the link at `shown` holds.
    link: PathBuf,
}

/// A hook called before each step of a commit (for tests that interrupt a
/// commit at every step).
pub(super) type StepHook = Box<dyn FnMut(&str) + Send>;

/// The files of one run, staged into a fresh version folder.
pub(super) struct VersionedSet {
    anchor: PathBuf,
    name: String,
    version: PathBuf,
    entries: Vec<Entry>,
    committed: bool,
    pub(super) hook: Option<StepHook>,
}

impl std::fmt::Debug for VersionedSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VersionedSet")
            .field("anchor", &self.anchor)
            .field("name", &self.name)
            .field("version", &self.version)
            .field("entries", &self.entries)
            .finish_non_exhaustive()
    }
}

impl VersionedSet {
    /// A new, empty set `name` anchored in `folder` (created if missing).
    pub(super) fn new(folder: &Path, name: &str) -> Result<VersionedSet> {
        let anchor = if folder.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            folder.to_path_buf()
        };
        if name.is_empty() || name.contains(['/', '\\', '\0']) {
            return Err(Error::Output {
                path: anchor,
                message: format!("'{name}' cannot name a set of outputs"),
            });
        }
        std::fs::create_dir_all(&anchor).map_err(|e| Error::io(&anchor, e))?;
        let version = fresh_folder(&anchor, name)?;
        Ok(VersionedSet {
            anchor,
            name: name.to_string(),
            version,
            entries: Vec::new(),
            committed: false,
            hook: None,
        })
    }

    /// Writes `path`'s new contents through `write` into the version folder.
    pub(super) fn stage(
        &mut self,
        path: &Path,
        write: impl FnOnce(&mut dyn WriteSeek) -> Result<()>,
    ) -> Result<()> {
        writable_target(path)?;
        let (key, link) = self.key_and_link(path)?;
        if self.entries.iter().any(|e| e.key == key) {
            return Err(Error::Output {
                path: path.to_path_buf(),
                message: "the same file is written twice in one run".to_string(),
            });
        }
        let staged = self.version.join(&key);
        let file = pending::inside(|| {
            OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&staged)
        })
        .map_err(|e| Error::io(path, e))?;
        let written = (|| {
            let mut writer = BufWriter::new(&file);
            write(&mut writer)?;
            let file = writer
                .into_inner()
                .map_err(|e| Error::io(path, e.into_error()))?;
            file.sync_all().map_err(|e| Error::io(path, e))
        })();
        if let Err(e) = written {
            let _ = std::fs::remove_file(&staged);
            return Err(e);
        }
        if let Ok(m) = std::fs::metadata(path) {
            let _ = std::fs::set_permissions(&staged, m.permissions());
        }
        self.entries.push(Entry {
            shown: path.to_path_buf(),
            key,
            link,
        });
        Ok(())
    }

    /// The paths staged so far, as their callers named them.
    pub(super) fn paths(&self) -> impl Iterator<Item = &Path> {
        self.entries.iter().map(|e| e.shown.as_path())
    }

    /// The name `path` has in the version folder, and what its link holds.
    fn key_and_link(&self, path: &Path) -> Result<(OsString, PathBuf)> {
        let Some(file_name) = path.file_name() else {
            return Err(Error::Output {
                path: path.to_path_buf(),
                message: "this names no file".to_string(),
            });
        };
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        let real_parent = parent.canonicalize().map_err(|e| Error::io(parent, e))?;
        let real_anchor = self
            .anchor
            .canonicalize()
            .map_err(|e| Error::io(&self.anchor, e))?;
        let pointer = self.pointer_name();
        if real_parent == real_anchor {
            return Ok((
                file_name.to_os_string(),
                Path::new(&pointer).join(file_name),
            ));
        }
        let mut key = OsString::from(format!(
            "{:016x}-",
            fnv1a(real_parent.as_os_str().as_bytes())
        ));
        key.push(file_name);
        let link = real_anchor.join(&pointer).join(&key);
        Ok((key, link))
    }

    fn pointer_name(&self) -> String {
        format!(".{}.outputs", self.name)
    }

    fn step(&mut self, what: &str) {
        if let Some(hook) = &mut self.hook {
            hook(what);
        }
    }

    /// Makes the staged files the visible set in one step (see the module's
    /// documentation) and returns their paths.
    pub(super) fn commit(mut self) -> Result<Vec<PathBuf>> {
        let _guard = pending::commit_guard();
        for e in &self.entries {
            writable_target(&e.shown)?;
        }
        self.step("write the manifest");
        write_manifest(&self.version, &self.entries)?;
        sync(&self.version);
        let pointer = self.anchor.join(self.pointer_name());
        let previous = current_version(&pointer, &self.name);
        self.adopt_foreign_names(&pointer, previous.as_deref())?;
        let missing: Vec<usize> = (0..self.entries.len())
            .filter(|&i| !is_our_link(&self.entries[i]))
            .collect();
        for i in missing {
            let what = format!("link {}", self.entries[i].shown.display());
            self.step(&what);
            let e = &self.entries[i];
            place_link(&e.shown, &e.link)?;
        }
        self.step("swap the set");
        swap_pointer(&pointer, &self.version)?;
        self.committed = true;
        sync(&self.anchor);
        pending::forget(&self.version);
        // Committed: what follows only tidies up, and cannot change what a
        // reader sees.
        self.remove_stale(previous.as_deref());
        Ok(std::mem::take(&mut self.entries)
            .into_iter()
            .map(|e| e.shown)
            .collect())
    }

    /// Takes every name of the set that is not yet a link of ours (a regular
    /// file, another link) into the previous version, then points the
    /// pointer there: each name then shows what it showed before, through
    /// the pointer, and can be replaced by a link.
    fn adopt_foreign_names(&mut self, pointer: &Path, previous: Option<&Path>) -> Result<()> {
        let foreign: Vec<usize> = (0..self.entries.len())
            .filter(|&i| {
                let e = &self.entries[i];
                !is_our_link(e) && std::fs::metadata(&e.shown).is_ok_and(|m| m.is_file())
            })
            .collect();
        if foreign.is_empty() {
            return Ok(());
        }
        let (keep_in, fresh) = match previous {
            Some(p) => (p.to_path_buf(), false),
            None => (fresh_folder(&self.anchor, &self.name)?, true),
        };
        for i in foreign {
            let what = format!("keep the previous {}", self.entries[i].shown.display());
            self.step(&what);
            let e = &self.entries[i];
            keep_contents(&e.shown, &keep_in.join(&e.key))?;
        }
        sync(&keep_in);
        if fresh {
            self.step("point at the previous files");
            swap_pointer(pointer, &keep_in)?;
            pending::forget(&keep_in);
            sync(&self.anchor);
        }
        Ok(())
    }

    /// After the swap: removes links to files the new set does not have,
    /// the previous version, and leftovers of runs killed earlier.
    fn remove_stale(&mut self, previous: Option<&Path>) {
        let keys: Vec<&OsStr> = self.entries.iter().map(|e| e.key.as_os_str()).collect();
        let pointer = self.pointer_name();
        // Links in the anchor folder into keys this set lacks.
        let mut stale: Vec<PathBuf> = Vec::new();
        if let Ok(names) = std::fs::read_dir(&self.anchor) {
            for entry in names.flatten() {
                let Ok(link) = std::fs::read_link(entry.path()) else {
                    continue;
                };
                let mut parts = link.components();
                let through_pointer = parts
                    .next()
                    .is_some_and(|c| c.as_os_str() == OsStr::new(&pointer));
                if let (true, Some(key), None) = (through_pointer, parts.next(), parts.next()) {
                    if !keys.contains(&key.as_os_str()) {
                        stale.push(entry.path());
                    }
                }
            }
        }
        // Links elsewhere that the previous set listed.
        if let Some(previous) = previous {
            for (key, shown) in read_manifest(previous) {
                if keys.contains(&key.as_os_str()) {
                    continue;
                }
                let ours = std::fs::read_link(&shown)
                    .is_ok_and(|l| l.is_absolute() && l.ends_with(Path::new(&pointer).join(&key)));
                if ours {
                    stale.push(shown);
                }
            }
        }
        for path in stale {
            let what = format!("remove the stale link {}", path.display());
            self.step(&what);
            let _ = std::fs::remove_file(&path);
        }
        self.step("remove the previous files");
        let current = self.version.file_name().map(OsStr::to_os_string);
        let prefixes = [
            format!(".{}.outputs-", self.name),
            format!("{pointer}.swap-"),
        ];
        if let Ok(names) = std::fs::read_dir(&self.anchor) {
            for entry in names.flatten() {
                let name = entry.file_name();
                let leftover = prefixes
                    .iter()
                    .any(|p| name.as_bytes().starts_with(p.as_bytes()));
                if leftover && Some(&name) != current.as_ref() {
                    let path = entry.path();
                    match std::fs::symlink_metadata(&path) {
                        Ok(m) if m.is_dir() => {
                            let _ = std::fs::remove_dir_all(&path);
                        }
                        _ => {
                            let _ = std::fs::remove_file(&path);
                        }
                    }
                }
            }
        }
        for e in &self.entries {
            remove_link_temporaries(&e.shown);
        }
    }
}

impl Drop for VersionedSet {
    /// An uncommitted set's version folder goes (a committed one's is the
    /// visible set, and no longer registered).
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.version);
        }
        pending::forget(&self.version);
    }
}

/// Creates `anchor/.name.outputs-PID-N`, registered as unfinished.
fn fresh_folder(anchor: &Path, name: &str) -> Result<PathBuf> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path = anchor.join(format!(".{name}.outputs-{}-{n}", std::process::id()));
        match pending::create(&path, |p| std::fs::create_dir(p)) {
            Ok(()) => return Ok(path),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(Error::io(anchor, e)),
        }
    }
}

/// The version folder the pointer names, if it is one of this set's.
fn current_version(pointer: &Path, name: &str) -> Option<PathBuf> {
    let target = std::fs::read_link(pointer).ok()?;
    let prefix = format!(".{name}.outputs-");
    let plain = target.components().count() == 1;
    let ours = target.as_os_str().as_bytes().starts_with(prefix.as_bytes());
    let folder = pointer.parent()?.join(&target);
    (plain && ours && folder.is_dir()).then_some(folder)
}

/// Whether the name of `e` is already a link of ours.
fn is_our_link(e: &Entry) -> bool {
    std::fs::read_link(&e.shown).is_ok_and(|l| l == e.link)
}

/// Makes `link` a symbolic link holding `target`, replacing whatever is
/// there in one rename.
fn place_link(link: &Path, target: &Path) -> Result<()> {
    let temp = link_temporary(link);
    pending::create(&temp, |t| std::os::unix::fs::symlink(target, t))
        .map_err(|e| Error::io(link, e))?;
    let made = std::fs::rename(&temp, link);
    if made.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    pending::forget(&temp);
    made.map_err(|e| Error::io(link, e))
}

/// The pointer, replaced by a link to `version` in one rename.
fn swap_pointer(pointer: &Path, version: &Path) -> Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let target = version.file_name().unwrap_or_default();
    let mut temp = pointer.as_os_str().to_os_string();
    temp.push(format!(
        ".swap-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let temp = PathBuf::from(temp);
    let _ = std::fs::remove_file(&temp);
    pending::create(&temp, |t| std::os::unix::fs::symlink(target, t))
        .map_err(|e| Error::io(pointer, e))?;
    let made = std::fs::rename(&temp, pointer);
    if made.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    pending::forget(&temp);
    made.map_err(|e| Error::io(pointer, e))
}

/// The hidden name a new link to `link` is made under before its rename.
fn link_temporary(link: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = link.file_name().unwrap_or_default();
    let mut temp = OsString::from(".");
    temp.push(name);
    temp.push(format!(
        ".radiosity-link-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    link.with_file_name(temp)
}

/// Removes leftovers of [`link_temporary`] beside `link` (from runs killed
/// between making a link and renaming it).
fn remove_link_temporaries(link: &Path) {
    let (Some(folder), Some(name)) = (link.parent(), link.file_name()) else {
        return;
    };
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let mut prefix = b".".to_vec();
    prefix.extend_from_slice(name.as_bytes());
    prefix.extend_from_slice(b".radiosity-link-");
    if let Ok(names) = std::fs::read_dir(folder) {
        for entry in names.flatten() {
            if entry.file_name().as_bytes().starts_with(&prefix) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// Puts the contents `shown` has now at `kept`: a hard link to the same
/// file, else a copy (another file system), renamed into place.
fn keep_contents(shown: &Path, kept: &Path) -> Result<()> {
    let source = shown.canonicalize().map_err(|e| Error::io(shown, e))?;
    let mut temp = kept.as_os_str().to_os_string();
    temp.push(".keep");
    let temp = PathBuf::from(temp);
    let _ = std::fs::remove_file(&temp);
    let linked = std::fs::hard_link(&source, &temp)
        .or_else(|_| std::fs::copy(&source, &temp).map(drop))
        .and_then(|()| File::open(&temp)?.sync_all())
        .and_then(|()| std::fs::rename(&temp, kept));
    if linked.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    linked.map_err(|e| Error::io(shown, e))
}

/// Lists the set's files in its version folder: the key and the name shown
/// of each, one per line (a name holding a tab or a line break is left out:
/// its link is then not removed by a later set that drops it).
fn write_manifest(version: &Path, entries: &[Entry]) -> Result<()> {
    let mut text = Vec::new();
    for e in entries {
        let (k, s) = (e.key.as_bytes(), e.shown.as_os_str().as_bytes());
        if [k, s]
            .iter()
            .any(|b| b.contains(&b'\t') || b.contains(&b'\n'))
        {
            continue;
        }
        text.extend_from_slice(k);
        text.push(b'\t');
        text.extend_from_slice(s);
        text.push(b'\n');
    }
    let path = version.join(MANIFEST);
    let mut file = File::create(&path).map_err(|e| Error::io(&path, e))?;
    file.write_all(&text)
        .and_then(|()| file.sync_all())
        .map_err(|e| Error::io(&path, e))
}

/// The (key, name shown) pairs of a version's manifest.
fn read_manifest(version: &Path) -> Vec<(OsString, PathBuf)> {
    let Ok(text) = std::fs::read(version.join(MANIFEST)) else {
        return Vec::new();
    };
    text.split(|b| *b == b'\n')
        .filter_map(|line| {
            let tab = line.iter().position(|b| *b == b'\t')?;
            let key = OsString::from_vec(line[..tab].to_vec());
            let shown = PathBuf::from(OsString::from_vec(line[tab + 1..].to_vec()));
            Some((key, shown))
        })
        .collect()
}

/// Syncs a folder, so that the names made in it survive a crash (best
/// effort).
fn sync(folder: &Path) {
    if let Ok(f) = File::open(folder) {
        let _ = f.sync_all();
    }
}

/// FNV-1a, 64 bits: a stable key for a folder (no need to resist anyone).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}
