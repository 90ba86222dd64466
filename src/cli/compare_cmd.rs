//! `radiosity compare`: a solve's per-surface radiosities against a reference.
//!
//! The two files must describe the same objects: every surface of either must
//! be in the other (matched by name), and every value must be a finite,
//! non-negative number; anything else is an error naming the file, the
//! surface and the field. A band whose reference value is zero has no relative
//! error: it is reported as the absolute difference instead and kept out of
//! the relative mean and maximum, so that one black band can neither make the
//! mean infinite nor hide behind it.

use super::args::CompareArgs;
use super::stdout::write_out;
use super::surface_table::{read_table, SurfaceRow, SurfaceTable};
use anyhow::{bail, Result};
use std::fmt::Write as _;

const BANDS: [&str; 3] = ["R", "G", "B"];

/// Largest relative difference between the areas the two files give one
/// surface: the solve sums its elements, the reference its surfaces, so they
/// agree to rounding; a different scene with the same object names differs
/// by far more.
const AREA_TOLERANCE: f64 = 1e-3;

/// Most names listed when surfaces are missing on either side.
const NAMES_SHOWN: usize = 8;

/// One band of one surface.
#[derive(Clone, Copy, Debug, PartialEq)]
enum BandError {
    /// (solution - reference) / reference.
    Relative(f64),
    /// The reference is zero: solution - reference.
    Absolute(f64),
}

/// One surface of the comparison.
#[derive(Debug)]
struct Row<'a> {
    reference: &'a SurfaceRow,
    bands: [BandError; 3],
}

/// The comparison of two checked tables.
#[derive(Debug)]
struct Comparison<'a> {
    rows: Vec<Row<'a>>,
    /// |relative error| of every counted (non-emitting, non-zero) band.
    relative: Vec<f64>,
}

/// Matches the tables by name and computes every band's error. Errors name
/// the surfaces only one side has.
fn compare<'a>(solution: &SurfaceTable, reference: &'a SurfaceTable) -> Result<Comparison<'a>> {
    let find = |t: &SurfaceTable, name: &str| t.rows.iter().position(|r| r.name == name);
    let missing: Vec<&str> = reference
        .rows
        .iter()
        .filter(|r| find(solution, &r.name).is_none())
        .map(|r| r.name.as_str())
        .collect();
    let extra: Vec<&str> = solution
        .rows
        .iter()
        .filter(|s| find(reference, &s.name).is_none())
        .map(|s| s.name.as_str())
        .collect();
    if !missing.is_empty() || !extra.is_empty() {
        bail!(
            "the solution and the reference do not describe the same objects: {}{}{}",
            listed("in the reference only", &missing),
            if missing.is_empty() || extra.is_empty() {
                ""
            } else {
                "; "
            },
            listed("in the solution only", &extra)
        );
    }
    let mut rows = Vec::with_capacity(reference.rows.len());
    let mut relative = Vec::new();
    for r in &reference.rows {
        let s = &solution.rows[find(solution, &r.name).expect("matched above")];
        if let (Some(sa), Some(ra)) = (s.area, r.area) {
            if (sa - ra).abs() > AREA_TOLERANCE * sa.max(ra) {
                bail!(
                    "surface '{}' has an area of {sa} m² in the solution and {ra} m² in the \
                     reference: they are not of the same scene",
                    r.name
                );
            }
        }
        let bands = std::array::from_fn(|k| {
            let (got, want) = (s.radiosity[k], r.radiosity[k]);
            if want == 0.0 {
                BandError::Absolute(got - want)
            } else {
                BandError::Relative((got - want) / want)
            }
        });
        if !r.emits {
            relative.extend(bands.iter().filter_map(|b| match b {
                BandError::Relative(e) => Some(e.abs()),
                BandError::Absolute(_) => None,
            }));
        }
        rows.push(Row {
            reference: r,
            bands,
        });
    }
    Ok(Comparison { rows, relative })
}

/// `what: 'a', 'b' (and N more)`, or nothing for an empty list.
fn listed(what: &str, names: &[&str]) -> String {
    if names.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = names
        .iter()
        .take(NAMES_SHOWN)
        .map(|n| format!("'{n}'"))
        .collect();
    let more = names.len().saturating_sub(NAMES_SHOWN);
    let tail = if more > 0 {
        format!(" (and {more} more)")
    } else {
        String::new()
    };
    format!("{what}: {}{tail}", shown.join(", "))
}

/// Runs `radiosity compare`: prints a table and the mean and largest relative
/// error over every band of every surface the reference marks as not
/// emitting (an emitter's radiosity is mostly its own emission, which would
/// flatter the mean; emitters are listed but not counted). Bands with a zero
/// reference are listed by their absolute difference below the table.
pub fn run(a: &CompareArgs) -> Result<()> {
    let solution = read_table(&a.solution)?;
    let reference = read_table(&a.reference)?;
    if let (Some(s), Some(r)) = (&solution.scene, &reference.scene) {
        if s != r {
            bail!(
                "{} is a solution of the scene '{s}' and {} a reference of '{r}': compare \
                 needs both of the same scene",
                a.solution.display(),
                a.reference.display()
            );
        }
    }
    let comparison = compare(&solution, &reference).map_err(|e| {
        e.context(format!(
            "comparing {} with {}",
            a.solution.display(),
            a.reference.display()
        ))
    })?;
    let mut text = table(&comparison);
    let c = &comparison.relative;
    if c.is_empty() {
        write_out(&text)?;
        bail!(
            "no band to compare: every surface emits or has a zero reference (see the absolute \
             differences above)"
        );
    }
    let mean = c.iter().sum::<f64>() / c.len() as f64;
    let max = c.iter().copied().fold(0.0, f64::max);
    writeln!(
        text,
        "mean per-surface error {:.3}%, largest {:.3}% ({} surface-bands)",
        100.0 * mean,
        100.0 * max,
        c.len()
    )?;
    write_out(&text)
}

/// The table of per-surface errors, and the bands with a zero reference.
fn table(c: &Comparison) -> String {
    let mut text = String::from(
        "surface          relative error (R, G, B) %         reference std. error %\n",
    );
    let mut zero_bands = Vec::new();
    for row in &c.rows {
        let r = row.reference;
        let cells: Vec<String> = row
            .bands
            .iter()
            .enumerate()
            .map(|(k, b)| match b {
                BandError::Relative(e) => format!("{:+7.3}", 100.0 * e),
                BandError::Absolute(d) => {
                    zero_bands.push((r.name.as_str(), BANDS[k], *d));
                    format!("{:>7}", "ref=0")
                }
            })
            .collect();
        let se: Vec<String> = (0..3)
            .map(|k| match (r.std_error, r.radiosity[k]) {
                (Some(x), v) if v > 0.0 => format!("{:.3}", 100.0 * x[k] / v),
                _ => "-".to_string(),
            })
            .collect();
        let _ = writeln!(
            text,
            "{:<16} {} {} {}{}   {} {} {}",
            r.name,
            cells[0],
            cells[1],
            cells[2],
            if r.emits {
                " (emitter, not counted)"
            } else {
                ""
            },
            se[0],
            se[1],
            se[2]
        );
    }
    if !zero_bands.is_empty() {
        let _ = writeln!(
            text,
            "{} surface-bands have a zero reference, so no relative error; they are left out \
             of the figures below. Absolute differences (solution - reference):",
            zero_bands.len()
        );
        for (name, band, d) in zero_bands {
            let _ = writeln!(text, "  {name} {band}: {d:+.6e}");
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::super::surface_table::parse_table;
    use super::*;

    fn table(rows: &[(&str, [f64; 3])]) -> SurfaceTable {
        let surfaces: Vec<serde_json::Value> = rows
            .iter()
            .map(|(n, b)| serde_json::json!({"name": n, "radiosity": b}))
            .collect();
        parse_table(&serde_json::json!({ "surfaces": surfaces }).to_string()).unwrap()
    }

    #[test]
    fn a_zero_reference_band_is_an_absolute_difference_kept_out_of_the_mean() {
        let reference = table(&[("a", [1.0, 0.0, 2.0])]);
        let solution = table(&[("a", [1.1, 0.25, 2.0])]);
        let c = compare(&solution, &reference).unwrap();
        assert_eq!(c.rows[0].bands[1], BandError::Absolute(0.25));
        assert_eq!(c.relative.len(), 2);
        assert!(c.relative.iter().all(|e| e.is_finite()));
        assert!((c.relative[0] - 0.1).abs() < 1e-12);
    }

    #[test]
    fn surfaces_of_another_size_are_another_scene() {
        let sized = |area: f64| {
            let json = serde_json::json!({"surfaces": [
                {"name": "a", "radiosity": [1.0, 1.0, 1.0], "area": area}
            ]});
            parse_table(&json.to_string()).unwrap()
        };
        assert!(compare(&sized(2.0), &sized(2.0 * (1.0 + 1e-9))).is_ok());
        let e = compare(&sized(2.0), &sized(3.0)).unwrap_err().to_string();
        assert!(
            e.contains("'a'") && e.contains("not of the same scene"),
            "{e}"
        );
    }

    #[test]
    fn surfaces_on_one_side_only_are_named() {
        let reference = table(&[("a", [1.0; 3]), ("b", [1.0; 3])]);
        let solution = table(&[("a", [1.0; 3]), ("c", [1.0; 3])]);
        let e = compare(&solution, &reference).unwrap_err().to_string();
        assert!(e.contains("reference only: 'b'"), "{e}");
        assert!(e.contains("solution only: 'c'"), "{e}");
    }
}
