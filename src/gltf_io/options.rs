//! What the importer repairs in a file, and how far.

use crate::error::{Error, Result};
use crate::scene::{Light, Overlaps, Scene, Sky};
use crate::solve::MAX_CONTRACTION;

/// The largest diffuse reflectance the importer keeps by default; every band
/// above it is clamped to it, with a warning naming the material.
///
/// Authoring tools default to a pure-white `baseColorFactor` of 1, which no
/// real surface reaches (fresh white paint reflects 0.8 to 0.9, the whitest
/// diffuse standards 0.99). At reflectance 1 a closed scene keeps every joule
/// for ever and has no bounded solution; the Gauss-Seidel solver refuses any
/// reflectance times row sum above [`MAX_CONTRACTION`]. Below that, each
/// reflection keeps the fraction `rho` of the light, so errors in the form
/// factors are amplified by up to `1 / (1 - rho)` and the solve needs sweeps
/// in proportion (see the project's research notes, section 7.1): 20 at
/// 0.95, 100 at 0.99, 1000 at 0.999. 0.95 keeps white surfaces as bright as
/// the brightest paints while bounding that amplification to 20.
pub const DEFAULT_MAX_REFLECTANCE: f64 = 0.95;

/// How the importer repairs what real files get wrong. Each repair is
/// reported in [`Scene::warnings`](crate::scene::Scene::warnings).
#[derive(Clone, Debug, PartialEq)]
pub struct LoadOptions {
    /// Coplanar surfaces that overlap, facing the same way:
    /// [`Scene::resolve_overlaps`](crate::scene::Scene::resolve_overlaps).
    pub overlaps: Overlaps,
    /// Reflectance bands above this are clamped to it (see
    /// [`DEFAULT_MAX_REFLECTANCE`]); from just above 0 to
    /// [`MAX_CONTRACTION`], the most the solver accepts.
    pub max_reflectance: f64,
    /// Treat every material as `doubleSided`: each surface becomes two
    /// patches back to back, so that faces pointing the wrong way still
    /// reflect light.
    pub double_sided: bool,
    /// A sky to light the scene with (see [`Sky`]), in place of any the
    /// scene has: models exported before anyone lit them are common.
    pub sky: Option<Sky>,
    /// A sun (a directional light, see [`crate::scene::sun`]) added to the
    /// scene's lights.
    pub sun: Option<Light>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            overlaps: Overlaps::default(),
            max_reflectance: DEFAULT_MAX_REFLECTANCE,
            double_sided: false,
            sky: None,
            sun: None,
        }
    }
}

impl LoadOptions {
    /// Checks the options' ranges; the error names the option.
    pub fn validate(&self) -> Result<()> {
        let m = self.max_reflectance;
        if !(m > 0.0 && m <= MAX_CONTRACTION) {
            return Err(Error::Setting {
                name: "max_reflectance",
                message: format!(
                    "must be above 0 and at most {MAX_CONTRACTION} (at 1 a closed scene has no \
                     bounded solution), got {m}"
                ),
            });
        }
        if let Some(sky) = &self.sky {
            sky.validate()?;
        }
        if let Some(sun) = &self.sun {
            sun.validate()?;
        }
        Ok(())
    }

    /// Gives `scene` the sky and the sun these options ask for.
    pub fn add_daylight(&self, scene: &mut Scene) {
        if self.sky.is_some() {
            scene.sky = self.sky;
        }
        scene.lights.extend(self.sun.clone());
    }
}
