//! Writing results to standard output when its reader may leave early.
//!
//! `println!` panics when the reader has gone (`radiosity compare A B | head`
//! closes the pipe after ten lines). A reader that stops reading wants no
//! more: that is not an error, and never a panic.

use std::io::{ErrorKind, Write};

/// Writes `text` to standard output. A closed pipe ends the writing quietly;
/// any other failure is an error.
pub fn write_out(text: &str) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("writing to standard output"))
        }
        _ => Ok(()),
    }
}
