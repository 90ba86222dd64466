//! Which solver runs, and the settings of the progressive one.

use crate::error::{Error, Result};
use std::str::FromStr;
use std::time::Duration;

/// The solver that turns form factors into radiosities.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SolverKind {
    /// Gathering: element-to-patch rows from receiver hemi-cubes, Gauss-Seidel
    /// on the patch system, then one gather per element.
    #[default]
    GaussSeidel,
    /// Progressive refinement (shooting): the patch with the most unshot power
    /// renders a hemi-cube of element ids and distributes that power. Each
    /// patch's factors are kept for its later shots, and once the first quick
    /// shots are done every leaf gathers its row and later shots deliver by
    /// the rows (see [`ProgressiveSettings::gather_rows`]).
    Progressive,
}

impl FromStr for SolverKind {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "gauss-seidel" => Ok(SolverKind::GaussSeidel),
            "progressive" => Ok(SolverKind::Progressive),
            _ => Err(format!(
                "unknown solver '{s}' (gauss-seidel or progressive)"
            )),
        }
    }
}

/// Stopping rules, previews and shooter geometry of the progressive solver.
/// The first stopping rule met ends the solve; the solution is then whatever
/// has been shot so far (never with the ambient term in it).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgressiveSettings {
    /// Converged when the unshot power, summed over patches and bands, is at
    /// most this fraction of the emitted power.
    pub tolerance: f64,
    /// Stop after this many shots.
    pub max_shots: Option<usize>,
    /// Stop once this much wall-clock time has passed since the solve began
    /// (checked before each shot). Unlike the other rules, where this stops
    /// depends on the machine. It bounds the shots: a solve that converges
    /// within it still ends in its shaped gathers (see
    /// [`Settings::shaped_gathers`](crate::Settings::shaped_gathers)), which
    /// may take it past the budget.
    pub time_budget: Option<Duration>,
    /// Hand a preview to the caller every this many shots.
    pub preview_every: Option<usize>,
    /// A shot renders one hemi-cube per cell of the shooting patch at this
    /// depth below it (`4^depth` hemi-cubes), each shooting the patch's unshot
    /// radiosity from its own area: smaller shooters see occluders from more
    /// places, which softens shadows and removes the bias of a single eye.
    pub shooter_depth: u8,
    /// Only shots carrying at least this fraction of the emitted power (bands
    /// summed) use the cells of `shooter_depth`; lighter ones shoot from one
    /// cell per patch, since their visibility errors weigh that much less.
    /// 0 makes every shot fine.
    pub fine_shot_power: f64,
    /// With adaptive refinement, a refinement pass runs each time the unshot
    /// fraction has fallen by this factor since the last pass (and once more
    /// when the tolerance is met), up to `RefineSettings::max_passes` passes.
    pub refine_factor: f64,
    /// Most bytes of form factors kept from each patch's shot for its next
    /// shots (see `ShotCache`); 0 renders every shot anew.
    pub shot_cache_bytes: usize,
    /// At the first refinement pass (on a uniform mesh: once the unshot
    /// fraction has fallen by `refine_factor`), every leaf gathers its row, as
    /// the Gauss-Seidel path does; what has been shot so far is gathered
    /// again with the rows, and later shots deliver by them. The solve then
    /// converges to the Gauss-Seidel solution itself, with shooter-side
    /// hemi-cubes only for the first, quick shots. Needs the rows to fit in
    /// `shot_cache_bytes`.
    pub gather_rows: bool,
}

/// The default unshot tolerance ([`ProgressiveSettings::tolerance`]). A
/// solve told to stop at a larger unshot fraction asks for an early,
/// partial answer, and by default makes no shaped gathers (see
/// [`Settings::shaped_gather_count`](crate::Settings::shaped_gather_count)):
/// they would solve the patch system to the end first.
pub const DEFAULT_UNSHOT_TOLERANCE: f64 = 1e-4;

/// The deepest shooter cells allowed (`4^4 = 256` hemi-cubes per shot).
pub(crate) const MAX_SHOOTER_DEPTH: u8 = 4;

impl Default for ProgressiveSettings {
    fn default() -> Self {
        ProgressiveSettings {
            tolerance: DEFAULT_UNSHOT_TOLERANCE,
            max_shots: None,
            time_budget: None,
            preview_every: None,
            shooter_depth: 1,
            fine_shot_power: 1e-3,
            refine_factor: 0.25,
            shot_cache_bytes: 256 << 20,
            gather_rows: true,
        }
    }
}

impl ProgressiveSettings {
    /// Checks every setting's range; the error names the setting by its
    /// path from [`Settings`](crate::Settings) (`progressive.max_shots`).
    pub fn validate(&self) -> Result<()> {
        let bad = |name, message: String| Err(Error::Setting { name, message });
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return bad(
                "progressive.tolerance",
                format!("must lie in (0, 1), got {}", self.tolerance),
            );
        }
        if self.max_shots == Some(0) {
            return bad("progressive.max_shots", "must be at least 1".to_string());
        }
        if self.preview_every == Some(0) {
            return bad(
                "progressive.preview_every",
                "must be at least 1".to_string(),
            );
        }
        if self.shooter_depth > MAX_SHOOTER_DEPTH {
            return bad(
                "progressive.shooter_depth",
                format!(
                    "must be at most {MAX_SHOOTER_DEPTH}, got {}",
                    self.shooter_depth
                ),
            );
        }
        if !(self.fine_shot_power.is_finite() && (0.0..=1.0).contains(&self.fine_shot_power)) {
            return bad(
                "progressive.fine_shot_power",
                format!("must lie in [0, 1], got {}", self.fine_shot_power),
            );
        }
        if !(self.refine_factor > 0.0 && self.refine_factor < 1.0) {
            return bad(
                "progressive.refine_factor",
                format!("must lie in (0, 1), got {}", self.refine_factor),
            );
        }
        Ok(())
    }
}
