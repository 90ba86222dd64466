//! Gauss-Seidel on the patch system, accelerated by residual-minimising
//! extrapolation, stopping on a residual bound.
//!
//! # The stopping bound
//!
//! Write the system as `K B = E` with `K = I - diag(rho) F` and let
//! `q = max_i rho_i sum_j F_ij` (the [`PatchSystem::contraction`]). For *any*
//! vector `B`, with residual `r = E + rho F B - B`, the error is
//! `B* - B = K^-1 r`, and because `rho F` is non-negative with row sums at most
//! `q < 1`, `|K^-1|_inf <= 1 + q + q^2 + ... = 1 / (1 - q)`. So
//! `|B - B*|_inf <= |r|_inf / (1 - q)`, whatever produced `B`: plain sweeps,
//! over-relaxed sweeps or the extrapolation below. The bound needs nothing
//! from the iteration but the true residual of the vector it stops on, which is
//! what is computed. (It does not hold for a *relative-change* rule, which
//! stops far too early when `rho` is close to 1.)
//!
//! # The accelerator
//!
//! In a closed scene with reflectance close to 1 the error of Gauss-Seidel is
//! dominated by one smooth mode that shrinks by about `rho` a sweep, so plain
//! sweeps need `O(1 / (1 - rho))` of them (about 6000 at `rho = 0.999`). After
//! each sweep from `B` to `B'`, the change `d = B' - B` points along that mode,
//! and the residual along the line `B' + c d` is `r' - c (r - r')` (as
//! `K d = r - r'`), known without another product with `F`. Taking the `c` that
//! minimises its 2-norm (per band, the bands being independent systems) removes
//! the mode in one step and can never leave a larger 2-norm residual than the
//! sweep alone (`c = 0` is a candidate). Negative values are clamped to 0 after
//! the step: the solution is non-negative, so clamping moves every component
//! towards it and keeps the bound. The extrapolation starts once a few plain
//! sweeps have not converged, so easy systems are solved exactly as before,
//! and stops for good if the residual stalls (plain sweeps always converge).

use super::PatchSystem;
use crate::error::{Error, Result, SolverFault};
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
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-5,
            max_iterations: 100_000,
        }
    }
}

/// What the solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SolveReport {
    /// Sweeps performed.
    pub iterations: usize,
    /// Sweeps followed by an extrapolation step (see the module notes).
    pub extrapolations: usize,
    /// Largest absolute residual `|E + rho F B - B|` at the end, any band.
    pub residual: f64,
    /// Bound on the largest absolute error of a patch radiosity.
    pub error_bound: f64,
    /// The contraction factor `max rho_i sum_j F_ij`.
    pub contraction: f64,
}

/// Plain sweeps before the extrapolation starts: systems far from singular
/// converge in about this many and never see it.
pub(super) const PLAIN_SWEEPS: usize = 8;

/// Sweeps without a new smallest residual after which the extrapolation is
/// switched off for the rest of the solve. Plain Gauss-Seidel contracts the
/// error by `q` a sweep in the max norm, whatever the start, so falling back to
/// it guarantees convergence where the extrapolation might only stall.
pub(super) const STALL_SWEEPS: usize = 64;

// The largest contraction factor accepted bounds the reflectance a scene
// may hold, so the scene, which checks its materials, owns it.
pub use crate::scene::MAX_CONTRACTION;

/// A radiosity value the iteration works on: three bands ([`Rgb`]), or one
/// (`f64`) for a grey scene, whose bands are equal and independent, so one
/// band's arithmetic is every band's, operation for operation.
trait Bands:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Mul<f64, Output = Self>
    + std::ops::AddAssign
{
    const ZERO: Self;
    const COUNT: usize;
    fn band(&self, k: usize) -> f64;
    fn band_mut(&mut self, k: usize) -> &mut f64;
    fn largest_abs(&self) -> f64;
    fn largest(&self) -> f64;
}

impl Bands for Rgb {
    const ZERO: Self = Rgb::ZERO;
    const COUNT: usize = 3;
    fn band(&self, k: usize) -> f64 {
        self.0[k]
    }
    fn band_mut(&mut self, k: usize) -> &mut f64 {
        &mut self.0[k]
    }
    fn largest_abs(&self) -> f64 {
        self.abs().max_band()
    }
    fn largest(&self) -> f64 {
        self.max_band()
    }
}

impl Bands for f64 {
    const ZERO: Self = 0.0;
    const COUNT: usize = 1;
    fn band(&self, _: usize) -> f64 {
        *self
    }
    fn band_mut(&mut self, _: usize) -> &mut f64 {
        self
    }
    fn largest_abs(&self) -> f64 {
        self.abs()
    }
    fn largest(&self) -> f64 {
        *self
    }
}

/// The patch system seen in one kind of [`Bands`].
struct BandSystem<'a, V> {
    rows: &'a [Vec<(u32, f64)>],
    emission: &'a [V],
    reflectance: &'a [V],
}

impl<V: Bands> BandSystem<'_, V> {
    fn len(&self) -> usize {
        self.rows.len()
    }

    /// `E_i + rho_i sum_j F_ij B_j`, as [`PatchSystem::update`].
    #[inline]
    fn update(&self, i: usize, b: &[V]) -> V {
        let mut s = V::ZERO;
        for &(j, f) in &self.rows[i] {
            s += b[j as usize] * f;
        }
        self.emission[i] + self.reflectance[i] * s
    }
}

/// `E + rho F B - B` for every patch.
fn residuals<V: Bands>(system: &BandSystem<'_, V>, b: &[V], out: &mut Vec<V>) {
    out.clear();
    out.extend((0..system.len()).map(|i| system.update(i, b) - b[i]));
}

fn max_abs<V: Bands>(r: &[V]) -> f64 {
    r.iter().map(Bands::largest_abs).fold(0.0, f64::max)
}

/// The patch with the largest `rho_i sum_j F_ij` (a NaN counts as largest),
/// with its reflectance and row sum, for messages.
fn worst_row(system: &PatchSystem) -> (usize, f64, f64) {
    let rows = system.rows.iter().zip(&system.reflectance).enumerate();
    let all = rows.map(|(i, (row, rho))| (i, rho.max_band(), row.iter().map(|e| e.1).sum::<f64>()));
    all.max_by(|a, b| {
        let key = |x: &(usize, f64, f64)| {
            let p = x.1 * x.2;
            if p.is_nan() {
                f64::INFINITY
            } else {
                p
            }
        };
        key(a).total_cmp(&key(b))
    })
    .unwrap_or((0, 0.0, 0.0))
}

/// Solves the patch system in place, starting from `b` (a warm start after a
/// refinement). Stops when the error bound is below `tolerance` times the
/// largest radiosity; fails with the residual reached after `max_iterations`
/// sweeps, and at once when the system has no bounded solution or one too
/// close to singular to mean anything (contraction above [`MAX_CONTRACTION`]).
pub fn gauss_seidel(
    system: &PatchSystem,
    b: &mut [Rgb],
    settings: &SolverSettings,
) -> Result<SolveReport> {
    gauss_seidel_with_source(system, &system.emission, b, settings)
}

/// [`gauss_seidel`] with `source` in place of the system's emission, from
/// `b`.
pub(crate) fn gauss_seidel_with_source(
    system: &PatchSystem,
    source: &[Rgb],
    b: &mut [Rgb],
    settings: &SolverSettings,
) -> Result<SolveReport> {
    let q = checked_contraction(system)?;
    let bands = BandSystem {
        rows: &system.rows,
        emission: source,
        reflectance: &system.reflectance,
    };
    iterate(&bands, q, b, settings)
}

/// [`gauss_seidel`] for a grey system (every reflectance and emission, and
/// the start `b`, equal in all three bands): iterates on one band and copies
/// it into the others. The bands of a grey system are the same independent
/// system, and one band goes through exactly the operations each band goes
/// through in [`gauss_seidel`], so the result and the report are the same
/// bits, for a third of the arithmetic. Fails if the system or `b` is not
/// grey.
pub(crate) fn gauss_seidel_grey(
    system: &PatchSystem,
    b: &mut [Rgb],
    settings: &SolverSettings,
) -> Result<SolveReport> {
    let grey = |v: &[Rgb]| v.iter().all(|x| x.is_grey());
    if !(grey(&system.emission) && grey(&system.reflectance) && grey(b)) {
        return Err(Error::solver(
            SolverFault::Internal,
            "the one-band solve needs grey reflectances, emissions and start values".into(),
        ));
    }
    let q = checked_contraction(system)?;
    let band = |v: &[Rgb]| v.iter().map(|x| x.0[0]).collect::<Vec<f64>>();
    let (emission, reflectance) = (band(&system.emission), band(&system.reflectance));
    let bands = BandSystem {
        rows: &system.rows,
        emission: &emission,
        reflectance: &reflectance,
    };
    let mut one = band(b);
    let report = iterate(&bands, q, &mut one, settings);
    for (x, v) in b.iter_mut().zip(one) {
        *x = Rgb::splat(v);
    }
    report
}

/// The contraction factor, or the error that explains why the system has no
/// meaningful solution.
fn checked_contraction(system: &PatchSystem) -> Result<f64> {
    let q = system.contraction();
    if q.is_nan() || q > MAX_CONTRACTION {
        let (patch, rho, sum) = worst_row(system);
        refuse_unbounded_row(patch, rho, sum)?;
        // A NaN anywhere else.
        return Err(Error::solver(
            SolverFault::NotANumber,
            format!(
                "reflectance times form-factor row sum is {q} (patch {patch}: reflectance {rho}, \
             row sum {sum}): not a number"
            ),
        ));
    }
    Ok(q)
}

/// The error for patch `patch` of reflectance `rho` (largest band) and row
/// sum `sum` when their product exceeds [`MAX_CONTRACTION`] (or is not a
/// number): the system has no meaningful solution. Both solvers refuse such a
/// scene with it.
pub(crate) fn refuse_unbounded_row(patch: usize, rho: f64, sum: f64) -> Result<()> {
    let q = rho * sum;
    if !q.is_nan() && q <= MAX_CONTRACTION {
        return Ok(());
    }
    let what = if q >= 1.0 || q.is_nan() {
        "light would grow without bound"
    } else {
        "the system is too close to singular for single-precision form factors"
    };
    let fault = if q.is_nan() {
        SolverFault::NotANumber
    } else {
        SolverFault::Unbounded
    };
    Err(Error::solver(
        fault,
        format!(
            "reflectance times form-factor row sum reaches {q:.7} (patch {patch}: reflectance \
         {rho}, row sum {sum:.7}), above the {MAX_CONTRACTION} allowed: {what}; lower the \
         reflectances closest to 1"
        ),
    ))
}

/// The iteration itself, on any [`Bands`], with contraction factor `q`.
fn iterate<V: Bands>(
    system: &BandSystem<'_, V>,
    q: f64,
    b: &mut [V],
    settings: &SolverSettings,
) -> Result<SolveReport> {
    let mut report = SolveReport {
        contraction: q,
        ..SolveReport::default()
    };
    let mut r = Vec::with_capacity(b.len());
    let mut r_next = Vec::with_capacity(b.len());
    let mut before: Vec<V> = Vec::with_capacity(b.len());
    residuals(system, b, &mut r);
    let mut accelerate = true;
    let (mut best, mut since_best) = (f64::INFINITY, 0);
    loop {
        let residual = max_abs(&r);
        if residual < best {
            (best, since_best) = (residual, 0);
        } else {
            since_best += 1;
            accelerate &= since_best < STALL_SWEEPS;
        }
        let scale = b.iter().map(Bands::largest).fold(0.0, f64::max);
        report.residual = residual;
        report.error_bound = residual / (1.0 - q);
        if !report.error_bound.is_finite() || !scale.is_finite() {
            return Err(Error::solver(
                SolverFault::Diverged,
                format!(
                    "the iteration diverged after {} sweeps (residual {residual})",
                    report.iterations
                ),
            ));
        }
        if report.error_bound <= settings.tolerance * scale || scale == 0.0 {
            return Ok(report);
        }
        if report.iterations >= settings.max_iterations {
            return Err(Error::solver(
                SolverFault::NotConverged,
                format!(
                    "no convergence after {} sweeps: residual {residual:.3e}, error bound {:.3e} \
                 (tolerance {:.1e} of {scale:.3e}): reflectances this close to 1 converge too \
                 slowly; lower them or loosen `solver.tolerance`",
                    report.iterations, report.error_bound, settings.tolerance
                ),
            ));
        }
        before.clear();
        before.extend_from_slice(b);
        for i in 0..system.len() {
            b[i] = system.update(i, b);
        }
        report.iterations += 1;
        residuals(system, b, &mut r_next);
        if accelerate && report.iterations >= PLAIN_SWEEPS && extrapolate(b, &before, &r, &r_next) {
            report.extrapolations += 1;
            residuals(system, b, &mut r);
        } else {
            std::mem::swap(&mut r, &mut r_next);
        }
    }
}

/// Moves `b` (just swept from `before`, whose residual was `r`; its own is
/// `r_next`) to `b + c (b - before)` with the `c` per band that minimises the
/// 2-norm of the residual, clamping at 0. Returns false, leaving `b` alone,
/// when no band has a useful step.
fn extrapolate<V: Bands>(b: &mut [V], before: &[V], r: &[V], r_next: &[V]) -> bool {
    let bands = V::COUNT;
    let mut num = [0.0; 3];
    let mut den = [0.0; 3];
    for (now, prev) in r_next.iter().zip(r) {
        for band in 0..bands {
            let dr = prev.band(band) - now.band(band);
            num[band] += now.band(band) * dr;
            den[band] += dr * dr;
        }
    }
    let step: [f64; 3] = std::array::from_fn(|band| match num[band] / den[band] {
        c if band < bands && c.is_finite() && c > 0.0 && den[band] > 0.0 => c,
        _ => 0.0,
    });
    if step == [0.0; 3] {
        return false;
    }
    for (x, prev) in b.iter_mut().zip(before) {
        for (band, c) in step.iter().enumerate().take(bands) {
            let v = x.band(band);
            *x.band_mut(band) = (v + c * (v - prev.band(band))).max(0.0);
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grey system of `n` patches, each seeing 8 others, with row sums 0.995
    /// and reflectance 0.99: nearly singular, so the extrapolation works too.
    fn nearly_singular_grey_system(n: usize) -> PatchSystem {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let rows = (0..n)
            .map(|i| {
                let mut js: Vec<u32> = (1..=8).map(|k| ((i + 7 * k) % n) as u32).collect();
                js.sort_unstable();
                js.dedup();
                let w: Vec<f64> = js.iter().map(|_| 0.5 + next()).collect();
                let total: f64 = w.iter().sum();
                js.into_iter()
                    .zip(w)
                    .map(|(j, x)| (j, 0.995 * x / total))
                    .collect()
            })
            .collect();
        PatchSystem {
            rows,
            reflectance: vec![Rgb::splat(0.99); n],
            emission: (0..n)
                .map(|i| Rgb::splat(if i % 5 == 0 { 1.0 + next() } else { 0.0 }))
                .collect(),
            balance: Default::default(),
        }
    }

    #[test]
    fn one_band_gauss_seidel_is_three_band_gauss_seidel_bit_for_bit() {
        let system = nearly_singular_grey_system(200);
        let settings = SolverSettings::default();
        let mut three = system.emission.clone();
        let mut one = system.emission.clone();
        let a = gauss_seidel(&system, &mut three, &settings).unwrap();
        let b = gauss_seidel_grey(&system, &mut one, &settings).unwrap();
        assert!(
            a.extrapolations > 0,
            "the test wants the extrapolation used"
        );
        assert_eq!(a, b);
        assert_eq!(
            three
                .iter()
                .map(|x| x.0.map(f64::to_bits))
                .collect::<Vec<_>>(),
            one.iter()
                .map(|x| x.0.map(f64::to_bits))
                .collect::<Vec<_>>()
        );
        // A coloured system is refused.
        let mut coloured = system;
        coloured.reflectance[3] = Rgb::new(0.5, 0.6, 0.7);
        let mut b = coloured.emission.clone();
        assert!(gauss_seidel_grey(&coloured, &mut b, &settings).is_err());
    }
}
