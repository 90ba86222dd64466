//! Source refinement: a patch whose own elements differ strongly is a poor
//! constant-radiosity source, so it is split and its children become patches.

use crate::formfactor::FormFactors;
use crate::mesh::Mesh;
use crate::solve::Radiosity;

/// Patches whose leaf radiosities spread (largest minus smallest, any band) by
/// more than `tolerance` times the brightest reflected radiosity, and whose
/// children would be no smaller than `min_area` and no deeper than
/// `max_patch_depth` below the initial cut. In patch order.
#[must_use]
pub(crate) fn mark_sources(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    tolerance: f64,
    min_area: f64,
    max_patch_depth: u8,
) -> Vec<u32> {
    let reference = mesh
        .elements
        .iter()
        .filter(|(_, e)| e.is_leaf())
        .map(|(k, e)| (radiosity.element(k) - e.emission).max_band())
        .fold(0.0, f64::max);
    if reference <= 0.0 {
        return Vec::new();
    }
    let mut out = Vec::new();
    for (p, patch) in mesh.patches.iter().enumerate() {
        // A face cluster is a source of many small surfaces: it does not split.
        if patch.is_cluster() {
            continue;
        }
        let root = &mesh.elements[patch.roots[0]];
        if root.depth >= max_patch_depth || patch.area * 0.25 < min_area {
            continue;
        }
        // Only exposed elements count: hidden ones take no part in the exchange.
        let leaves: Vec<_> = mesh
            .patch_leaves(p as u32)
            .into_iter()
            .filter(|k| form_factors.is_exposed(*k))
            .collect();
        if leaves.len() < 2 {
            continue;
        }
        let mut spread: f64 = 0.0;
        for band in 0..3 {
            let values = leaves.iter().map(|k| radiosity.element(*k)[band]);
            let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            spread = spread.max(hi - lo);
        }
        if spread > tolerance * reference {
            out.push(p as u32);
        }
    }
    out
}
