//! The form factors of one shot: from every receiving leaf to the shooting
//! patch, out of hemi-cubes at the shooter whose item buffer holds leaf ids.
//!
//! The shooting patch is cut into cells at [`ProgressiveSettings::shooter_depth`]
//! below it; each cell renders its own hemi-cube (in parallel) and shoots the
//! patch's unshot radiosity from its own area. The form factor `F_ei` from leaf
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
//!   the cell is split into four smaller shooters, up to [`MAX_SHOOTER_SPLITS`]
//!   times; what still exceeds 1 after that is clipped to 1 and counted.
//!
//! A cell whose eye is shut in (back faces fill most of its view, as under a
//! box standing on the floor) is split the same way, so that the part of the
//! cell outside still shoots; a receiver gathering from the patch would see
//! that part, and not the part inside.
//!
//! The implied row sum `sum_e F_ei A_e / A_i` is 1 in a closed scene, up to
//! the point sampling of each receiver (a leaf that straddles an occluder's
//! foot counts all its area, as it does when it gathers). Only where the
//! reflected part `sum_e rho_e F_ei A_e / A_i` would exceed 1 in some band,
//! so that a shot would create unshot power, is the shot scaled back, and
//! counted.
//!
//! [`ProgressiveSettings::shooter_depth`]: super::ProgressiveSettings::shooter_depth

use super::visibility::{partly_visible, visible_fractions};
use super::Receivers;
use crate::formfactor::hemicube::{Coverage, DeltaTable, Hemicube};
use crate::formfactor::{element_seed, point_to_polygon, FormFactorMethod, Sources};
use crate::math::{polygon_area, polygon_centroid, Rgb};
use crate::mesh::{Cell, Mesh};
use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;
use std::sync::Arc;

/// How many times a shooter cell may be split further when its eye is shut
/// in, or (classic) when a reciprocal form factor exceeds 1.
pub const MAX_SHOOTER_SPLITS: u8 = 3;

/// A cell's eye counts as shut in when back faces fill more than this part of
/// its view (by form factor).
pub const HIDDEN_EYE: f64 = 0.5;

/// The form factors of one shot and what computing them took.
#[derive(Clone, Debug, Default)]
pub struct ShotFactors {
    /// `(leaf index, F_ei)`: the form factor from each receiving leaf to the
    /// shooting patch, in increasing leaf order, zeros left out.
    pub factors: Vec<(u32, f64)>,
    /// `sum_e F_ei A_e / A_i` before any scaling (1 in a closed scene).
    pub implied_row_sum: f64,
    /// True when the reflected part of the implied row sum exceeded 1 in
    /// some band and the factors were scaled back.
    pub scaled: bool,
    /// Hemi-cubes rendered.
    pub hemicubes: u64,
    /// Polygon-face pairs scan converted.
    pub polygons_rasterized: u64,
    /// Pixels depth-tested.
    pub pixels_tested: u64,
    /// Classic shooter cells split because a reciprocal form factor exceeded 1.
    pub splits: usize,
    /// Classic reciprocal form factors still above 1 at the deepest split,
    /// clipped to 1.
    pub clips: usize,
    /// Cells split because their eye was shut in.
    pub hidden_splits: usize,
    /// Cells still shut in at the deepest split, which shot nothing.
    pub hidden_cells: usize,
    /// Hybrid: patches found partly visible from a cell, whose leaves were
    /// rendered one by one (summed over cells).
    pub partly_visible: usize,
}

/// One cell of the shooting patch, as a shooter.
struct Cellshooter {
    polygon: SmallVec<[DVec3; 4]>,
    area: f64,
    eye: DVec3,
    angle: f64,
}

/// Renders shots. Holds one hemi-cube per worker thread and reusable buffers.
#[derive(Debug)]
pub struct Shooter {
    cubes: Vec<Hemicube>,
    seed: u64,
    method: FormFactorMethod,
    depth: u8,
    /// Per patch, the open shooter cells found at its last shot.
    cells: Vec<Option<Vec<Cell>>>,
    dense: Vec<f64>,
    touched: Vec<u32>,
}

/// What one top-level cell of a shot produced.
#[derive(Default)]
struct CellResult {
    /// `(leaf index, form factor)` contributions.
    out: Vec<(u32, f64)>,
    counts: ShotFactors,
    /// The cells it turned out to consist of once shut-in parts were split
    /// off (and dropped where shut in at the deepest level).
    open: Vec<Cell>,
}

impl Shooter {
    /// A shooter rendering hemi-cubes with `table`, rotated by `seed`, turning
    /// pixels into form factors by `method`, from cells `depth` levels below
    /// the shooting patch.
    #[must_use]
    pub fn new(table: Arc<DeltaTable>, seed: u64, method: FormFactorMethod, depth: u8) -> Self {
        let workers = rayon::current_num_threads().max(1);
        Shooter {
            cubes: (0..workers)
                .map(|_| Hemicube::new(Arc::clone(&table), 0))
                .collect(),
            seed,
            method,
            depth,
            cells: Vec::new(),
            dense: Vec::new(),
            touched: Vec::new(),
        }
    }

    /// The form factors from every leaf of `receivers` to patch `patch`.
    /// Deterministic: the same at any thread count.
    pub fn factors(&mut self, mesh: &Mesh, receivers: &Receivers, patch: u32) -> ShotFactors {
        let p = &mesh.patches[patch as usize];
        if self.cells.len() < mesh.patches.len() {
            self.cells.resize(mesh.patches.len(), None);
        }
        // The cells found open at the patch's last shot (shut-in cells depend
        // on the geometry only, so their splits need not be found again).
        let cells = self.cells[patch as usize].take().unwrap_or_else(|| {
            let mut cells = vec![mesh.elements[p.root].cell];
            for _ in 0..self.depth {
                cells = cells.iter().flat_map(Cell::children).collect();
            }
            cells
        });
        let workers = self.cubes.len().min(cells.len()).max(1);
        let per = cells.len().div_ceil(workers).max(1);
        let groups: Vec<&[Cell]> = cells.chunks(per).collect();
        let ctx = CellContext {
            mesh,
            receivers,
            surface: p.surface,
            seed: self.seed,
            method: self.method,
            deepest: self.depth + MAX_SHOOTER_SPLITS,
        };
        let results: Vec<Vec<CellResult>> = self.cubes[..groups.len()]
            .par_iter_mut()
            .zip(groups.par_iter())
            .map(|(cube, group)| {
                group
                    .iter()
                    .map(|cell| {
                        let mut r = CellResult::default();
                        let before = cube.stats;
                        ctx.shoot(cube, cell, true, &mut r);
                        r.counts.hemicubes = cube.stats.hemicubes - before.hemicubes;
                        r.counts.polygons_rasterized =
                            cube.stats.polygons_rasterized - before.polygons_rasterized;
                        r.counts.pixels_tested = cube.stats.pixels_tested - before.pixels_tested;
                        r
                    })
                    .collect()
            })
            .collect();
        let results: Vec<CellResult> = results.into_iter().flatten().collect();
        self.cells[patch as usize] = Some(results.iter().flat_map(|r| r.open.clone()).collect());

        // Sum the cells' contributions per leaf, in a fixed order.
        if self.dense.len() < receivers.len() {
            self.dense.resize(receivers.len(), 0.0);
        }
        let mut shot = ShotFactors::default();
        for CellResult { out, counts, .. } in results {
            shot.hemicubes += counts.hemicubes;
            shot.polygons_rasterized += counts.polygons_rasterized;
            shot.pixels_tested += counts.pixels_tested;
            shot.splits += counts.splits;
            shot.clips += counts.clips;
            shot.hidden_splits += counts.hidden_splits;
            shot.hidden_cells += counts.hidden_cells;
            shot.partly_visible += counts.partly_visible;
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
        let mut row_sum = 0.0;
        let mut reflected = Rgb::ZERO;
        for &(i, f) in &shot.factors {
            let w = f * receivers.areas[i as usize] / p.area;
            row_sum += w;
            reflected += receivers.reflectances[i as usize] * w;
        }
        shot.implied_row_sum = row_sum;
        // Only a shot that would send back more than it takes needs scaling.
        let worst = reflected.max_band();
        if worst > 1.0 {
            shot.scaled = true;
            for e in &mut shot.factors {
                e.1 /= worst;
            }
        }
        shot
    }
}

/// What every cell of one shot shares.
struct CellContext<'a> {
    mesh: &'a Mesh,
    receivers: &'a Receivers,
    surface: u32,
    seed: u64,
    method: FormFactorMethod,
    /// Deepest cell level below the patch.
    deepest: u8,
}

impl CellContext<'_> {
    fn cell_shooter(&self, cell: &Cell) -> Cellshooter {
        let lattice = &self.mesh.surfaces[self.surface as usize];
        let polygon = lattice.polygon(cell);
        let area = polygon_area(&polygon);
        let eye = polygon_centroid(&polygon) + lattice.normal * (1e-6 * area.sqrt());
        let h = element_seed(self.seed, self.surface, cell);
        let angle = (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64) * std::f64::consts::TAU;
        Cellshooter {
            polygon,
            area,
            eye,
            angle,
        }
    }

    /// Shoots from one cell: splits it where its eye is shut in or (classic)
    /// a reciprocal exceeds 1, else adds its form factors. Cells found open
    /// are listed in `r.open` when `record` (not below a classic split, which
    /// depends on the receivers of the moment).
    fn shoot(&self, cube: &mut Hemicube, cell: &Cell, record: bool, r: &mut CellResult) {
        let s = self.cell_shooter(cell);
        let normal = self.mesh.surfaces[self.surface as usize].normal;
        // Hybrid renders patches first (see `visibility`); classic needs every
        // leaf's own pixel count.
        let first = match self.method {
            FormFactorMethod::Hybrid => &self.receivers.patch_sources,
            FormFactorMethod::Hemicube => &self.receivers.sources,
        };
        let seen = cube.coverage(first, s.eye, normal, s.angle, self.surface);
        let can_split = self.level_of(cell) < self.deepest && cell.size() >= 2;
        if seen.back_faces > HIDDEN_EYE {
            // The eye is shut in (a point of the floor under a box): it sees
            // nothing, but part of the cell may lie outside. Smaller cells find
            // that part; what stays shut in at the deepest level is seen by no
            // receiver, and shoots nothing, as it emits nothing when gathered.
            if can_split {
                r.counts.hidden_splits += 1;
                for child in cell.children() {
                    self.shoot(cube, &child, record, r);
                }
            } else {
                r.counts.hidden_cells += 1;
            }
            return;
        }
        if record {
            r.open.push(*cell);
        }
        match self.method {
            FormFactorMethod::Hybrid => {
                let leaves =
                    self.partly_visible_leaves(cube, &s, normal, &seen.polygons, &mut r.counts);
                self.hybrid(&s, normal, &seen.polygons, &leaves, &mut r.out);
            }
            FormFactorMethod::Hemicube => {
                let reciprocal: Vec<(u32, f64)> = seen
                    .polygons
                    .iter()
                    .filter(|c| c.won > 0.0)
                    .map(|c| (c.id, c.won * s.area / self.receivers.areas[c.id as usize]))
                    .collect();
                if can_split && reciprocal.iter().any(|e| e.1 > 1.0) {
                    r.counts.splits += 1;
                    for child in cell.children() {
                        self.shoot(cube, &child, false, r);
                    }
                    return;
                }
                for (i, f) in reciprocal {
                    if f > 1.0 {
                        r.counts.clips += 1;
                    }
                    r.out.push((i, f.min(1.0)));
                }
            }
        }
    }

    /// Renders the leaves of the partly visible patches among the other
    /// patches, and returns their coverage by leaf index.
    fn partly_visible_leaves(
        &self,
        cube: &mut Hemicube,
        s: &Cellshooter,
        normal: DVec3,
        patches: &[Coverage],
        counts: &mut ShotFactors,
    ) -> Vec<Coverage> {
        let partly = partly_visible(patches);
        counts.partly_visible += partly.len();
        if partly.is_empty() {
            return Vec::new();
        }
        let r = self.receivers;
        let extra: usize = partly
            .iter()
            .map(|&p| r.patch_leaves[p as usize].len())
            .sum();
        let mut mixed = Sources {
            polygons: Vec::with_capacity(r.patch_sources.polygons.len() + extra),
        };
        // Leaf index of each polygon of the mixed list; whole patches only hide.
        let mut leaf_of = Vec::with_capacity(mixed.polygons.capacity());
        let mut next = partly.iter().peekable();
        for (p, poly) in r.patch_sources.polygons.iter().enumerate() {
            if next.peek() == Some(&&(p as u32)) {
                next.next();
                let range = r.patch_leaves[p].clone();
                mixed.polygons.extend_from_slice(
                    &r.sources.polygons[range.start as usize..range.end as usize],
                );
                leaf_of.extend(range);
            } else {
                mixed.polygons.push(poly.clone());
                leaf_of.push(u32::MAX);
            }
        }
        let seen = cube.coverage(&mixed, s.eye, normal, s.angle, self.surface);
        seen.polygons
            .into_iter()
            .filter(|c| leaf_of[c.id as usize] != u32::MAX)
            .map(|c| Coverage {
                id: leaf_of[c.id as usize],
                ..c
            })
            .collect()
    }

    /// Hybrid: exact magnitude from each leaf's receiving point, visibility
    /// from the cell's item buffer.
    fn hybrid(
        &self,
        s: &Cellshooter,
        normal: DVec3,
        patches: &[Coverage],
        leaves: &[Coverage],
        out: &mut Vec<(u32, f64)>,
    ) {
        for (i, v) in visible_fractions(self.mesh, self.receivers, patches, leaves) {
            let eye = self.receivers.eyes[i as usize];
            // A leaf behind the shooter's plane cannot receive from its front,
            // even when it inherits a visible fraction from its ancestors.
            if (eye - s.eye).dot(normal) <= 0.0 {
                continue;
            }
            let f = point_to_polygon(eye, self.receivers.normals[i as usize], &s.polygon) * v;
            if f > 0.0 {
                out.push((i, f));
            }
        }
    }

    /// Depth of a cell below its patch (from the lattice cell sizes).
    fn level_of(&self, cell: &Cell) -> u8 {
        let root = 1u32 << crate::mesh::MAX_DEPTH;
        (root / cell.size().max(1)).trailing_zeros() as u8
    }
}
