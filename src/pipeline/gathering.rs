//! The gathering solver: every leaf's row, Gauss-Seidel on the patch system,
//! one gather per element; after each refinement pass, rows for the new
//! leaves only and a warm re-solve.

use super::strategy::{Next, Solver};
use super::workspace::Workspace;
use super::{Progress, SourcePassStats, Stage};
use crate::error::Result;
use crate::formfactor::{
    update_rows_for_splits, FormFactors, RowScene, RowState, Sources, SplitPatch,
};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::refine::mark_sources;
use crate::solution::Solution;
use crate::solve::source_shape::{PartViews, SourceShapes};
use crate::solve::{
    gather_bounces, gather_with, gauss_seidel, gauss_seidel_grey, gauss_seidel_with_source,
    shaped_factors, shaped_weights, GatherOptions, GatherTotals, KeptShapes, PatchSystem,
    SolveReport,
};
use crate::solve::{scene_is_closed, weight, Radiosity};
use std::time::Instant;

/// Most corrections of the patch radiosities after a shaped gather (see
/// `Gathering::shaped_gather`), each taking the ratios again. Measured
/// before the ratios were taken again: the Cornell box settled after one,
/// the atriums after two, the Ferren sculpture used all three. Since, the
/// 10 000-triangle atrium, the Ferren sculpture and the Blender Cornell box
/// use all three and the Cornell box two (see [`LEVEL_TOLERANCE`]); the low box's
/// gap side in `examples/gap_between_boxes.rs` comes out +3.08% with three
/// and +2.97% with four, where four shaped gathers of the kind before gave
/// +2.96%.
const LEVEL_CORRECTIONS: usize = 3;

/// The corrections after a shaped gather stop when what the shapes change
/// in any patch's mean moves, from one correction to the next, by no more
/// than this fraction of the largest patch radiosity, and no leaf's
/// radiosity moves by more than that between one shaped gather and the
/// next. A correction also takes the ratios again (see
/// `SourceShapes::refresh`), so the second test is what says the ratios
/// have settled. Until 2026-12-04 the ratios were asked instead: no factor
/// on a patch radiosity changing by more than 1e-3. That maximum is set by
/// a few receivers whose factors move far while what they gather hardly
/// does: on the Cornell box it was still 0.20 after the second correction,
/// when no leaf moved by more than 2.1e-5 of the largest radiosity, so
/// every solve made all three corrections.
const LEVEL_TOLERANCE: f64 = 1e-4;

/// Per patch, the mean of `radiosity` over its leaves weighted as its row
/// weighs them (see `crate::solve::PatchSystem`), or their area mean when they
/// weigh nothing. (Light groups correct their shaped gathers with it too.)
pub(crate) fn weighted_patch_means(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    leaves: &[ElementKey],
    closed: bool,
) -> Vec<Rgb> {
    let n = mesh.patches.len();
    let (mut weighted, mut by_area) = (vec![(0.0, Rgb::ZERO); n], vec![(0.0, Rgb::ZERO); n]);
    for &k in leaves {
        let e = &mesh.elements[k];
        let b = radiosity.element(k);
        let w = weight(mesh, form_factors, k, closed);
        let p = e.patch as usize;
        weighted[p].0 += w;
        weighted[p].1 += b * w;
        by_area[p].0 += e.area;
        by_area[p].1 += b * e.area;
    }
    weighted
        .iter()
        .zip(&by_area)
        .map(|(&(w, wb), &(a, ab))| {
            if w > 0.0 {
                wb * (1.0 / w)
            } else if a > 0.0 {
                ab * (1.0 / a)
            } else {
                Rgb::ZERO
            }
        })
        .collect()
}

/// Gauss-Seidel on the patch system, then the gather.
pub(crate) struct Gathering {
    system: PatchSystem,
    /// Patch radiosities.
    b: Vec<Rgb>,
    report: SolveReport,
    totals: GatherTotals,
    /// Sweeps over all solves.
    iterations: usize,
    /// A refinement pass found nothing more to split.
    settled: bool,
    /// Keep the last shaped gather's factors in the solution (for light
    /// groups, which gather with them; see `crate::light_groups`).
    pub(super) keep_shapes: bool,
    kept: Option<KeptShapes>,
}

impl Gathering {
    /// The first solution on the initial mesh of `ws`: every leaf's row, the
    /// patch system solved and gathered, then source splitting if asked for.
    pub(super) fn start(ws: &mut Workspace<'_>) -> Result<Self> {
        let leaves = ws.mesh.leaves();
        ws.compute_rows(&leaves, 0);
        let system = assemble(ws);
        let mut gathering = Gathering {
            b: system.emission.clone(),
            system,
            report: SolveReport::default(),
            totals: GatherTotals::default(),
            iterations: 0,
            settled: false,
            keep_shapes: false,
            kept: None,
        };
        let progress = ws.progress;
        let report = |done| {
            progress(Progress {
                stage: Stage::Solve,
                done,
                total: 1,
            });
        };
        report(0);
        gathering.solve_and_gather(ws)?;
        report(1);
        let refine = &ws.settings.refine;
        if let (None, Some(tolerance)) = (refine.uniform_depth, refine.source_tolerance) {
            for _ in 0..refine.source_passes {
                if !gathering.split_sources(ws, tolerance)? {
                    break;
                }
            }
        }
        Ok(gathering)
    }

    /// Takes over another solver's converged solution (the progressive
    /// solver's, whose shots leave every patch gathered by its mean) on the
    /// current mesh of `ws`, from its patch radiosities `b`: the leaves
    /// without a row in the store render one, the patch system is assembled,
    /// solved from `b` (a few sweeps: `b` solves nearly the same system) and
    /// gathered. Its [`Solver::finish`] then makes the shaped gathers.
    pub(super) fn take_over(ws: &mut Workspace<'_>, b: Vec<Rgb>) -> Result<Self> {
        let missing: Vec<ElementKey> = ws
            .mesh
            .leaves()
            .into_iter()
            .filter(|&k| matches!(ws.form_factors.state(k), RowState::Pending))
            .collect();
        let pass = ws.stats.passes.len() + 1;
        ws.compute_rows(&missing, pass);
        let system = assemble(ws);
        let mut gathering = Gathering {
            b,
            system,
            report: SolveReport::default(),
            totals: GatherTotals::default(),
            iterations: 0,
            settled: true,
            keep_shapes: false,
            kept: None,
        };
        gathering.solve_and_gather(ws)?;
        Ok(gathering)
    }
}

impl Solver for Gathering {
    fn advance(&mut self, ws: &mut Workspace<'_>) -> Result<Next> {
        Ok(if !self.settled && ws.may_refine() {
            Next::Refine
        } else {
            Next::Stop
        })
    }

    fn refined(
        &mut self,
        ws: &mut Workspace<'_>,
        fresh: &[ElementKey],
        pass: usize,
    ) -> Result<usize> {
        let mut touched: Vec<u32> = fresh.iter().map(|k| ws.mesh.elements[*k].patch).collect();
        touched.sort_unstable();
        touched.dedup();
        let before = ws.tally.hemicube.hemicubes;
        ws.compute_rows(fresh, pass);
        self.system.refresh(&ws.mesh, &ws.form_factors, &touched);
        if let Some(direct) = &ws.direct {
            direct.add_to_system(&mut self.system, &ws.mesh, &ws.form_factors);
        }
        ws.stats.skips.patch_rows_refreshed += touched.len();
        self.solve_and_gather(ws)?;
        Ok((ws.tally.hemicube.hemicubes - before) as usize)
    }

    fn nothing_to_refine(&mut self, _ws: &mut Workspace<'_>) -> Result<()> {
        self.settled = true;
        Ok(())
    }

    fn finish(mut self, mut ws: Workspace<'_>) -> Solution {
        if ws.settings.bounces.is_none() && ws.settings.shaped_gather_count() > 0 {
            let mut shaped = false;
            for _ in 0..ws.settings.shaped_gather_count() {
                shaped |= self.shaped_gather(&mut ws);
            }
            if shaped {
                // The elements no longer average to the solved patch
                // radiosities: each patch's radiosity becomes its elements'
                // area mean again.
                for p in 0..ws.mesh.patches.len() {
                    self.b[p] = ws.radiosity.patch_mean(&ws.mesh, &ws.mesh.patches[p]);
                }
                ws.radiosity.set_patches(&self.b);
            }
        }
        ws.finish_stats(&self.system, self.report, self.iterations, self.totals);
        ws.stats.warn();
        let mut solution = ws.into_solution(self.system);
        solution.light_groups.kept_shapes = self.kept.map(std::sync::Arc::new);
        solution
    }
}

impl Gathering {
    /// Gauss-Seidel on the patch system from the current radiosities, then
    /// the gather (both on one band in a grey scene); with
    /// `Settings::bounces`, a fixed number of reflections from the emission
    /// instead (no warm start).
    fn solve_and_gather(&mut self, ws: &mut Workspace<'_>) -> Result<()> {
        let t = Instant::now();
        let plan = &ws.plan;
        let options = GatherOptions {
            grey: plan.grey,
            rowless: plan.rowless_patch.as_deref(),
            balance: Some(&self.system.balance),
            direct: ws.direct.as_ref(),
            factors: None,
        };
        let (report, totals) = if let Some(n) = ws.settings.bounces {
            gather_bounces(
                &ws.mesh,
                &ws.form_factors,
                &mut ws.radiosity,
                &self.system,
                &mut self.b,
                n,
                &options,
            )?
        } else {
            let report = if plan.grey {
                ws.stats.skips.grey_solves += 1;
                gauss_seidel_grey(&self.system, &mut self.b, &ws.settings.solver)?
            } else {
                gauss_seidel(&self.system, &mut self.b, &ws.settings.solver)?
            };
            let totals = gather_with(
                &ws.mesh,
                &ws.form_factors,
                &mut ws.radiosity,
                &self.b,
                &options,
            );
            (report, totals)
        };
        self.iterations += report.iterations;
        self.report = report;
        self.totals = totals;
        ws.stats.seconds.solve += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// One gather from the solved patch radiosities in which near receivers
    /// see unevenly lit patches by their parts, as the last gather left them
    /// (see [`crate::solve::source_shape`]). The patch system stays as
    /// solved; each patch's receivers together gather from it what it sends
    /// them (its mean's total in a closed scene).
    /// Returns false, gathering nothing, when every patch is even.
    fn shaped_gather(&mut self, ws: &mut Workspace<'_>) -> bool {
        let t = Instant::now();
        let leaves = ws.mesh.leaves();
        let closed = scene_is_closed(&ws.mesh, &ws.form_factors, &leaves);
        let mut shapes = SourceShapes::new(&ws.mesh, &ws.form_factors, &ws.radiosity, closed);
        ws.stats.shaped_sources.push(shapes.len());
        if shapes.len() == 0 {
            // The gather would repeat the last one.
            ws.stats.shaped_corrections.push(0);
            ws.stats.shaped_views.push(0);
            return false;
        }
        let plan = &ws.plan;
        let options = GatherOptions {
            grey: plan.grey,
            rowless: plan.rowless_patch.as_deref(),
            balance: Some(&self.system.balance),
            direct: ws.direct.as_ref(),
            factors: None,
        };
        let scene = || RowScene::new(&ws.mesh, &ws.sources, &ws.plan.settings, &ws.plan.skips);
        let progress = ws.progress;
        let report = |done, total| {
            progress(Progress {
                stage: Stage::PartViews,
                done,
                total,
            });
        };
        let views = PartViews {
            scene: &scene,
            progress: &report,
        };
        let views = ws.settings.uses_part_views().then_some(&views);
        let Some(near) = shaped_weights(&ws.mesh, &ws.form_factors, &shapes, views) else {
            // No patch is shaped (not reached: `shapes` is not empty).
            ws.stats.shaped_corrections.push(0);
            ws.stats.shaped_views.push(0);
            return false;
        };
        ws.stats.shaped_views.push(near.views());
        let mut factors = shaped_factors(&ws.mesh, &ws.form_factors, &shapes, &options, &near);
        self.totals = gather_with(
            &ws.mesh,
            &ws.form_factors,
            &mut ws.radiosity,
            &self.b,
            &GatherOptions {
                factors: Some(&factors),
                ..options
            },
        );
        // The shaped gather moves light between receivers that reflect
        // differently, so its elements no longer average to a solution of
        // the patch system, and the light they pass on no longer balances
        // what they receive. The patch radiosities are corrected for what
        // the shapes change: each patch's mean over its elements, weighted
        // as its row weighs them, less the same mean after a plain gather
        // from the same radiosities. The system is solved again with that
        // change as extra emission, from the last radiosities, and gathered
        // again, until the change stays put. The ratios came from the parts'
        // values of the gather before the shaped one, in which the dark side
        // of a patch near its receivers was lit by the means of the patches
        // it sees; each correction also takes them again from what the last
        // gather left (with the same weights), passing one more bounce of
        // the detail between near patches, until they stay put too.
        let plain_options = GatherOptions {
            factors: None,
            ..options
        };
        let mut corrections = 0;
        let mut last: Option<Vec<Rgb>> = None;
        let leaf_values = |ws: &Workspace<'_>| -> Vec<Rgb> {
            leaves.iter().map(|&k| ws.radiosity.element(k)).collect()
        };
        let mut gathered = leaf_values(ws);
        let mut leaves_moved = f64::INFINITY;
        while corrections < LEVEL_CORRECTIONS {
            let mut plain = ws.radiosity.clone();
            gather_with(
                &ws.mesh,
                &ws.form_factors,
                &mut plain,
                &self.b,
                &plain_options,
            );
            let (mesh, ff) = (&ws.mesh, &ws.form_factors);
            let shaped = weighted_patch_means(mesh, ff, &ws.radiosity, &leaves, closed);
            let means = weighted_patch_means(mesh, ff, &plain, &leaves, closed);
            let change: Vec<Rgb> = shaped.iter().zip(&means).map(|(s, m)| *s - *m).collect();
            let largest = self.b.iter().map(|x| x.max_band()).fold(0.0, f64::max);
            let moved = last.as_ref().map_or(f64::INFINITY, |last| {
                change
                    .iter()
                    .zip(last)
                    .map(|(c, l)| (*c - *l).abs().max_band())
                    .fold(0.0, f64::max)
            });
            if moved.max(leaves_moved) <= LEVEL_TOLERANCE * largest {
                break;
            }
            let source: Vec<Rgb> = self
                .system
                .emission
                .iter()
                .zip(&change)
                .map(|(e, c)| *e + *c)
                .collect();
            last = Some(change);
            let before = self.b.clone();
            match gauss_seidel_with_source(&self.system, &source, &mut self.b, &ws.settings.solver)
            {
                Ok(report) => self.iterations += report.iterations,
                Err(e) => {
                    self.b = before;
                    ws.stats.warnings.push(format!(
                        "the patch radiosities were not corrected after a shaped gather ({e}); \
                         its light may not balance"
                    ));
                    break;
                }
            }
            corrections += 1;
            shapes.refresh(&ws.mesh, &ws.form_factors, &ws.radiosity, closed);
            // The last factors go before the next are taken: held together
            // they were the peak of a large scene's memory.
            drop(std::mem::take(&mut factors));
            factors = shaped_factors(&ws.mesh, &ws.form_factors, &shapes, &options, &near);
            self.totals = gather_with(
                &ws.mesh,
                &ws.form_factors,
                &mut ws.radiosity,
                &self.b,
                &GatherOptions {
                    factors: Some(&factors),
                    ..options
                },
            );
            let now = leaf_values(ws);
            leaves_moved = now
                .iter()
                .zip(&gathered)
                .map(|(a, b)| (*a - *b).abs().max_band())
                .fold(0.0, f64::max);
            gathered = now;
        }
        ws.stats.shaped_corrections.push(corrections);
        ws.stats.seconds.solve += t.elapsed().as_secs_f64();
        if self.keep_shapes {
            self.kept = Some(KeptShapes {
                shapes,
                near,
                corrections,
            });
        }
        true
    }

    /// One round of source-patch splitting: patches whose own elements
    /// differ widely become four patches, rows are brought up to date (most
    /// derived, the rest rendered anew) and the system solved again. Returns
    /// false when no patch was split.
    fn split_sources(&mut self, ws: &mut Workspace<'_>, tolerance: f64) -> Result<bool> {
        let t_pass = Instant::now();
        let refine = &ws.settings.refine;
        let mut marks = mark_sources(
            &ws.mesh,
            &ws.form_factors,
            &ws.radiosity,
            tolerance,
            ws.min_area,
            refine.max_patch_depth,
        );
        let room = ws
            .settings
            .max_patches
            .saturating_sub(ws.mesh.patches.len())
            / 3;
        marks.truncate(room);
        if marks.is_empty() {
            return Ok(false);
        }
        let mut splits = Vec::with_capacity(marks.len());
        for &p in &marks {
            let polygon = ws.mesh.patches[p as usize].polygon.clone();
            // The patch's root, if a leaf, splits first.
            let root = ws.mesh.patches[p as usize].roots[0];
            let root_was_leaf = ws.mesh.elements[root].is_leaf();
            let children = ws.mesh.split_patch(p);
            if root_was_leaf {
                let kids = ws.mesh.elements[root].children.clone();
                ws.split_done(root, &kids);
            }
            splits.push(SplitPatch {
                old: p,
                polygon,
                children,
            });
            for id in children {
                // Give each new patch the initial element depth below it.
                let top = ws.mesh.elements[ws.mesh.patches[id as usize].roots[0]].depth;
                for k in ws.mesh.patch_leaves(id) {
                    if ws.mesh.elements[k].depth < top + refine.initial_depth {
                        ws.split_to(k, top + refine.initial_depth);
                    }
                }
            }
        }
        // Rows refer to patches: their entries for the split patches are
        // derived where they can be, and the rest rendered anew.
        ws.sources = Sources::from_mesh(&ws.mesh);
        ws.plan.patches_changed(&ws.mesh);
        ws.update_direct();
        let t = Instant::now();
        let anew = update_rows_for_splits(&ws.mesh, &mut ws.form_factors, &ws.sources, &splits);
        ws.stats.seconds.form_factors += t.elapsed().as_secs_f64();
        ws.compute_rows(&anew, 0);
        self.system = assemble(ws);
        // The four patches of a split one start from their roots'
        // radiosities, the others from the last solve.
        self.b.resize(ws.mesh.patches.len(), Rgb::ZERO);
        for split in &splits {
            for id in split.children {
                let root = ws.mesh.patches[id as usize].roots[0];
                self.b[id as usize] = ws.radiosity.element(root);
            }
        }
        self.solve_and_gather(ws)?;
        ws.stats.source_passes.push(SourcePassStats {
            patches_split: marks.len(),
            patches: ws.mesh.patches.len(),
            elements: ws.mesh.leaf_count(),
            rows_rendered: anew.len(),
            seconds: t_pass.elapsed().as_secs_f64(),
        });
        Ok(true)
    }
}

/// The patch system of the leaves' rows, with the reflected light of the
/// punctual lights, if any, as emission.
fn assemble(ws: &Workspace<'_>) -> PatchSystem {
    let mut system = PatchSystem::from_mesh(&ws.mesh, &ws.form_factors);
    if let Some(direct) = &ws.direct {
        direct.add_to_system(&mut system, &ws.mesh, &ws.form_factors);
    }
    system
}
