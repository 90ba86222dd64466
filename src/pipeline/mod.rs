//! The whole solve: mesh, form factors, coarse solve, gather, refine, repeat.

mod coplanar;
mod probe;
mod progress;
mod progressive;
mod settings;
mod skips;
mod solution;
mod split_rows;
mod stats;

pub use coplanar::COPLANAR_GAP;
pub use probe::{ProbeHit, ProbeTolerance, SolutionProbe};
pub use progress::{Progress, Stage};
pub use progressive::{solve_with_previews, Preview};
pub use settings::Settings;
pub use skips::Skips;
pub use solution::{ObjectRadiosity, Solution};
pub use stats::MemoryFigures;
pub use stats::{
    EnergyBalance, HemicubeFigures, PassStats, SkipStats, SolveStats, SourcePassStats, StageSeconds,
};
pub use stats::{CLOSED_ESCAPE, ENERGY_WARNING};

use crate::error::{Error, Result};
use crate::formfactor::{compute_rows_with, Sources};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::refine::{mark_for_split, mark_sources};
use crate::scene::Scene;
use crate::solve::{
    gather_bounces, gather_with, gauss_seidel, gauss_seidel_grey, GatherOptions, GatherTotals,
    PatchSystem, SolveReport, SolverKind,
};
use skips::{RowPlan, RowTally};
use split_rows::{update_rows_for_splits, SplitPatch};
use std::time::Instant;

/// Solves `scene` with `settings`, reporting progress through `progress`.
/// `settings.solver_kind` chooses gathering (Gauss-Seidel) or shooting
/// (progressive refinement; see [`solve_with_previews`] for its previews).
pub fn solve(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Solution> {
    if settings.solver_kind == SolverKind::Progressive {
        return progressive::solve_progressive(scene, settings, progress, None);
    }
    settings.validate()?;
    if scene.surfaces.is_empty() {
        return Err(Error::Geometry(format!(
            "scene '{}' has no surfaces",
            scene.name
        )));
    }
    coplanar::check_coplanar_overlaps(scene)?;
    let started = Instant::now();
    let mut stats = SolveStats::default();
    let patch_size = settings.patch_size_for(scene);
    let refine = &settings.refine;
    let min_area = refine
        .min_element_area
        .unwrap_or_else(|| (scene.diameter() * 1e-3).powi(2));

    let t = Instant::now();
    let mut mesh = Mesh::new(scene, patch_size, settings.max_patches)?;
    let depth0 = refine.uniform_depth.unwrap_or(refine.initial_depth);
    split_uniformly(&mut mesh, depth0, refine.max_elements)?;
    stats.seconds.mesh = t.elapsed().as_secs_f64();

    let mut plan = RowPlan::new(&mesh, settings);
    let mut sources = Sources::from_mesh(&mesh);
    let mut tally = RowTally::default();

    let leaves = mesh.leaves();
    stats.seconds.form_factors +=
        compute_and_store_rows(&mut mesh, &sources, &leaves, &plan, &mut tally, 0, progress);

    let mut system = PatchSystem::from_mesh(&mesh);
    let mut b: Vec<Rgb> = system.emission.clone();
    progress(Progress {
        stage: Stage::Solve,
        done: 0,
        total: 1,
    });
    let (mut report, mut totals) =
        solve_and_gather(&mut mesh, &system, &mut b, settings, &plan, &mut stats)?;
    let mut iterations = report.iterations;
    progress(Progress {
        stage: Stage::Solve,
        done: 1,
        total: 1,
    });

    if let (None, Some(source_tolerance)) = (refine.uniform_depth, refine.source_tolerance) {
        for _ in 0..refine.source_passes {
            let t_pass = Instant::now();
            let mut marks = mark_sources(&mesh, source_tolerance, min_area, refine.max_patch_depth);
            let room = settings.max_patches.saturating_sub(mesh.patches.len()) / 3;
            marks.truncate(room);
            if marks.is_empty() {
                break;
            }
            let mut splits = Vec::with_capacity(marks.len());
            for &p in &marks {
                let polygon = mesh.patches[p as usize].polygon.clone();
                let children = mesh.split_patch(p);
                splits.push(SplitPatch {
                    old: p,
                    polygon,
                    children,
                });
                for id in children {
                    // Give each new patch the initial element depth below it.
                    let top = mesh.elements[mesh.patches[id as usize].root].depth;
                    for k in mesh.patch_leaves(id) {
                        if mesh.elements[k].depth < top + refine.initial_depth {
                            split_to(&mut mesh, k, top + refine.initial_depth);
                        }
                    }
                }
            }
            // Rows refer to patches: their entries for the split patches are
            // derived where they can be, and the rest rendered anew.
            sources = Sources::from_mesh(&mesh);
            plan.patches_changed(&mesh);
            let t = Instant::now();
            let anew = update_rows_for_splits(&mut mesh, &sources, &splits);
            stats.seconds.form_factors += t.elapsed().as_secs_f64();
            stats.seconds.form_factors +=
                compute_and_store_rows(&mut mesh, &sources, &anew, &plan, &mut tally, 0, progress);
            let leaves = mesh.leaves();
            system = PatchSystem::from_mesh(&mesh);
            b = mesh.patches.iter().map(|p| p.radiosity).collect();
            (report, totals) =
                solve_and_gather(&mut mesh, &system, &mut b, settings, &plan, &mut stats)?;
            iterations += report.iterations;
            stats.source_passes.push(SourcePassStats {
                patches_split: marks.len(),
                patches: mesh.patches.len(),
                elements: leaves.len(),
                rows_rendered: anew.len(),
                seconds: t_pass.elapsed().as_secs_f64(),
            });
        }
    }

    if refine.uniform_depth.is_none() {
        for pass in 1..=refine.max_passes {
            let t_pass = Instant::now();
            let room = refine.max_elements.saturating_sub(mesh.leaf_count());
            let marks = mark_for_split(&mesh, refine.tolerance, refine.max_depth, min_area, room);
            if marks.split.is_empty() {
                stats.final_max_difference = marks.max_difference;
                break;
            }
            let mut fresh: Vec<ElementKey> = Vec::new();
            for &k in &marks.split {
                fresh.extend(mesh.split(k));
            }
            for k in mesh.balance(fresh.clone()) {
                fresh.extend(mesh.elements[k].children.iter().copied());
            }
            fresh.retain(|k| mesh.elements[*k].is_leaf());
            let mut touched: Vec<u32> = fresh.iter().map(|k| mesh.elements[*k].patch).collect();
            touched.sort_unstable();
            touched.dedup();

            let hemicubes_before = tally.hemicube.hemicubes;
            stats.seconds.form_factors += compute_and_store_rows(
                &mut mesh, &sources, &fresh, &plan, &mut tally, pass, progress,
            );

            system.refresh(&mesh, &touched);
            stats.skips.patch_rows_refreshed += touched.len();
            (report, totals) =
                solve_and_gather(&mut mesh, &system, &mut b, settings, &plan, &mut stats)?;
            iterations += report.iterations;

            stats.passes.push(PassStats {
                pass,
                split: marks.split.len(),
                elements: mesh.leaf_count(),
                new_hemicubes: (tally.hemicube.hemicubes - hemicubes_before) as usize,
                seconds: t_pass.elapsed().as_secs_f64(),
                max_neighbour_difference: marks.max_difference,
                blocked: marks.blocked,
            });
            stats.final_max_difference = marks.max_difference;
        }
    }

    stats.finish(
        &mesh,
        &system,
        scene,
        settings,
        report,
        iterations,
        totals,
        tally.hemicube,
    );
    stats.skips.add_rows(&tally);
    stats.warn();
    stats.seconds.total = started.elapsed().as_secs_f64();
    Ok(Solution {
        mesh,
        patch_radiosity: b,
        system,
        stats,
    })
}

/// Splits the leaf `key` and its descendants down to `depth`.
fn split_to(mesh: &mut Mesh, key: ElementKey, depth: u8) {
    if mesh.elements[key].depth >= depth {
        return;
    }
    for k in mesh.split(key) {
        split_to(mesh, k, depth);
    }
}

/// Splits every patch to `depth`, failing if that would exceed `max_elements`.
pub(crate) fn split_uniformly(mesh: &mut Mesh, depth: u8, max_elements: usize) -> Result<()> {
    let leaves = mesh.patches.len() as f64 * 4f64.powi(i32::from(depth));
    if leaves > max_elements as f64 {
        return Err(Error::Limit(format!(
            "{} patches split to depth {depth} give {leaves} elements, more than the \
             element budget of {max_elements}",
            mesh.patches.len()
        )));
    }
    for _ in 0..depth {
        for k in mesh.leaves() {
            mesh.split(k);
        }
    }
    Ok(())
}

/// Gauss-Seidel on the patch system from the current `b`, then the gather
/// (both on one band in a grey scene); with `settings.bounces`, a fixed number
/// of reflections from the emission instead (no warm start). Adds the seconds
/// to the stats.
fn solve_and_gather(
    mesh: &mut Mesh,
    system: &PatchSystem,
    b: &mut [Rgb],
    settings: &Settings,
    plan: &RowPlan,
    stats: &mut SolveStats,
) -> Result<(SolveReport, GatherTotals)> {
    let t = Instant::now();
    let options = GatherOptions {
        grey: plan.grey,
        rowless: plan.rowless_patch.as_deref(),
        balance: Some(&system.balance),
    };
    if let Some(n) = settings.bounces {
        let (report, totals) = gather_bounces(mesh, system, b, n, &options)?;
        stats.seconds.solve += t.elapsed().as_secs_f64();
        return Ok((report, totals));
    }
    let report = if plan.grey {
        stats.skips.grey_solves += 1;
        gauss_seidel_grey(system, b, &settings.solver)?
    } else {
        gauss_seidel(system, b, &settings.solver)?
    };
    let totals = gather_with(mesh, b, &options);
    stats.seconds.solve += t.elapsed().as_secs_f64();
    Ok((report, totals))
}

/// Computes and stores the rows of those `keys` that need one (`plan`);
/// returns the seconds it took.
fn compute_and_store_rows(
    mesh: &mut Mesh,
    sources: &Sources,
    keys: &[ElementKey],
    plan: &RowPlan,
    tally: &mut RowTally,
    pass: usize,
    progress: &(dyn Fn(Progress) + Sync),
) -> f64 {
    let started = Instant::now();
    let (keys, left_out) = plan.needing_rows(mesh, keys);
    tally.zero_reflectance_rows += left_out as u64;
    let keys = &keys[..];
    let total = keys.len();
    let report = |done| {
        progress(Progress {
            stage: Stage::FormFactors { pass },
            done,
            total,
        });
    };
    report(0);
    let (rows, s) = compute_rows_with(mesh, sources, keys, &plan.settings, &plan.skips, &report);
    for (k, row) in keys.iter().zip(rows) {
        mesh.elements[*k].row = row;
    }
    tally.hemicube.add(&s);
    started.elapsed().as_secs_f64()
}
