//! The size parameter: from a target triangle count to a layout (bays,
//! balusters or solid parapets) and a tessellation density, found by
//! counting candidate scenes with the generator itself.

use super::generator::generate;
use super::sink::Counter;
use super::{MAX_TRIANGLES, MIN_TRIANGLES};
use crate::error::{Error, Result};

/// Fewest bays along the court.
pub const MIN_BAYS: u32 = 3;
/// Most bays along the court.
pub const MAX_BAYS: u32 = 64;
/// Lowest tessellation density (segments per metre of curved outline).
pub const MIN_DENSITY: f64 = 0.5;
/// Highest tessellation density (segments per metre).
pub const MAX_DENSITY: f64 = 100.0;
/// Bays of the smallest target's layout.
pub(super) const BAYS_AT_MIN: u32 = 5;
/// From this target up the balustrades have turned balusters; below it they
/// are solid parapets (a few hundred balusters would not fit the budget).
pub(crate) const BALUSTERS_FROM: usize = 60_000;

/// The layout and tessellation of an atrium. [`AtriumSize::for_target`]
/// derives one from a triangle count; [`atrium_sized`](super::atrium_sized)
/// builds any valid one (smaller scenes than the documented range, for tests
/// and experiments).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtriumSize {
    /// Bays along the court, [`MIN_BAYS`] to [`MAX_BAYS`]: the building is
    /// `4 * bays` metres long, with `bays - 1` columns per side and storey.
    pub bays: u32,
    /// Turned balusters between the gallery columns (else solid parapets).
    pub balusters: bool,
    /// Segments per metre along curved outlines (columns, arches, balusters,
    /// cloth, furniture), [`MIN_DENSITY`] to [`MAX_DENSITY`]; each curve has
    /// a minimum number of segments whatever the density.
    pub density: f64,
}

impl AtriumSize {
    /// Fails with [`Error::Setting`] when a field is out of its range.
    pub fn validate(&self) -> Result<()> {
        if !(MIN_BAYS..=MAX_BAYS).contains(&self.bays) {
            return Err(Error::Setting {
                name: "bays",
                message: format!("must be {MIN_BAYS} to {MAX_BAYS}, got {}", self.bays),
            });
        }
        if !(self.density.is_finite() && (MIN_DENSITY..=MAX_DENSITY).contains(&self.density)) {
            return Err(Error::Setting {
                name: "density",
                message: format!(
                    "must be {MIN_DENSITY} to {MAX_DENSITY} segments per metre, got {}",
                    self.density
                ),
            });
        }
        Ok(())
    }

    /// The triangles the scene of this size has (a quad counts as two),
    /// counted without building it.
    pub fn triangles(&self) -> Result<usize> {
        self.validate()?;
        let mut counter = Counter::default();
        generate(&mut counter, *self)?;
        Ok(counter.triangles)
    }

    /// The size whose scene has about `target` triangles: the layout for
    /// that size, and the density whose count comes closest to the target
    /// (within 10% over [`MIN_TRIANGLES`] to [`MAX_TRIANGLES`]; the tests
    /// check a sweep of targets). Fails with [`Error::Setting`] outside that
    /// range.
    pub fn for_target(target: usize) -> Result<AtriumSize> {
        if !(MIN_TRIANGLES..=MAX_TRIANGLES).contains(&target) {
            return Err(Error::Setting {
                name: "triangles",
                message: format!("must be {MIN_TRIANGLES} to {MAX_TRIANGLES}, got {target}"),
            });
        }
        let layout = AtriumSize {
            bays: bays_for(target),
            balusters: target >= BALUSTERS_FROM,
            density: MIN_DENSITY,
        };
        closest_density(layout, target)
    }
}

/// Bays for a target: one more each time the target doubles, from
/// [`BAYS_AT_MIN`] at [`MIN_TRIANGLES`] (11 at 1 000 000), so that the court
/// grows longer as the curves grow finer. Integer arithmetic only.
fn bays_for(target: usize) -> u32 {
    BAYS_AT_MIN + (target / MIN_TRIANGLES).max(1).ilog2()
}

/// Searches the density of `layout` whose triangle count is closest to
/// `target`. The count never falls as the density rises (every segment count
/// is a rounded-up multiple of it), so bisection brackets the step where it
/// crosses the target.
fn closest_density(layout: AtriumSize, target: usize) -> Result<AtriumSize> {
    let with = |density: f64| AtriumSize { density, ..layout };
    let count = |density: f64| with(density).triangles();
    let (mut lo, mut hi) = (MIN_DENSITY, MIN_DENSITY);
    let mut hi_count = count(hi)?;
    let mut lo_count = hi_count;
    while hi_count < target && hi < MAX_DENSITY {
        (lo, lo_count) = (hi, hi_count);
        hi = (2.0 * hi).min(MAX_DENSITY);
        hi_count = count(hi)?;
    }
    if lo_count >= target || hi_count < target {
        // The whole range lies on one side of the target.
        return Ok(with(if hi_count < target { hi } else { lo }));
    }
    // Invariant: count(lo) < target <= count(hi).
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let n = count(mid)?;
        if n < target {
            (lo, lo_count) = (mid, n);
        } else {
            (hi, hi_count) = (mid, n);
        }
        if hi_count - lo_count <= 1 || hi_count.abs_diff(target) * 200 <= target {
            break;
        }
    }
    let best = if target - lo_count < hi_count - target {
        lo
    } else {
        hi
    };
    Ok(with(best))
}
