//! When a progressive solve stops.

use super::ProgressiveSettings;
use crate::solution::StopReason;
use std::time::Instant;

/// The stopping rules of one solve, with the time it started.
#[derive(Clone, Debug)]
pub(crate) struct Stopping<'a> {
    settings: &'a ProgressiveSettings,
    started: Instant,
}

impl<'a> Stopping<'a> {
    /// The rules of `settings`, the time budget counted from `started`.
    #[must_use]
    pub(crate) fn new(settings: &'a ProgressiveSettings, started: Instant) -> Self {
        Stopping { settings, started }
    }

    /// True when the unshot fraction has reached the tolerance.
    #[must_use]
    pub(crate) fn converged(&self, unshot_fraction: f64) -> bool {
        unshot_fraction <= self.settings.tolerance
    }

    /// The first rule that says stop after `shots` shots with `unshot_fraction`
    /// left, checked in the order tolerance, shot limit, time budget.
    #[must_use]
    pub(crate) fn check(&self, shots: usize, unshot_fraction: f64) -> Option<StopReason> {
        if self.converged(unshot_fraction) {
            return Some(StopReason::Converged);
        }
        if self.settings.max_shots.is_some_and(|m| shots >= m) {
            return Some(StopReason::ShotLimit);
        }
        if self
            .settings
            .time_budget
            .is_some_and(|b| self.started.elapsed() >= b)
        {
            return Some(StopReason::TimeBudget);
        }
        None
    }
}
