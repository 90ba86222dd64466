//! Diffuse materials: reflectance per band and emitted exitance.

use super::Texture;
use crate::error::{Error, Result};
use crate::math::Rgb;
use glam::DVec2;
use std::sync::Arc;

/// The largest contraction factor accepted. Form factors are stored in single
/// precision, so row sums carry errors of about `1e-7`; a row-sum error `delta`
/// shifts the solution by about `delta / (1 - q)` relative, which passes 1% when
/// `1 - q` falls below `1e-5`. Such a system (a closed scene with reflectance
/// above 0.99999) has no meaningful solution at this precision and is refused.
pub const MAX_CONTRACTION: f64 = 1.0 - 1e-5;

/// A Lambertian material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name for messages and stats.
    pub name: String,
    /// Diffuse reflectance per band, each in [0, 1]: with a base-colour
    /// texture, its mean over the whole image (what surfaces without texture
    /// coordinates get).
    pub reflectance: Rgb,
    /// The base-colour texture: each element of a surface with texture
    /// coordinates gets the texture's mean over its footprint.
    pub base_texture: Option<Arc<Texture>>,
    /// Emitted exitance E = pi * L_e per band (W/m^2 in the scene's units), >= 0:
    /// with an emissive texture, its mean over the whole image.
    pub emission: Rgb,
    /// The emissive texture, its texels times the exitance factor (pi times
    /// `emissiveFactor` times the emissive strength): each element of a
    /// surface with texture coordinates emits the texture's mean over its
    /// footprint.
    pub emissive_texture: Option<Arc<Texture>>,
    /// Whether the source material was marked double-sided. The importer
    /// (and [`Scene::make_double_sided`](super::Scene::make_double_sided))
    /// has already put a copy of each such surface back to back with it, and
    /// hemi-cubes rely on that: they do not draw these surfaces' backs, which
    /// a front always covers. A scene built by hand that sets this must add
    /// the copies too.
    pub double_sided: bool,
}

impl Material {
    /// A material from its reflectance and emitted *radiance* (as glTF stores it);
    /// the exitance is pi times the radiance. Rejects reflectance outside [0, 1]
    /// and negative or non-finite values, naming the material.
    pub(crate) fn from_radiance(name: &str, reflectance: Rgb, radiance: Rgb) -> Result<Self> {
        let m = Material {
            name: name.to_string(),
            reflectance,
            base_texture: None,
            emission: radiance * std::f64::consts::PI,
            emissive_texture: None,
            double_sided: false,
        };
        m.validate()?;
        Ok(m)
    }

    /// Checks the physical ranges; the error names the material and the fault.
    pub fn validate(&self) -> Result<()> {
        let err = |message: String| Error::Material {
            material: self.name.clone(),
            message,
        };
        if !self.reflectance.is_finite() {
            return Err(err(format!(
                "reflectance {:?} is not finite",
                self.reflectance.0
            )));
        }
        if self.reflectance.max_band() > 1.0 {
            return Err(err(format!(
                "reflectance {:?} is above 1 (a diffuse surface cannot reflect more than it receives)",
                self.reflectance.0
            )));
        }
        if self.reflectance.min_band() < 0.0 {
            return Err(err(format!(
                "reflectance {:?} is negative",
                self.reflectance.0
            )));
        }
        if !self.emission.is_finite() {
            return Err(err(format!("emission {:?} is not finite", self.emission.0)));
        }
        if self.emission.min_band() < 0.0 {
            return Err(err(format!("emission {:?} is negative", self.emission.0)));
        }
        // A subnormal double carries fewer significant bits than the solve
        // needs, and arithmetic on such values is slow enough to stall it.
        if self.emission.0.iter().any(|e| *e != 0.0 && !e.is_normal()) {
            return Err(err(format!(
                "emission {:?} has a band below {:e}, the smallest normal double: too \
                 small to be represented; results are linear in emission, so scale every \
                 emission of the scene up by the same factor",
                self.emission.0,
                f64::MIN_POSITIVE
            )));
        }
        Ok(())
    }

    /// The reflectance at texture coordinates `uv` (of the set the surface
    /// carries): the base-colour texture there, or the material's reflectance
    /// without a texture or coordinates.
    #[must_use]
    pub fn reflectance_at(&self, uv: Option<DVec2>) -> Rgb {
        match (&self.base_texture, uv) {
            (Some(t), Some(uv)) => t.value_at(uv),
            _ => self.reflectance,
        }
    }

    /// The emitted exitance at texture coordinates `uv`: the emissive texture
    /// there, or the material's emission without a texture or coordinates.
    #[must_use]
    pub fn emission_at(&self, uv: Option<DVec2>) -> Rgb {
        match (&self.emissive_texture, uv) {
            (Some(t), Some(uv)) => t.value_at(uv),
            _ => self.emission,
        }
    }

    /// True when the material emits in any band.
    #[must_use]
    pub fn is_emitter(&self) -> bool {
        self.emission.max_band() > 0.0
    }
}
