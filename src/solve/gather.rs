//! One gather from patches to leaf elements.

use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use rayon::prelude::*;

/// Power totals of a gather, for the energy balance.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct GatherTotals {
    /// Emitted power, sum of `A_e E_e` (per band).
    pub emitted: Rgb,
    /// Absorbed power, sum of `A_e (1 - rho_e) H_e` with irradiance
    /// `H_e = sum_j F_ej B_j`.
    pub absorbed: Rgb,
}

/// Sets every leaf's radiosity to `E + rho sum_j F_ej B_j` from the patch
/// radiosities `b`, every interior node's to the area-weighted mean of its
/// children, and every patch's to `b`. Returns the power totals.
pub fn gather(mesh: &mut Mesh, b: &[Rgb]) -> GatherTotals {
    let leaves: Vec<ElementKey> = mesh.leaves();
    let results: Vec<(Rgb, Rgb)> = leaves
        .par_iter()
        .map(|&k| {
            let e = &mesh.elements[k];
            let lattice = &mesh.surfaces[e.surface as usize];
            let mut h = Rgb::ZERO;
            for &(j, f) in e.row.entries() {
                h += b[j as usize] * f64::from(f);
            }
            (lattice.emission + lattice.reflectance * h, h)
        })
        .collect();
    let mut totals = GatherTotals::default();
    for (&k, (radiosity, h)) in leaves.iter().zip(&results) {
        let e = &mut mesh.elements[k];
        e.radiosity = *radiosity;
        let lattice = &mesh.surfaces[e.surface as usize];
        totals.emitted += lattice.emission * e.area;
        totals.absorbed += (Rgb::ONE - lattice.reflectance) * *h * e.area;
    }
    for k in mesh.top_roots.clone() {
        push_up(mesh, k);
    }
    for (p, bp) in b.iter().enumerate() {
        mesh.patches[p].radiosity = *bp;
    }
    totals
}

/// Area-weighted mean radiosity of the subtree at `key`, stored in each node.
pub(crate) fn push_up(mesh: &mut Mesh, key: ElementKey) -> Rgb {
    let children = mesh.elements[key].children.clone();
    if children.is_empty() {
        return mesh.elements[key].radiosity;
    }
    let mut sum = Rgb::ZERO;
    for c in children {
        let r = push_up(mesh, c);
        sum += r * mesh.elements[c].area;
    }
    let e = &mut mesh.elements[key];
    e.radiosity = sum / e.area;
    e.radiosity
}
