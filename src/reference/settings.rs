//! How many paths to trace, with which seed, and how paths end.

use crate::error::{Error, Result};

/// Settings of a reference run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceSettings {
    /// Independent paths per probe point, or sample points (one path each) per
    /// object mean. At least 2, so that a standard error exists. The standard
    /// error falls as 1/sqrt(paths).
    pub paths: u64,
    /// Seed of every random stream. The same seed gives the same bits at any
    /// thread count.
    pub seed: u64,
    /// Reflections traced in full before Russian roulette may end a path.
    /// Roulette is unbiased; it only trades variance for speed.
    pub min_bounces_before_roulette: u32,
    /// Hard cap on reflections after the first receiving point. This is the one
    /// biased choice: it drops light that has reflected more than
    /// `max_bounces + 1` times, a relative share of at most
    /// `rho_max^(max_bounces + 1)` (4e-5 at rho_max = 0.99 with the default
    /// 1024; below 1e-46 at rho_max = 0.9). Zero gives direct light only.
    pub max_bounces: u32,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        ReferenceSettings {
            paths: 10_000,
            seed: 0,
            min_bounces_before_roulette: 3,
            max_bounces: 1024,
        }
    }
}

impl ReferenceSettings {
    /// Checks the ranges; the error names the setting.
    pub fn validate(&self) -> Result<()> {
        if self.paths < 2 {
            return Err(Error::Setting {
                name: "paths",
                message: format!(
                    "{} paths give no standard error; use at least 2",
                    self.paths
                ),
            });
        }
        Ok(())
    }
}
