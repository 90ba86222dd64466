//! Plots of a sweep: error against time (log-log, one curve per method) and
//! error against subdivision depth, each as SVG and PNG.

use super::plot_style::{colour, ensure_font, CAPTION_SIZE, FONT, LABEL_SIZE, TICK_SIZE};
use super::{ErrorMetric, Method, RunRecord};
use crate::error::{Error, Result};
use crate::output::Outputs;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One curve: a method's runs as `(x, y)` points, in record order.
struct Curve {
    method: Method,
    metric: ErrorMetric,
    label: String,
    points: Vec<(f64, f64)>,
}

/// One chart of a figure.
struct Panel {
    caption: String,
    x_desc: &'static str,
    y_desc: String,
    curves: Vec<Curve>,
    /// Where the legend goes: a corner the curves usually leave empty.
    legend: SeriesLabelPosition,
}

/// Draws the error of every run against its seconds, log-log, one curve per
/// method: the mean error in the left panel, the largest in the right. Writes
/// `svg` and `png`, both or neither (see [`crate::output`]). Runs with a zero
/// error (which a log axis cannot show) are left out of the curves.
pub fn write_time_plot(scene: &str, records: &[RunRecord], svg: &Path, png: &Path) -> Result<()> {
    let mut outputs = Outputs::new();
    stage_time_plot(&mut outputs, scene, records, svg, png)?;
    outputs.commit().map(drop)
}

/// [`write_time_plot`] into a caller's set of outputs.
pub fn stage_time_plot(
    outputs: &mut Outputs,
    scene: &str,
    records: &[RunRecord],
    svg: &Path,
    png: &Path,
) -> Result<()> {
    let panels: Vec<Panel> = [ErrorMetric::Mean, ErrorMetric::Max]
        .into_iter()
        .map(|metric| Panel {
            caption: format!("{scene}: {} error against time", metric.name()),
            x_desc: "wall-clock seconds of the solve",
            y_desc: format!("{} relative error", metric.name()),
            curves: methods_present(records)
                .into_iter()
                .map(|method| Curve {
                    method,
                    metric,
                    label: method.label().to_string(),
                    points: records
                        .iter()
                        .filter(|r| r.method == method)
                        .map(|r| (r.seconds, metric.of(&r.errors)))
                        .collect(),
                })
                .collect(),
            // Error falls with time: the lower left stays empty.
            legend: SeriesLabelPosition::LowerLeft,
        })
        .collect();
    write_figure(outputs, &panels, (1400, 600), (svg, png), true)
}

/// Draws mean and largest error against uniform subdivision depth (the
/// [`Method::Uniform`] runs), and the [`Method::Patches`] runs at the depth
/// whose elements are as large as their patches (`log2(base_patch_size /
/// patch size)`). Writes `svg` and `png` (both or neither) and returns `true`,
/// or writes nothing and returns `false` when there are no such runs.
pub fn write_depth_plot(
    scene: &str,
    records: &[RunRecord],
    base_patch_size: f64,
    svg: &Path,
    png: &Path,
) -> Result<bool> {
    let mut outputs = Outputs::new();
    let drawn = stage_depth_plot(&mut outputs, scene, records, base_patch_size, svg, png)?;
    outputs.commit()?;
    Ok(drawn)
}

/// [`write_depth_plot`] into a caller's set of outputs.
pub fn stage_depth_plot(
    outputs: &mut Outputs,
    scene: &str,
    records: &[RunRecord],
    base_patch_size: f64,
    svg: &Path,
    png: &Path,
) -> Result<bool> {
    let mut curves = Vec::new();
    for method in [Method::Uniform, Method::Patches] {
        for metric in [ErrorMetric::Mean, ErrorMetric::Max] {
            let points: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.method == method)
                .map(|r| {
                    let depth = match method {
                        Method::Patches => (base_patch_size / r.parameter).log2(),
                        _ => r.parameter,
                    };
                    (depth, metric.of(&r.errors))
                })
                .collect();
            if !points.is_empty() {
                curves.push(Curve {
                    method,
                    metric,
                    label: format!("{}: {} error", method.label(), metric.name()),
                    points,
                });
            }
        }
    }
    if curves.is_empty() {
        return Ok(false);
    }
    let panel = Panel {
        caption: format!("{scene}: error against subdivision depth"),
        x_desc: "depth d: elements 1/2^d of the base patch size",
        y_desc: "relative error".to_string(),
        curves,
        // The largest errors start high on the left and fall to the right.
        legend: SeriesLabelPosition::UpperRight,
    };
    write_figure(outputs, &[panel], (900, 600), (svg, png), false)?;
    Ok(true)
}

fn methods_present(records: &[RunRecord]) -> Vec<Method> {
    Method::ALL
        .into_iter()
        .filter(|m| records.iter().any(|r| r.method == *m))
        .collect()
}

/// Draws the panels side by side into an SVG file and a PNG file, staged in
/// `outputs`.
fn write_figure(
    outputs: &mut Outputs,
    panels: &[Panel],
    size: (u32, u32),
    (svg, png): (&Path, &Path),
    log_x: bool,
) -> Result<()> {
    ensure_font(svg)?;
    let failed = |path: &Path| {
        let path = path.to_path_buf();
        move |message: String| Error::Output { path, message }
    };
    let mut svg_text = String::new();
    {
        let root = SVGBackend::with_string(&mut svg_text, size).into_drawing_area();
        draw_panels(&root, panels, log_x).map_err(failed(svg))?;
        root.present().map_err(|e| failed(svg)(e.to_string()))?;
    }
    outputs.stage_bytes(svg, svg_text.as_bytes())?;
    let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        draw_panels(&root, panels, log_x).map_err(failed(png))?;
        root.present().map_err(|e| failed(png)(e.to_string()))?;
    }
    let image = image::RgbImage::from_raw(size.0, size.1, pixels)
        .ok_or_else(|| failed(png)("the bitmap has the wrong size".into()))?;
    crate::render::stage_rgb8_png(outputs, &image, png)
}

fn draw_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[Panel],
    log_x: bool,
) -> std::result::Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((1, panels.len().max(1)));
    for (area, panel) in areas.iter().zip(panels) {
        let (x, y) = bounds(panel, log_x);
        let y_spec = (y.0..y.1)
            .log_scale()
            .with_key_points(log_ticks(y))
            .with_light_points(log_minor_ticks(y));
        if log_x {
            let x_spec = (x.0..x.1)
                .log_scale()
                .with_key_points(log_ticks(x))
                .with_light_points(log_minor_ticks(x));
            draw_panel(area, panel, x_spec, y_spec, (true, 10))?;
        } else {
            // About one label per unit of depth.
            let labels = ((x.1 - x.0).floor() as usize + 1).clamp(2, 12);
            draw_panel(area, panel, x.0..x.1, y_spec, (false, labels))?;
        }
    }
    Ok(())
}

/// Draws one chart with the x axis `x_spec` and a log y axis. `x_axis` says
/// whether the x axis is logarithmic and how many labels a linear one wants.
fn draw_panel<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    x_spec: X,
    y_spec: Y,
    x_axis: (bool, usize),
) -> std::result::Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let text = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (log_x, x_labels) = x_axis;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, (FONT, CAPTION_SIZE))
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(text)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_desc)
        .y_desc(&panel.y_desc)
        .axis_desc_style((FONT, LABEL_SIZE))
        .label_style((FONT, TICK_SIZE))
        .x_labels(x_labels)
        .x_label_formatter(&|v| short_number(*v))
        .y_label_formatter(&|v| format!("{}%", short_number(*v * 100.0)))
        .draw()
        .map_err(text)?;
    for curve in &panel.curves {
        let points: Vec<(f64, f64)> = curve
            .points
            .iter()
            .copied()
            .filter(|p| (p.0 > 0.0 || !log_x) && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
            .collect();
        let style = colour(curve.method);
        // The largest error is drawn thinner, with hollow markers.
        let (width, radius) = match curve.metric {
            ErrorMetric::Max => (1, 3),
            _ => (3, 5),
        };
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                style.stroke_width(width),
            ))
            .map_err(text)?
            .label(&curve.label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], style.stroke_width(width))
            });
        chart
            .draw_series(
                points
                    .iter()
                    .map(|p| Circle::new(*p, radius, style.filled())),
            )
            .map_err(text)?;
    }
    chart
        .configure_series_labels()
        .label_font((FONT, LABEL_SIZE))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(panel.legend.clone())
        .draw()
        .map_err(text)?;
    Ok(())
}

/// The axis ranges: the data's extent, widened by a factor of 2 each way on a
/// log axis and by 0.3 on a linear one. Points a log axis cannot show (zero or
/// negative) are left out.
fn bounds(panel: &Panel, log_x: bool) -> ((f64, f64), (f64, f64)) {
    let shown =
        |p: &&(f64, f64)| (p.0 > 0.0 || !log_x) && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = x;
    for p in panel
        .curves
        .iter()
        .flat_map(|c| c.points.iter())
        .filter(shown)
    {
        x = (x.0.min(p.0), x.1.max(p.0));
        y = (y.0.min(p.1), y.1.max(p.1));
    }
    if !x.0.is_finite() {
        return ((1e-3, 1.0), (1e-3, 1.0));
    }
    let widen_log = |(lo, hi): (f64, f64)| (lo / 2.0, hi.max(lo * 1.01) * 2.0);
    let x = if log_x {
        widen_log(x)
    } else {
        (x.0 - 0.3, x.1 + 0.3)
    };
    (x, widen_log(y))
}

/// Labelled ticks of a log axis over `range`: the powers of ten inside it,
/// with 2 and 5 times them as well when fewer than three powers fit.
fn log_ticks(range: (f64, f64)) -> Vec<f64> {
    let decades = |mantissas: &[f64]| -> Vec<f64> {
        let (lo, hi) = (
            range.0.log10().floor() as i32,
            range.1.log10().ceil() as i32,
        );
        (lo..=hi)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (range.0..=range.1).contains(v))
            .collect()
    };
    let powers = decades(&[1.0]);
    if powers.len() >= 3 {
        powers
    } else {
        decades(&[1.0, 2.0, 5.0])
    }
}

/// Unlabelled grid lines of a log axis: 1 to 9 times each power of ten.
fn log_minor_ticks(range: (f64, f64)) -> Vec<f64> {
    let (lo, hi) = (
        range.0.log10().floor() as i32,
        range.1.log10().ceil() as i32,
    );
    (lo..=hi)
        .flat_map(|k| (1..10).map(move |m| f64::from(m) * 10f64.powi(k)))
        .filter(|v| (range.0..=range.1).contains(v))
        .collect()
}

/// A tick label with two significant digits and no trailing zeros.
fn short_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let decimals = (1 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_are_decades_or_one_two_five() {
        assert_eq!(log_ticks((0.0005, 2.0)), vec![0.001, 0.01, 0.1, 1.0]);
        let narrow = log_ticks((0.15, 3.0));
        assert_eq!(narrow.len(), 4, "{narrow:?}");
        assert!((narrow[0] - 0.2).abs() < 1e-12 && (narrow[3] - 2.0).abs() < 1e-12);
        // 0.5 to 0.9, then 1, 2 and 3.
        assert_eq!(log_minor_ticks((0.5, 3.0)).len(), 8);
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(short_number(0.25), "0.25");
        assert_eq!(short_number(5.0), "5");
        assert_eq!(short_number(20.0), "20");
        assert_eq!(short_number(0.001), "0.001");
        assert_eq!(short_number(0.0020), "0.002");
        assert_eq!(short_number(1.5), "1.5");
    }
}
