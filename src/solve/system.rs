//! The coarse patch system assembled from element rows.

use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::Mesh;

/// Patch rows `F_ij = (1 / A_i) sum_e A_e F_ej` with the reflectance and
/// emission of each patch.
///
/// The sums run over the patch's *exposed* elements: those whose hemi-cube saw
/// some front face. An element that sees nothing (a floor element under a box
/// standing on it sees only the box's back faces) is, by reciprocity, seen by
/// nothing, so it takes no part in the exchange; counting its area would dilute
/// the patch's radiosity as a source and darken everything the patch lights.
/// A patch with no exposed element keeps an empty row.
#[derive(Clone, Debug, Default)]
pub struct PatchSystem {
    /// Sparse rows, `(j, F_ij)` in increasing `j`.
    pub rows: Vec<Vec<(u32, f64)>>,
    /// Reflectance per patch.
    pub reflectance: Vec<Rgb>,
    /// Emitted exitance per patch.
    pub emission: Vec<Rgb>,
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
        };
        let all: Vec<u32> = (0..n as u32).collect();
        s.refresh(mesh, form_factors, &all);
        s
    }

    /// Recomputes the rows of the given patches (after their leaves changed).
    pub fn refresh(&mut self, mesh: &Mesh, form_factors: &FormFactors, patches: &[u32]) {
        let mut dense: Vec<f64> = Vec::new();
        let mut touched: Vec<u32> = Vec::new();
        for &p in patches {
            let leaves = mesh.patch_leaves(p);
            let area: f64 = leaves
                .iter()
                .filter(|k| form_factors.is_exposed(**k))
                .map(|k| mesh.elements[*k].area)
                .sum();
            for k in leaves {
                let w = mesh.elements[k].area / area;
                for &(j, f) in form_factors.entries(k) {
                    let j = j as usize;
                    if j >= dense.len() {
                        dense.resize(mesh.patches.len(), 0.0);
                    }
                    if dense[j] == 0.0 {
                        touched.push(j as u32);
                    }
                    dense[j] += w * f64::from(f);
                }
            }
            touched.sort_unstable();
            self.rows[p as usize] = touched
                .iter()
                .map(|&j| (j, std::mem::take(&mut dense[j as usize])))
                .collect();
            touched.clear();
        }
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
