//! The daylight options of every command that loads a scene: `--sky`, its
//! brightness, and `--sun`.

use super::args::LoadArgs;
use anyhow::{bail, Result};
use radiosity::scene::{sun, Light, Sky, SkyModel};

/// The illuminance of an overcast day, the sky's brightness when none is
/// given: a horizontal surface out of doors under a thick, even overcast
/// receives about 10 000 lux.
const DEFAULT_SKY_LUX: f64 = 10_000.0;

impl LoadArgs {
    /// The sky `--sky` and its brightness options ask for.
    pub fn sky(&self) -> Result<Option<Sky>> {
        let Some(kind) = &self.sky else {
            return Ok(None);
        };
        let model = match kind.as_str() {
            "uniform" => SkyModel::Uniform,
            "overcast" => SkyModel::Overcast,
            other => bail!("--sky: unknown sky '{other}' (uniform or overcast)"),
        };
        let sky = match (self.sky_luminance, self.sky_illuminance) {
            (Some(l), _) => Sky::with_zenith_luminance(model, l),
            (None, lux) => Sky::with_horizontal_illuminance(model, lux.unwrap_or(DEFAULT_SKY_LUX)),
        };
        // The library's message names the setting (`sky`), which the
        // error printer turns into the flag.
        sky.validate()?;
        Ok(Some(sky))
    }

    /// The sun `--sun AZIMUTH,ELEVATION,LUX` asks for.
    pub fn sun(&self) -> Result<Option<Light>> {
        let Some(text) = &self.sun else {
            return Ok(None);
        };
        let values: Vec<f64> = text
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| {
                anyhow::anyhow!("--sun: '{text}' is not three numbers AZIMUTH,ELEVATION,LUX")
            })?;
        let [azimuth, elevation, lux] = values[..] else {
            bail!("--sun: '{text}' is not three numbers AZIMUTH,ELEVATION,LUX");
        };
        Ok(Some(sun(azimuth, elevation, lux)?))
    }
}
