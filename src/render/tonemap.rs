//! From linear radiance to 8-bit sRGB: exposure, tone mapping, transfer curve.

use super::HdrImage;
use crate::math::Rgb;
use crate::{Error, Result};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// How linear values above display white are brought into `[0, 1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ToneMap {
    /// Values above 1 are clipped to 1 (`"clamp"`).
    #[serde(rename = "clamp")]
    Clamp,
    /// `x / (1 + x)` per channel (`"reinhard"`).
    #[serde(rename = "reinhard")]
    Reinhard,
    /// Stephen Hill's fit of the ACES reference rendering and output
    /// transforms, with its sRGB-to-ACES input and output matrices (`"aces"`).
    #[serde(rename = "aces")]
    #[default]
    AcesFitted,
}

impl ToneMap {
    /// Every tone map, for listing choices.
    pub const ALL: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::AcesFitted];

    /// The name [`ToneMap::from_str`] accepts.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Reinhard => "reinhard",
            ToneMap::AcesFitted => "aces",
        }
    }

    /// Maps a linear value (already scaled by the exposure) to linear display
    /// values in `[0, 1]`. Negative and NaN bands count as 0.
    #[must_use]
    pub fn apply(self, linear: Rgb) -> Rgb {
        // Cap so that infinities stay finite through the rational curves.
        let x = Rgb(linear.0.map(|v| if v > 0.0 { v.min(1e30) } else { 0.0 }));
        let mapped = match self {
            ToneMap::Clamp => x,
            ToneMap::Reinhard => Rgb(x.0.map(|v| v / (1.0 + v))),
            ToneMap::AcesFitted => {
                let fitted = Rgb(mat3(&ACES_INPUT, x).0.map(rrt_and_odt_fit));
                mat3(&ACES_OUTPUT, fitted)
            }
        };
        Rgb(mapped.0.map(|v| v.clamp(0.0, 1.0)))
    }
}

/// Linear sRGB to the ACES fit's working space (with the RRT's saturation).
const ACES_INPUT: [[f64; 3]; 3] = [
    [0.59719, 0.35458, 0.04823],
    [0.07600, 0.90834, 0.01566],
    [0.02840, 0.13383, 0.83777],
];

/// The ACES fit's output (with the ODT's saturation) back to linear sRGB.
const ACES_OUTPUT: [[f64; 3]; 3] = [
    [1.60475, -0.53108, -0.07367],
    [-0.10208, 1.10813, -0.00605],
    [-0.00327, -0.07276, 1.07602],
];

fn mat3(m: &[[f64; 3]; 3], v: Rgb) -> Rgb {
    Rgb(m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2]))
}

/// The rational fit of the ACES RRT followed by the sRGB ODT.
fn rrt_and_odt_fit(v: f64) -> f64 {
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    a / b
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ToneMap {
    type Err = Error;

    /// Parses `"clamp"`, `"reinhard"` or `"aces"` (any case).
    fn from_str(s: &str) -> Result<Self> {
        ToneMap::ALL
            .into_iter()
            .find(|t| t.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| Error::Setting {
                name: "tone_map",
                message: format!("unknown tone map '{s}'; choose clamp, reinhard or aces"),
            })
    }
}

/// The sRGB transfer function (IEC 61966-2-1): linear `[0, 1]` to encoded
/// `[0, 1]`. Input outside `[0, 1]` (or NaN) is clamped first.
#[must_use]
pub fn srgb_encode(linear: f64) -> f64 {
    let v = if linear > 0.0 { linear.min(1.0) } else { 0.0 };
    if v <= 0.0031308 {
        12.92 * v
    } else {
        // 1.055 x - 0.055, written so that 1 maps to exactly 1.
        1.0 + 1.055 * (v.powf(1.0 / 2.4) - 1.0)
    }
}

/// An 8-bit sRGB preview: each pixel is scaled by `2^exposure_stops`, tone
/// mapped, encoded with [`srgb_encode`] and rounded to the nearest level.
#[must_use]
pub fn to_srgb8(img: &HdrImage, exposure_stops: f64, tone: ToneMap) -> image::RgbImage {
    let scale = exposure_stops.exp2();
    let mut out = image::RgbImage::new(img.width, img.height);
    // A row of pixels per task: the encoding's powers are most of a
    // preview's cost, and each pixel is its own.
    let row = 3 * img.width.max(1) as usize;
    out.par_chunks_mut(row)
        .zip(img.pixels.par_chunks(img.width.max(1) as usize))
        .for_each(|(dst, src)| {
            for (d, s) in dst.chunks_exact_mut(3).zip(src) {
                let display = tone.apply(*s * scale);
                for (byte, v) in d.iter_mut().zip(display.0) {
                    *byte = (srgb_encode(v) * 255.0).round() as u8;
                }
            }
        });
    out
}

/// The display value (after tone mapping, before sRGB encoding) that
/// [`auto_exposure`] gives the bright end of the image.
pub(crate) const AUTO_EXPOSURE_TARGET: f64 = 0.8;

/// The luminance percentile [`auto_exposure`] maps to [`AUTO_EXPOSURE_TARGET`].
pub(crate) const AUTO_EXPOSURE_PERCENTILE: f64 = 0.97;

/// The exposure in stops that takes the 97th percentile of pixel luminance to
/// a grey that `tone` maps to 0.8 (linear display value, before sRGB encoding;
/// 231 of 255 after it). Pixels of zero luminance (background, black
/// surfaces) and non-finite pixels are left out; with nothing left, 0.
#[must_use]
pub fn auto_exposure(img: &HdrImage, tone: ToneMap) -> f64 {
    auto_exposure_above(img, tone, 0.0)
}

/// [`auto_exposure`] leaving out pixels whose luminance is at most `floor`
/// as well: numerical noise on surfaces no light reaches (1e-12 of a lamp)
/// is not to be exposed for when nothing else is in view.
#[must_use]
pub(crate) fn auto_exposure_above(img: &HdrImage, tone: ToneMap, floor: f64) -> f64 {
    let mut lum: Vec<f64> = img
        .pixels
        .iter()
        .map(|p| p.luminance())
        .filter(|l| l.is_finite() && *l > 0.0 && *l > floor)
        .collect();
    if lum.is_empty() {
        return 0.0;
    }
    let rank = ((lum.len() - 1) as f64 * AUTO_EXPOSURE_PERCENTILE).round() as usize;
    let (_, &mut bright, _) = lum.select_nth_unstable_by(rank, f64::total_cmp);
    (grey_mapped_to(tone, AUTO_EXPOSURE_TARGET) / bright).log2()
}

/// The grey level `x` with `tone.apply(x)` equal to `target` in every band
/// (bisection: every tone map is increasing on grey).
fn grey_mapped_to(tone: ToneMap, target: f64) -> f64 {
    let mapped = |x: f64| tone.apply(Rgb::splat(x)).luminance();
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while mapped(hi) < target && hi < 1e12 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if mapped(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_and_rejects_others() {
        assert_eq!("clamp".parse::<ToneMap>().unwrap(), ToneMap::Clamp);
        assert_eq!("Reinhard".parse::<ToneMap>().unwrap(), ToneMap::Reinhard);
        assert_eq!("aces".parse::<ToneMap>().unwrap(), ToneMap::AcesFitted);
        let e = "filmic".parse::<ToneMap>().unwrap_err().to_string();
        assert!(e.contains("filmic"), "{e}");
        for t in ToneMap::ALL {
            assert_eq!(t.to_string().parse::<ToneMap>().unwrap(), t);
        }
    }

    #[test]
    fn curves_at_known_points() {
        let r = ToneMap::Reinhard.apply(Rgb::new(1.0, 3.0, 0.0));
        assert_eq!(r, Rgb::new(0.5, 0.75, 0.0));
        assert_eq!(
            ToneMap::Clamp.apply(Rgb::new(2.0, 0.25, -1.0)),
            Rgb::new(1.0, 0.25, 0.0)
        );
        // The ACES fit by hand on grey 1 (both matrices keep grey within 1e-5):
        // (1.0245786 - 0.000090537) / (0.983729 + 0.4329510 + 0.238081).
        let expected = (1.0245786 - 0.000090537) / (0.983729 + 0.4329510 + 0.238081);
        let a = ToneMap::AcesFitted.apply(Rgb::ONE);
        for k in 0..3 {
            assert!((a[k] - expected).abs() < 2e-5, "{a:?}");
        }
        // Saturates to 1 and never goes negative.
        assert_eq!(ToneMap::AcesFitted.apply(Rgb::splat(1e6)).max_band(), 1.0);
        assert_eq!(ToneMap::AcesFitted.apply(Rgb::ZERO), Rgb::ZERO);
        assert_eq!(ToneMap::Reinhard.apply(Rgb::splat(f64::INFINITY)), Rgb::ONE);
        assert_eq!(ToneMap::Reinhard.apply(Rgb::splat(f64::NAN)), Rgb::ZERO);
    }

    #[test]
    fn a_floor_leaves_out_noise_that_alone_would_set_the_exposure() {
        let mut img = HdrImage::new(4, 1);
        img.set(0, 0, Rgb::splat(1e-12));
        img.set(1, 0, Rgb::splat(2e-12));
        // Noise alone: exposed up to display grey.
        assert!(auto_exposure(&img, ToneMap::Clamp) > 35.0);
        // Above a floor of 1e-6, nothing is left: no exposure change.
        assert_eq!(auto_exposure_above(&img, ToneMap::Clamp, 1e-6), 0.0);
        // A lit pixel above the floor sets it: 0.8 / 0.4 is one stop.
        img.set(2, 0, Rgb::splat(0.4));
        let stops = auto_exposure_above(&img, ToneMap::Clamp, 1e-6);
        assert!((stops - 1.0).abs() < 1e-9, "{stops}");
    }

    #[test]
    fn grey_target_inverts_the_curve() {
        assert!((grey_mapped_to(ToneMap::Clamp, 0.8) - 0.8).abs() < 1e-12);
        assert!((grey_mapped_to(ToneMap::Reinhard, 0.8) - 4.0).abs() < 1e-9);
        let x = grey_mapped_to(ToneMap::AcesFitted, 0.8);
        assert!((ToneMap::AcesFitted.apply(Rgb::splat(x)).luminance() - 0.8).abs() < 1e-9);
    }
}
