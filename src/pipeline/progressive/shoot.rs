//! The form factors of one shot: from every receiving leaf to the shooting
//! patch, out of hemi-cubes at the shooter whose item buffer holds leaf ids.
//!
//! The shooting patch is cut into cells some levels below it (see
//! [`ProgressiveSettings::shooter_depth`]); each cell renders its own hemi-cube
//! (in parallel) and shoots the patch's unshot radiosity from its own area. The form factor `F_ei` from leaf
//! `e` to the patch is the sum over cells `s` of:
//!
//! - [`FormFactorMethod::Hybrid`]: `F_exact(e -> s) * v_s(e)`, Lambert's exact
//!   form factor from the leaf's receiving point to the cell polygon times the
//!   fraction of the leaf the cell's eye sees (see [`super::visibility`]). This
//!   is the gathering side's hybrid turned around: the item buffer decides
//!   visibility, the magnitude is exact, and no reciprocal `F_se A_s / A_e` is
//!   ever formed, so nothing can exceed 1 in the near field.
//! - [`FormFactorMethod::Hemicube`]: the classic reciprocal `F_se A_s / A_e`
//!   with `F_se` the leaf's delta form factors. Where one of these exceeds 1
//!   the cell is split into four smaller shooters, again and again until no
//!   reciprocal exceeds 1 (which it cannot once the cell is no larger than
//!   the receiver); only at the lattice's finest cell would one be clipped to
//!   1, and counted. Near-field splits can be many: a point-sampled shooter
//!   is a poor model of a large patch close to its receivers, which is what
//!   the hybrid form avoids.
//!
//! Only the patch's exposed leaves shoot (see `Receivers::exposed`): a leaf
//! shut inside an object, as under a box standing on the floor, sees nothing
//! but back faces, so gathering leaves it out of the exchange. A cell holding
//! both exposed and shut-in leaves is split until each part holds one kind,
//! and a cell of shut-in leaves shoots nothing. The patch's unshot power then
//! leaves from its exposed area alone, as gathering has its exposed elements
//! alone stand for the patch. (Cells as coarse as the shooter depth alone
//! counted the shut-in part of a cell straddling a box's foot as shooting
//! area: both blocks of the Cornell box came out 0.7-0.95% darker than with
//! gathering.) As a guard, a cell of exposed leaves whose own eye is shut in
//! (back faces fill most of its view) is split too, up to
//! [`MAX_SHOOTER_SPLITS`] times.
//!
//! The factors leave out the patch's open scale and any scaling back of a
//! shot (see [`ShootingState::deliver`]), so that they can be kept for the
//! patch's next shots (see [`super::ShotCache`]).
//!
//! [`ShootingState::deliver`]: super::ShootingState::deliver
//! [`ProgressiveSettings::shooter_depth`]: super::ProgressiveSettings::shooter_depth

use super::cell::{CellContext, CellResult};
use super::Receivers;
use crate::formfactor::hemicube::{DeltaTable, Hemicube, HemicubeStats};
use crate::formfactor::FormFactorMethod;
use crate::mesh::{Cell, Mesh};
use rayon::prelude::*;
use std::sync::Arc;

/// How many times a shooter cell may be split further when its eye is shut
/// in.
pub(crate) const MAX_SHOOTER_SPLITS: u8 = 3;

/// A cell's eye counts as shut in when back faces fill more than this part of
/// its view (by form factor).
pub(super) const HIDDEN_EYE: f64 = 0.5;

/// The form factors of one shot and what computing them took.
#[derive(Clone, Debug, Default)]
pub(crate) struct ShotFactors {
    /// `(leaf index, F_ei)`: the form factor from each receiving leaf to the
    /// shooting patch, in increasing leaf order, zeros left out.
    pub factors: Vec<(u32, f64)>,
    /// The hemi-cubes' work.
    pub work: HemicubeStats,
    /// What the shooter cells did.
    pub cells: CellCounts,
}

/// What the cells of a shot did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CellCounts {
    /// Classic shooter cells split because a reciprocal form factor exceeded 1.
    pub splits: usize,
    /// Classic reciprocal form factors still above 1 at the lattice's finest
    /// cell, clipped to 1.
    pub clips: usize,
    /// Cells split because part of them is shut in (exposed and shut-in
    /// leaves both, or a shut-in eye).
    pub hidden_splits: usize,
    /// Cells that shot nothing: all their leaves shut in, or their eye still
    /// shut in at the deepest split.
    pub hidden_cells: usize,
    /// Hybrid: patches found partly visible from a cell, whose leaves were
    /// rendered one by one (summed over cells).
    pub partly_visible: usize,
}

impl std::ops::AddAssign for CellCounts {
    fn add_assign(&mut self, other: CellCounts) {
        self.splits += other.splits;
        self.clips += other.clips;
        self.hidden_splits += other.hidden_splits;
        self.hidden_cells += other.hidden_cells;
        self.partly_visible += other.partly_visible;
    }
}

/// A shooter cell and the surface it lies on (a face cluster's cells lie
/// on several).
type SurfaceCell = (u32, Cell);

/// Renders shots. Holds one hemi-cube per worker thread and reusable buffers.
#[derive(Debug)]
pub(crate) struct Shooter {
    cubes: Vec<Hemicube>,
    seed: u64,
    method: FormFactorMethod,
    /// Per patch, the cell depth and the open shooter cells found at its last
    /// shot.
    cells: Vec<Option<(u8, Vec<SurfaceCell>)>>,
    dense: Vec<f64>,
    touched: Vec<u32>,
}

impl Shooter {
    /// A shooter rendering hemi-cubes with `table`, rotated by `seed`, turning
    /// pixels into form factors by `method`; `skip_empty_faces` as
    /// [`Hemicube::set_skip_empty_faces`].
    #[must_use]
    pub(crate) fn new(
        table: Arc<DeltaTable>,
        seed: u64,
        method: FormFactorMethod,
        skip_empty_faces: bool,
    ) -> Self {
        let workers = rayon::current_num_threads().max(1);
        Shooter {
            cubes: (0..workers)
                .map(|_| {
                    let mut cube = Hemicube::new(Arc::clone(&table), 0);
                    cube.set_skip_empty_faces(skip_empty_faces);
                    cube
                })
                .collect(),
            seed,
            method,
            cells: Vec::new(),
            dense: Vec::new(),
            touched: Vec::new(),
        }
    }

    /// Forgets the shooter cells found so far: they depend on which leaves are
    /// exposed, so they must be found again once the mesh is refined.
    pub(crate) fn forget_cells(&mut self) {
        self.cells.clear();
    }

    /// The form factors from every leaf of `receivers` to patch `patch`,
    /// shooting from its cells `depth` levels below it. Deterministic: the
    /// same at any thread count.
    pub(crate) fn factors(
        &mut self,
        mesh: &Mesh,
        receivers: &Receivers,
        patch: u32,
        depth: u8,
    ) -> ShotFactors {
        let p = &mesh.patches[patch as usize];
        if self.cells.len() < mesh.patches.len() {
            self.cells.resize(mesh.patches.len(), None);
        }
        // The cells found open at the patch's last shot (shut-in parts depend
        // on the geometry and the leaves only, so their splits need not be
        // found again until the mesh is refined).
        let cached = self.cells[patch as usize]
            .take()
            .filter(|(d, _)| *d == depth)
            .map(|(_, c)| c);
        // (surface, cell) pairs: a face cluster's roots lie on its surfaces.
        let cells = cached.unwrap_or_else(|| {
            p.roots
                .iter()
                .flat_map(|&root| {
                    let e = &mesh.elements[root];
                    let mut cells = vec![e.cell];
                    for _ in 0..depth {
                        cells = cells.iter().flat_map(Cell::children).collect();
                    }
                    cells.into_iter().map(move |c| (e.surface, c))
                })
                .collect()
        });
        let workers = self.cubes.len().min(cells.len()).max(1);
        let per = cells.len().div_ceil(workers).max(1);
        let groups: Vec<&[SurfaceCell]> = cells.chunks(per).collect();
        let ctx = CellContext {
            mesh,
            receivers,
            patch,
            surface: p.surface,
            seed: self.seed,
            method: self.method,
            deepest: depth + MAX_SHOOTER_SPLITS,
        };
        let results: Vec<Vec<(u32, CellResult)>> = self.cubes[..groups.len()]
            .par_iter_mut()
            .zip(groups.par_iter())
            .map(|(cube, group)| {
                group
                    .iter()
                    .map(|&(surface, cell)| {
                        let mut r = CellResult::default();
                        let before = cube.stats;
                        CellContext { surface, ..ctx }.shoot(cube, &cell, true, &mut r);
                        r.work = cube.stats - before;
                        (surface, r)
                    })
                    .collect()
            })
            .collect();
        let results: Vec<(u32, CellResult)> = results.into_iter().flatten().collect();
        self.cells[patch as usize] = Some((
            depth,
            results
                .iter()
                .flat_map(|(s, r)| r.open.iter().map(|c| (*s, *c)))
                .collect(),
        ));

        // Sum the cells' contributions per leaf, in a fixed order.
        if self.dense.len() < receivers.len() {
            self.dense.resize(receivers.len(), 0.0);
        }
        let mut shot = ShotFactors::default();
        for (
            _,
            CellResult {
                out, counts, work, ..
            },
        ) in results
        {
            shot.work += work;
            shot.cells += counts;
            for (i, f) in out {
                let slot = &mut self.dense[i as usize];
                if *slot == 0.0 {
                    self.touched.push(i);
                }
                *slot += f;
            }
        }
        self.touched.sort_unstable();
        shot.factors = self
            .touched
            .drain(..)
            .map(|i| (i, std::mem::take(&mut self.dense[i as usize])))
            .filter(|e| e.1 > 0.0)
            .collect();
        shot
    }
}
