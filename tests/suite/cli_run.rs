//! Running the command-line tool from tests: a fresh folder per test, the
//! binary with arguments, its standard error as text.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty folder `name` under the tests' temporary folder `group`.
pub fn fresh_folder(group: &str, name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The `radiosity` binary run with `args`, to completion.
pub fn radiosity(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(args)
        .output()
        .expect("the radiosity binary runs")
}

/// What the run wrote to standard error.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A reader that stops reading (`radiosity reference ... | head`) is no
/// error: the command ends quietly instead of panicking on the closed pipe.
#[test]
fn output_to_a_closed_pipe_ends_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_radiosity"))
        .args(["reference", "penumbra_parallel", "--paths", "200"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the command writes anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
}
