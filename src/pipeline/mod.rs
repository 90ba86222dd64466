//! The whole solve: mesh, form factors, coarse solve, gather, refine, repeat.
//!
//! One driver runs both solvers: `Workspace::prepare` checks
//! the settings and the scene and cuts the mesh; the chosen solver (gathering
//! or shooting) produces a first solution; then, while the mesh adapts, the
//! driver marks and splits the leaves that differ from their neighbours and
//! the solver brings its solution up to the new mesh.

mod fill_stats;
mod gathering;
mod light_checks;
mod memory;
mod progress;
mod progressive;
mod row_groups;
mod scale;
mod settings;
mod skips;
mod strategy;
mod workspace;

pub use crate::solve::SolverSettings;
pub(crate) use gathering::weighted_patch_means;
pub use progress::{Progress, Stage};
pub use progressive::{Preview, ProgressiveSettings, SolverKind, DEFAULT_UNSHOT_TOLERANCE};
pub(crate) use scale::times_pow2;
pub use settings::{Settings, DEFAULT_MAX_MEMORY, DEFAULT_SHAPED_GATHERS, MAX_SHAPED_GATHERS};
pub use skips::Skips;
// The figures of a solve belong to the solution; kept here too, where
// they were first published.
pub use crate::solution::{
    DirectFigures, EnergyBalance, HemicubeFigures, MemoryFigures, PassStats, SkipStats, SolveStats,
    SourcePassStats, StageSeconds,
};

use crate::error::Result;
use crate::scene::Scene;
use crate::solution::Solution;
use gathering::Gathering;
use progressive::Shooting;
use std::time::Instant;
use strategy::{Next, Solver};
use workspace::Workspace;

/// Solves `scene` with `settings`, reporting progress through `progress`.
/// `settings.solver_kind` chooses gathering (Gauss-Seidel) or shooting
/// (progressive refinement; see [`solve_with_previews`] for its previews).
pub fn solve(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Solution> {
    solve_with_previews(scene, settings, progress, &mut |_| {})
}

/// Solves `scene` like [`solve`], and with the progressive solver also hands
/// a [`Preview`] to `preview` every `settings.progressive.preview_every`
/// shots. (Gauss-Seidel has no previews.)
pub fn solve_with_previews(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
    preview: &mut dyn FnMut(&Preview<'_>),
) -> Result<Solution> {
    let mut ws = Workspace::prepare(scene, settings, progress)?;
    match settings.solver_kind {
        SolverKind::GaussSeidel => match Gathering::start(&mut ws) {
            Ok(solver) => drive(ws, solver),
            Err(e) => Err(ws.explain(e)),
        },
        SolverKind::Progressive => match Shooting::start(&mut ws, Some(preview)) {
            Ok(solver) => drive(ws, solver),
            Err(e) => Err(ws.explain(e)),
        },
    }
}

/// Solves `scene` like [`solve`], keeping the last shaped gather's factors
/// in the solution for its light groups (see [`crate::light_groups`]). The
/// progressive solver's shaped gathers are the gathering solver's, made
/// once the shots have converged.
pub(crate) fn solve_keeping_shapes(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Solution> {
    let mut ws = Workspace::prepare(scene, settings, progress)?;
    match settings.solver_kind {
        SolverKind::GaussSeidel => match Gathering::start(&mut ws) {
            Ok(mut solver) => {
                solver.keep_shapes = true;
                drive(ws, solver)
            }
            Err(e) => Err(ws.explain(e)),
        },
        SolverKind::Progressive => match Shooting::start(&mut ws, None) {
            Ok(mut solver) => {
                solver.keep_shapes = true;
                drive(ws, solver)
            }
            Err(e) => Err(ws.explain(e)),
        },
    }
}

/// Runs `solver` to the end: refinement passes whenever it asks for one.
fn drive(mut ws: Workspace<'_>, mut solver: impl Solver) -> Result<Solution> {
    loop {
        match solver.advance(&mut ws) {
            Ok(Next::Refine) => {}
            Ok(_) => break,
            // A light whose irradiance overflows makes the solver diverge:
            // name the light instead.
            Err(e) => return Err(ws.explain(e)),
        }
        let t_pass = Instant::now();
        let marks = ws.mark();
        let unshared = ws.unshare_groups();
        if marks.split.is_empty() && unshared.is_empty() {
            solver.nothing_to_refine(&mut ws)?;
            continue;
        }
        let pass = ws.stats.passes.len() + 1;
        let mut fresh = ws.split_marked(&marks);
        // A member split just now has its children among the fresh leaves.
        fresh.extend(
            unshared
                .into_iter()
                .filter(|&k| ws.mesh.elements[k].is_leaf()),
        );
        let new_hemicubes = match solver.refined(&mut ws, &fresh, pass) {
            Ok(n) => n,
            Err(e) => return Err(ws.explain(e)),
        };
        ws.stats.passes.push(PassStats {
            pass,
            split: marks.split.len(),
            facing: marks.facing,
            elements: ws.mesh.leaf_count(),
            new_hemicubes,
            seconds: t_pass.elapsed().as_secs_f64(),
            max_neighbour_difference: marks.max_difference,
            blocked: marks.blocked,
        });
    }
    let candidates = std::mem::take(&mut ws.dark_candidates);
    ws.warn_dark_lights(&candidates);
    Ok(solver.finish(ws))
}
