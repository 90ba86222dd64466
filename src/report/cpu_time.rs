//! Processor time of the whole process, for timing runs on a shared machine.

/// User plus system CPU seconds the process has used so far, over all its
/// threads (`getrusage(RUSAGE_SELF)`), or `None` where that call is not
/// available or fails.
///
/// On a machine shared with other work, wall-clock time counts the time the
/// process waited for a core; CPU time does not, so differences of it measure
/// the work of a run more steadily. It does count every worker thread, so on
/// `n` busy cores it runs up to `n` times faster than the wall clock.
#[must_use]
pub fn process_cpu_seconds() -> Option<f64> {
    imp::process_cpu_seconds()
}

#[cfg(unix)]
mod imp {
    pub(super) fn process_cpu_seconds() -> Option<f64> {
        // SAFETY: `getrusage` only writes the `rusage` it is given, which is a
        // plain C struct for which all-zero bytes are a valid value.
        let usage = unsafe {
            let mut usage: libc::rusage = std::mem::zeroed();
            if libc::getrusage(libc::RUSAGE_SELF, &mut usage) != 0 {
                return None;
            }
            usage
        };
        let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Some(seconds(usage.ru_utime) + seconds(usage.ru_stime))
    }
}

#[cfg(not(unix))]
mod imp {
    pub(super) fn process_cpu_seconds() -> Option<f64> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn cpu_time_grows_with_work() {
        let before = process_cpu_seconds().expect("getrusage works on unix");
        // Some arithmetic the optimiser cannot drop.
        let mut x = 0.0f64;
        for i in 0..20_000_000u64 {
            x += (i as f64).sqrt();
        }
        std::hint::black_box(x);
        let after = process_cpu_seconds().unwrap();
        assert!(after > before, "{before} -> {after}");
    }
}
