//! The progressive solve over a scene: the same mesh as the Gauss-Seidel path,
//! then shots until a stopping rule is met, with refinement passes between
//! shots and previews handed to the caller.

mod preview;

pub use preview::Preview;

use super::{split_uniformly, PassStats, Progress, Settings, Solution, SolveStats, Stage};
use crate::error::{Error, Result};
use crate::formfactor::hemicube::{DeltaTable, HemicubeStats};
use crate::formfactor::{compute_rows, Row, RowSettings, Sources};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::refine::{mark_for_split, RefineSettings};
use crate::scene::Scene;
use crate::solve::balance::{balance, Receiver as BalanceReceiver, CLOSED_OPEN_SKY};
use crate::solve::dark_patches;
use crate::solve::progressive::{
    adopt, ambient_term, regather, settle, HistoryPoint, ProgressiveStats, Receivers, Shooter,
    ShootingPass, ShootingState, ShotCache, StopReason, Stopping,
};
use crate::solve::{
    push_up, refuse_unbounded_row, GatherTotals, PatchSystem, SolveReport, SolverKind,
    MAX_CONTRACTION,
};
use slotmap::SecondaryMap;
use std::sync::Arc;
use std::time::Instant;

/// Solves `scene` like [`super::solve`], and with the progressive solver also
/// hands a [`Preview`] to `preview` every `settings.progressive.preview_every`
/// shots. (Gauss-Seidel has no previews.)
pub fn solve_with_previews(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
    preview: &mut dyn FnMut(&Preview<'_>),
) -> Result<Solution> {
    match settings.solver_kind {
        SolverKind::GaussSeidel => super::solve(scene, settings, progress),
        SolverKind::Progressive => solve_progressive(scene, settings, progress, Some(preview)),
    }
}

/// Everything the shooting loop works on.
struct Run<'a> {
    settings: &'a Settings,
    progress: &'a (dyn Fn(Progress) + Sync),
    started: Instant,
    mesh: Mesh,
    state: ShootingState,
    receivers: Receivers,
    cache: ShotCache,
    patch_sources: Sources,
    row_settings: RowSettings,
    min_area: f64,
    stats: SolveStats,
    figures: ProgressiveStats,
    hemicube: HemicubeStats,
    shots: usize,
    row_sum_total: f64,
    /// Whether every leaf has gathered its row once (see
    /// `ProgressiveSettings::gather_rows`), or tried to.
    rows_tried: bool,
    /// For each leaf with a gathering row: the row's sum, the form factor of
    /// the back faces and of the open sky it sees. The sum is the gathering
    /// path's own exposure of the leaf (0 for a shut-in leaf), which then
    /// replaces the shooter's fan of rays, so that both paths weigh the leaves
    /// alike; the other two say where the rest of its light goes.
    row_view: SecondaryMap<ElementKey, [f64; 3]>,
    /// Whether the cache holds every leaf's gathering row and the scene is
    /// closed, so that shots deliver by the balanced rows, as Gauss-Seidel
    /// gathers (see [`crate::solve::balance`]).
    balanced: bool,
    /// Whether the gathered rows find the scene closed: the leaves are then
    /// weighed by their exposure, as Gauss-Seidel weighs them.
    closed: bool,
}

/// The progressive solve (see the module docs).
pub(crate) fn solve_progressive(
    scene: &Scene,
    settings: &Settings,
    progress: &(dyn Fn(Progress) + Sync),
    mut preview: Option<&mut dyn FnMut(&Preview<'_>)>,
) -> Result<Solution> {
    settings.validate()?;
    if scene.surfaces.is_empty() {
        return Err(Error::Geometry(format!(
            "scene '{}' has no surfaces",
            scene.name
        )));
    }
    let started = Instant::now();
    let ps = &settings.progressive;
    let refine = &settings.refine;

    let t = Instant::now();
    let mut mesh = Mesh::new(scene, settings.patch_size_for(scene), settings.max_patches)?;
    split_uniformly(
        &mut mesh,
        refine.uniform_depth.unwrap_or(refine.initial_depth),
        refine.max_elements,
    )?;
    let table = Arc::new(DeltaTable::new(settings.hemicube_resolution));
    let mut run = Run {
        settings,
        progress,
        started,
        state: ShootingState::new(&mesh),
        receivers: Receivers::new(&mesh),
        cache: ShotCache::new(mesh.patches.len(), ps.shot_cache_bytes),
        patch_sources: Sources::from_mesh(&mesh),
        row_settings: RowSettings {
            table: Arc::clone(&table),
            seed: settings.seed,
            method: settings.form_factors,
            emitter_rays: settings.emitter_rays,
            emitter_sampling: settings.emitter_sampling,
        },
        min_area: refine
            .min_element_area
            .unwrap_or_else(|| (scene.diameter() * 1e-3).powi(2)),
        mesh,
        stats: SolveStats::default(),
        figures: ProgressiveStats {
            shooter_depth: ps.shooter_depth,
            ..ProgressiveStats::default()
        },
        hemicube: HemicubeStats::default(),
        shots: 0,
        row_sum_total: 0.0,
        rows_tried: !ps.gather_rows,
        row_view: SecondaryMap::new(),
        balanced: false,
        closed: false,
    };
    refuse_unbounded(&run.mesh, &run.patch_sources, &run.row_settings)?;
    run.state.expose(&run.mesh, &run.receivers);
    run.stats.seconds.mesh = t.elapsed().as_secs_f64();
    let mut shooter = Shooter::new(table, settings.seed, settings.form_factors);
    let stopping = Stopping::new(ps, started);
    let adaptive = refine.uniform_depth.is_none();
    let mut fraction = run.unshot_fraction();
    let initial_fraction = fraction;
    let mut last_pass_fraction = fraction;
    let mut next_history = fraction;

    let stop = loop {
        if let Some(reason) = stopping.check(run.shots, fraction) {
            // Converged on the current mesh: refine once more if allowed, and
            // shoot on if that changed anything.
            let more = reason == StopReason::Converged
                && adaptive
                && run.state.emitted_power() > 0.0
                && run.figures.passes.len() < refine.max_passes
                && run.refine_pass(fraction);
            if !more {
                break reason;
            }
            shooter.forget_cells();
            fraction = run.unshot_fraction();
            last_pass_fraction = fraction;
            continue;
        }
        let refining = adaptive && run.figures.passes.len() < refine.max_passes;
        if !run.rows_tried && !refining && fraction <= ps.refine_factor * initial_fraction {
            // No refinement pass to gather the rows at.
            run.gather_rows(0);
            shooter.forget_cells();
            fraction = run.unshot_fraction();
            continue;
        }
        if refining && fraction <= ps.refine_factor * last_pass_fraction {
            run.refine_pass(fraction);
            shooter.forget_cells();
            fraction = run.unshot_fraction();
            last_pass_fraction = fraction;
            continue;
        }
        let Some(shooter_patch) = run.state.choose_shooter() else {
            break StopReason::Converged;
        };
        run.shoot(&mut shooter, shooter_patch);
        fraction = run.unshot_fraction();
        run.report_shot(fraction);
        if run.shots == 1 || fraction <= next_history {
            run.record_history(fraction);
            next_history = fraction * 10f64.powf(-0.25);
        }
        if let (Some(every), Some(callback)) = (ps.preview_every, preview.as_mut()) {
            if run.shots.is_multiple_of(every) {
                callback(&Preview {
                    shots: run.shots,
                    unshot_fraction: fraction,
                    ambient: ambient_term(&run.mesh, &run.state.unshot, &run.state.exposure),
                    seconds: run.started.elapsed().as_secs_f64(),
                    mesh: &run.mesh,
                });
            }
        }
    };
    if run.figures.history.last().map(|h| h.shots) != Some(run.shots) {
        run.record_history(fraction);
    }
    Ok(run.finish(scene, stop, fraction))
}

impl Run<'_> {
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

    /// One shot from `patch`.
    fn shoot(&mut self, shooter: &mut Shooter, patch: u32) {
        let t = Instant::now();
        let ps = &self.settings.progressive;
        let power = self.state.unshot_power_of(patch) / self.state.emitted_power();
        let depth = if power >= ps.fine_shot_power {
            ps.shooter_depth
        } else {
            0
        };
        let mut rendered = None;
        if self.cache.get(patch, depth).is_none() {
            let shot = shooter.factors(&self.mesh, &self.receivers, patch, depth);
            let keyed: Vec<(ElementKey, f64)> = shot
                .factors
                .iter()
                .map(|&(i, f)| (self.receivers.leaves[i as usize], f))
                .collect();
            let f = &mut self.figures;
            f.shot_hemicubes += shot.hemicubes;
            f.shooter_splits += shot.splits;
            f.reciprocity_clips += shot.clips;
            f.hidden_eye_splits += shot.hidden_splits;
            f.hidden_cells += shot.hidden_cells;
            self.hemicube.hemicubes += shot.hemicubes;
            self.hemicube.polygons_rasterized += shot.polygons_rasterized;
            self.hemicube.pixels_tested += shot.pixels_tested;
            rendered = self.cache.store(patch, depth, keyed).err();
        } else {
            self.figures.cached_shots += 1;
        }
        self.stats.seconds.form_factors += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let before = self.state.unshot_power();
        let factors = match &rendered {
            Some(f) => f.as_slice(),
            None => self.cache.get(patch, depth).unwrap_or_default(),
        };
        let delivery = self.state.deliver(&mut self.mesh, patch, factors);
        let after = self.state.unshot_power();
        if (0..3).any(|b| after[b] > before[b] * (1.0 + 1e-12)) {
            self.figures.unshot_increases += 1;
        }
        // Shooting the light of one patch while others hold negative
        // corrections can leave more light delivered than was emitted.
        if self.balanced && settle(&mut self.mesh, &mut self.state, &self.receivers) {
            self.figures.settled += 1;
        }
        self.stats.seconds.solve += t.elapsed().as_secs_f64();

        self.shots += 1;
        let f = &mut self.figures;
        f.fine_shots += usize::from(depth > 0);
        f.scaled_shots += usize::from(delivery.scaled);
        f.row_sums_above_one += usize::from(delivery.implied_row_sum > 1.0);
        f.max_implied_row_sum = f.max_implied_row_sum.max(delivery.implied_row_sum);
        f.shot_cache_bytes = f.shot_cache_bytes.max(self.cache.bytes());
        self.row_sum_total += delivery.implied_row_sum;
    }

    fn report_shot(&self, fraction: f64) {
        // Progress from 1 down to the tolerance, on a log scale, in thousandths.
        let tolerance = self.settings.progressive.tolerance;
        let done = if fraction <= 0.0 {
            1.0
        } else {
            (fraction.ln() / tolerance.ln()).clamp(0.0, 1.0)
        };
        (self.progress)(Progress {
            stage: Stage::Shoot {
                shots: self.shots,
                unshot_fraction: fraction,
            },
            done: (done * 1000.0).round() as usize,
            total: 1000,
        });
    }

    fn record_history(&mut self, fraction: f64) {
        self.figures.history.push(HistoryPoint {
            shots: self.shots,
            seconds: self.started.elapsed().as_secs_f64(),
            unshot_fraction: fraction,
        });
    }

    /// One refinement pass between shots: split where neighbours differ, then
    /// let the new leaves gather what has been shot. Returns false when
    /// nothing was split.
    fn refine_pass(&mut self, fraction: f64) -> bool {
        let t_pass = Instant::now();
        let refine: &RefineSettings = &self.settings.refine;
        let room = refine.max_elements.saturating_sub(self.receivers.len());
        let marks = mark_for_split(
            &self.mesh,
            refine.tolerance,
            refine.max_depth,
            self.min_area,
            room,
        );
        self.stats.final_max_difference = marks.max_difference;
        if marks.split.is_empty() {
            if !self.rows_tried {
                self.gather_rows(self.figures.passes.len() + 1);
            }
            return false;
        }
        let pass = self.figures.passes.len() + 1;
        let mut fresh: Vec<ElementKey> = Vec::new();
        for &k in &marks.split {
            fresh.extend(self.mesh.split(k));
        }
        for k in self.mesh.balance(fresh.clone()) {
            fresh.extend(self.mesh.elements[k].children.iter().copied());
        }
        fresh.retain(|k| self.mesh.elements[*k].is_leaf());
        self.receivers = Receivers::new(&self.mesh);

        let (change, new_hemicubes) = if self.rows_tried {
            let rows = self.rows_for(&fresh, pass);
            self.cache.refine(&self.mesh, &fresh, &rows);
            self.note_rows(&fresh, &rows);
            let kept = self.figures.rows_gathered_after_shots.is_some();
            self.balanced = kept && self.closed;
            let change = if kept {
                // New rows change the balance of every row: every leaf
                // gathers what was shot again, by the rows.
                self.rebalance();
                let change = self.expose()
                    + regather(
                        &mut self.mesh,
                        &mut self.state,
                        &self.receivers,
                        &self.cache,
                    );
                if self.balanced && settle(&mut self.mesh, &mut self.state, &self.receivers) {
                    self.figures.settled += 1;
                }
                change
            } else {
                // The new leaves gather what was shot as it was shot.
                self.expose() + adopt(&mut self.mesh, &mut self.state, &fresh, &rows)
            };
            (change, fresh.len())
        } else {
            self.gather_rows(pass)
        };
        let emitted = self.state.emitted_power();
        self.figures.passes.push(ShootingPass {
            pass,
            after_shots: self.shots,
            unshot_fraction: fraction,
            unshot_change: change.0.iter().sum::<f64>() / emitted,
        });
        self.stats.passes.push(PassStats {
            pass,
            split: marks.split.len(),
            elements: self.receivers.len(),
            new_hemicubes,
            seconds: t_pass.elapsed().as_secs_f64(),
            max_neighbour_difference: marks.max_difference,
            blocked: marks.blocked,
        });
        true
    }

    /// Gathering rows for `keys` (hemi-cubes at the leaves, as the
    /// Gauss-Seidel path renders them), with progress as refinement pass
    /// `pass`.
    fn rows_for(&mut self, keys: &[ElementKey], pass: usize) -> Vec<Row> {
        let t = Instant::now();
        let total = keys.len();
        let progress = self.progress;
        let report = |done| {
            progress(Progress {
                stage: Stage::FormFactors { pass },
                done,
                total,
            });
        };
        report(0);
        let (rows, s) = compute_rows(
            &self.mesh,
            &self.patch_sources,
            keys,
            &self.row_settings,
            &report,
        );
        self.stats.seconds.form_factors += t.elapsed().as_secs_f64();
        self.hemicube.hemicubes += s.hemicubes;
        self.hemicube.polygons_rasterized += s.polygons_rasterized;
        self.hemicube.pixels_tested += s.pixels_tested;
        rows
    }

    /// Every leaf gathers its row (see `ProgressiveSettings::gather_rows`):
    /// what has been shot is gathered again with the rows, and the rows
    /// become the shots' factors. Returns the change in unshot power and the
    /// number of rows.
    fn gather_rows(&mut self, pass: usize) -> (Rgb, usize) {
        self.rows_tried = true;
        let leaves = self.mesh.leaves();
        let rows = self.rows_for(&leaves, pass);
        self.note_rows(&leaves, &rows);
        if self.cache.gather(self.mesh.patches.len(), &leaves, &rows) {
            self.figures.rows_gathered_after_shots = Some(self.shots);
            self.balanced = self.closed;
            self.rebalance();
        } else {
            // Too many for the budget: shots go on rendering, and what the
            // cache held for leaves a pass just replaced is stale.
            self.cache = ShotCache::new(
                self.mesh.patches.len(),
                self.settings.progressive.shot_cache_bytes,
            );
        }
        // What was shot is gathered again, by the rows, from each patch as
        // its exposure weighs it.
        let change = self.expose() + adopt(&mut self.mesh, &mut self.state, &leaves, &rows);
        (change, leaves.len())
    }

    /// Remembers the sums and hidden parts of the rows of `keys`, and
    /// whether the rows find the scene closed.
    fn note_rows(&mut self, keys: &[ElementKey], rows: &[Row]) {
        for (&k, row) in keys.iter().zip(rows) {
            self.row_view
                .insert(k, [row.sum(), row.back_faces(), row.open()]);
        }
        // As `solve::balance::is_closed` judges it: the open sky of the leaves
        // that see a front face or emit.
        let (mut open, mut total) = (0.0, 0.0);
        for (k, [sum, _, sky]) in &self.row_view {
            if let Some(e) = self.mesh.elements.get(k).filter(|e| e.is_leaf()) {
                let emits = self.mesh.surfaces[e.surface as usize].emission != Rgb::ZERO;
                if *sum > 0.0 || emits {
                    open += e.area * sky;
                    total += e.area;
                }
            }
        }
        self.closed = total > 0.0 && open <= CLOSED_OPEN_SKY * total;
    }

    /// Balances the rows the cache holds (see [`crate::solve::balance`]), as
    /// the Gauss-Seidel path balances its rows, and has the shots deliver by
    /// them.
    fn rebalance(&mut self) {
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
                patch: self.mesh.elements[*k].patch,
                area,
                entries: row,
            })
            .collect();
        let b = balance(
            &receivers,
            self.mesh.patches.len(),
            &dark_patches(&self.mesh),
        );
        self.state.set_balance(&self.receivers, Some(&b));
    }

    /// Takes the leaves' exposure from the receivers, with the rows' verdict
    /// in place of the fan of rays wherever a leaf has a row: its row sum in a
    /// closed scene, else 1 if it sees any front face. Returns the change in
    /// unshot power.
    fn expose(&mut self) -> Rgb {
        for (i, k) in self.receivers.leaves.iter().enumerate() {
            if let Some(&[sum, ..]) = self.row_view.get(*k) {
                self.receivers.exposed[i] = sum > 0.0;
                self.receivers.exposure[i] = match (self.closed, sum > 0.0) {
                    (true, _) => sum,
                    (false, true) => 1.0,
                    (false, false) => 0.0,
                };
            }
        }
        self.state.expose(&self.mesh, &self.receivers)
    }

    /// The solution: patch radiosities as leaf means, interior nodes filled
    /// in, the figures.
    fn finish(mut self, scene: &Scene, stop: StopReason, fraction: f64) -> Solution {
        let mesh = &mut self.mesh;
        let mut patch_radiosity = Vec::with_capacity(mesh.patches.len());
        for p in 0..mesh.patches.len() {
            let root = mesh.patches[p].root;
            let b = push_up(mesh, root);
            mesh.patches[p].radiosity = b;
            patch_radiosity.push(b);
        }
        let mut emitted = Rgb::ZERO;
        for k in mesh.leaves() {
            let e = &mesh.elements[k];
            emitted += mesh.surfaces[e.surface as usize].emission * e.area;
        }
        let (mut back_faces, mut escaped) = (Rgb::ZERO, Rgb::ZERO);
        for (k, [_, back, open]) in &self.row_view {
            if let Some(e) = mesh.elements.get(k).filter(|e| e.is_leaf()) {
                back_faces += e.radiosity * (e.area * back);
                escaped += e.radiosity * (e.area * open);
            }
        }
        let totals = GatherTotals {
            emitted,
            absorbed: self.state.absorbed_power(mesh),
            back_faces,
            escaped,
        };
        // Progressive keeps no gathering rows: the system holds reflectance and
        // emission with empty rows.
        let system = PatchSystem::from_mesh(mesh);
        let report = SolveReport {
            iterations: self.shots,
            residual: self.state.residual(),
            error_bound: 0.0,
            contraction: 0.0,
            extrapolations: 0,
        };
        let mut stats = std::mem::take(&mut self.stats);
        stats.finish(
            mesh,
            &system,
            scene,
            self.settings,
            report,
            self.shots,
            totals,
            self.hemicube,
        );
        let f = &mut self.figures;
        f.shots = self.shots;
        f.stop = stop;
        f.unshot_fraction = fraction;
        f.ambient = ambient_term(mesh, &self.state.unshot, &self.state.exposure);
        f.mean_implied_row_sum = if self.shots > 0 {
            self.row_sum_total / self.shots as f64
        } else {
            0.0
        };
        stats.hemicube.mean_row_sum = f.mean_implied_row_sum;
        stats.hemicube.max_row_sum = f.max_implied_row_sum;
        stats.energy.truncated |= stop != StopReason::Converged;
        stats.warn();
        stats.progressive = Some(std::mem::take(f));
        stats.seconds.total = self.started.elapsed().as_secs_f64();
        Solution {
            mesh: self.mesh,
            patch_radiosity,
            system,
            stats,
        }
    }
}

/// Refuses a scene whose system Gauss-Seidel would refuse: one where some
/// patch's reflectance times its row sum exceeds [`MAX_CONTRACTION`] (a closed
/// room with a wall of reflectance 1, where light would never die out).
/// Only a reflectance above that bound can do it, so only the leaves of such
/// patches render their gathering rows here, and the patch's row sum is the
/// one the Gauss-Seidel path's patch system gives it: the exposure-weighted
/// mean of its leaves' row sums.
fn refuse_unbounded(mesh: &Mesh, sources: &Sources, settings: &RowSettings) -> Result<()> {
    for p in 0..mesh.patches.len() as u32 {
        let rho = mesh.patch_reflectance(p).max_band();
        if rho <= MAX_CONTRACTION {
            continue;
        }
        let leaves = mesh.patch_leaves(p);
        let (rows, _) = compute_rows(mesh, sources, &leaves, settings, &|_| {});
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
