//! Gauss-Seidel on the patch system, stopping on a residual bound.

use super::PatchSystem;
use crate::error::{Error, Result};
use crate::math::Rgb;

/// When to stop.
#[derive(Clone, Debug)]
pub struct SolverSettings {
    /// Stop when the bound on the largest error of any patch radiosity,
    /// `|r|_inf / (1 - q)` with `q` the contraction factor, falls below this
    /// fraction of the largest radiosity.
    pub tolerance: f64,
    /// Sweeps after which a solve that has not converged fails.
    pub max_iterations: usize,
    /// Over-relaxation factor (1 is plain Gauss-Seidel; up to about 1.9 speeds up
    /// nearly singular systems with reflectance close to 1).
    pub relaxation: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-5,
            max_iterations: 100_000,
            relaxation: 1.0,
        }
    }
}

/// What the solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SolveReport {
    /// Sweeps performed.
    pub iterations: usize,
    /// Largest absolute residual `|E + rho F B - B|` at the end, any band.
    pub residual: f64,
    /// Bound on the largest absolute error of a patch radiosity.
    pub error_bound: f64,
    /// The contraction factor `max rho_i sum_j F_ij`.
    pub contraction: f64,
}

fn max_residual(system: &PatchSystem, b: &[Rgb]) -> f64 {
    (0..system.len())
        .map(|i| (system.update(i, b) - b[i]).abs().max_band())
        .fold(0.0, f64::max)
}

/// Solves the patch system in place, starting from `b` (a warm start after a
/// refinement). Stops when the error bound is below `tolerance` times the
/// largest radiosity; fails with the residual reached after `max_iterations`,
/// or at once when the system has no bounded solution (contraction >= 1).
pub fn gauss_seidel(
    system: &PatchSystem,
    b: &mut [Rgb],
    settings: &SolverSettings,
) -> Result<SolveReport> {
    let q = system.contraction();
    if q >= 1.0 {
        return Err(Error::Solver(format!(
            "reflectance times form-factor row sum reaches {q:.6} >= 1: light would grow \
             without bound (a closed scene with reflectance 1?)"
        )));
    }
    let omega = settings.relaxation;
    let mut report = SolveReport {
        contraction: q,
        ..SolveReport::default()
    };
    loop {
        let residual = max_residual(system, b);
        let scale = b.iter().map(|x| x.max_band()).fold(0.0, f64::max);
        report.residual = residual;
        report.error_bound = residual / (1.0 - q);
        if !report.error_bound.is_finite() {
            return Err(Error::Solver(format!(
                "the iteration diverged after {} sweeps (residual {residual})",
                report.iterations
            )));
        }
        if report.error_bound <= settings.tolerance * scale || scale == 0.0 {
            return Ok(report);
        }
        if report.iterations >= settings.max_iterations {
            return Err(Error::Solver(format!(
                "no convergence after {} sweeps: residual {residual:.3e}, error bound {:.3e} \
                 (tolerance {:.1e} of {scale:.3e}); raise --max-iterations or use over-relaxation",
                report.iterations, report.error_bound, settings.tolerance
            )));
        }
        for i in 0..system.len() {
            let gs = system.update(i, b);
            b[i] = if omega == 1.0 {
                gs
            } else {
                b[i] + (gs - b[i]) * omega
            };
        }
        report.iterations += 1;
    }
}
