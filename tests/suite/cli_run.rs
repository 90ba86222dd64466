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
