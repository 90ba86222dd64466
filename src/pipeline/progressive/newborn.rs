//! New elements born of a refinement pass during shooting receive what their
//! patches' sources have already shot, by one gather against the shot part of
//! the patch radiosities.

use super::{Receivers, ShootingState, ShotCache};
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;

/// Sets each new leaf's irradiance to `sum_j F_ej S_j` from its gathering row
/// in `form_factors` (`F_ej` to patch `j` as the gather takes it: a facet
/// that borrows its group lead's row sees the emitters itself; with the
/// balance's scales when shots deliver by them) and the radiosity `S_j` patch `j` has shot, then
/// re-sums the touched patches. Returns the change in unshot power per band
/// (what the better estimate added to or took from the patches' unshot
/// light).
pub(crate) fn adopt(
    mesh: &Mesh,
    radiosity: &mut Radiosity,
    state: &mut ShootingState,
    form_factors: &FormFactors,
    keys: &[ElementKey],
) -> Rgb {
    for &k in keys {
        let mut h = Rgb::ZERO;
        for (j, f) in form_factors.gathered_entries(k) {
            h += state.shot[j as usize] * (f * state.delivery_scale(j, k));
        }
        state.set_leaf(mesh, radiosity, k, h);
    }
    let mut patches: Vec<u32> = keys.iter().map(|k| mesh.elements[*k].patch).collect();
    patches.sort_unstable();
    patches.dedup();
    resum(mesh, radiosity, state, &patches)
}

/// Sets every leaf's irradiance to what the patches have shot, delivered by
/// the factors `cache` holds for every patch (the transposed gathering rows),
/// and re-sums every patch: after the rows or their balance changed, the
/// state is then what shooting by them would have given. Returns the change
/// in unshot power per band.
pub(crate) fn regather(
    mesh: &Mesh,
    radiosity: &mut Radiosity,
    state: &mut ShootingState,
    receivers: &Receivers,
    cache: &ShotCache,
) -> Rgb {
    let mut h = vec![Rgb::ZERO; receivers.len()];
    for j in 0..mesh.patches.len() as u32 {
        let shot = state.shot[j as usize];
        for &(k, f) in cache.get(j, u8::MAX).unwrap_or_default() {
            if let Some(&i) = receivers.index.get(k) {
                h[i as usize] += shot * (f * state.delivery_scale(j, k));
            }
        }
    }
    let before = state.signed_unshot_power();
    for (&k, h) in receivers.leaves.iter().zip(h) {
        state.set_leaf(mesh, radiosity, k, h);
    }
    let patches: Vec<u32> = (0..mesh.patches.len() as u32).collect();
    resum(mesh, radiosity, state, &patches);
    state.signed_unshot_power() - before
}

/// Where the signed unshot power of a band is negative, scales what has
/// been shot, and with it every leaf's irradiance, so that it is zero;
/// returns whether it did. Only for a state whose irradiances are what the
/// balanced rows deliver from what has been shot (after [`regather`], and
/// shots by those rows), which is linear in it.
///
/// A refined mesh may absorb more than the coarser one did (at rho = 0.999,
/// refining around a lamp hung 1 mm under the ceiling raised the absorption
/// of the gap above it and took back 12% of the light in one pass): what the
/// patches have shot is then more than the new solution holds, and their
/// unshot power, the light still to deliver, is negative. A shot of positive
/// light while other patches hold such negative corrections can overshoot
/// too. Since the balanced rows conserve light, the signed unshot power is
/// exactly the emitted power not yet absorbed, `sum_e w_e E_e - sum_e (A_e -
/// w_e rho_e) H_e` (`w_e` the leaves' weights), and scaling what has been shot
/// by the factor that makes it zero, in each band where it is negative,
/// leaves a state that holds no more light than was emitted. It is only the
/// starting point the shots go on from; they converge to the same solution,
/// and faster: in the room with the lamp at rho = 0.999 the solve took
/// 975 000 shots with the negative corrections, 328 000 with the scaled state.
pub(crate) fn settle(
    mesh: &Mesh,
    radiosity: &mut Radiosity,
    state: &mut ShootingState,
    receivers: &Receivers,
) -> bool {
    let unshot = state.signed_unshot_power();
    if (0..3).all(|band| unshot[band] >= 0.0) {
        return false;
    }
    // Light emitted from the exposed parts, and what the irradiance takes
    // out of the exchange (absorbed, or sent to back faces or the sky).
    let (mut emitted, mut taken) = (Rgb::ZERO, Rgb::ZERO);
    for (i, &k) in receivers.leaves.iter().enumerate() {
        let e = &mesh.elements[k];
        let w = receivers.areas[i] * receivers.exposure[i];
        let h = state.irradiance.get(k).copied().unwrap_or(Rgb::ZERO);
        emitted += e.emission * w;
        if let Some(hd) = state.direct_irradiance(k) {
            // Reflected punctual light is emission to the exchange.
            emitted += e.reflectance * hd * w;
        }
        taken += (Rgb::splat(e.area) - e.reflectance * w) * h;
    }
    let mut scale = Rgb::ONE;
    for band in 0..3 {
        if unshot[band] < 0.0 && taken[band] > emitted[band] {
            scale[band] = emitted[band] / taken[band];
        }
    }
    if scale == Rgb::ONE {
        return false;
    }
    // What is no longer counted as shot is unshot again: radiosity stays
    // shot plus unshot.
    for (s, u) in state.shot.iter_mut().zip(&mut state.unshot) {
        let kept = *s * scale;
        *u += *s - kept;
        *s = kept;
    }
    for &k in &receivers.leaves {
        let h = state.irradiance.get(k).copied().unwrap_or(Rgb::ZERO);
        state.set_leaf(mesh, radiosity, k, h * scale);
    }
    let patches: Vec<u32> = (0..mesh.patches.len() as u32).collect();
    resum(mesh, radiosity, state, &patches);
    true
}

/// Re-sums `patches`; the change in unshot power per band.
fn resum(mesh: &Mesh, radiosity: &Radiosity, state: &mut ShootingState, patches: &[u32]) -> Rgb {
    let mut change = Rgb::ZERO;
    for &p in patches {
        change += state.resum_patch(mesh, radiosity, p) * state.exposure[p as usize];
    }
    change
}
