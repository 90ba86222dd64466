//! CSV tables of a sweep.

use super::{ReferencePoints, RunRecord};
use std::fmt::Write as _;

/// The columns of [`runs_csv`], in order.
pub const RUN_COLUMNS: [&str; 17] = [
    "scene",
    "method",
    "parameter",
    "seconds",
    "cpu_seconds",
    "patches",
    "elements",
    "hemicubes",
    "form_factors",
    "patch_form_factors",
    "max_depth",
    "mean_error",
    "rms_error",
    "max_error",
    "l1_error",
    "points",
    "reference_error",
];

/// One row per run, with a header row of [`RUN_COLUMNS`]. `seconds` are
/// wall-clock seconds, `cpu_seconds` user plus system CPU seconds of the
/// process (empty where the platform does not tell). `form_factors` are
/// the element-to-patch form factors stored; `mean_error`, `rms_error`,
/// `max_error` and `l1_error` are [`ErrorSummary`](super::ErrorSummary)'s;
/// `reference_error` is the reference's own mean relative standard error (the
/// same on every row).
#[must_use]
pub fn runs_csv(scene: &str, reference: &ReferencePoints, records: &[RunRecord]) -> String {
    let mut out = RUN_COLUMNS.join(",");
    out.push('\n');
    let noise = reference.mean_relative_std_error();
    for r in records {
        let _ = writeln!(
            out,
            "{},{},{},{:.4},{},{},{},{},{},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{},{:.3e}",
            csv_field(scene),
            r.method,
            r.parameter,
            r.seconds,
            r.cpu_seconds.map_or(String::new(), |c| format!("{c:.4}")),
            r.patches,
            r.elements,
            r.hemicubes,
            r.form_factors,
            r.patch_form_factors,
            r.max_depth,
            r.errors.mean,
            r.errors.rms,
            r.errors.max,
            r.errors.l1,
            r.errors.points,
            noise
        );
    }
    out
}

/// One row per run and non-emitting object: the relative error of the object's
/// mean radiosity (band mean and largest band) and the reference's relative
/// standard error. Only a header when no run measured objects.
#[must_use]
pub fn objects_csv(scene: &str, records: &[RunRecord]) -> String {
    let mut out = String::from(
        "scene,method,parameter,object,mean_band_error,max_band_error,reference_error\n",
    );
    for r in records {
        for o in &r.objects {
            let _ = writeln!(
                out,
                "{},{},{},{},{:.6e},{:.6e},{:.3e}",
                csv_field(scene),
                r.method,
                r.parameter,
                csv_field(&o.name),
                o.error,
                o.max_band_error,
                o.reference_std_error
            );
        }
    }
    out
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn awkward_names_are_quoted() {
        assert_eq!(csv_field("floor"), "floor");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    }
}
