//! The coarse patch system assembled from element rows.

use super::balance::{balance, is_closed, Balance, Receiver};
use crate::math::Rgb;
use crate::mesh::{Element, Mesh};

/// Patch rows `F_ij = sum_e w_e F_ej / sum_e w_e` with the reflectance and
/// emission of each patch.
///
/// An element that sees nothing (a floor element under a box standing on it
/// sees only the box's back faces) is, by reciprocity, seen by nothing, so it
/// takes no part in the exchange: its weight `w_e` is 0, else its area.
///
/// In a closed scene (see [`super::balance::is_closed`]) the weight is its
/// area times its row sum, `w_e = A_e sum_j F_ej`: its *exposure*, the part
/// of its view that front faces fill. By reciprocity that is how much the
/// other receivers together see of it, so the patch radiosity these rows
/// solve for, the same weighted mean of its elements' radiosities, is the one
/// that carries the power the patch really sends to them. An element of the
/// ceiling above a lamp hung 1 mm below it sees the lamp's back over 97% of
/// its view and the room through the gap: it is lit only through that gap and
/// lights the room only through it. Counting such elements at their whole
/// area diluted the patch's radiosity as a source, and the power they were
/// taken to send into the lamp's back was lost: 3% of the light in a closed
/// room at rho = 0.9, 30% at 0.99. The element rows are then also balanced
/// (see [`super::balance`]): every patch's receivers gather exactly what it
/// sends, every receiver keeps its own row sum. The patch rows are assembled
/// from the balanced rows, `F_ij = sum_e w_e r_e F_ej c_j / sum_e w_e`, and the
/// gather uses the same scales.
#[derive(Clone, Debug, Default)]
pub struct PatchSystem {
    /// Sparse rows, `(j, F_ij)` in increasing `j`.
    pub rows: Vec<Vec<(u32, f64)>>,
    /// Reflectance per patch.
    pub reflectance: Vec<Rgb>,
    /// Emitted exitance per patch.
    pub emission: Vec<Rgb>,
    /// The scales that balance the element rows, receivers in the order of
    /// [`Mesh::leaves`] when the system was assembled (empty: none, as in an
    /// open scene).
    pub balance: Balance,
}

/// The weight of an element in its patch's row and radiosity as a source
/// (see [`PatchSystem`]): in a `closed` scene its exposure, its area times
/// its row sum; elsewhere its area if it sees any front face.
#[must_use]
pub(crate) fn weight(e: &Element, closed: bool) -> f64 {
    if closed {
        e.area * e.row.sum()
    } else if e.row.is_empty() {
        0.0
    } else {
        e.area
    }
}

impl PatchSystem {
    /// Assembles every patch row from the leaves' rows.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let n = mesh.patches.len();
        let mut s = PatchSystem {
            rows: vec![Vec::new(); n],
            reflectance: (0..n as u32).map(|p| mesh.patch_reflectance(p)).collect(),
            emission: (0..n as u32).map(|p| mesh.patch_emission(p)).collect(),
            balance: Balance::default(),
        };
        s.assemble(mesh, None);
        s
    }

    /// Brings the rows up to date after the leaves of the given patches
    /// changed. In a closed scene new leaves change the balance of every row,
    /// so every patch row is assembled again (a pass over the element rows,
    /// as the gather makes); elsewhere only the rows of `patches` change.
    pub fn refresh(&mut self, mesh: &Mesh, patches: &[u32]) {
        self.assemble(mesh, Some(patches));
    }

    /// Balances the element rows of a closed scene and assembles the patch
    /// rows: every one, or only those of `only` where nothing is balanced
    /// now or was before.
    fn assemble(&mut self, mesh: &Mesh, only: Option<&[u32]>) {
        let leaves = mesh.leaves();
        let closed = is_closed(leaves.iter().map(|k| {
            let e = &mesh.elements[*k];
            let emits = mesh.surfaces[e.surface as usize].emission != Rgb::ZERO;
            (e.area, &e.row, emits)
        }));
        let was_balanced = !self.balance.seen.is_empty();
        self.balance = if closed {
            let receivers: Vec<Receiver<'_>> = leaves
                .iter()
                .map(|k| {
                    let e = &mesh.elements[*k];
                    Receiver {
                        patch: e.patch,
                        area: e.area,
                        entries: e.row.entries(),
                    }
                })
                .collect();
            balance(&receivers, mesh.patches.len(), &dark_patches(mesh))
        } else {
            Balance::default()
        };
        let mut dense: Vec<f64> = vec![0.0; mesh.patches.len()];
        let mut touched: Vec<u32> = Vec::new();
        match only.filter(|_| !was_balanced && self.balance.seen.is_empty()) {
            Some(patches) => {
                for &p in patches {
                    // Nothing is balanced: the receivers' order is not needed.
                    let group = mesh.patch_leaves(p);
                    self.assemble_patch(mesh, p, &group, 0, closed, &mut dense, &mut touched);
                }
            }
            None => {
                // Leaves come patch by patch.
                let mut start = 0;
                while start < leaves.len() {
                    let p = mesh.elements[leaves[start]].patch;
                    let end = start
                        + leaves[start..]
                            .iter()
                            .take_while(|k| mesh.elements[**k].patch == p)
                            .count();
                    let group = &leaves[start..end];
                    self.assemble_patch(mesh, p, group, start, closed, &mut dense, &mut touched);
                    start = end;
                }
            }
        }
    }

    /// Assembles the row of patch `p` from its leaves `group`, the first of
    /// them receiver `first` of the balance.
    #[allow(clippy::too_many_arguments)]
    fn assemble_patch(
        &mut self,
        mesh: &Mesh,
        p: u32,
        group: &[crate::mesh::ElementKey],
        first: usize,
        closed: bool,
        dense: &mut [f64],
        touched: &mut Vec<u32>,
    ) {
        let total: f64 = group
            .iter()
            .map(|k| weight(&mesh.elements[*k], closed))
            .sum();
        for (i, k) in (first..).zip(group) {
            let e = &mesh.elements[*k];
            if e.row.is_empty() {
                continue;
            }
            let w = weight(e, closed) / total;
            for &(j, f) in e.row.entries() {
                if dense[j as usize] == 0.0 {
                    touched.push(j);
                }
                dense[j as usize] +=
                    w * f64::from(f) * self.balance.entry(i, p as usize, j as usize);
            }
        }
        touched.sort_unstable();
        self.rows[p as usize] = touched
            .iter()
            .map(|&j| (j, std::mem::take(&mut dense[j as usize])))
            .collect();
        touched.clear();
    }

    /// Number of patches.
    #[must_use]
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True for an empty system.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Stored form factors.
    #[must_use]
    pub fn nonzeros(&self) -> usize {
        self.rows.iter().map(Vec::len).sum()
    }

    /// The largest `rho_i * sum_j F_ij` over patches and bands: the contraction
    /// factor of the iteration in the max norm (below 1 for a solvable system).
    #[must_use]
    pub fn contraction(&self) -> f64 {
        self.rows
            .iter()
            .zip(&self.reflectance)
            .map(|(row, rho)| rho.max_band() * row.iter().map(|e| e.1).sum::<f64>())
            .fold(0.0, f64::max)
    }

    /// `E_i + rho_i sum_j F_ij B_j` for patch `i`.
    #[inline]
    #[must_use]
    pub fn update(&self, i: usize, b: &[Rgb]) -> Rgb {
        let mut s = Rgb::ZERO;
        for &(j, f) in &self.rows[i] {
            s += b[j as usize] * f;
        }
        self.emission[i] + self.reflectance[i] * s
    }
}

/// Per patch, whether it neither emits nor reflects: it carries no light,
/// and takes no part in the balance (see [`balance`]).
#[must_use]
pub(crate) fn dark_patches(mesh: &Mesh) -> Vec<bool> {
    (0..mesh.patches.len() as u32)
        .map(|p| mesh.patch_reflectance(p) == Rgb::ZERO && mesh.patch_emission(p) == Rgb::ZERO)
        .collect()
}
