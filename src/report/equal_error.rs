//! How much faster one method reaches an error than another.

use super::{ErrorMetric, Method, RunRecord};

/// One run of the faster candidate against the cheapest run of the other
/// method that is at least as accurate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EqualErrorSpeedup {
    /// The run's parameter.
    pub parameter: f64,
    /// Its error (in the metric compared).
    pub error: f64,
    /// Its seconds.
    pub seconds: f64,
    /// The cheapest run of the other method with an error no larger, if any:
    /// its parameter, error and seconds.
    pub rival: Option<(f64, f64, f64)>,
}

impl EqualErrorSpeedup {
    /// The rival's seconds over this run's: above 1 when this run is faster at
    /// equal or better error. `None` when no rival run is that accurate.
    #[must_use]
    pub fn speedup(&self) -> Option<f64> {
        self.rival.map(|(_, _, s)| s / self.seconds)
    }
}

/// For every run of `candidate` (in record order), the cheapest run of `rival`
/// whose `metric` error is no larger. This compares measured runs only; it
/// never interpolates between them, so the speedups are lower bounds where the
/// rival's curve is coarse.
#[must_use]
pub fn equal_error_speedups(
    records: &[RunRecord],
    candidate: Method,
    rival: Method,
    metric: ErrorMetric,
) -> Vec<EqualErrorSpeedup> {
    records
        .iter()
        .filter(|r| r.method == candidate)
        .map(|r| {
            let error = metric.of(&r.errors);
            let rival = records
                .iter()
                .filter(|o| o.method == rival && metric.of(&o.errors) <= error)
                .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
                .map(|o| (o.parameter, metric.of(&o.errors), o.seconds));
            EqualErrorSpeedup {
                parameter: r.parameter,
                error,
                seconds: r.seconds,
                rival,
            }
        })
        .collect()
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
            record(Method::Adaptive, 0.1, 2.0, 0.04),
            record(Method::Adaptive, 0.01, 3.0, 0.01),
        ];
        let s = equal_error_speedups(
            &records,
            Method::Adaptive,
            Method::Uniform,
            ErrorMetric::Mean,
        );
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].rival, Some((3.0, 0.02, 16.0)));
        assert_eq!(s[0].speedup(), Some(8.0));
        assert_eq!(s[1].rival, None);
        assert_eq!(s[1].speedup(), None);
    }
}
