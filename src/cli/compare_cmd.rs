//! `radiosity compare`: a solve's per-surface radiosities against a reference.

use super::args::CompareArgs;
use anyhow::{bail, Context, Result};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
struct Surface {
    name: String,
    radiosity: [f64; 3],
    #[serde(default)]
    std_error: Option<[f64; 3]>,
    #[serde(default)]
    emits: bool,
}

#[derive(Deserialize)]
struct Surfaces {
    surfaces: Vec<Surface>,
}

fn read(path: &Path) -> Result<Vec<Surface>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let s: Surfaces = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: no 'surfaces' list of name and radiosity",
            path.display()
        )
    })?;
    Ok(s.surfaces)
}

/// Runs `radiosity compare`: prints a table and the mean and largest relative
/// error over every band of every surface the reference marks as not
/// emitting (an emitter's radiosity is mostly its own emission, which would
/// flatter the mean; emitters are listed but not counted).
pub fn run(a: &CompareArgs) -> Result<()> {
    let solution = read(&a.solution)?;
    let reference = read(&a.reference)?;
    let mut errors = Vec::new();
    println!("surface          relative error (R, G, B) %         reference std. error %");
    for r in &reference {
        let Some(s) = solution.iter().find(|s| s.name == r.name) else {
            bail!(
                "surface '{}' of the reference is not in {}",
                r.name,
                a.solution.display()
            );
        };
        let e: Vec<f64> = (0..3)
            .map(|k| (s.radiosity[k] - r.radiosity[k]) / r.radiosity[k])
            .collect();
        let se: Vec<f64> = (0..3)
            .map(|k| r.std_error.map_or(f64::NAN, |x| x[k] / r.radiosity[k]))
            .collect();
        let emitter = r.emits;
        println!(
            "{:<16} {:+7.3} {:+7.3} {:+7.3}{}   {:.3} {:.3} {:.3}",
            r.name,
            100.0 * e[0],
            100.0 * e[1],
            100.0 * e[2],
            if emitter {
                " (emitter, not counted)"
            } else {
                ""
            },
            100.0 * se[0],
            100.0 * se[1],
            100.0 * se[2]
        );
        if !emitter {
            errors.extend(e.iter().map(|x| x.abs()));
        }
    }
    if errors.is_empty() {
        bail!("no surface to compare");
    }
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let max = errors.iter().copied().fold(0.0, f64::max);
    println!(
        "mean per-surface error {:.3}%, largest {:.3}% ({} surface-bands)",
        100.0 * mean,
        100.0 * max,
        errors.len()
    );
    Ok(())
}
