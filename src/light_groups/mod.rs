//! Light groups: one refined mesh, one solution per group of sources.
//!
//! Radiosity is linear in emission. So the mesh is refined once, for every
//! light on, and then each group of sources (by default each emissive
//! material and each punctual light; see [`LightGroups`]) is solved on its
//! own on that mesh with its rows: the patch system for its emission and the
//! reflected direct light of its punctual lights, then the gather (see
//! `solve.rs` for which steps are linear). The solution's radiosity is the
//! groups' sum, and a mix `sum s_k B_k` stands for the scene with each
//! group's emission scaled by `s_k` ([`LightGroups::scaled_scene`]): what a
//! viewer's sliders show without solving again. Without shaped gathers
//! (`Settings::shaped_gathers` of 0) both are exact to the groups' solver
//! tolerance ([`GROUP_TOLERANCE`]); a shaped gather's ratios are not linear in
//! emission, and each group is shaped by its own light, so that a mix differs
//! from a new solve by a small part of what shaping changes (measured in
//! `papers/light-groups.md`).
//!
//! ```
//! use radiosity::light_groups::{solve_with_light_groups, LightGroups};
//! # fn main() -> radiosity::Result<()> {
//! let scene = radiosity::scenes::cornell_box();
//! let groups = LightGroups::each(&scene);
//! let mut solution = solve_with_light_groups(&scene, &Default::default(), &groups, &|_| {})?;
//! let lamp = solution.with_group(0, |s| s.object_radiosity(&scene));
//! # assert!(!lamp.is_empty());
//! # Ok(())
//! # }
//! ```

mod solve;

pub use crate::scene::light_groups::{GroupPattern, GroupRule, LightGroup, LightGroups};
pub use solve::GROUP_TOLERANCE;

use crate::error::{Error, Result};
use crate::pipeline::{solve_keeping_shapes, Progress, Settings};
use crate::pipeline::{SolverKind, DEFAULT_UNSHOT_TOLERANCE};
use crate::scene::Scene;
use crate::solution::Solution;

/// Solves `scene` with `settings` (the mesh refined for every light on),
/// then each of `groups` on the refined mesh: the solution's radiosity is
/// their sum, and [`Solution::with_group`] shows one group alone.
///
/// # Errors
///
/// [`Error::Setting`] (named `light_groups`) for a progressive solve that
/// may stop before it converges (a shot limit, a time budget, or an unshot
/// tolerance above [`DEFAULT_UNSHOT_TOLERANCE`]): each group is solved to
/// convergence on the refined mesh, so their sum would not be the solve it
/// stands for; and when `groups` do not partition the scene's sources (see
/// [`LightGroups::validate`]); any error of the solve.
pub fn solve_with_light_groups(
    scene: &Scene,
    settings: &Settings,
    groups: &LightGroups,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Solution> {
    let p = &settings.progressive;
    if settings.solver_kind == SolverKind::Progressive
        && (p.max_shots.is_some()
            || p.time_budget.is_some()
            || p.tolerance > DEFAULT_UNSHOT_TOLERANCE)
    {
        return Err(Error::Setting {
            name: "light_groups",
            message: format!(
                "light groups solve each group to convergence on the refined mesh, so the \
                 progressive solve they split must converge too: no shot limit or time \
                 budget, and an unshot tolerance of at most {DEFAULT_UNSHOT_TOLERANCE:e}"
            ),
        });
    }
    groups.validate(scene)?;
    let mut solution = solve_keeping_shapes(scene, settings, progress)?;
    solve::solve_groups(scene, settings, groups, &mut solution, progress)?;
    Ok(solution)
}
