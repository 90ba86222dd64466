//! The options of the images a command writes: cameras, size, exposure, tone
//! map, extra HDR and false-colour outputs. Shared by `solve` and `render`.

use super::camera_arg::parse_camera;
use super::checks::{check_exposure, check_image_size};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use radiosity::render::ToneMap;
use radiosity::scene::Camera;

/// Cameras and image options.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// A view: EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEGREES (vertical
    /// field of view). Repeat for several views of one solution. Default: the
    /// scene's first camera, else a view that frames the scene.
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Vec<String>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512)]
    pub height: u32,
    /// Exposure of the PNG in stops [default: automatic].
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// Tone map of the PNG: clamp, reinhard or aces.
    #[arg(long, default_value = "aces")]
    pub tonemap: String,
    /// Also write NAME.hdr: linear radiance as Radiance RGBE, beside NAME.exr.
    #[arg(long)]
    pub hdr: bool,
    /// Also write NAME_false.png: the luminance of the radiance on a colour
    /// ramp with a legend, on a log scale, or linear with
    /// --false-colour=linear.
    #[arg(
        long = "false-colour",
        value_name = "SCALE",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "log"
    )]
    pub false_colour: Option<FalseColourScale>,
    /// The false-colour ramp's range, LO,HI, in luminance of radiance
    /// (W/m^2/sr) [default: the first view's range].
    #[arg(
        long = "false-colour-range",
        value_name = "LO,HI",
        requires = "false_colour",
        allow_hyphen_values = true
    )]
    pub false_colour_range: Option<String>,
}

/// How luminance is placed on the false-colour ramp.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FalseColourScale {
    /// Logarithmic: equal ratios take equal lengths of the ramp.
    Log,
    /// Linear.
    Linear,
}

/// [`ViewArgs`] checked and parsed, before any work is done.
#[derive(Clone, Debug)]
pub struct ViewPlan {
    /// The `--camera` views (empty: use the scene's).
    pub cameras: Vec<Camera>,
    /// The PNG tone map.
    pub tone: ToneMap,
    /// The false-colour scale and, if given, its range.
    pub false_colour: Option<(FalseColourScale, Option<(f64, f64)>)>,
}

impl ViewArgs {
    /// Checks the image size and parses the cameras, tone map and
    /// false-colour range.
    pub fn plan(&self) -> Result<ViewPlan> {
        check_image_size(self.width, self.height)?;
        check_exposure(self.exposure)?;
        let tone: ToneMap = self.tonemap.parse().map_err(anyhow::Error::msg)?;
        let cameras = self
            .camera
            .iter()
            .map(|c| parse_camera(c))
            .collect::<Result<_>>()?;
        let range = self
            .false_colour_range
            .as_deref()
            .map(parse_range)
            .transpose()?;
        if let (Some(FalseColourScale::Log), Some((lo, _))) = (self.false_colour, range) {
            if lo <= 0.0 {
                bail!(
                    "--false-colour-range: a log scale needs LO > 0 (or use --false-colour=linear)"
                );
            }
        }
        Ok(ViewPlan {
            cameras,
            tone,
            false_colour: self.false_colour.map(|s| (s, range)),
        })
    }
}

/// Parses `LO,HI` with LO < HI, both finite.
fn parse_range(text: &str) -> Result<(f64, f64)> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .with_context(|| format!("--false-colour-range '{text}': expected LO,HI"))?;
    match v[..] {
        [lo, hi] if lo.is_finite() && hi.is_finite() && lo < hi => Ok((lo, hi)),
        _ => bail!("--false-colour-range '{text}': expected two finite numbers LO,HI with LO < HI"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_and_reject() {
        assert_eq!(parse_range("0.01, 20").unwrap(), (0.01, 20.0));
        assert_eq!(parse_range("-1,1").unwrap(), (-1.0, 1.0));
        assert!(parse_range("1").is_err());
        assert!(parse_range("2,1").is_err());
        assert!(parse_range("0,inf").is_err());
        assert!(parse_range("a,b").is_err());
    }
}
