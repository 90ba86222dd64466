//! Luminance shown on a perceptual colour ramp, with a labelled legend.

use super::font::{draw_text, fill_rect, text_width, GLYPH_HEIGHT};
use super::HdrImage;
use crate::{Error, Result};
use image::RgbImage;

/// Ten evenly spaced samples of the viridis colour map (sRGB), dark to light.
/// Viridis is perceptually uniform and reads in grey and for colour-blind
/// viewers.
const RAMP: [[u8; 3]; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x49, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6e, 0xce, 0x58],
    [0xb5, 0xde, 0x2b],
    [0xfd, 0xe7, 0x25],
];

const PANEL: [u8; 3] = [24, 24, 24];
const INK: [u8; 3] = [230, 230, 230];

/// The ramp colour at `t` in `[0, 1]` (clamped), linear between samples.
fn ramp(t: f64) -> [u8; 3] {
    let pos = t.clamp(0.0, 1.0) * (RAMP.len() - 1) as f64;
    let i = (pos.floor() as usize).min(RAMP.len() - 2);
    let f = pos - i as f64;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    [0, 1, 2].map(|k| (f64::from(a[k]) + (f64::from(b[k]) - f64::from(a[k])) * f).round() as u8)
}

/// Where a luminance falls on the scale from `lo` to `hi`.
#[derive(Clone, Copy)]
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Scale {
    /// The ramp position of `value`, unclamped; `None` if it has none (NaN, or
    /// not positive on a log scale).
    fn position(&self, value: f64) -> Option<f64> {
        if !value.is_finite() && !value.is_nan() {
            return Some(if value > 0.0 { 1.0 } else { 0.0 });
        }
        if self.log {
            (value > 0.0).then(|| (value / self.lo).ln() / (self.hi / self.lo).ln())
        } else {
            (!value.is_nan()).then(|| (value - self.lo) / (self.hi - self.lo))
        }
    }

    /// Values for the legend's tick marks: five even steps, or on a log scale
    /// spanning at least two powers of ten, those powers plus the ends of the
    /// range where they do not crowd a power.
    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let first = (self.lo.log10() - 1e-9).ceil() as i32;
            let last = (self.hi.log10() + 1e-9).floor() as i32;
            if last > first {
                let stride = ((last - first) / 8 + 1) as usize;
                let mut ticks: Vec<f64> = (first..=last)
                    .step_by(stride)
                    .map(|k| 10f64.powi(k))
                    .collect();
                // Label the ends too, unless a power of ten sits close by.
                for end in [self.lo, self.hi] {
                    let t = self.position(end).unwrap_or(0.0);
                    let clear = ticks
                        .iter()
                        .all(|&v| (self.position(v).unwrap_or(0.0) - t).abs() > 0.1);
                    if clear {
                        ticks.push(end);
                    }
                }
                ticks.sort_by(f64::total_cmp);
                return ticks;
            }
            (0..5)
                .map(|i| self.lo * (self.hi / self.lo).powf(f64::from(i) / 4.0))
                .collect()
        } else {
            (0..5)
                .map(|i| self.lo + (self.hi - self.lo) * f64::from(i) / 4.0)
                .collect()
        }
    }
}

/// A label of at most about seven characters from the font's set.
fn format_tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".to_string();
    }
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (1e-2..1e4).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).clamp(0, 4) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.1e}");
        match s.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim(mantissa.to_string())),
            None => s,
        }
    }
}

/// A false-colour view of `img`: each pixel's luminance placed on a viridis
/// ramp from `lo` (dark) to `hi` (light), linearly or, with `log`, on a log
/// scale. Values outside the range take the end colours; on a log scale,
/// pixels of zero luminance (background) are black. A legend panel with a
/// colour bar, tick marks and numeric labels is added on the right, so the
/// result is wider than `img`.
///
/// Fails when the range is empty or not finite, or `log` with `lo <= 0`.
pub fn false_colour(img: &HdrImage, lo: f64, hi: f64, log: bool) -> Result<RgbImage> {
    if !(lo.is_finite() && hi.is_finite() && lo < hi) || (log && lo <= 0.0) {
        return Err(Error::Setting {
            name: "false_colour_range",
            message: format!(
                "{lo} to {hi} is not a usable range{}",
                if log {
                    " for a log scale (needs 0 < lo < hi)"
                } else {
                    " (needs lo < hi)"
                }
            ),
        });
    }
    let scale = Scale { lo, hi, log };
    let font = (img.height / 150).max(1);
    let ticks: Vec<(f64, String)> = scale
        .ticks()
        .into_iter()
        .map(|v| (v, format_tick(v)))
        .collect();
    let label_width = ticks
        .iter()
        .map(|(_, s)| text_width(s, font))
        .max()
        .unwrap_or(0);
    // Margin, bar, tick, gap, labels, margin (in font pixels except labels).
    let (margin, bar, tick, gap) = (4 * font, 6 * font, 3 * font, 2 * font);
    let panel_width = margin + bar + tick + gap + label_width + margin;
    let mut out = RgbImage::from_pixel(img.width + panel_width, img.height, image::Rgb(PANEL));
    for (i, p) in img
        .pixels
        .iter()
        .enumerate()
        .take(img.width as usize * img.height as usize)
    {
        let (x, y) = (i as u32 % img.width, i as u32 / img.width);
        let colour = scale.position(p.luminance()).map_or([0, 0, 0], ramp);
        out.put_pixel(x, y, image::Rgb(colour));
    }
    draw_legend(
        &mut out,
        img.width + margin,
        bar,
        tick,
        gap,
        font,
        &scale,
        &ticks,
    );
    Ok(out)
}

/// Draws the colour bar with its top at the highest value, and the tick marks
/// and labels beside it, leaving room for half a label above and below.
#[allow(clippy::too_many_arguments)]
fn draw_legend(
    out: &mut RgbImage,
    left: u32,
    bar: u32,
    tick: u32,
    gap: u32,
    font: u32,
    scale: &Scale,
    ticks: &[(f64, String)],
) {
    let pad = i64::from(GLYPH_HEIGHT * font);
    let top = pad;
    let bottom = i64::from(out.height()) - 1 - pad;
    if bottom - top < 2 {
        return;
    }
    let span = (bottom - top) as f64;
    let (left, bar, tick, gap) = (
        i64::from(left),
        i64::from(bar),
        i64::from(tick),
        i64::from(gap),
    );
    for y in top..=bottom {
        let t = (bottom - y) as f64 / span;
        fill_rect(out, left, y, bar, 1, ramp(t));
    }
    let thickness = i64::from(font);
    for (value, label) in ticks {
        let Some(t) = scale.position(*value) else {
            continue;
        };
        let y = bottom - (t.clamp(0.0, 1.0) * span).round() as i64;
        fill_rect(out, left + bar, y - thickness / 2, tick, thickness, INK);
        let text_top = y - i64::from(GLYPH_HEIGHT * font) / 2;
        draw_text(out, left + bar + tick + gap, text_top, font, label, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    #[test]
    fn ramp_ends_and_midpoint() {
        assert_eq!(ramp(0.0), RAMP[0]);
        assert_eq!(ramp(1.0), RAMP[9]);
        assert_eq!(ramp(-3.0), RAMP[0]);
        // t = 0.5 lies halfway between samples 4 and 5.
        let mid: [u8; 3] = [0, 1, 2]
            .map(|k| ((f64::from(RAMP[4][k]) + f64::from(RAMP[5][k])) / 2.0).round() as u8);
        assert_eq!(ramp(0.5), mid);
    }

    #[test]
    fn tick_labels_are_short_and_exact_enough() {
        assert_eq!(format_tick(0.0), "0");
        assert_eq!(format_tick(0.1 * 3.0), "0.3");
        assert_eq!(format_tick(12.5), "12.5");
        assert_eq!(format_tick(1234.0), "1234");
        assert_eq!(format_tick(0.0123), "0.0123");
        assert_eq!(format_tick(1e-5), "1e-5");
        assert_eq!(format_tick(-2.5e6), "-2.5e6");
        assert_eq!(format_tick(100_000.0), "1e5");
    }

    #[test]
    fn log_ticks_are_decades() {
        // The ends 0.005 and 20 lie 0.08 and 0.09 of the bar from 0.01 and 10.
        let s = Scale {
            lo: 0.005,
            hi: 20.0,
            log: true,
        };
        assert_eq!(s.ticks(), vec![0.01, 0.1, 1.0, 10.0]);
        // Here they lie 0.21 of the bar from the nearest power: labelled.
        let s = Scale {
            lo: 0.002,
            hi: 5.0,
            log: true,
        };
        assert_eq!(s.ticks(), vec![0.002, 0.01, 0.1, 1.0, 5.0]);
        let s = Scale {
            lo: 0.005,
            hi: 20.0,
            log: true,
        };
        assert_eq!(s.ticks(), vec![0.01, 0.1, 1.0, 10.0]);
        let s = Scale {
            lo: 0.0,
            hi: 2.0,
            log: false,
        };
        assert_eq!(s.ticks(), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
    }

    #[test]
    fn maps_luminance_and_adds_a_legend() {
        let mut img = HdrImage::new(4, 200);
        img.set(0, 0, Rgb::splat(0.01)); // at lo
        img.set(1, 0, Rgb::splat(100.0)); // above hi
        img.set(2, 0, Rgb::splat(1.0)); // geometric middle of 0.01..100
                                        // (3, 0) stays black: background.
        let out = false_colour(&img, 0.01, 100.0, true).unwrap();
        assert!(out.width() > img.width);
        assert_eq!(out.height(), 200);
        assert_eq!(out.get_pixel(0, 0).0, RAMP[0]);
        assert_eq!(out.get_pixel(1, 0).0, RAMP[9]);
        assert_eq!(out.get_pixel(2, 0).0, ramp(0.5));
        assert_eq!(out.get_pixel(3, 0).0, [0, 0, 0]);
        // The bar's top row is the top colour, its bottom row the bottom colour.
        let bar_x = img.width + 4 + 1;
        let pad = GLYPH_HEIGHT;
        assert_eq!(out.get_pixel(bar_x, pad).0, RAMP[9]);
        assert_eq!(out.get_pixel(bar_x, 199 - pad).0, RAMP[0]);
        // Some label ink right of the bar.
        let ink = out
            .enumerate_pixels()
            .filter(|(x, _, p)| *x > bar_x + 6 && p.0 == INK)
            .count();
        assert!(ink > 20, "{ink}");
    }

    #[test]
    fn rejects_unusable_ranges() {
        let img = HdrImage::new(2, 2);
        assert!(false_colour(&img, 1.0, 1.0, false).is_err());
        assert!(false_colour(&img, 0.0, 1.0, true).is_err());
        assert!(false_colour(&img, 0.0, f64::NAN, false).is_err());
        assert!(false_colour(&img, 0.0, 1.0, false).is_ok());
    }
}
