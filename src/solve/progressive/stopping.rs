//! When a progressive solve stops.

use super::ProgressiveSettings;
use serde::Serialize;
use std::time::Instant;

/// Why a progressive solve stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The unshot fraction reached the tolerance (or nothing emits).
    #[default]
    Converged,
    /// The shot limit was reached.
    ShotLimit,
    /// The time budget ran out.
    TimeBudget,
}

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
