//! The progressive solver as the one driver runs it: shots until a stopping
//! rule is met, refinement passes when the unshot power has fallen far
//! enough, and the solution with its figures.

use super::{
    adopt, ambient_term, regather, PreviewCallback, Receivers, Shooter, Shooting, ShootingState,
    ShotCache, Stopping,
};
use crate::error::Result;
use crate::formfactor::compute_rows;
use crate::math::Rgb;
use crate::mesh::ElementKey;
use crate::pipeline::gathering::Gathering;
use crate::pipeline::strategy::{Next, Solver};
use crate::pipeline::workspace::Workspace;
use crate::solution::{ProgressiveStats, ShootingPass, Solution, StopReason};
use crate::solve::{refuse_unbounded_row, GatherTotals, PatchSystem, SolveReport, MAX_CONTRACTION};

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
        if let Some(gathering) = self.hand_over(&mut ws, patch_radiosity) {
            self.file_figures(&mut ws);
            return gathering.finish(ws);
        }
        let mesh = &ws.mesh;
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
        // The patch system of the rows in the store (those the leaves have
        // rendered; none for a leaf whose shots rendered its factors).
        let system = PatchSystem::from_mesh(mesh, &ws.form_factors);
        let report = SolveReport {
            iterations: self.shots,
            residual: self.state.residual(),
            error_bound: 0.0,
            contraction: 0.0,
            extrapolations: 0,
        };
        ws.finish_stats(&system, report, self.shots, totals);
        self.file_figures(&mut ws);
        ws.stats.warn();
        ws.stats.seconds.total = ws.started.elapsed().as_secs_f64();
        ws.into_solution(system)
    }
}

impl Shooting<'_> {
    /// The gathering solver in charge of the converged solution, from the
    /// patch radiosities `b`, when the solve is to end in shaped gathers
    /// (see `Settings::shaped_gathers`): shots gather every patch by its
    /// mean, and a shaped gather needs the patch system and its level
    /// corrections, which are the gathering solver's. `None` when no shaped gather is
    /// due, or when a stopping rule other than convergence ended the shots
    /// (said in a warning: the user asked for a bounded solve), or when the
    /// patch system cannot be solved (also said).
    fn hand_over(&self, ws: &mut Workspace<'_>, b: Vec<Rgb>) -> Option<Gathering> {
        let count = ws.settings.shaped_gather_count();
        // (A fixed number of bounces is refused with this solver.)
        if count == 0 {
            return None;
        }
        if self.stop != StopReason::Converged {
            let rule = match self.stop {
                StopReason::ShotLimit => "the shot limit",
                _ => "the time budget",
            };
            ws.stats.warnings.push(format!(
                "the shots stopped at {rule} before converging: patches are gathered by \
                 their means, without the {count} shaped gather(s) a converged solve makes"
            ));
            return None;
        }
        match Gathering::take_over(ws, b) {
            Ok(mut gathering) => {
                gathering.keep_shapes = self.keep_shapes;
                Some(gathering)
            }
            Err(e) => {
                ws.stats.warnings.push(format!(
                    "the converged shots were not handed to the gathering solver for the \
                     shaped gathers ({e}): patches are gathered by their means"
                ));
                None
            }
        }
    }

    /// The mean row sum the shots implied.
    fn implied_row_sum(&self) -> f64 {
        if self.shots > 0 {
            self.row_sum_total / self.shots as f64
        } else {
            0.0
        }
    }

    /// Files the progressive figures in the solve's stats.
    fn file_figures(&mut self, ws: &mut Workspace<'_>) {
        let implied = self.implied_row_sum();
        let f = &mut self.figures;
        f.shots = self.shots;
        f.stop = self.stop;
        f.unshot_fraction = self.fraction;
        f.ambient = ambient_term(&ws.mesh, &self.state.unshot, &self.state.exposure);
        f.mean_implied_row_sum = implied;
        ws.stats.energy.truncated |= self.stop != StopReason::Converged;
        ws.stats.progressive = Some(std::mem::take(f));
    }
}

impl<'p> Shooting<'p> {
    /// Starts shooting on the initial mesh of `ws`, handing previews to
    /// `preview` if given.
    pub(crate) fn start(
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
            keep_shapes: false,
            stop: StopReason::default(),
        })
    }

    /// Ends the solve for `reason`.
    pub(super) fn stop_for(&mut self, reason: StopReason) -> Next {
        self.stop = reason;
        Next::Stop
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
