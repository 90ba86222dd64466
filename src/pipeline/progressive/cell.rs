//! One cell of a shooting patch as a shooter: its hemi-cube, the splits where
//! its eye is shut in or (classic) a reciprocal exceeds 1, and the form factors
//! it contributes (see [`super::shoot`] for the forms).

use super::shoot::{CellCounts, HIDDEN_EYE};
use super::visibility::{partly_visible, ray_fraction, visible_fractions, ShooterEye};
use super::Receivers;
use crate::formfactor::hemicube::{Coverage, Hemicube, HemicubeStats};
use crate::formfactor::{
    element_seed, point_to_polygon, receiving_point, FormFactorMethod, Sources,
};
use crate::math::{clip_to_halfspace, polygon_area, polygon_centroid};
use crate::mesh::{Cell, Mesh};
use glam::DVec3;
use smallvec::SmallVec;

/// One cell of the shooting patch, as a shooter.
struct CellShooter {
    polygon: SmallVec<[DVec3; 4]>,
    area: f64,
    eye: DVec3,
    angle: f64,
}

/// What one top-level cell of a shot produced.
#[derive(Default)]
pub(super) struct CellResult {
    /// `(leaf index, form factor)` contributions.
    pub(super) out: Vec<(u32, f64)>,
    /// What its cells did.
    pub(super) counts: CellCounts,
    /// Its hemi-cubes' work.
    pub(super) work: HemicubeStats,
    /// The cells it turned out to consist of once shut-in parts were split
    /// off (and dropped where shut in at the deepest level).
    pub(super) open: Vec<Cell>,
}

/// What every cell of one shot shares (but its surface: a face cluster's
/// cells lie on several).
#[derive(Clone, Copy)]
pub(super) struct CellContext<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) receivers: &'a Receivers,
    /// The shooting patch.
    pub(super) patch: u32,
    pub(super) surface: u32,
    pub(super) seed: u64,
    pub(super) method: FormFactorMethod,
    /// Deepest cell level below the patch for splits of shut-in cells.
    pub(super) deepest: u8,
}

impl CellContext<'_> {
    fn cell_shooter(&self, cell: &Cell) -> CellShooter {
        let lattice = &self.mesh.surfaces[self.surface as usize];
        let polygon = lattice.polygon(cell);
        let area = polygon_area(&polygon);
        let eye = receiving_point(polygon_centroid(&polygon), lattice.normal, area);
        let h = element_seed(self.seed, self.surface, cell);
        let angle = (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64) * std::f64::consts::TAU;
        CellShooter {
            polygon,
            area,
            eye,
            angle,
        }
    }

    /// Area of the exposed and of the shut-in leaves of the shooting patch
    /// within `cell` (a cell inside one leaf takes that leaf's side whole).
    fn exposure(&self, cell: &Cell) -> (f64, f64) {
        let r = self.receivers;
        let (mut exposed, mut hidden) = (0.0, 0.0);
        for i in r.patch_leaves[self.patch as usize].clone() {
            let i = i as usize;
            let leaf = &self.mesh.elements[r.leaves[i]].cell;
            let area = if cell.holds(leaf) {
                r.areas[i]
            } else if leaf.holds(cell) {
                let whole = polygon_area(&self.mesh.surfaces[self.surface as usize].polygon(cell));
                return if r.exposed[i] {
                    (whole, 0.0)
                } else {
                    (0.0, whole)
                };
            } else {
                continue;
            };
            if r.exposed[i] {
                exposed += area;
            } else {
                hidden += area;
            }
        }
        (exposed, hidden)
    }

    /// Shoots from one cell: splits it where part of it is shut in (leaves
    /// that are not exposed, or an eye that is shut in) or (classic) a
    /// reciprocal exceeds 1, else adds its form factors. Cells found open are
    /// listed in `r.open` when `record` (not below a classic split, which
    /// depends on the receivers of the moment).
    pub(super) fn shoot(&self, cube: &mut Hemicube, cell: &Cell, record: bool, r: &mut CellResult) {
        // Only the exposed leaves take part in the exchange, so only they
        // shoot: a cell holding both kinds is split until each part is one
        // kind (which ends at the leaves themselves, at the latest), and a cell
        // of shut-in leaves shoots only from what sticks out of the object.
        let (exposed, hidden) = self.exposure(cell);
        if exposed <= 0.0 {
            self.shut_in(cell, record, r);
            return;
        }
        if hidden > 0.0 {
            r.counts.hidden_splits += 1;
            for child in cell.children() {
                self.shoot(cube, &child, record, r);
            }
            return;
        }
        let s = self.cell_shooter(cell);
        let normal = self.mesh.surfaces[self.surface as usize].normal;
        // Hybrid renders patches first (see `visibility`); classic needs every
        // leaf's own pixel count.
        let first = match self.method {
            FormFactorMethod::Hybrid => &self.receivers.patch_sources,
            FormFactorMethod::Hemicube => &self.receivers.sources,
        };
        let seen = cube.coverage(
            first,
            s.eye,
            normal,
            s.angle,
            self.surface,
            self.receivers.twins.as_deref(),
        );
        if seen.back_faces > HIDDEN_EYE {
            let can_split = self.level_of(cell) < self.deepest && cell.size() >= 2;
            // The eye is shut in though the cell's leaves are not (their
            // centres lie outside the object, the cell's centre inside):
            // smaller cells find the part outside; what is still shut in at the
            // deepest level shoots only past the object's faces.
            if can_split {
                r.counts.hidden_splits += 1;
                for child in cell.children() {
                    self.shoot(cube, &child, record, r);
                }
            } else {
                self.shut_in(cell, record, r);
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
                // No level limit here: once a cell is no larger than the
                // receivers it overshoots, `F_se A_s / A_e <= F_se <= 1`, so
                // the splitting stops by itself (or at the lattice's finest
                // cell).
                if cell.size() >= 2 && reciprocal.iter().any(|e| e.1 > 1.0) {
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

    /// A cell shut inside an object renders nothing: its eye sees only back
    /// faces. But the part of it sticking out past one of the object's faces
    /// (a floor leaf straddling a block's foot, its centre under the block)
    /// lights that face, and gathering counts it, as the face's leaves see
    /// the whole patch above their horizon. It shoots to those faces alone,
    /// from that part (see [`Self::cut_by_receivers`]). The cell is kept in
    /// the patch's cells (`record`) so that it does so at every shot.
    fn shut_in(&self, cell: &Cell, record: bool, r: &mut CellResult) {
        r.counts.hidden_cells += 1;
        if record {
            r.open.push(*cell);
        }
        if self.method == FormFactorMethod::Hybrid {
            let s = self.cell_shooter(cell);
            let normal = self.mesh.surfaces[self.surface as usize].normal;
            self.cut_by_receivers(&s, normal, &mut r.out);
        }
    }

    /// Renders the leaves of the partly visible patches among the other
    /// patches, and returns their coverage by leaf index.
    fn partly_visible_leaves(
        &self,
        cube: &mut Hemicube,
        s: &CellShooter,
        normal: DVec3,
        patches: &[Coverage],
        counts: &mut CellCounts,
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
        let mut polygons = Vec::with_capacity(r.patch_sources.polygons.len() + extra);
        // Leaf index of each polygon of the mixed list; whole patches only hide.
        let mut leaf_of = Vec::with_capacity(polygons.capacity());
        let mut next = partly.iter().peekable();
        for p in 0..r.patch_sources.patch_count() as u32 {
            if next.peek() == Some(&&p) {
                next.next();
                let range = r.patch_leaves[p as usize].clone();
                polygons.extend_from_slice(
                    &r.sources.polygons[range.start as usize..range.end as usize],
                );
                leaf_of.extend(range);
            } else {
                for poly in r.patch_sources.patch(p) {
                    polygons.push(poly.clone());
                    leaf_of.push(u32::MAX);
                }
            }
        }
        // Every polygon its own item, so that each leaf is counted apart.
        let mixed = Sources::one_per_patch(polygons);
        let seen = cube.coverage(
            &mixed,
            s.eye,
            normal,
            s.angle,
            self.surface,
            self.receivers.twins.as_deref(),
        );
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
        s: &CellShooter,
        normal: DVec3,
        patches: &[Coverage],
        leaves: &[Coverage],
        out: &mut Vec<(u32, f64)>,
    ) {
        let eye = ShooterEye {
            occluders: &self.receivers.occluders,
            point: s.eye,
            surface: self.surface,
        };
        for (i, v) in visible_fractions(self.receivers, patches, leaves, &eye) {
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
        self.cut_by_receivers(s, normal, out);
    }

    /// Hybrid, for the patches whose plane cuts the cell with the cell's eye
    /// behind it (a floor cell beside a block, past the end of the block's
    /// side face): the item buffer shows the patch from behind, so it gives
    /// none of its leaves a visible fraction, yet the part of the cell in
    /// front of the plane lights them. Their visibility is judged by shadow
    /// rays from the middle of that part instead; the magnitude, Lambert's
    /// formula from each leaf, counts that part alone by clipping the cell at
    /// the leaf's horizon. (Without this both blocks of the Cornell box got
    /// about 1% less light from the floor than gathering gives them.)
    fn cut_by_receivers(&self, s: &CellShooter, normal: DVec3, out: &mut Vec<(u32, f64)>) {
        let r = self.receivers;
        let margin = 1e-9 * s.area.sqrt();
        for poly in &r.patch_sources.polygons {
            if poly.surface == self.surface {
                continue;
            }
            let p = poly.patch as usize;
            let (origin, n) = (poly.vertices[0], poly.normal);
            if n.dot(s.eye - origin) > 0.0 || !s.polygon.iter().any(|v| n.dot(*v - origin) > margin)
            {
                continue;
            }
            let front = clip_to_halfspace(&s.polygon, origin, n);
            if front.len() < 3 {
                continue;
            }
            let eye = ShooterEye {
                occluders: &r.occluders,
                point: receiving_point(polygon_centroid(&front), normal, s.area),
                surface: self.surface,
            };
            for i in r.patch_leaves[p].clone() {
                // A face cluster's other surfaces have polygons of their own.
                if r.sources.polygons[i as usize].surface != poly.surface {
                    continue;
                }
                let at = r.eyes[i as usize];
                if (at - eye.point).dot(normal) <= 0.0 {
                    continue;
                }
                let f = point_to_polygon(at, r.normals[i as usize], &s.polygon);
                if f <= 0.0 {
                    continue;
                }
                let v = ray_fraction(r, i, &eye);
                if v > 0.0 {
                    out.push((i, f * v));
                }
            }
        }
    }

    /// Depth of a cell below its patch (from the lattice cell sizes).
    fn level_of(&self, cell: &Cell) -> u8 {
        let root = 1u32 << crate::mesh::MAX_DEPTH;
        (root / cell.size().max(1)).trailing_zeros() as u8
    }
}
