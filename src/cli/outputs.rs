//! What every command does around its outputs: one writer at a time, never
//! over one of its own inputs, and sets of files replaced in one step.

use anyhow::{bail, Result};
use radiosity::gltf_io::{input_files, ImportLimits};
use radiosity::output::{OutputLock, Outputs};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Test-only: when set to a number of seconds, every commit prints
/// `commit step: WHAT` on standard error before each of its steps and waits
/// that long, so that a test can kill the process at each step. Not an
/// option users see; nothing else reads it.
const COMMIT_PAUSE_VARIABLE: &str = "RADIOSITY_TEST_COMMIT_PAUSE";

/// Takes the lock on the outputs `name` in `folder` (see [`OutputLock`]).
pub fn lock_set(folder: &Path, name: &str) -> Result<OutputLock> {
    Ok(OutputLock::acquire(folder, name)?)
}

/// Takes the lock on the single output file `path`.
pub fn lock_file(path: &Path) -> Result<OutputLock> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    Ok(OutputLock::acquire(folder, &name)?)
}

/// A set of outputs `name` in `folder`, replaced in one step at its commit.
pub fn output_set(folder: &Path, name: &str) -> Result<Outputs> {
    let mut outputs = Outputs::set(folder, name)?;
    pause_between_steps(&mut outputs);
    Ok(outputs)
}

/// The test hook of [`COMMIT_PAUSE_VARIABLE`], if the variable is set.
pub fn pause_between_steps(outputs: &mut Outputs) {
    let Some(seconds) = std::env::var(COMMIT_PAUSE_VARIABLE)
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0 && *s < 3600.0)
    else {
        return;
    };
    outputs.on_commit_step(move |what| {
        eprintln!("commit step: {what}");
        std::thread::sleep(Duration::from_secs_f64(seconds));
    });
}

/// The files a scene argument reads: a glTF file and the buffers and images
/// it names; nothing for a built-in scene's name.
pub fn scene_inputs(scene: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let path = scene.as_ref();
    if !path.exists() {
        return Ok(Vec::new());
    }
    Ok(input_files(path, &ImportLimits::default())?)
}

/// Refuses to go on when any of `outputs` would replace one of `inputs`:
/// the same path once both are made absolute and links are followed, or
/// the same file (device and inode) under another name.
pub fn refuse_overwriting_inputs(outputs: &[PathBuf], inputs: &[PathBuf]) -> Result<()> {
    let inputs: Vec<(PathBuf, Identity)> = inputs
        .iter()
        .filter_map(|p| Some((p.clone(), Identity::of(p)?)))
        .collect();
    for output in outputs {
        let Some(out) = Identity::of(output) else {
            continue;
        };
        if let Some((input, _)) = inputs.iter().find(|(_, id)| id.same_as(&out)) {
            bail!(
                "{} is an input of this command ({}); writing it would destroy it: write \
                 the output elsewhere",
                output.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// What tells two names of one file apart from two files: the absolute
/// path with links followed (the folder's, for a file not there yet), and
/// for an existing file its device and inode.
#[derive(Debug, PartialEq)]
struct Identity {
    path: PathBuf,
    inode: Option<(u64, u64)>,
}

impl Identity {
    fn of(path: &Path) -> Option<Identity> {
        let real = path.canonicalize().ok().or_else(|| {
            let parent = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            Some(parent.canonicalize().ok()?.join(path.file_name()?))
        })?;
        Some(Identity {
            inode: inode(&real),
            path: real,
        })
    }

    fn same_as(&self, other: &Identity) -> bool {
        self.path == other.path || (self.inode.is_some() && self.inode == other.inode)
    }
}

#[cfg(unix)]
fn inode(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let m = std::fs::metadata(path).ok()?;
    Some((m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn inode(_: &Path) -> Option<(u64, u64)> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn another_name_of_an_input_is_refused() {
        let dir = std::env::temp_dir().join(format!("radiosity_cli_inputs_{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let scene = dir.join("scene.gltf");
        std::fs::write(&scene, "{}").unwrap();
        let inputs = [scene.clone()];
        let through_sub = dir.join("sub").join("..").join("scene.gltf");
        assert!(refuse_overwriting_inputs(&[through_sub], &inputs).is_err());
        let hard = dir.join("hard.gltf");
        let _ = std::fs::remove_file(&hard);
        std::fs::hard_link(&scene, &hard).unwrap();
        let e = refuse_overwriting_inputs(&[hard], &inputs).unwrap_err();
        assert!(e.to_string().contains("is an input"), "{e}");
        assert!(refuse_overwriting_inputs(&[dir.join("other.png")], &inputs).is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
