//! `radiosity diff`: compare two linear images.

use super::outputs::{lock_file, refuse_overwriting_inputs};
use anyhow::{bail, Context, Result};
use clap::Args;
use radiosity::output::check_target;
use radiosity::render::{self, DiffMetrics};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// `radiosity diff`.
#[derive(Args, Debug, Clone)]
pub struct DiffArgs {
    /// The image to judge (OpenEXR or Radiance HDR).
    pub a: PathBuf,
    /// The reference it is judged against (OpenEXR or Radiance HDR); relative
    /// RMSE is relative to its root mean square.
    pub b: PathBuf,
    /// The difference image |A - B|: .exr or .hdr (linear), or .png (false
    /// colour, linear from 0 to the largest difference, with a legend)
    /// [default: A_diff.exr beside A].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Print the metrics as JSON (relative_rmse is null when B is black and A
    /// is not).
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Report<'a> {
    a: String,
    b: String,
    output: String,
    width: u32,
    height: u32,
    #[serde(flatten)]
    metrics: &'a DiffMetrics,
}

/// Runs `radiosity diff`.
pub fn run(a: &DiffArgs) -> Result<()> {
    let output = a.output.clone().unwrap_or_else(|| default_output(&a.a));
    let kind = output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(kind.as_deref(), Some("exr" | "hdr" | "png")) {
        bail!(
            "{}: the difference image must be .exr, .hdr or .png",
            output.display()
        );
    }
    check_target(&output)?;
    refuse_overwriting_inputs(std::slice::from_ref(&output), &[a.a.clone(), a.b.clone()])?;
    let _lock = lock_file(&output)?;
    let image_a = render::read_hdr_image(&a.a)?;
    let image_b = render::read_hdr_image(&a.b)?;
    let (difference, metrics) = render::diff(&image_a, &image_b)
        .with_context(|| format!("comparing {} with {}", a.a.display(), a.b.display()))?;
    match kind.as_deref() {
        Some("exr") => render::write_exr(&difference, &output)?,
        Some("hdr") => render::write_hdr(&difference, &output)?,
        _ => {
            // An identical pair still gets a (flat) picture with a legend.
            let top = if metrics.max_abs > 0.0 {
                metrics.max_abs
            } else {
                1.0
            };
            let picture = render::false_colour(&difference, 0.0, top, false)?;
            render::write_rgb8_png(&picture, &output)?;
        }
    }
    // Written, not printed: a closed pipe (`| head`) is an error, not a panic.
    let mut stdout = std::io::stdout().lock();
    if a.json {
        let report = Report {
            a: a.a.display().to_string(),
            b: a.b.display().to_string(),
            output: output.display().to_string(),
            width: image_a.width,
            height: image_a.height,
            metrics: &metrics,
        };
        writeln!(stdout, "{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        writeln!(stdout, "MAE           {:.6e}", metrics.mae)?;
        writeln!(stdout, "RMSE          {:.6e}", metrics.rmse)?;
        writeln!(stdout, "relative RMSE {:.6e}", metrics.relative_rmse)?;
        writeln!(stdout, "max |A - B|   {:.6e}", metrics.max_abs)?;
        writeln!(stdout, "wrote {}", output.display())?;
    }
    Ok(())
}

/// `A_diff.exr` in A's folder.
fn default_output(a: &Path) -> PathBuf {
    let stem = a
        .file_stem()
        .map_or_else(|| "image".into(), |s| s.to_string_lossy().into_owned());
    a.with_file_name(format!("{stem}_diff.exr"))
}
