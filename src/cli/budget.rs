//! The memory limit covers the whole process: what the process already
//! holds (the program, the scene) and what the images and probes will take
//! come off `--max-memory` before the rest is handed to the solve, and a run
//! that cannot fit is refused before anything large is allocated.

use super::peak_memory::resident_bytes;
use anyhow::{bail, Result};
use radiosity::Settings;

/// Bytes one image pixel takes while a view is rendered and encoded: the
/// 2 x 2 supersampled radiance and depth, the image itself, and the EXR and
/// PNG encoders' buffers (a 2048 x 2048 view peaked at 668 MB).
pub const IMAGE_BYTES_PER_PIXEL: u64 = 160;

/// Bytes per byte of a probe points file: the text itself, and per line of
/// at least 12 bytes a point (48 bytes) and its output row (about 200).
pub const PROBE_BYTES_PER_TEXT_BYTE: u64 = 1 + 250 / 12;

/// What one view of `width` x `height` pixels takes while it is rendered
/// (views are rendered one after another; a mesh overlay copies the image).
pub fn image_bytes(width: u32, height: u32, overlay: bool) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    pixels * IMAGE_BYTES_PER_PIXEL + if overlay { pixels * 24 } else { 0 }
}

/// `settings` with its memory limit lowered by what the process holds now
/// and by `others` (what else the run will take, each named for the
/// message); refuses the run when nothing is left.
pub fn solve_settings(settings: &Settings, others: &[(&str, u64)]) -> Result<Settings> {
    let limit = settings.max_memory;
    let held = resident_bytes().unwrap_or(0);
    let taken: u64 = held + others.iter().map(|(_, b)| b).sum::<u64>();
    if taken >= limit {
        let parts: Vec<String> = std::iter::once(format!(
            "the process holds {} already (the program and the scene)",
            gb(held)
        ))
        .chain(
            others
                .iter()
                .map(|(what, b)| format!("{what} need {}", gb(*b))),
        )
        .collect();
        bail!(
            "the memory limit of {} (--max-memory) cannot hold this run: {}; raise \
             --max-memory, or ask for less",
            gb(limit),
            parts.join(", ")
        );
    }
    Ok(Settings {
        max_memory: limit - taken,
        ..settings.clone()
    })
}

/// `bytes` for a person: "1.25 GB", "420 MB".
pub fn gb(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_and_what_the_process_holds_come_off_the_limit() {
        let settings = Settings {
            max_memory: 1 << 40,
            ..Settings::default()
        };
        let image = image_bytes(2048, 2048, false);
        assert_eq!(image, 2048 * 2048 * 160);
        let left = solve_settings(&settings, &[("the images", image)]).unwrap();
        assert!(left.max_memory <= (1 << 40) - image, "{}", left.max_memory);
        let small = Settings {
            max_memory: 100_000_000,
            ..Settings::default()
        };
        let e = solve_settings(&small, &[("the images", image)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("the images need 671 MB"), "{e}");
    }
}
