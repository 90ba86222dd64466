//! Output files written whole or not at all.
//!
//! Every file the library and the command-line tool write goes through
//! [`Outputs`]: each file is written to a temporary file in its target's own
//! folder, flushed to the disk, and only then renamed over the target. A rename
//! within one folder replaces the target in one step, so a reader never sees a
//! half-written file, and a write that fails part way (a full disk, a file-size
//! limit, an encoder error, a crash) leaves the previous file as it was.
//!
//! One [`Outputs`] holds all the files of one run: they are all staged first
//! and renamed together by [`Outputs::commit`] at the end, so that a run that
//! fails leaves none of its targets changed (an `.exr` is not replaced while its
//! `.json` and `.png` keep the previous run's values). Temporaries of a run that
//! fails, or of a set dropped without a commit, are removed.
//!
//! [`write_file`] and [`write_bytes`] are the one-file case. [`check_target`] and [`prepare_folder`]
//! let a command find out before any expensive work whether its outputs can be
//! written at all.

mod folder;
mod staged;

pub use folder::{check_target, prepare_folder};
pub use staged::{write_bytes, write_file, Outputs, WriteSeek};
