//! The coarse patch system assembled from element rows.

use super::balance::{balance, is_closed, Balance, Receiver};
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};

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

/// The weight of leaf `k` in its patch's row and radiosity as a source (see
/// [`PatchSystem`]): in a `closed` scene its exposure, its area times its row
/// sum; elsewhere its area if it sees any front face.
#[must_use]
pub(crate) fn weight(mesh: &Mesh, form_factors: &FormFactors, k: ElementKey, closed: bool) -> f64 {
    let area = mesh.elements[k].area;
    let state = form_factors.state(k);
    if closed {
        area * state.view().map_or(0.0, |v| v.sum)
    } else if state.is_exposed() {
        area * state.view().map_or(1.0, |v| v.visible())
    } else {
        0.0
    }
}

/// Whether the leaves' rows find the scene closed (see
/// [`super::balance::is_closed`]).
#[must_use]
pub(crate) fn scene_is_closed(
    mesh: &Mesh,
    form_factors: &FormFactors,
    leaves: &[ElementKey],
) -> bool {
    is_closed(leaves.iter().map(|&k| {
        let e = &mesh.elements[k];
        let emits = e.emission != Rgb::ZERO;
        let view = form_factors.view(k).unwrap_or_default();
        (e.area, view, emits)
    }))
}

impl PatchSystem {
    /// Assembles every patch row from the leaves' rows.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh, form_factors: &FormFactors) -> Self {
        let n = mesh.patches.len();
        let mut s = PatchSystem {
            rows: vec![Vec::new(); n],
            reflectance: (0..n as u32).map(|p| mesh.patch_reflectance(p)).collect(),
            emission: (0..n as u32).map(|p| mesh.patch_emission(p)).collect(),
            balance: Balance::default(),
        };
        s.assemble(mesh, form_factors, None);
        s
    }

    /// Brings the rows up to date after the leaves of the given patches
    /// changed. In a closed scene new leaves change the balance of every row,
    /// so every patch row is assembled again (a pass over the element rows,
    /// as the gather makes); elsewhere only the rows of `patches` change.
    pub fn refresh(&mut self, mesh: &Mesh, form_factors: &FormFactors, patches: &[u32]) {
        self.assemble(mesh, form_factors, Some(patches));
    }

    /// Balances the element rows of a closed scene and assembles the patch
    /// rows: every one, or only those of `only` where nothing is balanced
    /// now or was before.
    fn assemble(&mut self, mesh: &Mesh, form_factors: &FormFactors, only: Option<&[u32]>) {
        let leaves = mesh.leaves();
        let closed = scene_is_closed(mesh, form_factors, &leaves);
        let was_balanced = !self.balance.seen.is_empty();
        self.balance = if closed {
            let receivers: Vec<Receiver<'_>> = leaves
                .iter()
                .map(|&k| {
                    let e = &mesh.elements[k];
                    Receiver {
                        patch: e.patch,
                        area: e.area,
                        entries: form_factors.entries(k),
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
                    let at = AssembleAt { first: 0, closed };
                    self.assemble_patch(
                        mesh,
                        form_factors,
                        p,
                        &group,
                        at,
                        &mut dense,
                        &mut touched,
                    );
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
                    let at = AssembleAt {
                        first: start,
                        closed,
                    };
                    self.assemble_patch(mesh, form_factors, p, group, at, &mut dense, &mut touched);
                    start = end;
                }
            }
        }
    }

    /// Assembles the row of patch `p` from its leaves `group`.
    #[allow(clippy::too_many_arguments)]
    fn assemble_patch(
        &mut self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        p: u32,
        group: &[ElementKey],
        at: AssembleAt,
        dense: &mut [f64],
        touched: &mut Vec<u32>,
    ) {
        let closed = at.closed;
        let total: f64 = group
            .iter()
            .map(|k| weight(mesh, form_factors, *k, closed))
            .sum();
        for (i, &k) in (at.first..).zip(group) {
            let entries = form_factors.entries(k);
            if entries.is_empty() {
                continue;
            }
            // A partly covered leaf's row is its mean over its area; as a
            // source, its visible part stands for it (see `contacts.rs`).
            let visible = form_factors.view(k).map_or(1.0, |v| v.visible());
            let w = weight(mesh, form_factors, k, closed) / total / visible;
            // What a facet that borrows its lead's row sees of the
            // emitters itself (see `FormFactors::emitter_shift`).
            let shift = form_factors.emitter_shift(k);
            let (scale, added) =
                shift.map_or((1.0, &[][..]), |s| (f64::from(s.scale), &s.entries[..]));
            let scaled = entries.iter().map(|&(j, f)| (j, f64::from(f) * scale));
            let added = added.iter().map(|&(j, d)| (j, f64::from(d)));
            for (j, f) in scaled.chain(added) {
                if dense[j as usize] == 0.0 {
                    touched.push(j);
                }
                dense[j as usize] += w * f * self.balance.entry(i, p as usize, j as usize);
            }
        }
        touched.sort_unstable();
        // A shift can bring a sum back to exactly 0 before it grows again.
        touched.dedup();
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

/// Where a patch's leaves stand among the balance's receivers, and whether
/// the scene is closed.
#[derive(Clone, Copy)]
struct AssembleAt {
    /// The receiver index of the group's first leaf.
    first: usize,
    closed: bool,
}

/// Per patch, whether it neither emits nor reflects: it carries no light,
/// and takes no part in the balance (see [`balance`]).
#[must_use]
pub(crate) fn dark_patches(mesh: &Mesh) -> Vec<bool> {
    (0..mesh.patches.len() as u32)
        .map(|p| mesh.patch_reflectance(p) == Rgb::ZERO && mesh.patch_emission(p) == Rgb::ZERO)
        .collect()
}
