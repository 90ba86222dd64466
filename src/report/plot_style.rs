//! Colours, sizes and the embedded font of the plots.

use super::Method;
use crate::error::{Error, Result};
use plotters::style::{register_font, FontStyle, RGBColor};
use std::path::Path;
use std::sync::OnceLock;

/// The font family name the plots ask for.
pub(crate) const FONT: &str = "sans-serif";
/// Caption size in pixels.
pub(crate) const CAPTION_SIZE: u32 = 24;
/// Axis description and legend size in pixels.
pub(crate) const LABEL_SIZE: u32 = 18;
/// Tick label size in pixels.
pub(crate) const TICK_SIZE: u32 = 15;

/// The colour of a method's curve (colour-blind-safe hues, one per method).
pub(crate) fn colour(method: Method) -> RGBColor {
    match method {
        Method::Uniform => RGBColor(0, 114, 178),
        Method::Adaptive => RGBColor(213, 94, 0),
        Method::Hemicube => RGBColor(0, 158, 115),
        Method::Patches => RGBColor(204, 121, 167),
        Method::Progressive => RGBColor(0, 0, 0),
    }
}

/// Registers DejaVu Sans (embedded by the `dejavu` crate, so no system font is
/// needed) as the plots' font, once per process.
pub(crate) fn ensure_font(path: &Path) -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok());
    if ok {
        Ok(())
    } else {
        Err(Error::Output {
            path: path.to_path_buf(),
            message: "the embedded DejaVu Sans font could not be parsed".into(),
        })
    }
}
