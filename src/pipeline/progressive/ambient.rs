//! The ambient term of progressive refinement, for display only.
//!
//! Light not yet shot will still arrive somewhere. Spread evenly over a closed
//! scene of mean reflectance `rho_avg`, unshot power `U` raises every radiosity
//! by `rho * Amb` with `Amb = U / (sum A - sum rho A)` (the unshot radiosity
//! times the interreflection factor `1 / (1 - rho_avg)`). Adding it makes early
//! previews about as bright as the converged image instead of too dark. It is
//! never fed back into the solution, and it goes to zero with the unshot power.

use crate::math::Rgb;
use crate::mesh::Mesh;

/// The ambient radiosity per band for the patches' `unshot` radiosities,
/// each sent from its patch's `exposure` (see
/// [`super::ShootingState::exposure`]). A band with no absorption anywhere
/// has no finite ambient estimate and gets 0.
#[must_use]
pub(crate) fn ambient_term(mesh: &Mesh, unshot: &[Rgb], exposure: &[f64]) -> Rgb {
    let mut unshot_power = Rgb::ZERO;
    let mut area = 0.0;
    let mut reflecting = Rgb::ZERO;
    for ((p, u), w) in mesh.patches.iter().zip(unshot).zip(exposure) {
        unshot_power += *u * *w;
        area += p.area;
        reflecting += mesh.surfaces[p.surface as usize].reflectance * p.area;
    }
    let mut amb = Rgb::ZERO;
    for band in 0..3 {
        let absorbing = area - reflecting[band];
        if absorbing > 1e-12 * area {
            amb[band] = unshot_power[band] / absorbing;
        }
    }
    amb
}
