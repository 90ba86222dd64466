//! Progressive refinement (Cohen, Chen, Wallace, Greenberg 1988): instead of
//! solving for every patch at once, the patch with the most unshot power
//! shoots it to every leaf element it sees, and its unshot radiosity becomes
//! zero. Each receiving leaf `e` gains `dB_e = rho_e dB_i F_ei` (with `F_ei =
//! F_ie A_i / A_e` in the classic form), and its patch's unshot radiosity the
//! area-weighted share. No form factor has to be computed before the first
//! shot, so early results come in time linear in the number of patches, and
//! the result converges to the solution of the same radiosity system as
//! gathering. A patch's factors are kept for its later shots (within a byte
//! budget), which then render nothing.
//!
//! Shooter-side hemi-cubes see the receivers from a few points of a large
//! patch, which is where classic implementations lose accuracy in cluttered
//! scenes. By default the shots turn to the gathering rows once the first
//! quick shots are done (see [`ProgressiveSettings::gather_rows`]): at the
//! first refinement pass every leaf renders its own hemi-cube, as in the
//! Gauss-Seidel path, what has been shot is gathered again with the rows, and
//! from then on a shot of patch `j` delivers `F_ej` from each leaf's row. The
//! solve then converges to the Gauss-Seidel solution of its mesh.
//!
//! The parts, one file each:
//!
//! - [`settings`](ProgressiveSettings): [`SolverKind`], stopping rules, shooter
//!   cells, refinement pace;
//! - `ShootingState`: radiosity, unshot and shot radiosity per patch,
//!   irradiance per leaf;
//! - `Receivers`: the leaves as an item-buffer polygon list;
//! - `Shooter`: the form factors of one shot (see its module for the hybrid
//!   and classic forms, and how reciprocals above 1 are handled);
//! - `ShotCache`: each patch's form factors, kept for its next shots;
//! - `visible_fractions`: the visible part of each leaf from the item buffer;
//! - `ambient_term`: the display-only ambient term;
//! - `Stopping`: unshot fraction, shot count, time budget;
//! - `adopt`: new elements of a refinement pass gather what has been shot;
//!
//! - `driver`: the solver as the one driver runs it (start, shots until a
//!   stopping rule, refinement passes, the solution), with `shots` (one shot,
//!   its progress and previews) and `gathered_rows` (the turn to the gathering
//!   rows);
//! - [`Preview`]: what the preview callback sees.
//!
//! The figures ([`ProgressiveStats`](crate::solution::ProgressiveStats)) and
//! [`StopReason`](crate::solution::StopReason) are part of the solve's stats.

mod ambient;
mod cache;
mod cell;
mod driver;
mod gathered_rows;
mod newborn;
mod preview;
mod receivers;
mod settings;
mod shoot;
mod shots;
mod state;
mod stopping;
mod visibility;

use ambient::ambient_term;
use cache::ShotCache;
use newborn::{adopt, regather, settle};
pub use preview::Preview;
use receivers::Receivers;
pub use settings::{ProgressiveSettings, SolverKind, DEFAULT_UNSHOT_TOLERANCE};
use shoot::Shooter;
use state::ShootingState;
use stopping::Stopping;

use crate::solution::{ProgressiveStats, StopReason};

/// The preview callback of a progressive solve.
pub(crate) type PreviewCallback<'p> = &'p mut dyn FnMut(&Preview<'_>);

/// The progressive solver's own state between the driver's calls.
pub(crate) struct Shooting<'p> {
    preview: Option<PreviewCallback<'p>>,
    state: ShootingState,
    receivers: Receivers,
    cache: ShotCache,
    shooter: Shooter,
    figures: ProgressiveStats,
    shots: usize,
    row_sum_total: f64,
    /// Whether every leaf has gathered its row once (see
    /// `ProgressiveSettings::gather_rows`), or tried to.
    rows_tried: bool,
    /// Whether the cache holds every leaf's gathering row and the scene is
    /// closed, so that shots deliver by the balanced rows, as Gauss-Seidel
    /// gathers (see [`crate::solve::balance`]).
    balanced: bool,
    /// Whether the gathered rows find the scene closed: the leaves are then
    /// weighed by their exposure, as Gauss-Seidel weighs them.
    closed: bool,
    /// The unshot fraction now, at the start, and at the last refinement
    /// pass; and where the next history point is due.
    fraction: f64,
    initial_fraction: f64,
    last_pass_fraction: f64,
    next_history: f64,
    /// Keep the shaped gathers' factors in the solution (for light groups;
    /// see `Gathering::keep_shapes`).
    pub(crate) keep_shapes: bool,
    /// The stopping rule that asked for one more refinement pass.
    final_pass: Option<StopReason>,
    /// Whether the refinement pass just run split anything (`None` until
    /// the next pass).
    last_pass_split: Option<bool>,
    stop: StopReason,
}
