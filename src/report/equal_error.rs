//! How much faster one method reaches an error than another.

use super::{ErrorMetric, Method, RunRecord};

/// Which time of a run to compare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clock {
    /// [`RunRecord::seconds`]: wall-clock time.
    Wall,
    /// [`RunRecord::cpu_seconds`]: CPU time of the process, steadier on a
    /// shared machine. Runs without it are left out.
    Cpu,
}

impl Clock {
    /// The run's time on this clock.
    #[must_use]
    pub(crate) fn of(self, record: &RunRecord) -> Option<f64> {
        match self {
            Clock::Wall => Some(record.seconds),
            Clock::Cpu => record.cpu_seconds,
        }
    }
}

/// One run of the faster candidate against the cheapest run of the other
/// method that is at least as accurate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EqualErrorSpeedup {
    /// The run's parameter.
    pub parameter: f64,
    /// Its error (in the metric compared).
    pub error: f64,
    /// Its seconds (on the clock compared).
    pub seconds: f64,
    /// The cheapest run of the other method with an error no larger, if any:
    /// its parameter, error and seconds.
    pub rival: Option<(f64, f64, f64)>,
    /// The other method's seconds at exactly this run's error, interpolated
    /// linearly in log error and log time between two of its runs, one less
    /// and one more accurate (the cheapest such estimate); `None` when no two
    /// of its runs bracket the error.
    pub rival_interpolated_seconds: Option<f64>,
}

impl EqualErrorSpeedup {
    /// The rival's seconds over this run's: above 1 when this run is faster at
    /// equal or better error. `None` when no rival run is that accurate.
    #[cfg(test)]
    #[must_use]
    pub(crate) fn speedup(&self) -> Option<f64> {
        self.rival.map(|(_, _, s)| s / self.seconds)
    }

    /// [`Self::rival_interpolated_seconds`] over this run's seconds.
    #[must_use]
    pub(crate) fn interpolated_speedup(&self) -> Option<f64> {
        self.rival_interpolated_seconds.map(|s| s / self.seconds)
    }
}

/// For every run of `candidate` (in record order), the cheapest run of `rival`
/// whose `metric` error is no larger, and the rival's time interpolated at the
/// candidate's error, all times on `clock`. The measured rival run may be more
/// accurate than needed, so where the rival's curve is coarse
/// [`EqualErrorSpeedup::speedup`] overstates the candidate's advantage; the
/// interpolated figure does not. Runs without a time on `clock` are left out.
#[must_use]
pub(crate) fn equal_error_speedups(
    records: &[RunRecord],
    candidate: Method,
    rival: Method,
    metric: ErrorMetric,
    clock: Clock,
) -> Vec<EqualErrorSpeedup> {
    let rival_method = rival;
    let timed = |method: Method| {
        records
            .iter()
            .filter(move |r| r.method == method)
            .filter_map(move |r| clock.of(r).map(|t| (r, t)))
    };
    timed(candidate)
        .map(|(r, seconds)| {
            let error = metric.of(&r.errors);
            let rival = timed(rival_method)
                .filter(|(o, _)| metric.of(&o.errors) <= error)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(o, t)| (o.parameter, metric.of(&o.errors), t));
            let curve: Vec<(f64, f64)> = timed(rival_method)
                .map(|(o, t)| (t, metric.of(&o.errors)))
                .collect();
            EqualErrorSpeedup {
                parameter: r.parameter,
                error,
                seconds,
                rival,
                rival_interpolated_seconds: interpolated_seconds(curve, error),
            }
        })
        .collect()
}

/// The time at which a curve of `(seconds, error)` runs reaches `error`: on
/// the curve's Pareto front (the runs that no faster run beats in error), log
/// time is interpolated linearly in log error between the two neighbouring
/// runs that bracket `error`. `None` when the front does not reach `error` or
/// starts below it.
fn interpolated_seconds(mut runs: Vec<(f64, f64)>, error: f64) -> Option<f64> {
    runs.retain(|(t, e)| *t > 0.0 && *e > 0.0);
    runs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for run in runs {
        if front.last().is_none_or(|last| run.1 < last.1) {
            front.push(run);
        }
    }
    if front.iter().any(|p| p.1 == error) {
        return front.iter().find(|p| p.1 == error).map(|p| p.0);
    }
    front.windows(2).find_map(|pair| {
        let ((t_coarse, e_coarse), (t_fine, e_fine)) = (pair[0], pair[1]);
        (e_fine < error && error < e_coarse).then(|| {
            let w = (error.ln() - e_coarse.ln()) / (e_fine.ln() - e_coarse.ln());
            (t_coarse.ln() + w * (t_fine.ln() - t_coarse.ln())).exp()
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::ErrorSummary;

    fn record(method: Method, parameter: f64, seconds: f64, mean: f64) -> RunRecord {
        RunRecord {
            method,
            parameter,
            seconds,
            cpu_seconds: Some(2.0 * seconds),
            patches: 0,
            elements: 0,
            hemicubes: 0,
            form_factors: 0,
            patch_form_factors: 0,
            max_depth: 0,
            errors: ErrorSummary {
                mean,
                rms: mean,
                max: mean,
                l1: mean,
                points: 1,
            },
            objects: Vec::new(),
        }
    }

    #[test]
    fn the_cheapest_rival_at_least_as_accurate_is_chosen() {
        let records = [
            record(Method::Uniform, 1.0, 1.0, 0.10),
            record(Method::Uniform, 2.0, 4.0, 0.05),
            record(Method::Uniform, 3.0, 16.0, 0.02),
            // Slower and less accurate than depth 2: off the front, ignored.
            record(Method::Uniform, 9.0, 5.0, 0.06),
            record(Method::Adaptive, 0.1, 2.0, 0.04),
            record(Method::Adaptive, 0.01, 3.0, 0.01),
        ];
        let s = equal_error_speedups(
            &records,
            Method::Adaptive,
            Method::Uniform,
            ErrorMetric::Mean,
            Clock::Wall,
        );
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].rival, Some((3.0, 0.02, 16.0)));
        assert_eq!(s[0].speedup(), Some(8.0));
        assert_eq!(s[1].rival, None);
        assert_eq!(s[1].speedup(), None);
        // 0.04 lies between uniform's 0.05 (4 s) and 0.02 (16 s), neighbours
        // on its front: in log-log, w = ln(0.8) / ln(0.4), t = 4 * 4^w.
        let w = 0.8f64.ln() / 0.4f64.ln();
        let t = 4.0 * 4f64.powf(w);
        assert!((s[0].rival_interpolated_seconds.unwrap() - t).abs() < 1e-12);
        assert!((s[0].interpolated_speedup().unwrap() - t / 2.0).abs() < 1e-12);
        assert_eq!(s[1].rival_interpolated_seconds, None);
        // The test records' CPU time is twice the wall time: the same ratios.
        let cpu = equal_error_speedups(
            &records,
            Method::Adaptive,
            Method::Uniform,
            ErrorMetric::Mean,
            Clock::Cpu,
        );
        assert_eq!(cpu[0].rival, Some((3.0, 0.02, 32.0)));
        assert!((cpu[0].interpolated_speedup().unwrap() - t / 2.0).abs() < 1e-12);
        // A run without a CPU time is left out of CPU comparisons.
        let mut partial = records.to_vec();
        partial[2].cpu_seconds = None;
        let cpu = equal_error_speedups(
            &partial,
            Method::Adaptive,
            Method::Uniform,
            ErrorMetric::Mean,
            Clock::Cpu,
        );
        assert_eq!(cpu[0].rival, None);
    }
}
