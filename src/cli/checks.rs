//! Checks of command-line values that the library cannot make for the CLI:
//! bounds on threads, seconds and image sizes, each with the reason for it.
//! Every subcommand runs its checks before loading or solving anything.

use anyhow::{bail, Context, Result};
use std::time::Duration;

/// Most worker threads `--threads` may ask for. More threads than cores only
/// add overhead, and each reserves a stack; 1024 is far beyond any machine this
/// runs on, yet a fixed bound, so that a command that works on one machine is
/// not refused on another with fewer cores.
pub const MAX_THREADS: usize = 1024;

/// Longest `--time-budget`, in seconds (about 31.7 years). Larger values, and
/// anything `std::time::Duration` cannot hold (1e20 s), are refused rather
/// than quietly shortened: leaving the option out means no time limit.
pub const MAX_TIME_BUDGET_SECONDS: f64 = 1e9;

/// Longest image side in pixels. The renderer supersamples 2 x 2, and its
/// sample grid allows at most 32768 samples a side.
pub const MAX_IMAGE_SIDE: u32 = 16_384;

/// Most pixels in one image: 2^25, room for 8K UHD (7680 x 4320). Rendering
/// takes about 160 bytes per pixel (supersampled radiance, depth and the
/// encoders' buffers), so this bound is about 5 GiB.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 25;

/// Largest `--exposure` magnitude in stops: 2^1000 is still a finite scale
/// factor in double precision, and no display needs more.
pub const MAX_EXPOSURE_STOPS: f64 = 1000.0;

/// Refuses an `--exposure` that is not a finite number of stops within
/// [`MAX_EXPOSURE_STOPS`] (NaN gave a black image without a word).
pub fn check_exposure(stops: Option<f64>) -> Result<()> {
    match stops {
        Some(s) if !(s.is_finite() && s.abs() <= MAX_EXPOSURE_STOPS) => bail!(
            "--exposure must be a number of stops from -{MAX_EXPOSURE_STOPS} to \
             {MAX_EXPOSURE_STOPS}, got {s}"
        ),
        _ => Ok(()),
    }
}

/// A pool of `threads` workers (all cores when `None`); refuses 0 and more
/// than [`MAX_THREADS`].
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        check_threads(n)?;
        pool = pool.num_threads(n);
    }
    pool.build().context("starting the worker threads")
}

/// Refuses a `--threads` count of 0 or above [`MAX_THREADS`].
pub fn check_threads(n: usize) -> Result<()> {
    if n == 0 {
        bail!("--threads must be at least 1");
    }
    if n > MAX_THREADS {
        bail!("--threads {n} is more than the limit of {MAX_THREADS} worker threads");
    }
    Ok(())
}

/// `--time-budget` as a duration: refuses 0, NaN, negative and infinite
/// values and anything above [`MAX_TIME_BUDGET_SECONDS`].
pub fn time_budget(seconds: Option<f64>) -> Result<Option<Duration>> {
    let Some(t) = seconds else {
        return Ok(None);
    };
    if !(t.is_finite() && t > 0.0) {
        bail!(
            "--time-budget must be a number of seconds above 0, got {t} (a budget of 0 stops \
             before the first shot: a black picture)"
        );
    }
    if t > MAX_TIME_BUDGET_SECONDS {
        bail!(
            "--time-budget {t:e} s is more than the limit of {MAX_TIME_BUDGET_SECONDS:e} s \
             (about 31 years); leave the option out for no time limit"
        );
    }
    // In range by the checks above, so this cannot fail.
    Duration::try_from_secs_f64(t)
        .map(Some)
        .with_context(|| format!("--time-budget {t}"))
}

/// Refuses an image size with a zero side, a side above [`MAX_IMAGE_SIDE`] or
/// more than [`MAX_IMAGE_PIXELS`] pixels.
pub fn check_image_size(width: u32, height: u32) -> Result<()> {
    for (name, side) in [("--width", width), ("--height", height)] {
        if side == 0 || side > MAX_IMAGE_SIDE {
            bail!("{name} must be 1 to {MAX_IMAGE_SIDE} pixels, got {side}");
        }
    }
    let pixels = u64::from(width) * u64::from(height);
    if pixels > MAX_IMAGE_PIXELS {
        bail!(
            "an image of {width} x {height} pixels ({pixels}) is more than the limit of \
             {MAX_IMAGE_PIXELS} pixels (rendering takes about 160 bytes per pixel)"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts_outside_one_to_the_bound_are_refused() {
        assert!(check_threads(0).is_err());
        assert!(check_threads(1).is_ok());
        assert!(check_threads(MAX_THREADS).is_ok());
        let e = check_threads(100_000).unwrap_err().to_string();
        assert!(e.contains("100000") && e.contains("1024"), "{e}");
    }

    #[test]
    fn time_budgets_that_a_duration_cannot_hold_are_refused() {
        assert_eq!(time_budget(None).unwrap(), None);
        assert_eq!(
            time_budget(Some(1.5)).unwrap(),
            Some(Duration::from_millis(1500))
        );
        for bad in [1e20, f64::NAN, -1.0, f64::INFINITY, 1.1e9, 0.0, -0.0] {
            assert!(time_budget(Some(bad)).is_err(), "{bad} accepted");
        }
    }

    #[test]
    fn exposures_that_are_not_a_finite_number_of_stops_are_refused() {
        assert!(check_exposure(None).is_ok());
        assert!(check_exposure(Some(-3.5)).is_ok());
        for bad in [f64::NAN, f64::INFINITY, 1e300, -1001.0] {
            assert!(check_exposure(Some(bad)).is_err(), "{bad} accepted");
        }
    }

    #[test]
    fn image_sizes_with_a_zero_or_absurd_side_are_refused() {
        assert!(check_image_size(512, 512).is_ok());
        assert!(check_image_size(7680, 4320).is_ok());
        assert!(check_image_size(0, 512).is_err());
        assert!(check_image_size(512, 0).is_err());
        assert!(check_image_size(20_000, 1).is_err());
        assert!(check_image_size(16_384, 16_384).is_err());
    }
}
