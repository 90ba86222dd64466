//! Stopping on a signal without losing or mixing outputs.
//!
//! SIGINT (Ctrl-C), SIGTERM and SIGHUP are blocked in every thread and taken
//! by one watcher thread with `sigwait`. The watcher stops the work at once,
//! wherever it is (in a hemi-cube, a solver sweep, an image encoder), without
//! the library having to look for a flag: it removes the run's temporaries
//! and staging folders (waiting first for a commit under way, which takes
//! milliseconds, so the outputs are the previous set or the new one, never a
//! mix), says so, and exits with 128 plus the signal's number (130, 143,
//! 129), as a shell reports a process the signal killed.
//!
//! SIGXFSZ (a write beyond the file-size limit, `ulimit -f`) is ignored, so
//! that the write fails with EFBIG and the run ends with an error naming the
//! file instead of dying without a word.

use anyhow::Result;

/// Installs the handling. Call it first thing in `main`, before any other
/// thread starts: threads inherit the blocked signals.
#[cfg(unix)]
pub fn install() -> Result<()> {
    // SAFETY: plain libc calls on a signal set this function owns; they
    // change the process's signal dispositions and this thread's mask,
    // before any other thread exists.
    let set = unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for s in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, s);
        }
        let blocked = libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        if blocked != 0 {
            anyhow::bail!("blocking signals for the watcher thread failed ({blocked})");
        }
        set
    };
    std::thread::Builder::new()
        .name("signals".to_string())
        .spawn(move || loop {
            let mut signal = 0;
            // SAFETY: `set` lives in this closure; `sigwait` writes `signal`.
            if unsafe { libc::sigwait(&set, &mut signal) } == 0 {
                stop(signal);
            }
        })?;
    Ok(())
}

/// Elsewhere, the default handling.
#[cfg(not(unix))]
pub fn install() -> Result<()> {
    Ok(())
}

/// Removes what the run has under way and exits as the signal asks.
#[cfg(unix)]
fn stop(signal: i32) -> ! {
    let name = match signal {
        libc::SIGINT => "SIGINT",
        libc::SIGTERM => "SIGTERM",
        libc::SIGHUP => "SIGHUP",
        _ => "a signal",
    };
    // Held until the exit, so that no commit starts after the clean-up.
    let _stopped = radiosity::output::remove_unfinished();
    eprintln!(
        "\nradiosity: stopped by {name}; unfinished outputs removed (the files of this run \
         that were not yet committed are as they were before it)"
    );
    std::process::exit(128 + signal);
}
