//! Per-object mean radiosity errors against the Monte Carlo object means.

use super::ERROR_FLOOR_FRACTION;
use crate::error::{Error, GeometryFault, Result};
use crate::math::Rgb;
use crate::reference::{Reference, ReferenceSettings};
use crate::scene::Scene;
use crate::solution::Solution;
use serde::Serialize;

/// The path-traced mean radiosity of one object.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObjectReference {
    /// The object's name.
    pub name: String,
    /// Whether any of its surfaces emits (its errors are then not measured).
    pub emits: bool,
    /// Its area-weighted mean radiosity per band.
    pub radiosity: Rgb,
    /// The standard error of that mean per band.
    pub std_error: Rgb,
}

/// The mean radiosity of every object of `scene` from `paths` uniformly
/// placed paths each ([`Reference::object_means`]).
pub fn object_reference(scene: &Scene, paths: u64, seed: u64) -> Result<Vec<ObjectReference>> {
    let reference = Reference::new(scene)?;
    let settings = ReferenceSettings {
        paths,
        seed,
        ..ReferenceSettings::default()
    };
    let means = reference.object_means(&settings)?;
    Ok(scene
        .objects
        .iter()
        .zip(means)
        .enumerate()
        .map(|(i, (o, m))| ObjectReference {
            name: o.name.clone(),
            emits: scene
                .surfaces
                .iter()
                .any(|s| s.object as usize == i && scene.material_of(s).is_emitter()),
            radiosity: m.radiosity,
            std_error: m.std_error,
        })
        .collect())
}

/// The error of one object's mean radiosity.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObjectError {
    /// The object's name.
    pub name: String,
    /// `|B - R| / max(R, f)` averaged over the bands, with `f`
    /// [`ERROR_FLOOR_FRACTION`] of the area-weighted mean reference radiosity
    /// of the non-emitting objects.
    pub error: f64,
    /// The largest band's relative error.
    pub max_band_error: f64,
    /// The reference's standard error on the same scale, averaged over bands.
    pub reference_std_error: f64,
}

/// The mean-radiosity error of every non-emitting object with area, in scene
/// order. Fails if `reference` does not list the scene's objects.
pub(crate) fn object_errors(
    solution: &Solution,
    scene: &Scene,
    reference: &[ObjectReference],
) -> Result<Vec<ObjectError>> {
    let solved = solution.object_radiosity(scene);
    let names_match = solved.len() == reference.len()
        && solved.iter().zip(reference).all(|(s, r)| s.name == r.name);
    if !names_match {
        return Err(Error::geometry(
            GeometryFault::Mismatch,
            format!(
                "the object reference lists {} objects, scene '{}' has {} (or names differ)",
                reference.len(),
                scene.name,
                solved.len()
            ),
        ));
    }
    let lit = || {
        solved
            .iter()
            .zip(reference)
            .filter(|(s, r)| !r.emits && s.area > 0.0)
    };
    let area: f64 = lit().map(|(s, _)| s.area).sum();
    let weighted = lit().fold(Rgb::ZERO, |a, (s, r)| a + r.radiosity * s.area);
    let floor = if area > 0.0 {
        weighted * (ERROR_FLOOR_FRACTION / area)
    } else {
        Rgb::ZERO
    };
    Ok(lit()
        .map(|(s, r)| {
            let scale = |k: usize| r.radiosity[k].max(floor[k]).max(f64::MIN_POSITIVE);
            let band = |k: usize| (s.radiosity[k] - r.radiosity[k]).abs() / scale(k);
            let errors = [band(0), band(1), band(2)];
            ObjectError {
                name: s.name.clone(),
                error: errors.iter().sum::<f64>() / 3.0,
                max_band_error: errors.iter().copied().fold(0.0, f64::max),
                reference_std_error: (0..3).map(|k| r.std_error[k] / scale(k)).sum::<f64>() / 3.0,
            }
        })
        .collect())
}
