//! Checks of the punctual lights against what they reach: a light that
//! reaches no surface's front (a lamp shut inside a closed box, a sun over
//! a closed room) is named in a warning instead of leaving a black picture
//! without a word, and a light whose irradiance overflows is named in the
//! error instead of the solver's "diverged".

use super::workspace::Workspace;
use crate::error::Error;
use crate::scene::{Light, LightKind};
use crate::solve::DirectLight;

/// Above this many lights only the case of every light dark is looked for:
/// telling which of many lights is dark takes a pass of shadow rays each.
pub(crate) const MOST_LIGHTS_CHECKED_ONE_BY_ONE: usize = 32;

impl Workspace<'_> {
    /// The shining lights that give the current leaves no light: all of
    /// them when the lights together give none; else, up to
    /// [`MOST_LIGHTS_CHECKED_ONE_BY_ONE`] lights, each one looked at alone.
    pub(super) fn dark_lights(&self, among: &[usize]) -> Vec<usize> {
        let Some(direct) = &self.direct else {
            return Vec::new();
        };
        let lights = &self.scene.lights;
        let shining: Vec<usize> = among
            .iter()
            .copied()
            .filter(|&i| lights[i].shines())
            .collect();
        if shining.is_empty() {
            return Vec::new();
        }
        if direct.incident_power(&self.mesh).max_band() <= 0.0 {
            return shining;
        }
        if shining.len() > MOST_LIGHTS_CHECKED_ONE_BY_ONE {
            return Vec::new();
        }
        shining
            .into_iter()
            .filter(|&i| {
                let mut alone = DirectLight::default();
                alone.update(
                    &self.mesh,
                    &self.sources,
                    std::slice::from_ref(&lights[i]),
                    None,
                );
                alone.incident_power(&self.mesh).max_band() <= 0.0
            })
            .collect()
    }

    /// After the solve, on the final mesh: a warning naming each light of
    /// `candidates` (dark on the first mesh) that is still dark.
    pub(super) fn warn_dark_lights(&mut self, candidates: &[usize]) {
        if candidates.is_empty() {
            return;
        }
        let dark = self.dark_lights(candidates);
        for i in dark {
            let light = &self.scene.lights[i];
            let why = match light.kind {
                LightKind::Directional => {
                    "a sun whose rays meet only the backs of surfaces or nothing (outside a \
                     closed room, or below the ground)"
                }
                _ => {
                    "shut inside a closed object, facing away from every surface, or out of \
                     range of them"
                }
            };
            self.stats.warnings.push(format!(
                "punctual light '{}' reaches no surface's front: it adds no light ({why})",
                light.name
            ));
        }
    }

    /// An error naming the light whose irradiance is not finite on some
    /// leaf (the light nearest that leaf), if there is such a leaf.
    pub(super) fn overflowing_light(&self) -> Option<Error> {
        let direct = self.direct.as_ref()?;
        let k = self
            .mesh
            .leaves()
            .into_iter()
            .find(|&k| !direct.irradiance(k).is_finite())?;
        let at = self.mesh.elements[k].centroid;
        let nearest = self
            .scene
            .lights
            .iter()
            .filter(|l| l.kind != LightKind::Directional)
            .min_by(|a, b| a.position.distance(at).total_cmp(&b.position.distance(at)))?;
        Some(overflow_error(nearest, nearest.position.distance(at)))
    }

    /// [`Workspace::overflowing_light`] in place of `error` (a solver's
    /// "diverged" when the cause is a light), else `error` as it is.
    pub(super) fn explain(&self, error: Error) -> Error {
        self.overflowing_light().unwrap_or(error)
    }
}

/// The error for `light`, whose irradiance overflows at `distance`.
fn overflow_error(light: &Light, distance: f64) -> Error {
    Error::Light {
        light: format!("'{}'", light.name),
        message: format!(
            "its irradiance ({:e} cd over the square of {distance:e} m) is beyond what a \
             double holds at a surface that close: move the light off the surface, or lower \
             its intensity",
            light.intensity * light.colour.max_band()
        ),
    }
}
