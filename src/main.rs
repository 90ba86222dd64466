//! The `radiosity` command-line tool: a thin layer over the library.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    keep_freed_memory();
    let result = cli::run();
    // A signal's clean-up is under way in the watcher thread, which ends
    // the process with the signal's status when it is done; what the work
    // met meanwhile (a temporary refused) is no error of its own.
    while radiosity::output::stopping() {
        std::thread::park();
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // The library names its settings; the CLI says which flag sets each.
            eprintln!("error: {}", cli::with_flags(format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}

/// Asks glibc's allocator to keep memory the solver frees for its next
/// allocations, as it learns to do after a while anyway. By default a
/// block of 128 KiB or more is mapped on its own and unmapped when freed,
/// and a free top of the heap beyond 128 KiB is handed back; the next such
/// block then comes as fresh zeroed pages, one fault each. A solve makes
/// and drops many lists of that size (rows, radiosities, weights), so a
/// quarter of the default job's page faults came from that round trip.
/// The first two limits are the largest glibc itself moves them to as it
/// sees such blocks freed (32 MiB, and twice that for the heap's top),
/// taken from the start; the heap also grows 16 MiB at a time. The
/// library, which other programs embed, leaves their allocator alone.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets allocator parameters; it is called before
    // any thread is started, with parameters and values glibc documents.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
        libc::mallopt(libc::M_TOP_PAD, 16 << 20);
    }
}
