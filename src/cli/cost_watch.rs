//! A warning, when the form factors begin, that the hemi-cube resolution is
//! out of proportion to the work it buys: the first pass's hemi-cube count
//! (the progress total) times the pixels of each, with the time it takes.

use radiosity::pipeline::{Progress, Stage};
use std::sync::Mutex;

/// Resolutions up to this are never warned about: the `converge` sweep's
/// largest default is 256, and 512 is a fine hemi-cube for any patch.
pub const QUIET_RESOLUTION: usize = 512;

/// Pixels drawn in the first pass above which a resolution past
/// [`QUIET_RESOLUTION`] is warned about: half a minute of one core at the
/// [`PIXELS_PER_SECOND`] measured.
pub const WARN_PIXELS: f64 = 3e9;

/// Hemi-cube pixels one core draws a second (a 220-patch room: 150 M at
/// resolution 256, 83 M at 1024; 2026-12-07).
pub const PIXELS_PER_SECOND: f64 = 1e8;

/// Watches the progress reports for the first pass of form factors.
pub struct CostWatch {
    resolution: usize,
    threads: usize,
    warning: Mutex<Option<Option<String>>>,
}

impl CostWatch {
    /// A watch for hemi-cubes of `resolution` drawn on `threads` threads.
    pub fn new(resolution: usize, threads: usize) -> Self {
        CostWatch {
            resolution,
            threads,
            warning: Mutex::new(None),
        }
    }

    /// Looks at one progress report; returns the warning the first time the
    /// first pass's form factors begin, if the cost is out of proportion.
    pub fn observe(&self, p: Progress) -> Option<String> {
        if !matches!(p.stage, Stage::FormFactors { pass: 0 }) {
            return None;
        }
        let mut slot = self.warning.lock().unwrap_or_else(|e| e.into_inner());
        if slot.is_some() {
            return None;
        }
        let warning = cost_warning(self.resolution, p.total, self.threads);
        *slot = Some(warning.clone());
        warning
    }

    /// The warning given, if any.
    pub fn warning(&self) -> Option<String> {
        self.warning
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
            .flatten()
    }
}

/// The warning for `hemicubes` hemi-cubes at `resolution` on `threads`
/// threads, or `None` when the cost is in proportion.
pub fn cost_warning(resolution: usize, hemicubes: usize, threads: usize) -> Option<String> {
    let per_cube = 3.0 * (resolution as f64).powi(2);
    let pixels = per_cube * hemicubes as f64;
    if resolution <= QUIET_RESOLUTION || pixels <= WARN_PIXELS {
        return None;
    }
    let minutes = pixels / PIXELS_PER_SECOND / threads.max(1) as f64 / 60.0;
    Some(format!(
        "--hemicube-res {resolution} is out of proportion: the first pass draws {hemicubes} \
         hemi-cubes of {:.1} M pixels each, {:.1} G pixels in all (about {minutes:.0} minutes \
         on {threads} thread(s) at 100 M pixels a second), and more in each refinement pass; \
         the form factors' error falls only as the square of the resolution, and 64 to 256 \
         is plenty for most scenes",
        per_cube / 1e6,
        pixels / 1e9,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_huge_resolution_on_a_small_room_is_warned_with_its_figure() {
        // The case: 880 hemi-cubes at 4096 (44 G pixels).
        let w = cost_warning(4096, 880, 2).unwrap();
        assert!(
            w.contains("50.3 M pixels") && w.contains("44.3 G pixels"),
            "{w}"
        );
        // Ordinary resolutions, and a large one with few hemi-cubes, pass.
        assert!(cost_warning(256, 1_000_000, 1).is_none());
        assert!(cost_warning(1024, 100, 1).is_none());
        assert!(cost_warning(1024, 1000, 1).is_some());
    }
}
