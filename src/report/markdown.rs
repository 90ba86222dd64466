//! The Markdown report of a sweep.

use super::{
    equal_error_speedups, Clock, ErrorMetric, Method, ReferenceKind, ReferencePoints, RunRecord,
    ERROR_FLOOR_FRACTION,
};
use std::fmt::Write as _;

/// A Markdown report: how the reference was made, one table row per run, the
/// equal-error comparisons between methods present, and per-object errors when
/// measured. Errors are in percent with three significant digits.
#[must_use]
pub fn markdown_report(scene: &str, reference: &ReferencePoints, records: &[RunRecord]) -> String {
    let mut out = format!("# Run time against error: {scene}\n\n");
    let n = reference.points.len();
    match reference.kind {
        ReferenceKind::Exact => {
            let _ = writeln!(
                out,
                "Reference: the exact oracle at {n} points spread over the floor."
            );
        }
        ReferenceKind::MonteCarlo { paths, seed } => {
            let _ = writeln!(
                out,
                "Reference: Monte Carlo path tracing at {n} points spread over the \
                 non-emitting surfaces, {paths} paths each (seed {seed}); its mean \
                 relative standard error is {} ({:.1} s).",
                percent(reference.mean_relative_std_error()),
                reference.seconds
            );
        }
    }
    let f = reference.error_floor;
    let _ = writeln!(
        out,
        "Relative error at a point: |B - R| / max(R, f) per band, averaged over the \
         bands, with f = {:.0}% of the points' mean reference radiosity \
         ({:.4}, {:.4}, {:.4}); mean, RMS and max are over the points. The L1 error \
         is the mean |B - R| over the mean R. Seconds: wall-clock time of the \
         library solve, the shortest of its repeats, on a shared machine; CPU \
         seconds: user plus system time of the process over all its threads \
         during the solve, the smallest of the repeats.\n",
        ERROR_FLOOR_FRACTION * 100.0,
        f[0],
        f[1],
        f[2]
    );
    parameters_note(&mut out, records);
    out.push_str(
        "| method | parameter | seconds | CPU seconds | patches | elements | hemi-cubes | \
         form factors | max depth | mean error | RMS error | max error | L1 error |\n",
    );
    out.push_str(
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: \
         | ---: |\n",
    );
    for r in records {
        let _ = writeln!(
            out,
            "| {} | {} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.method,
            parameter(r.parameter),
            r.seconds,
            r.cpu_seconds.map_or(String::new(), |c| format!("{c:.3}")),
            r.patches,
            r.elements,
            r.hemicubes,
            r.form_factors,
            r.max_depth,
            percent(r.errors.mean),
            percent(r.errors.rms),
            percent(r.errors.max),
            percent(r.errors.l1)
        );
    }
    equal_error_section(&mut out, records);
    objects_section(&mut out, records);
    out
}

/// One line per method present saying what its parameter is.
fn parameters_note(out: &mut String, records: &[RunRecord]) {
    for method in Method::ALL {
        if records.iter().any(|r| r.method == method) {
            let _ = writeln!(
                out,
                "- {method}: {}; parameter: {}.",
                method.label(),
                method.parameter_name()
            );
        }
    }
    out.push('\n');
}

/// For each pair of methods present, the cheapest rival run at least as
/// accurate as each candidate run, and the rival's interpolated time, in mean,
/// L1 and largest error; the last column repeats the interpolated ratio in CPU
/// time.
fn equal_error_section(out: &mut String, records: &[RunRecord]) {
    let present = |m: Method| records.iter().any(|r| r.method == m);
    let pairs = [
        (Method::Adaptive, Method::Uniform),
        (Method::Adaptive, Method::Patches),
        (Method::Uniform, Method::Patches),
        (Method::Progressive, Method::Adaptive),
    ];
    for (candidate, rival) in pairs {
        if !(present(candidate) && present(rival)) {
            continue;
        }
        let _ = write!(
            out,
            "\n## {candidate} against {rival} at equal error\n\n\
             For each {candidate} run: the fastest {rival} run with an error no larger and \
             how many times longer it took (that run may be more accurate than needed, \
             which flatters the {candidate} run); then the {rival} time interpolated at \
             exactly this error, in log-log between the two neighbouring runs of its \
             Pareto front, and that ratio (empty where the {rival} runs do not bracket \
             the error). Ratios above 1 mean the {candidate} run is faster. Times are \
             wall-clock seconds; the last column is the interpolated ratio in CPU \
             seconds instead.\n\n\
             | metric | {candidate} run | error | seconds | fastest {rival} run as accurate | \
             its error | its seconds | ratio | {rival} seconds at this error | ratio | \
             CPU ratio |\n\
             | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
        );
        for metric in [ErrorMetric::Mean, ErrorMetric::L1, ErrorMetric::Max] {
            let wall = equal_error_speedups(records, candidate, rival, metric, Clock::Wall);
            let cpu = equal_error_speedups(records, candidate, rival, metric, Clock::Cpu);
            for s in wall {
                let cpu_ratio = cpu
                    .iter()
                    .find(|c| c.parameter == s.parameter)
                    .and_then(|c| c.interpolated_speedup());
                let _ = write!(
                    out,
                    "| {} | {} | {} | {:.3} | ",
                    metric.name(),
                    parameter(s.parameter),
                    percent(s.error),
                    s.seconds
                );
                match s.rival {
                    Some((p, e, t)) => {
                        let _ = write!(
                            out,
                            "{} | {} | {t:.3} | {:.2} | ",
                            parameter(p),
                            percent(e),
                            t / s.seconds
                        );
                    }
                    None => out.push_str("none | | | | "),
                }
                match s.rival_interpolated_seconds {
                    Some(t) => {
                        let _ = write!(out, "{t:.3} | {:.2} | ", t / s.seconds);
                    }
                    None => out.push_str("| | "),
                }
                match cpu_ratio {
                    Some(ratio) => {
                        let _ = writeln!(out, "{ratio:.2} |");
                    }
                    None => out.push_str("|\n"),
                }
            }
        }
    }
}

/// A table of per-object errors, one row per run that measured them.
fn objects_section(out: &mut String, records: &[RunRecord]) {
    let Some(first) = records.iter().find(|r| !r.objects.is_empty()) else {
        return;
    };
    out.push_str(
        "\n## Per-object mean radiosity errors\n\n\
         Relative error of each non-emitting object's area-weighted mean radiosity \
         against the path-traced object means (band mean; reference standard error \
         in the last row).\n\n| method | parameter |",
    );
    for o in &first.objects {
        let _ = write!(out, " {} |", o.name);
    }
    out.push_str("\n| --- | ---: |");
    out.push_str(&" ---: |".repeat(first.objects.len()));
    out.push('\n');
    for r in records.iter().filter(|r| !r.objects.is_empty()) {
        let _ = write!(out, "| {} | {} |", r.method, parameter(r.parameter));
        for o in &r.objects {
            let _ = write!(out, " {} |", percent(o.error));
        }
        out.push('\n');
    }
    out.push_str("| reference | standard error |");
    for o in &first.objects {
        let _ = write!(out, " {} |", percent(o.reference_std_error));
    }
    out.push('\n');
}

/// A parameter with at most three significant digits after the point (patch
/// sizes are long fractions).
fn parameter(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || x.abs() >= 100.0 {
        return format!("{x}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `x` as a percentage with three significant digits.
fn percent(x: f64) -> String {
    let p = x * 100.0;
    if !(p.is_finite() && p > 0.0) {
        return format!("{p}%");
    }
    let decimals = (2 - p.log10().floor() as i32).max(0) as usize;
    format!("{p:.decimals$}%")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentages_keep_three_significant_digits() {
        assert_eq!(percent(0.012_345), "1.23%");
        assert_eq!(percent(0.000_123_4), "0.0123%");
        assert_eq!(percent(0.5), "50.0%");
        assert_eq!(percent(2.0), "200%");
        assert_eq!(percent(0.0), "0%");
        assert_eq!(parameter(0.096_074_038), "0.0961");
        assert_eq!(parameter(0.0125), "0.0125");
        assert_eq!(parameter(128.0), "128");
        assert_eq!(parameter(4.0), "4");
        assert_eq!(parameter(0.05), "0.05");
    }
}
