//! Figures of a progressive solve, part of the stats JSON.

use crate::math::Rgb;
use serde::Serialize;

/// Where a refinement pass fell during shooting (its mesh figures are in the
/// solve's `passes`, numbered alike).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ShootingPass {
    /// Pass number, from 1.
    pub pass: usize,
    /// Shots before the pass.
    pub after_shots: usize,
    /// Unshot fraction before the pass.
    pub unshot_fraction: f64,
    /// Signed change of the unshot power caused by the pass, over emitted
    /// power, bands summed: new elements gather what has been shot more
    /// accurately than their parents received it, and their patches' unshot
    /// radiosity takes up the difference so that what was shot stays shot.
    pub unshot_change: f64,
}

/// One point of the convergence history.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct HistoryPoint {
    /// Shots so far.
    pub shots: usize,
    /// Seconds since the solve began.
    pub seconds: f64,
    /// Unshot fraction.
    pub unshot_fraction: f64,
}

/// What a progressive solve did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ProgressiveStats {
    /// Shots taken.
    pub shots: usize,
    /// Why it stopped.
    pub stop: StopReason,
    /// Unshot power over emitted power at the end, bands summed.
    pub unshot_fraction: f64,
    /// The lowest the signed unshot power (bands summed, over emitted power)
    /// fell below zero during the solve (0 if it never did). Light still to be delivered cannot be less than
    /// none, so in a solve that conserves energy it stays above minus the
    /// stopping tolerance: it is negative only while corrections (a
    /// refinement pass, the gathered rows) take back light already shot, and
    /// then by no more than they take back.
    pub lowest_signed_unshot_fraction: f64,
    /// Times what had been shot was scaled back because the signed unshot
    /// power of a band had fallen below zero (see `settle`): after a
    /// refinement pass took back light already shot, or a shot of positive
    /// light while other patches held negative corrections.
    pub settled: usize,
    /// The ambient term at the end (display only; not in the solution).
    pub ambient: Rgb,
    /// Shooter cell depth below each shooting patch, for the fine shots.
    pub shooter_depth: u8,
    /// Shots heavy enough to use cells at `shooter_depth` (the others shot
    /// from one cell per patch).
    pub fine_shots: usize,
    /// Hemi-cubes rendered by shots (the refinement gathers are counted in the
    /// hemi-cube figures of the solve).
    pub shot_hemicubes: u64,
    /// Shots that reused the form factors kept from the patch's earlier shot
    /// (and rendered nothing).
    pub cached_shots: usize,
    /// Most bytes the kept form factors took.
    pub shot_cache_bytes: usize,
    /// Shots before every leaf gathered its row and shots turned to the
    /// rows (see `ProgressiveSettings::gather_rows`); `None` if they never did.
    pub rows_gathered_after_shots: Option<usize>,
    /// Classic shooter cells split because a reciprocal form factor exceeded 1.
    pub shooter_splits: usize,
    /// Classic reciprocal form factors still above 1 at the lattice's finest
    /// shooter cell, clipped to 1.
    pub reciprocity_clips: usize,
    /// Shooter cells split because part of them is shut inside an object:
    /// they hold both exposed and shut-in leaves, or their eye is shut in.
    pub hidden_eye_splits: usize,
    /// Shooter cells that shot nothing: all their leaves are shut in, or their
    /// eye still is at the deepest split.
    pub hidden_cells: usize,
    /// Shots whose implied row sum exceeded 1 (point sampling of the
    /// receivers, in particular of those that straddle an occluder's foot).
    pub row_sums_above_one: usize,
    /// Shots whose reflected part `sum_e rho_e F_ei A_e / W_i` (with the
    /// balance's scales) exceeded 1 in some band (they would have raised the
    /// unshot power) and were scaled back to 1.
    pub scaled_shots: usize,
    /// Mean implied row sum of the shots, `sum_e F_ei A_e / W_i` with `W_i`
    /// the shooting patch's exposure.
    pub mean_implied_row_sum: f64,
    /// Largest implied row sum before scaling.
    pub max_implied_row_sum: f64,
    /// Shots after which the unshot power of some band was larger than before
    /// (a form-factor error; 0 expected).
    pub unshot_increases: usize,
    /// Refinement passes during shooting.
    pub passes: Vec<ShootingPass>,
    /// Unshot fraction over time: the first shot, then each time the fraction
    /// has fallen by a further factor of ten to the quarter, and the last shot.
    pub history: Vec<HistoryPoint>,
}

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
