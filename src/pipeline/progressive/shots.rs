//! One shot of the progressive solver, and what it reports: progress, the
//! convergence history and previews.

use super::{ambient_term, settle, Preview, Shooting};
use crate::mesh::ElementKey;
use crate::pipeline::workspace::Workspace;
use crate::pipeline::{Progress, Stage};
use crate::solution::HistoryPoint;
use std::time::Instant;

impl Shooting<'_> {
    /// One shot from `patch`.
    pub(super) fn shoot(&mut self, ws: &mut Workspace<'_>, patch: u32) {
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

    pub(super) fn report_shot(&self, ws: &Workspace<'_>) {
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

    pub(super) fn record_history(&mut self, ws: &Workspace<'_>) {
        self.figures.history.push(HistoryPoint {
            shots: self.shots,
            seconds: ws.started.elapsed().as_secs_f64(),
            unshot_fraction: self.fraction,
        });
    }

    pub(super) fn show_preview(&mut self, ws: &Workspace<'_>) {
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

    /// Where a band's signed unshot power has gone negative under balanced
    /// rows, scales what has been shot back (see `settle`).
    pub(super) fn settle(&mut self, ws: &mut Workspace<'_>) {
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
    pub(super) fn unshot_fraction(&mut self) -> f64 {
        let emitted = self.state.emitted_power();
        if emitted > 0.0 {
            let signed = self.state.signed_unshot_power().0.iter().sum::<f64>() / emitted;
            let lowest = &mut self.figures.lowest_signed_unshot_fraction;
            *lowest = lowest.min(signed);
        }
        self.state.unshot_fraction()
    }
}
