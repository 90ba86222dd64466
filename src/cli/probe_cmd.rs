//! `radiosity probe`: solve, then write the radiosity at given points as CSV.

use super::args::ProbeArgs;
use super::budget::{solve_settings, PROBE_BYTES_PER_TEXT_BYTE};
use super::checks::thread_pool;
use super::outputs::{lock_file, refuse_overwriting_inputs, scene_inputs};
use super::progress_bar::Bars;
use super::setting_flags::with_flags;
use super::solve_cmd::{load, load_options, read_text, settings};
use anyhow::{bail, Context, Result};
use glam::DVec3;
use radiosity::output::{check_target, write_bytes};
use radiosity::scenes::penumbra::{self, PenumbraSpec};
use radiosity::solution::ProbeTolerance;
use radiosity::Settings;
use std::fmt::Write as _;
use std::path::Path;

/// One probe: a point and the front normal of the surface it should lie on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbePoint {
    /// The point.
    pub point: DVec3,
    /// The normal, as given (not normalised).
    pub normal: DVec3,
}

/// Runs `radiosity probe`. The options, the points file and the output file
/// are checked before the scene is loaded.
pub fn run(a: &ProbeArgs) -> Result<()> {
    let pool = thread_pool(a.settings.threads)?;
    let settings = settings(&a.settings)?;
    pool.install(|| run_in_pool(a, &settings))
}

fn run_in_pool(a: &ProbeArgs, settings: &Settings) -> Result<()> {
    // The points and their rows, counted before the file is read.
    let text_bytes = std::fs::metadata(&a.points).map_or(0, |m| m.len());
    let points_bytes = text_bytes.saturating_mul(PROBE_BYTES_PER_TEXT_BYTE);
    solve_settings(settings, &[("the probe points", points_bytes)])?;
    let text = read_text(&a.points).context("reading the points file")?;
    let points = parse_points(&text).with_context(|| format!("{}", a.points.display()))?;
    let oracle = if a.exact {
        Some(exact_oracle(&a.scene)?)
    } else {
        None
    };
    let tolerance = ProbeTolerance {
        relative_distance: a.plane_tolerance,
        normal_degrees: a.normal_tolerance,
    };
    tolerance.validate()?;
    let _lock = match &a.output {
        Some(path) => {
            check_target(path)?;
            let mut inputs = scene_inputs(&a.scene)?;
            inputs.push(a.points.clone());
            refuse_overwriting_inputs(std::slice::from_ref(path), &inputs)?;
            Some(lock_file(path)?)
        }
        None => None,
    };

    let scene = load(&a.scene, &load_options(&a.settings.load)?)?;
    for w in &scene.warnings {
        eprintln!("warning: {}", with_flags(w));
    }
    let rows = points.len() as u64 * 250;
    let settings = &solve_settings(settings, &[("the probe rows", rows)])?;
    let bars = Bars::new(a.quiet)
        .watching_cost(settings.hemicube_resolution, rayon::current_num_threads());
    let solution = radiosity::solve(&scene, settings, &|p| bars.update(p))
        .with_context(|| format!("solving '{}'", scene.name))?;
    bars.finish();

    let prober = solution.probe_with(tolerance)?;
    let mut out = header(oracle.is_some());
    let mut misses = 0;
    for p in &points {
        let hit = prober.hit(p.point, p.normal);
        misses += usize::from(hit.is_none());
        let exact = match (&oracle, &hit) {
            (Some(spec), Some(h)) => Some(spec.exact_radiosity(h.point).ok()),
            (Some(_), None) => Some(None),
            (None, _) => None,
        };
        write_row(&mut out, p, hit.map(|h| h.radiosity), exact);
    }
    match &a.output {
        Some(path) => write_bytes(path, out.as_bytes())?,
        None => super::stdout::write_out(&out)?,
    }
    if misses > 0 && !a.quiet {
        eprintln!(
            "warning: {misses} of {} points lie on no surface with the given normal \
             (their rows say so in the status column)",
            points.len()
        );
    }
    Ok(())
}

/// The penumbra spec of a built-in scene name, for `--exact`.
fn exact_oracle(scene: &str) -> Result<PenumbraSpec> {
    let built_in = !Path::new(scene).exists();
    match penumbra::by_name(scene) {
        Some(spec) if built_in => Ok(spec),
        _ => bail!(
            "--exact needs a built-in penumbra scene given by name ({}), not '{scene}'",
            penumbra::VARIANTS.map(|(n, _)| n).join(", ")
        ),
    }
}

/// Parses `x,y,z,nx,ny,nz` lines. A byte-order mark (a spreadsheet's "CSV
/// UTF-8") and blank lines are skipped; the first non-blank line is a header
/// if none of its fields is a number, so that a first point with a typo is
/// an error rather than a header dropped without a word. Errors name the
/// line.
pub fn parse_points(text: &str) -> Result<Vec<ProbePoint>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut points = Vec::new();
    let mut first = true;
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed: Vec<Option<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        let numbers: Option<Vec<f64>> = parsed.iter().copied().collect();
        let is_first = std::mem::replace(&mut first, false);
        let Some(v) = numbers else {
            if is_first && parsed.iter().all(Option::is_none) {
                continue;
            }
            bail!(
                "line {}: expected six numbers x,y,z,nx,ny,nz, got '{line}'",
                index + 1
            );
        };
        if v.len() != 6 {
            bail!(
                "line {}: expected six numbers x,y,z,nx,ny,nz, got {}",
                index + 1,
                v.len()
            );
        }
        if v.iter().any(|x| !x.is_finite()) {
            bail!("line {}: numbers must be finite, got '{line}'", index + 1);
        }
        let normal = DVec3::new(v[3], v[4], v[5]);
        if normal == DVec3::ZERO {
            bail!("line {}: the normal is zero", index + 1);
        }
        points.push(ProbePoint {
            point: DVec3::new(v[0], v[1], v[2]),
            normal,
        });
    }
    Ok(points)
}

fn header(exact: bool) -> String {
    let mut h = String::from(
        "x,y,z,nx,ny,nz,radiosity_r,radiosity_g,radiosity_b,radiance_r,radiance_g,radiance_b",
    );
    if exact {
        h.push_str(",exact_radiosity_r,exact_radiosity_g,exact_radiosity_b");
    }
    h.push_str(",status\n");
    h
}

/// One output row. `exact` is `None` without `--exact`, `Some(None)` where the
/// oracle has no value for the point.
fn write_row(
    out: &mut String,
    p: &ProbePoint,
    radiosity: Option<radiosity::math::Rgb>,
    exact: Option<Option<radiosity::math::Rgb>>,
) {
    let (q, n) = (p.point, p.normal);
    let _ = write!(out, "{},{},{},{},{},{}", q.x, q.y, q.z, n.x, n.y, n.z);
    let mut status = "ok";
    match radiosity {
        Some(b) => {
            let l = b / std::f64::consts::PI;
            let _ = write!(
                out,
                ",{},{},{},{},{},{}",
                b[0], b[1], b[2], l[0], l[1], l[2]
            );
        }
        None => {
            out.push_str(",,,,,,");
            status = "error: no surface holds this point with this normal";
        }
    }
    match exact {
        Some(Some(e)) => {
            let _ = write!(out, ",{},{},{}", e[0], e[1], e[2]);
        }
        Some(None) => {
            out.push_str(",,,");
            if radiosity.is_some() {
                status = "ok; no exact value off the floor";
            }
        }
        None => {}
    }
    let _ = writeln!(out, ",{status}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_parse_with_or_without_a_header_and_bad_lines_are_named() {
        let with = parse_points("x,y,z,nx,ny,nz\n1,2,3,0,1,0\n\n 4, 5, 6, 0, 0, -2\n").unwrap();
        assert_eq!(with.len(), 2);
        assert_eq!(with[1].point, DVec3::new(4.0, 5.0, 6.0));
        assert_eq!(with[1].normal, DVec3::new(0.0, 0.0, -2.0));
        let without = parse_points("1,2,3,0,1,0\n").unwrap();
        assert_eq!(without, with[..1]);
        let e = parse_points("1,2,3,0,1,0\nx,y,z,nx,ny,nz\n").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        let e = parse_points("1,2,3,0,1\n").unwrap_err();
        assert!(e.to_string().contains("got 5"), "{e}");
        let e = parse_points("1,2,3,0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("zero"), "{e}");
        let e = parse_points("1,2,inf,0,1,0\n").unwrap_err();
        assert!(e.to_string().contains("finite"), "{e}");
    }

    #[test]
    fn a_byte_order_mark_is_skipped_and_a_first_row_with_a_typo_is_an_error() {
        let bom = parse_points("\u{feff}0.5,0,0.5,0,1,0\n0.2,0,0.2,0,1,0\n").unwrap();
        assert_eq!(bom.len(), 2);
        assert_eq!(bom[0].point, DVec3::new(0.5, 0.0, 0.5));
        let header = parse_points("\u{feff}x,y,z,nx,ny,nz\n0.2,0,0.2,0,1,0\n").unwrap();
        assert_eq!(header.len(), 1);
        let e = parse_points("0.5,0,0.5x,0,1,0\n0.2,0,0.2,0,1,0\n").unwrap_err();
        assert!(e.to_string().contains("line 1"), "{e}");
    }

    #[test]
    fn rows_leave_missing_values_empty_and_say_why() {
        let p = ProbePoint {
            point: DVec3::new(0.5, 0.0, -1.0),
            normal: DVec3::Y,
        };
        let mut out = String::new();
        write_row(&mut out, &p, None, Some(None));
        assert_eq!(
            out,
            "0.5,0,-1,0,1,0,,,,,,,,,,error: no surface holds this point with this normal\n"
        );
        let mut out = String::new();
        write_row(&mut out, &p, Some(radiosity::math::Rgb::splat(2.0)), None);
        let fields: Vec<&str> = out.trim_end().split(',').collect();
        assert_eq!(fields.len(), header(false).trim_end().split(',').count());
        assert_eq!(fields[6], "2");
        assert_eq!(
            fields[9].parse::<f64>().unwrap(),
            2.0 / std::f64::consts::PI
        );
        assert_eq!(fields[12], "ok");
    }
}
