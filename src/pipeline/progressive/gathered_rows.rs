//! The progressive solver's turn to the gathering rows (see
//! `ProgressiveSettings::gather_rows`): every leaf renders its own row, what
//! has been shot is gathered again with the rows, and shots deliver by them,
//! balanced as Gauss-Seidel's rows are in a closed scene.

use super::{adopt, Shooting, ShotCache};
use crate::math::Rgb;
use crate::mesh::ElementKey;
use crate::pipeline::workspace::Workspace;
use crate::solve::balance::{balance, Receiver as BalanceReceiver};
use crate::solve::{dark_patches, scene_is_closed};

impl Shooting<'_> {
    /// Every leaf gathers its row (see `ProgressiveSettings::gather_rows`):
    /// what has been shot is gathered again with the rows, and the rows
    /// become the shots' factors. Returns the change in unshot power and the
    /// number of rows.
    pub(super) fn gather_rows(&mut self, ws: &mut Workspace<'_>, pass: usize) -> (Rgb, usize) {
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
        // The store keeps the rows beside the cache's transposed copy: the
        // refinement's facing split reads them, as does the gathering solver
        // that takes a converged solve over for its shaped gathers.
        (change, leaves.len())
    }

    /// Takes the leaves' exposure from the receivers, with the rows' verdict
    /// in place of the fan of rays wherever a leaf has a row: its row sum in a
    /// closed scene, else 1 if it sees any front face. Returns the change in
    /// unshot power.
    pub(super) fn expose(&mut self, ws: &Workspace<'_>) -> Rgb {
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
    pub(super) fn note_closed(&mut self, ws: &Workspace<'_>) {
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
    pub(super) fn rebalance(&mut self, ws: &Workspace<'_>) {
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
}
