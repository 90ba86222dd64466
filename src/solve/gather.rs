//! One gather from patches to leaf elements.

use super::Radiosity;
use crate::formfactor::FormFactors;
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

/// Sets every leaf's radiosity in `radiosity` to `E + rho sum_j F_ej B_j`
/// from the patch radiosities `b` and the leaves' rows, every interior node's
/// to the area-weighted mean of its children, and every patch's to `b`.
/// Returns the power totals.
pub fn gather(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &mut Radiosity,
    b: &[Rgb],
) -> GatherTotals {
    gather_with(mesh, form_factors, radiosity, b, &GatherOptions::default())
}

/// How [`gather_with`] works.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct GatherOptions<'a> {
    /// Every reflectance, emission and patch radiosity is grey: gather one
    /// band and copy it (the same bits as three bands, for a third of the
    /// arithmetic).
    pub grey: bool,
    /// Per patch, true when its elements were given no rows because they
    /// reflect nothing (see [`crate::pipeline::Skips`]). The power such a
    /// patch absorbs is then summed from the other elements' rows by
    /// reciprocity: element `e` sends `A_e F_ej B_e` of its power to patch
    /// `j`, which absorbs all of it.
    pub rowless: Option<&'a [bool]>,
}

/// [`gather`] with `options`.
pub(crate) fn gather_with(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &mut Radiosity,
    b: &[Rgb],
    options: &GatherOptions<'_>,
) -> GatherTotals {
    let leaves: Vec<ElementKey> = mesh.leaves();
    let rowless = options.rowless;
    // Per leaf: radiosity, irradiance, and the form factor of its row to
    // patches without rows.
    let results: Vec<(Rgb, Rgb, f64)> = leaves
        .par_iter()
        .map(|&k| {
            let e = &mesh.elements[k];
            let lattice = &mesh.surfaces[e.surface as usize];
            let entries = form_factors.entries(k);
            let h = if options.grey {
                let mut h = 0.0;
                for &(j, f) in entries {
                    h += b[j as usize].0[0] * f64::from(f);
                }
                Rgb::splat(h)
            } else {
                let mut h = Rgb::ZERO;
                for &(j, f) in entries {
                    h += b[j as usize] * f64::from(f);
                }
                h
            };
            let to_rowless = rowless.map_or(0.0, |flags| {
                entries
                    .iter()
                    .filter(|(j, _)| flags[*j as usize])
                    .map(|&(_, f)| f64::from(f))
                    .sum()
            });
            let radiosity = if options.grey {
                let (rho, emission) = (lattice.reflectance.0[0], lattice.emission.0[0]);
                Rgb::splat(emission + rho * h.0[0])
            } else {
                lattice.emission + lattice.reflectance * h
            };
            (radiosity, h, to_rowless)
        })
        .collect();
    let mut totals = GatherTotals::default();
    for (&k, (value, h, to_rowless)) in leaves.iter().zip(&results) {
        radiosity.set_element(k, *value);
        let e = &mesh.elements[k];
        let lattice = &mesh.surfaces[e.surface as usize];
        totals.emitted += lattice.emission * e.area;
        totals.absorbed += (Rgb::ONE - lattice.reflectance) * *h * e.area;
        if *to_rowless > 0.0 {
            totals.absorbed += *value * (e.area * to_rowless);
        }
    }
    for &k in &mesh.top_roots {
        radiosity.push_up(mesh, k);
    }
    radiosity.set_patches(b);
    totals
}
