//! The shooting solver (progressive refinement) as the driver runs it: shots
//! until a stopping rule is met, refinement passes when the unshot power has
//! fallen far enough, previews handed to the caller.

mod preview;

pub use preview::Preview;

use super::strategy::{Next, Solver};
use super::workspace::Workspace;
use super::{Progress, Stage};
use crate::error::Result;
use crate::formfactor::compute_rows;
use crate::math::Rgb;
use crate::mesh::ElementKey;
use crate::solution::Solution;
use crate::solve::balance::{balance, Receiver as BalanceReceiver};
use crate::solve::progressive::{
    adopt, ambient_term, regather, settle, HistoryPoint, ProgressiveStats, Receivers, Shooter,
    ShootingPass, ShootingState, ShotCache, StopReason, Stopping,
};
use crate::solve::{
    dark_patches, refuse_unbounded_row, scene_is_closed, GatherTotals, PatchSystem, SolveReport,
    MAX_CONTRACTION,
};
use std::time::Instant;

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
    /// The stopping rule that asked for one more refinement pass.
    final_pass: Option<StopReason>,
    /// Whether the refinement pass just run split anything (`None` until
    /// the next pass).
    last_pass_split: Option<bool>,
    stop: StopReason,
}

impl Solver for Shooting<'_> {
    fn advance(&mut self, ws: &mut Workspace<'_>) -> Result<Next> {
        if let Some(split) = self.last_pass_split.take() {
            if let Some(reason) = self.final_pass.take() {
                if !split {
                    return Ok(self.stop_for(reason));
                }
            }
            self.shooter.forget_cells();
            self.fraction = self.unshot_fraction();
            self.last_pass_fraction = self.fraction;
        }
        let ps = &ws.settings.progressive;
        loop {
            if let Some(reason) = Stopping::new(ps, ws.started).check(self.shots, self.fraction) {
                // Converged on the current mesh: refine once more if allowed,
                // and shoot on if that changed anything.
                if reason == StopReason::Converged
                    && ws.may_refine()
                    && self.state.emitted_power() > 0.0
                {
                    self.final_pass = Some(reason);
                    return Ok(Next::Refine);
                }
                return Ok(self.stop_for(reason));
            }
            let refining = ws.may_refine();
            if !self.rows_tried
                && !refining
                && self.fraction <= ps.refine_factor * self.initial_fraction
            {
                // No refinement pass to gather the rows at.
                self.gather_rows(ws, 0);
                self.shooter.forget_cells();
                self.fraction = self.unshot_fraction();
                continue;
            }
            if refining && self.fraction <= ps.refine_factor * self.last_pass_fraction {
                return Ok(Next::Refine);
            }
            let Some(shooter_patch) = self.state.choose_shooter() else {
                return Ok(self.stop_for(StopReason::Converged));
            };
            self.shoot(ws, shooter_patch);
            self.fraction = self.unshot_fraction();
            self.report_shot(ws);
            if self.shots == 1 || self.fraction <= self.next_history {
                self.record_history(ws);
                self.next_history = self.fraction * 10f64.powf(-0.25);
            }
            self.show_preview(ws);
        }
    }

    fn refined(
        &mut self,
        ws: &mut Workspace<'_>,
        fresh: &[ElementKey],
        pass: usize,
    ) -> Result<usize> {
        self.receivers = Receivers::new(&ws.mesh);
        self.state.set_direct(ws.direct.as_ref());
        let (change, new_hemicubes) = if self.rows_tried {
            ws.compute_rows(fresh, pass);
            self.cache.refine(&ws.mesh, &ws.form_factors, fresh);
            self.note_closed(ws);
            let kept = self.figures.rows_gathered_after_shots.is_some();
            self.balanced = kept && self.closed;
            let change = if kept {
                // New rows change the balance of every row: every leaf
                // gathers what was shot again, by the rows.
                self.rebalance(ws);
                let change = self.expose(ws)
                    + regather(
                        &ws.mesh,
                        &mut ws.radiosity,
                        &mut self.state,
                        &self.receivers,
                        &self.cache,
                    );
                self.settle(ws);
                change
            } else {
                // The new leaves gather what was shot as it was shot.
                self.expose(ws)
                    + adopt(
                        &ws.mesh,
                        &mut ws.radiosity,
                        &mut self.state,
                        &ws.form_factors,
                        fresh,
                    )
            };
            for &k in fresh {
                ws.form_factors.release(k);
            }
            (change, fresh.len())
        } else {
            self.gather_rows(ws, pass)
        };
        let emitted = self.state.emitted_power();
        self.figures.passes.push(ShootingPass {
            pass,
            after_shots: self.shots,
            unshot_fraction: self.fraction,
            unshot_change: change.0.iter().sum::<f64>() / emitted,
        });
        self.last_pass_split = Some(true);
        Ok(new_hemicubes)
    }

    fn nothing_to_refine(&mut self, ws: &mut Workspace<'_>) -> Result<()> {
        if !self.rows_tried {
            self.gather_rows(ws, ws.stats.passes.len() + 1);
        }
        self.last_pass_split = Some(false);
        Ok(())
    }

    fn finish(mut self, mut ws: Workspace<'_>) -> Solution {
        if self.figures.history.last().map(|h| h.shots) != Some(self.shots) {
            self.record_history(&ws);
        }
        let mesh = &ws.mesh;
        let patch_radiosity: Vec<Rgb> = mesh
            .patches
            .iter()
            .map(|p| ws.radiosity.patch_mean(mesh, p))
            .collect();
        ws.radiosity.set_patches(&patch_radiosity);
        let mut emitted = Rgb::ZERO;
        for k in mesh.leaves() {
            let e = &mesh.elements[k];
            emitted += e.emission * e.area;
        }
        if let Some(direct) = &ws.direct {
            // What punctual lights deliver counts as emitted into the scene.
            emitted += direct.incident_power(mesh);
        }
        let mut totals = GatherTotals {
            emitted,
            absorbed: self.state.absorbed_power(mesh),
            ..GatherTotals::default()
        };
        for k in mesh.leaves() {
            if let Some(view) = ws.form_factors.view(k) {
                totals.add_hidden(mesh.elements[k].area, ws.radiosity.element(k), view);
            }
        }
        // The shots' factors live in the shot cache, not in the store: the
        // system holds reflectance and emission with empty rows.
        let system = PatchSystem::from_mesh(mesh, &ws.form_factors);
        let report = SolveReport {
            iterations: self.shots,
            residual: self.state.residual(),
            error_bound: 0.0,
            contraction: 0.0,
            extrapolations: 0,
        };
        ws.finish_stats(&system, report, self.shots, totals);
        let f = &mut self.figures;
        f.shots = self.shots;
        f.stop = self.stop;
        f.unshot_fraction = self.fraction;
        f.ambient = ambient_term(&ws.mesh, &self.state.unshot, &self.state.exposure);
        f.mean_implied_row_sum = if self.shots > 0 {
            self.row_sum_total / self.shots as f64
        } else {
            0.0
        };
        ws.stats.hemicube.mean_row_sum = f.mean_implied_row_sum;
        ws.stats.hemicube.max_row_sum = f.max_implied_row_sum;
        ws.stats.energy.truncated |= self.stop != StopReason::Converged;
        ws.stats.warn();
        ws.stats.progressive = Some(std::mem::take(f));
        ws.stats.seconds.total = ws.started.elapsed().as_secs_f64();
        ws.into_solution(system)
    }
}

impl<'p> Shooting<'p> {
    /// Starts shooting on the initial mesh of `ws`, handing previews to
    /// `preview` if given.
    pub(super) fn start(
        ws: &mut Workspace<'_>,
        preview: Option<PreviewCallback<'p>>,
    ) -> Result<Self> {
        let settings = ws.settings;
        let ps = &settings.progressive;
        refuse_unbounded(ws)?;
        let mut state = ShootingState::new(&ws.mesh, ws.direct.as_ref());
        let receivers = Receivers::new(&ws.mesh);
        state.expose(&ws.mesh, &ws.radiosity, &receivers);
        let fraction = state.unshot_fraction();
        Ok(Shooting {
            preview,
            cache: ShotCache::new(ws.mesh.patches.len(), ps.shot_cache_bytes),
            shooter: Shooter::new(
                ws.plan.settings.table.clone(),
                settings.seed,
                settings.form_factors,
                settings.skips.empty_faces,
            ),
            figures: ProgressiveStats {
                shooter_depth: ps.shooter_depth,
                ..ProgressiveStats::default()
            },
            state,
            receivers,
            shots: 0,
            row_sum_total: 0.0,
            rows_tried: !ps.gather_rows,
            balanced: false,
            closed: false,
            fraction,
            initial_fraction: fraction,
            last_pass_fraction: fraction,
            next_history: fraction,
            final_pass: None,
            last_pass_split: None,
            stop: StopReason::default(),
        })
    }

    /// Ends the solve for `reason`.
    fn stop_for(&mut self, reason: StopReason) -> Next {
        self.stop = reason;
        Next::Stop
    }

    /// One shot from `patch`.
    fn shoot(&mut self, ws: &mut Workspace<'_>, patch: u32) {
        let t = Instant::now();
        let ps = &ws.settings.progressive;
        let power = self.state.unshot_power_of(patch) / self.state.emitted_power();
        let depth = if power >= ps.fine_shot_power {
            ps.shooter_depth
        } else {
            0
        };
        let mut rendered = None;
        if self.cache.get(patch, depth).is_none() {
            let shot = self
                .shooter
                .factors(&ws.mesh, &self.receivers, patch, depth);
            let keyed: Vec<(ElementKey, f64)> = shot
                .factors
                .iter()
                .map(|&(i, f)| (self.receivers.leaves[i as usize], f))
                .collect();
            let f = &mut self.figures;
            f.shot_hemicubes += shot.work.hemicubes;
            f.shooter_splits += shot.cells.splits;
            f.reciprocity_clips += shot.cells.clips;
            f.hidden_eye_splits += shot.cells.hidden_splits;
            f.hidden_cells += shot.cells.hidden_cells;
            ws.tally.hemicube += shot.work;
            rendered = self.cache.store(patch, depth, keyed).err();
        } else {
            self.figures.cached_shots += 1;
        }
        ws.stats.seconds.form_factors += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let before = self.state.unshot_power();
        let factors = match &rendered {
            Some(f) => f.as_slice(),
            None => self.cache.get(patch, depth).unwrap_or_default(),
        };
        let delivery = self
            .state
            .deliver(&ws.mesh, &mut ws.radiosity, patch, factors);
        let after = self.state.unshot_power();
        if (0..3).any(|b| after[b] > before[b] * (1.0 + 1e-12)) {
            self.figures.unshot_increases += 1;
        }
        // Shooting the light of one patch while others hold negative
        // corrections can leave more light delivered than was emitted.
        self.settle(ws);
        ws.stats.seconds.solve += t.elapsed().as_secs_f64();

        self.shots += 1;
        let f = &mut self.figures;
        f.fine_shots += usize::from(depth > 0);
        f.scaled_shots += usize::from(delivery.scaled);
        f.row_sums_above_one += usize::from(delivery.implied_row_sum > 1.0);
        f.max_implied_row_sum = f.max_implied_row_sum.max(delivery.implied_row_sum);
        f.shot_cache_bytes = f.shot_cache_bytes.max(self.cache.bytes());
        self.row_sum_total += delivery.implied_row_sum;
    }

    fn report_shot(&self, ws: &Workspace<'_>) {
        // Progress from 1 down to the tolerance, on a log scale, in thousandths.
        let tolerance = ws.settings.progressive.tolerance;
        let fraction = self.fraction;
        let done = if fraction <= 0.0 {
            1.0
        } else {
            (fraction.ln() / tolerance.ln()).clamp(0.0, 1.0)
        };
        (ws.progress)(Progress {
            stage: Stage::Shoot {
                shots: self.shots,
                unshot_fraction: fraction,
            },
            done: (done * 1000.0).round() as usize,
            total: 1000,
        });
    }

    fn record_history(&mut self, ws: &Workspace<'_>) {
        self.figures.history.push(HistoryPoint {
            shots: self.shots,
            seconds: ws.started.elapsed().as_secs_f64(),
            unshot_fraction: self.fraction,
        });
    }

    fn show_preview(&mut self, ws: &Workspace<'_>) {
        let (Some(every), Some(callback)) =
            (ws.settings.progressive.preview_every, &mut self.preview)
        else {
            return;
        };
        if self.shots.is_multiple_of(every) {
            let ambient = ambient_term(&ws.mesh, &self.state.unshot, &self.state.exposure);
            // The caller sees the scene's own scale: a solve at another one
            // hands out a restored copy (the mesh's emissions stay scaled;
            // a preview reads only radiosities and reflectances).
            let restored;
            let radiosity = if ws.scale.is_one() {
                &ws.radiosity
            } else {
                let mut copy = ws.radiosity.clone();
                copy.map_values(|v| ws.scale.restore_rgb(v));
                restored = copy;
                &restored
            };
            callback(&Preview {
                shots: self.shots,
                unshot_fraction: self.fraction,
                ambient: ws.scale.restore_rgb(ambient),
                seconds: ws.started.elapsed().as_secs_f64(),
                mesh: &ws.mesh,
                radiosity,
            });
        }
    }

    /// Every leaf gathers its row (see `ProgressiveSettings::gather_rows`):
    /// what has been shot is gathered again with the rows, and the rows
    /// become the shots' factors. Returns the change in unshot power and the
    /// number of rows.
    fn gather_rows(&mut self, ws: &mut Workspace<'_>, pass: usize) -> (Rgb, usize) {
        self.rows_tried = true;
        let leaves = ws.mesh.leaves();
        ws.compute_rows(&leaves, pass);
        self.note_closed(ws);
        if self
            .cache
            .gather(ws.mesh.patches.len(), &ws.form_factors, &leaves)
        {
            self.figures.rows_gathered_after_shots = Some(self.shots);
            self.balanced = self.closed;
            self.rebalance(ws);
        } else {
            // Too many for the budget: shots go on rendering, and what the
            // cache held for leaves a pass just replaced is stale.
            self.cache = ShotCache::new(
                ws.mesh.patches.len(),
                ws.settings.progressive.shot_cache_bytes,
            );
        }
        // What was shot is gathered again, by the rows, from each patch as
        // its exposure weighs it.
        let change = self.expose(ws)
            + adopt(
                &ws.mesh,
                &mut ws.radiosity,
                &mut self.state,
                &ws.form_factors,
                &leaves,
            );
        // The cache holds the entries now (or shots render them again).
        for &k in &leaves {
            ws.form_factors.release(k);
        }
        (change, leaves.len())
    }

    /// Takes the leaves' exposure from the receivers, with the rows' verdict
    /// in place of the fan of rays wherever a leaf has a row: its row sum in a
    /// closed scene, else 1 if it sees any front face. Returns the change in
    /// unshot power.
    fn expose(&mut self, ws: &Workspace<'_>) -> Rgb {
        for (i, k) in self.receivers.leaves.iter().enumerate() {
            if let Some(view) = ws.form_factors.view(*k) {
                let seen = view.sum > 0.0;
                self.receivers.exposed[i] = seen;
                let visible = view.visible();
                self.receivers.visible[i] = visible;
                self.receivers.exposure[i] = match (self.closed, seen) {
                    (true, _) => view.sum,
                    (false, true) => visible,
                    (false, false) => 0.0,
                };
            }
        }
        self.state.expose(&ws.mesh, &ws.radiosity, &self.receivers)
    }

    /// Whether the rows computed so far find the scene closed (as
    /// [`crate::solve::balance::is_closed`] judges it).
    fn note_closed(&mut self, ws: &Workspace<'_>) {
        let computed: Vec<ElementKey> = ws
            .mesh
            .leaves()
            .into_iter()
            .filter(|k| ws.form_factors.view(*k).is_some())
            .collect();
        self.closed = scene_is_closed(&ws.mesh, &ws.form_factors, &computed);
    }

    /// Balances the rows the cache holds (see [`crate::solve::balance`]), as
    /// the Gauss-Seidel path balances its rows, and has the shots deliver by
    /// them.
    fn rebalance(&mut self, ws: &Workspace<'_>) {
        if !self.balanced {
            self.state.set_balance(&self.receivers, None);
            return;
        }
        let rows = self.cache.rows(&self.receivers);
        let receivers: Vec<BalanceReceiver<'_>> = rows
            .iter()
            .zip(&self.receivers.leaves)
            .zip(&self.receivers.areas)
            .map(|((row, k), &area)| BalanceReceiver {
                patch: ws.mesh.elements[*k].patch,
                area,
                entries: row,
            })
            .collect();
        let b = balance(&receivers, ws.mesh.patches.len(), &dark_patches(&ws.mesh));
        self.state.set_balance(&self.receivers, Some(&b));
    }

    /// Where a band's signed unshot power has gone negative under balanced
    /// rows, scales what has been shot back (see `settle`).
    fn settle(&mut self, ws: &mut Workspace<'_>) {
        if self.balanced
            && settle(
                &ws.mesh,
                &mut ws.radiosity,
                &mut self.state,
                &self.receivers,
            )
        {
            self.figures.settled += 1;
        }
    }

    /// The unshot fraction (magnitudes) now; notes the signed one's lowest.
    fn unshot_fraction(&mut self) -> f64 {
        let emitted = self.state.emitted_power();
        if emitted > 0.0 {
            let signed = self.state.signed_unshot_power().0.iter().sum::<f64>() / emitted;
            let lowest = &mut self.figures.lowest_signed_unshot_fraction;
            *lowest = lowest.min(signed);
        }
        self.state.unshot_fraction()
    }
}

/// Refuses a scene whose system Gauss-Seidel would refuse: one where some
/// patch's reflectance times its row sum exceeds [`MAX_CONTRACTION`] (a closed
/// room with a wall of reflectance 1, where light would never die out).
/// Only a reflectance above that bound can do it, so only the leaves of such
/// patches render their gathering rows here, and the patch's row sum is the
/// one the Gauss-Seidel path's patch system gives it: the exposure-weighted
/// mean of its leaves' row sums.
fn refuse_unbounded(ws: &Workspace<'_>) -> Result<()> {
    let mesh = &ws.mesh;
    for p in 0..mesh.patches.len() as u32 {
        let rho = mesh.patch_reflectance(p).max_band();
        if rho <= MAX_CONTRACTION {
            continue;
        }
        let leaves = mesh.patch_leaves(p);
        let (rows, _) = compute_rows(mesh, &ws.sources, &leaves, &ws.plan.settings, &|_| {});
        let (mut weighted, mut total) = (0.0, 0.0);
        for (k, row) in leaves.iter().zip(&rows) {
            let w = mesh.elements[*k].area * row.sum();
            weighted += w * row.sum();
            total += w;
        }
        let sum = if total > 0.0 { weighted / total } else { 0.0 };
        refuse_unbounded_row(p as usize, rho, sum)?;
    }
    Ok(())
}
