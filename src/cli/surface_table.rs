//! The per-surface radiosity tables that `compare` reads: the `surfaces` list
//! of a solve's stats JSON or of a `radiosity reference` file, checked field by
//! field so that a file that does not fit is an error naming what is wrong.

use super::solve_cmd::read_text;
use anyhow::{bail, Context, Result};
use serde_json::Value;
use std::collections::HashSet;
use std::path::Path;

/// One surface (scene object) of a table.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceRow {
    /// The object's name, by which the two tables are matched.
    pub name: String,
    /// Mean radiosity per band, finite and >= 0.
    pub radiosity: [f64; 3],
    /// Standard error per band (references only), finite and >= 0.
    pub std_error: Option<[f64; 3]>,
    /// Whether the object emits (references only).
    pub emits: bool,
    /// Its area in square metres, if the file gives it.
    pub area: Option<f64>,
}

/// A checked table.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceTable {
    /// The scene the file names, if it names one.
    pub scene: Option<String>,
    /// The surfaces, in the file's order, with distinct names.
    pub rows: Vec<SurfaceRow>,
}

/// Reads and checks the table of `path`.
pub fn read_table(path: &Path) -> Result<SurfaceTable> {
    let text = read_text(path)?;
    parse_table(&text).with_context(|| format!("{}", path.display()))
}

/// Checks the JSON text of a table: a `surfaces` list, not empty, of objects
/// with a `name` (distinct), a `radiosity` of three finite numbers >= 0, and
/// optionally a `std_error` like it and an `emits` flag.
pub fn parse_table(text: &str) -> Result<SurfaceTable> {
    let doc: Value = serde_json::from_str(text).context("not valid JSON")?;
    let Some(list) = doc.get("surfaces").and_then(Value::as_array) else {
        bail!(
            "no 'surfaces' list (expected the stats JSON of `radiosity solve` or the output \
             of `radiosity reference`)"
        );
    };
    if list.is_empty() {
        bail!("the 'surfaces' list is empty");
    }
    let mut rows = Vec::with_capacity(list.len());
    let mut names = HashSet::new();
    for (i, s) in list.iter().enumerate() {
        let Some(name) = s.get("name").and_then(Value::as_str) else {
            bail!("surface {i} has no 'name' string");
        };
        let here = format!("surface {i} ('{name}')");
        if !names.insert(name.to_string()) {
            bail!("{here}: the name appears twice, and surfaces are matched by name");
        }
        let radiosity = bands(s.get("radiosity"))
            .with_context(|| format!("{here}: 'radiosity'"))?
            .with_context(|| format!("{here}: 'radiosity' is missing"))?;
        let std_error =
            bands(s.get("std_error")).with_context(|| format!("{here}: 'std_error'"))?;
        let emits = match s.get("emits") {
            None | Some(Value::Null) => false,
            Some(Value::Bool(b)) => *b,
            Some(other) => bail!("{here}: 'emits' must be true or false, got {other}"),
        };
        let area = match s.get("area") {
            None | Some(Value::Null) => None,
            Some(v) => match v.as_f64() {
                Some(a) if a.is_finite() && a >= 0.0 => Some(a),
                _ => bail!("{here}: 'area' must be a finite number >= 0, got {v}"),
            },
        };
        rows.push(SurfaceRow {
            name: name.to_string(),
            radiosity,
            std_error,
            emits,
            area,
        });
    }
    Ok(SurfaceTable {
        scene: doc.get("scene").and_then(Value::as_str).map(str::to_string),
        rows,
    })
}

/// Three finite numbers >= 0, each 0 or a normal double, or `None` for an
/// absent (or null) field. A subnormal value (below 2.2e-308) carries too
/// few significant bits to measure an error against: a relative error over
/// it overflows.
fn bands(value: Option<&Value>) -> Result<Option<[f64; 3]>> {
    let value = match value {
        None | Some(Value::Null) => return Ok(None),
        Some(v) => v,
    };
    let numbers: Option<Vec<f64>> = value
        .as_array()
        .map(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<f64>>>())
        .unwrap_or(None);
    match numbers.as_deref() {
        Some(&[r, g, b]) if [r, g, b].iter().all(|x| x.is_finite() && *x >= 0.0) => {
            if let Some(x) = [r, g, b].iter().find(|x| **x != 0.0 && !x.is_normal()) {
                bail!(
                    "{x:e} is below {:e}, the smallest normal double: too small to measure \
                     an error against (results are linear: scale the scene's light up)",
                    f64::MIN_POSITIVE
                );
            }
            Ok(Some([r, g, b]))
        }
        // A solve writes a non-finite value as null, so null bands land here.
        _ => bail!("must be three finite numbers >= 0, got {value}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn well_formed_tables_parse() {
        let t = parse_table(
            r#"{"scene": "s", "surfaces": [
                {"name": "a", "radiosity": [1, 2, 3]},
                {"name": "b", "radiosity": [0, 0.5, 1], "std_error": [0.1, 0.1, 0.1], "emits": true}
            ]}"#,
        )
        .unwrap();
        assert_eq!(t.scene.as_deref(), Some("s"));
        assert_eq!(t.rows[1].std_error, Some([0.1; 3]));
        assert!(t.rows[1].emits && !t.rows[0].emits);
    }

    #[test]
    fn every_kind_of_misfit_is_named() {
        let cases = [
            ("[]", "no 'surfaces' list"),
            (r#"{"surfaces": []}"#, "empty"),
            (r#"{"surfaces": [{"radiosity": [1, 1, 1]}]}"#, "no 'name'"),
            (r#"{"surfaces": [{"name": "a"}]}"#, "'radiosity' is missing"),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, null, 1]}]}"#,
                "three finite numbers",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1]}]}"#,
                "three finite numbers",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, -1, 1]}]}"#,
                "three finite numbers",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1, 1], "std_error": "x"}]}"#,
                "'std_error'",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1, 1], "emits": 1}]}"#,
                "'emits'",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1e-310, 1]}]}"#,
                "smallest normal double",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1, 1], "area": -2}]}"#,
                "'area'",
            ),
            (
                r#"{"surfaces": [{"name": "a", "radiosity": [1, 1, 1]}, {"name": "a", "radiosity": [1, 1, 1]}]}"#,
                "appears twice",
            ),
        ];
        for (text, expected) in cases {
            let e = format!("{:#}", parse_table(text).unwrap_err());
            assert!(e.contains(expected), "{text}: {e}");
        }
    }
}
