//! A truncated solution: emitted light and a fixed number of reflections.
//!
//! The full solution of `B = E + rho F B` is the sum of every generation of
//! reflected light, `B = E + (rho F) E + (rho F)^2 E + ...`. Keeping the first
//! `N + 1` terms gives the radiosity after exactly `N` reflections, which the
//! Jacobi iteration produces one term per step:
//!
//! ```text
//! B^(0)   = E
//! B^(k+1) = E + rho F B^(k)      (so B^(k) = sum_{j<=k} (rho F)^j E)
//! ```
//!
//! (Gauss-Seidel would mix generations within a sweep, so it cannot stop after
//! a given number.) With `N = 1` this is direct illumination only: what a ray
//! tracer with no ambient term computes for diffuse surfaces, the comparison
//! the seed paper draws with its Ferren sculpture example.
//!
//! The element gather adds one reflection of its own (`B_e = E_e + rho_e
//! sum_j F_ej B_j`), so [`gather_bounces`] gathers from `B^(N-1)` to give the
//! elements exactly `N` reflections, like the patches' `B^(N)`.

use super::{gather_with, GatherOptions, GatherTotals, PatchSystem, Radiosity, SolveReport};
use crate::error::{Error, Result};
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::Mesh;

/// The most reflections a truncated solve may ask for: beyond a few dozen the
/// truncation is invisible next to the full solution, which is cheaper.
pub(crate) const MAX_BOUNCES: u32 = 1000;

/// `B^(reflections)`: the patch radiosities after exactly `reflections`
/// reflections of the emitted light (see the module notes), every band at once.
/// `0` gives the emission alone.
#[must_use]
pub(crate) fn bounced_radiosity(system: &PatchSystem, reflections: u32) -> Vec<Rgb> {
    bounced_from(system, system.emission.clone(), reflections)
}

/// `B^(reflections)` from `B^(0) = first`. With punctual lights the system's
/// emission holds their reflected light, `E + D`, which is one reflection
/// in: `B^(0)` is then the surfaces' emission alone, and every later
/// generation `E + D + rho F B`.
fn bounced_from(system: &PatchSystem, first: Vec<Rgb>, reflections: u32) -> Vec<Rgb> {
    let mut b = first;
    let mut next = b.clone();
    for _ in 0..reflections {
        for (i, out) in next.iter_mut().enumerate() {
            *out = system.update(i, &b);
        }
        std::mem::swap(&mut b, &mut next);
    }
    b
}

/// Element radiosities carrying exactly `bounces` reflections: gathers from
/// the patch radiosities `B^(bounces - 1)`, then leaves `B^(bounces)` in `b`
/// and in the mesh's patches, so that patches and elements agree on what they
/// hold. The report's `iterations` is `bounces` (Jacobi steps); its residual
/// and error bound measure how far the truncated patch radiosities are from
/// the full solution (the bound is infinite where the system does not
/// contract). Fails for `bounces` of 0 or above [`MAX_BOUNCES`].
pub(crate) fn gather_bounces(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &mut Radiosity,
    system: &PatchSystem,
    b: &mut [Rgb],
    bounces: u32,
    options: &GatherOptions<'_>,
) -> Result<(SolveReport, GatherTotals)> {
    check_bounces(bounces)?;
    let before = if options.direct.is_some() {
        let emitted = (0..mesh.patches.len() as u32)
            .map(|p| mesh.patch_emission(p))
            .collect();
        bounced_from(system, emitted, bounces - 1)
    } else {
        bounced_radiosity(system, bounces - 1)
    };
    let totals = gather_with(mesh, form_factors, radiosity, &before, options);
    for (i, out) in b.iter_mut().enumerate() {
        *out = system.update(i, &before);
    }
    radiosity.set_patches(b);
    let residual = (0..system.len())
        .map(|i| (system.update(i, b) - b[i]).abs().max_band())
        .fold(0.0, f64::max);
    let q = system.contraction();
    let report = SolveReport {
        iterations: bounces as usize,
        extrapolations: 0,
        residual,
        error_bound: if q < 1.0 {
            residual / (1.0 - q)
        } else {
            f64::INFINITY
        },
        contraction: q,
    };
    Ok((report, totals))
}

/// Checks the number of reflections of a truncated solve; the error names the
/// setting.
pub(crate) fn check_bounces(bounces: u32) -> Result<()> {
    if (1..=MAX_BOUNCES).contains(&bounces) {
        return Ok(());
    }
    Err(Error::Setting {
        name: "bounces",
        message: format!(
            "must be 1 (direct light only) to {MAX_BOUNCES}, got {bounces}; leave it out for \
             the full solution"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed enclosure of `n` patches that all see each other equally
    /// (`F_ij = 1 / n`, rows summing to 1), all emitting `e` with reflectance
    /// `rho`: every generation is uniform, so `B^(N) = e sum_{k<=N} rho^k`.
    fn furnace(n: usize, e: Rgb, rho: Rgb) -> PatchSystem {
        let row: Vec<(u32, f64)> = (0..n as u32).map(|j| (j, 1.0 / n as f64)).collect();
        PatchSystem {
            rows: vec![row; n],
            reflectance: vec![rho; n],
            emission: vec![e; n],
            balance: Default::default(),
        }
    }

    #[test]
    fn each_step_adds_one_generation_of_the_geometric_series() {
        let e = Rgb::new(1.0, 2.0, 0.5);
        let rho = Rgb::new(0.5, 0.8, 0.25);
        let system = furnace(5, e, rho);
        for n in 0..6u32 {
            let b = bounced_radiosity(&system, n);
            for band in 0..3 {
                let expected: f64 = (0..=n).map(|k| e[band] * rho[band].powi(k as i32)).sum();
                for bi in &b {
                    assert!(
                        (bi[band] - expected).abs() <= 1e-12 * expected,
                        "n {n} band {band}: {} vs {expected}",
                        bi[band]
                    );
                }
            }
        }
    }

    #[test]
    fn one_bounce_lights_a_receiver_by_emitter_times_form_factor() {
        // Patch 0 emits 3 and sees nothing; patch 1 (reflectance 0.6) sees
        // patch 0 with F = 0.25 and itself not at all. One reflection:
        // B_1 = 0.6 * 0.25 * 3; more reflections add nothing (patch 0 sees
        // nothing and patch 1 only patch 0).
        let system = PatchSystem {
            rows: vec![vec![], vec![(0, 0.25)]],
            reflectance: vec![Rgb::splat(0.5), Rgb::splat(0.6)],
            emission: vec![Rgb::splat(3.0), Rgb::ZERO],
            balance: Default::default(),
        };
        assert_eq!(bounced_radiosity(&system, 0)[1], Rgb::ZERO);
        let direct = 0.6 * 0.25 * 3.0;
        for n in 1..4 {
            let b = bounced_radiosity(&system, n);
            assert!((b[1][0] - direct).abs() < 1e-15, "{n}: {:?}", b[1]);
            assert_eq!(b[0], Rgb::splat(3.0));
        }
    }

    #[test]
    fn zero_and_too_many_bounces_are_refused_by_name() {
        for n in [0, MAX_BOUNCES + 1] {
            let e = check_bounces(n).unwrap_err().to_string();
            assert!(e.contains("bounces"), "{e}");
        }
        assert!(check_bounces(1).is_ok());
        assert!(check_bounces(MAX_BOUNCES).is_ok());
    }
}
