//! The process's peak resident memory, for the stats JSON.

/// The most memory the process has held resident so far, in bytes: Linux's
/// high-water mark `VmHWM` from `/proc/self/status` (the figure
/// `getrusage`'s `ru_maxrss` gives). `None` on other systems or if the file
/// cannot be read.
pub fn peak_resident_bytes() -> Option<u64> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm(&status)
}

/// The memory the process holds resident now, in bytes (`VmRSS`). `None`
/// on other systems or if the file cannot be read.
pub fn resident_bytes() -> Option<u64> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_kib(&status, "VmRSS:")
}

/// `VmHWM` in bytes from the text of `/proc/self/status` (given in kB, which
/// the kernel means as KiB).
fn parse_vm_hwm(status: &str) -> Option<u64> {
    parse_kib(status, "VmHWM:")
}

/// The figure of the line starting with `key` in a `/proc` file, given in
/// kB (which the kernel means as KiB), in bytes.
fn parse_kib(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let mut words = line[key.len()..].split_whitespace();
    let value: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => value.checked_mul(1024),
        _ => None,
    }
}

/// The machine's memory in bytes: `MemTotal` from `/proc/meminfo`. `None`
/// on other systems or if the file cannot be read.
pub fn machine_bytes() -> Option<u64> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_kib(&info, "MemTotal:")
}

/// What a solve may hold when `--max-memory` is not given: three quarters of
/// the machine's memory, leaving room for the system and the images, or the
/// library's default where the machine cannot be asked.
pub fn default_max_memory() -> u64 {
    machine_bytes().map_or(radiosity::DEFAULT_MAX_MEMORY, |b| b / 4 * 3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_high_water_mark_in_kib() {
        let status = "Name:\tradiosity\nVmPeak:\t  900 kB\nVmHWM:\t   12345 kB\nVmRSS:\t 10 kB\n";
        assert_eq!(parse_vm_hwm(status), Some(12345 * 1024));
        assert_eq!(parse_vm_hwm("VmRSS:\t 10 kB\n"), None);
        assert_eq!(parse_vm_hwm("VmHWM:\t 10 MB\n"), None);
    }

    #[test]
    fn a_linux_process_has_a_peak() {
        if cfg!(target_os = "linux") {
            // At least the bytes of a buffer this test keeps resident.
            let held = std::hint::black_box(vec![1u8; 8 << 20]);
            let peak = peak_resident_bytes().unwrap();
            assert!(peak >= held.len() as u64, "{peak}");
        }
    }
}
