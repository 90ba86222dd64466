//! Output files written whole or not at all, and sets of them replaced
//! together.
//!
//! Every file the library and the command-line tool write goes through
//! [`Outputs`]: each file is written to a staging place on its target's file
//! system, flushed to the disk, and only then made visible by a rename, so a
//! reader never sees a half-written file, and a write that fails part way (a
//! full disk, a file-size limit, an encoder error, a crash) leaves the
//! previous file as it was.
//!
//! One [`Outputs`] holds all the files of one run: they are all staged first
//! and made visible together by [`Outputs::commit`] at the end, so that a run
//! that fails leaves none of its targets changed. [`Outputs::new`] stages
//! each file beside its target and renames them one by one; a set made by
//! [`Outputs::set`] keeps its files in a hidden version folder behind links
//! and swaps them all in one rename, so that not even a process killed in
//! the middle of its commit leaves a mix of two runs' files (see the
//! `set` module for the layout). Temporaries of a run that fails, or of a
//! set dropped without a commit, are removed.
//!
//! [`OutputLock`] keeps a second run from writing the same set at the same
//! time, and [`remove_unfinished`] lets a program stopped by a signal remove
//! its temporaries without cutting a commit in half.
//!
//! [`write_file`] and [`write_bytes`] are the one-file case. [`check_target`] and [`prepare_folder`]
//! let a command find out before any expensive work whether its outputs can be
//! written at all.

mod folder;
mod lock;
mod pending;
#[cfg(unix)]
mod set;
mod staged;

pub use folder::{check_target, prepare_folder};
pub use lock::OutputLock;
pub use pending::{remove_unfinished, stopping, Stopped};
pub use staged::{write_bytes, write_file, Outputs, WriteSeek};
