//! Per-object figures: what users compare against references.

use crate::math::Rgb;
use serde::Serialize;
use std::f64::consts::PI;

/// Area and mean radiosity of one scene object (a glTF node with a mesh).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ObjectRadiosity {
    /// The object's name.
    pub name: String,
    /// Its area in square metres.
    pub area: f64,
    /// Its area-weighted mean radiosity (exitance), per band.
    pub radiosity: Rgb,
}

impl ObjectRadiosity {
    /// The mean radiance a camera sees on the object: radiosity / pi, since
    /// its surfaces are diffuse.
    #[must_use]
    pub fn radiance(&self) -> Rgb {
        self.radiosity / PI
    }
}
