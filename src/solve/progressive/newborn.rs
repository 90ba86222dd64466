//! New elements born of a refinement pass during shooting receive what their
//! patches' sources have already shot, by one gather against the shot part of
//! the patch radiosities.

use super::ShootingState;
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;

/// Sets each new leaf's irradiance to `sum_j F_ej S_j` from its gathering row
/// in `form_factors` (`F_ej` to patch `j`) and the radiosity `S_j` patch `j`
/// has shot, then re-sums the touched patches. Returns the change in unshot
/// power per band (what the better estimate added to or took from the
/// patches' unshot light).
pub(crate) fn adopt(
    mesh: &Mesh,
    radiosity: &mut Radiosity,
    state: &mut ShootingState,
    form_factors: &FormFactors,
    keys: &[ElementKey],
) -> Rgb {
    for &k in keys {
        let mut h = Rgb::ZERO;
        for &(j, f) in form_factors.entries(k) {
            // What the patch shot came from its open part only.
            h += state.shot[j as usize] * (state.open_scale[j as usize] * f64::from(f));
        }
        state.set_leaf(mesh, radiosity, k, h);
    }
    let mut patches: Vec<u32> = keys.iter().map(|k| mesh.elements[*k].patch).collect();
    patches.sort_unstable();
    patches.dedup();
    let mut change = Rgb::ZERO;
    for p in patches {
        change += state.resum_patch(mesh, radiosity, p) * mesh.patches[p as usize].area;
    }
    change
}
