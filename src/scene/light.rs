//! Punctual lights (glTF's `KHR_lights_punctual`): point, spot and
//! directional sources outside the mesh.
//!
//! # Units
//!
//! One photometric system for every source, so that a scene mixing lamps
//! modelled as emissive surfaces with punctual lights is consistent:
//! emissive surfaces have a radiance in cd/m² (`emissiveFactor` times
//! `KHR_materials_emissive_strength`), and their exitance is pi times it;
//! point and spot lights an intensity in candela (cd = lm/sr); directional
//! lights an illuminance in lux (lm/m²) on a surface facing them. Radiosity
//! and irradiance then come out in lm/m². (A scene in radiometric units, W
//! and W/sr, reads the same way with watts for lumens.)
//!
//! A light's irradiance at a point follows the extension's definitions: the
//! inverse square law with the recommended window to zero at `range`, and
//! for a spot the recommended smooth falloff between its inner and outer
//! cones. Visibility is not the light's business: the solver and the
//! reference cast their own shadow rays to [`Incident::target`].

use crate::error::{Error, Result};
use crate::math::Rgb;
use glam::DVec3;
use std::f64::consts::FRAC_PI_2;

/// What kind of punctual light, with the parameters of its kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light in every direction from a point; intensity in candela.
    Point,
    /// Light in a cone about [`Light::direction`]; intensity in candela on
    /// its axis, full inside `inner_cone` and falling smoothly to zero at
    /// `outer_cone` (angles from the axis, radians,
    /// `0 <= inner_cone <= outer_cone <= pi/2`).
    Spot {
        /// Angle from the axis where the falloff begins.
        inner_cone: f64,
        /// Angle from the axis where the light ends.
        outer_cone: f64,
    },
    /// Parallel light along [`Light::direction`] from infinitely far (a sun);
    /// intensity is the illuminance in lux on a surface facing it.
    Directional,
}

/// A punctual light placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// A name for messages and stats: the light's, and its node's.
    pub name: String,
    /// Point, spot or directional.
    pub kind: LightKind,
    /// Linear RGB colour (each band at least 0; glTF gives 0 to 1).
    pub colour: Rgb,
    /// Candela for point and spot lights, lux for directional ones.
    pub intensity: f64,
    /// Distance beyond which a point or spot light gives nothing (`None`:
    /// unlimited). Ignored for directional lights.
    pub range: Option<f64>,
    /// World position (ignored for directional lights).
    pub position: DVec3,
    /// Unit direction the light travels along: a spot's axis, a sun's rays
    /// (the node's -Z axis in glTF). Ignored for point lights.
    pub direction: DVec3,
}

/// Where a shadow ray from a lit point must go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// The light's position.
    Point(DVec3),
    /// Out of the scene along this unit direction (a directional light).
    Infinity(DVec3),
}

/// What a light sends to a point, before its receiver's cosine and any
/// occluder: the irradiance on a surface facing the light squarely.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Irradiance (lm/m², per band) on a surface facing the light.
    pub normal_irradiance: Rgb,
    /// Unit direction from the point towards the light.
    pub towards: DVec3,
    /// Where the shadow ray goes.
    pub target: Target,
}

impl Incident {
    /// The irradiance on a surface with unit `normal` (none from behind).
    #[must_use]
    pub fn on(&self, normal: DVec3) -> Rgb {
        let cos = normal.dot(self.towards);
        if cos > 0.0 {
            self.normal_irradiance * cos
        } else {
            Rgb::ZERO
        }
    }
}

impl Light {
    /// A point light of `intensity` candela and `colour` at `position`.
    #[must_use]
    pub fn point(name: &str, position: DVec3, colour: Rgb, intensity: f64) -> Self {
        Light {
            name: name.to_string(),
            kind: LightKind::Point,
            colour,
            intensity,
            range: None,
            position,
            direction: DVec3::NEG_Z,
        }
    }

    /// A spot light at `position` shining along `direction` (normalised
    /// here), with the extension's cone angles in radians.
    #[must_use]
    pub fn spot(
        name: &str,
        position: DVec3,
        direction: DVec3,
        cones: (f64, f64),
        colour: Rgb,
        intensity: f64,
    ) -> Self {
        Light {
            name: name.to_string(),
            kind: LightKind::Spot {
                inner_cone: cones.0,
                outer_cone: cones.1,
            },
            colour,
            intensity,
            range: None,
            position,
            direction: direction.normalize_or_zero(),
        }
    }

    /// A directional light (a sun) whose rays travel along `direction`
    /// (normalised here), giving `illuminance` lux on a surface facing it.
    #[must_use]
    pub fn directional(name: &str, direction: DVec3, colour: Rgb, illuminance: f64) -> Self {
        Light {
            name: name.to_string(),
            kind: LightKind::Directional,
            colour,
            intensity: illuminance,
            range: None,
            position: DVec3::ZERO,
            direction: direction.normalize_or_zero(),
        }
    }

    /// Checks every value; the error names the light and the fault.
    pub fn validate(&self) -> Result<()> {
        let err = |message: String| Error::Light {
            light: format!("'{}'", self.name),
            message,
        };
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return Err(err(format!(
                "intensity {} is not a finite number of at least 0",
                self.intensity
            )));
        }
        if !self.colour.is_finite() || self.colour.min_band() < 0.0 {
            return Err(err(format!(
                "colour {:?} must be finite and at least 0 in every band",
                self.colour.0
            )));
        }
        // The ends of floating point, as for emission: a subnormal value has
        // too few significant bits (1e-310 cd gave an all-white picture), and
        // a light beyond single precision (the most an emissive strength can
        // be) makes radiosities no image file holds (3.4e38 cd gave an EXR
        // of infinities).
        let values = [
            self.intensity,
            self.colour[0],
            self.colour[1],
            self.colour[2],
        ];
        if values.iter().any(|v| *v != 0.0 && !v.is_normal()) {
            return Err(err(format!(
                "intensity {:e} or colour {:?} is below {:e}, the smallest normal double: too \
                 small to be represented; results are linear in light, so scale every light \
                 and emission of the scene up by the same factor",
                self.intensity,
                self.colour.0,
                f64::MIN_POSITIVE
            )));
        }
        let strongest = self.intensity * self.colour.max_band();
        if strongest.max(self.intensity) > f64::from(f32::MAX) {
            return Err(err(format!(
                "intensity {:e} times colour {:?} is above {:e}, the largest single-precision \
                 number (the most an emissive strength can be, and more than an image file \
                 holds); results are linear in light, so scale every light and emission of \
                 the scene down by the same factor",
                self.intensity,
                self.colour.0,
                f32::MAX
            )));
        }
        if let Some(range) = self.range {
            if !(range.is_finite() && range > 0.0) {
                return Err(err(format!(
                    "range {range} must be a finite distance above 0 (leave it out for no limit)"
                )));
            }
        }
        if !self.position.is_finite() {
            return Err(err(format!("position {:?} is not finite", self.position)));
        }
        let aims = !matches!(self.kind, LightKind::Point);
        if aims && !(self.direction.is_finite() && (self.direction.length() - 1.0).abs() < 1e-9) {
            return Err(err(format!(
                "direction {:?} is not a unit vector (its node's transform collapses its -Z axis)",
                self.direction
            )));
        }
        if let LightKind::Spot {
            inner_cone,
            outer_cone,
        } = self.kind
        {
            if !(inner_cone.is_finite() && outer_cone.is_finite()) {
                return Err(err("cone angles must be finite".to_string()));
            }
            if !(0.0..=FRAC_PI_2).contains(&outer_cone) || outer_cone <= 0.0 {
                return Err(err(format!(
                    "outerConeAngle {outer_cone} must be above 0 and at most pi/2"
                )));
            }
            if !(0.0..=outer_cone).contains(&inner_cone) {
                return Err(err(format!(
                    "innerConeAngle {inner_cone} must be from 0 to the outerConeAngle \
                     {outer_cone}"
                )));
            }
        }
        Ok(())
    }

    /// True when the light gives any light at all.
    #[must_use]
    pub(crate) fn shines(&self) -> bool {
        self.intensity > 0.0 && self.colour.max_band() > 0.0
    }

    /// What the light sends to `point`, before the receiver's cosine and
    /// occluders; `None` where it sends nothing (outside a spot's cone,
    /// beyond its range, at the light itself).
    #[must_use]
    pub fn incident(&self, point: DVec3) -> Option<Incident> {
        let power = self.colour * self.intensity;
        if let LightKind::Directional = self.kind {
            return Some(Incident {
                normal_irradiance: power,
                towards: -self.direction,
                target: Target::Infinity(-self.direction),
            });
        }
        let span = self.position - point;
        let d2 = span.length_squared();
        if d2 <= 0.0 || d2.is_nan() {
            return None;
        }
        let d = d2.sqrt();
        let towards = span / d;
        let mut scale = range_window(self.range, d) / d2;
        if let LightKind::Spot {
            inner_cone,
            outer_cone,
        } = self.kind
        {
            scale *= spot_falloff(inner_cone, outer_cone, self.direction.dot(-towards));
        }
        (scale > 0.0).then(|| Incident {
            normal_irradiance: power * scale,
            towards,
            target: Target::Point(self.position),
        })
    }

    /// The power it sends out (lm per band) for a point light, `4 pi I`;
    /// `None` for spots and suns, whose power depends on what they meet.
    #[must_use]
    pub fn point_power(&self) -> Option<Rgb> {
        (self.kind == LightKind::Point && self.range.is_none())
            .then(|| self.colour * (4.0 * std::f64::consts::PI * self.intensity))
    }
}

/// The extension's recommended window on the inverse square law: 1 near the
/// light, falling smoothly to 0 at `range`, `clamp(1 - (d / range)^4, 0, 1)`.
#[must_use]
pub(crate) fn range_window(range: Option<f64>, distance: f64) -> f64 {
    match range {
        None => 1.0,
        Some(r) => (1.0 - (distance / r).powi(4)).clamp(0.0, 1.0),
    }
}

/// The extension's recommended spot falloff at `cos_angle` from the axis:
/// the cosine mapped linearly from the outer cone (0) to the inner (1),
/// clamped, then squared for a smooth edge. Where the cones meet the ramp is
/// the extension's steepest, 1/0.001 in cosine.
#[must_use]
pub(crate) fn spot_falloff(inner_cone: f64, outer_cone: f64, cos_angle: f64) -> f64 {
    let (cos_inner, cos_outer) = (inner_cone.cos(), outer_cone.cos());
    let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
    let t = ((cos_angle - cos_outer) * scale).clamp(0.0, 1.0);
    t * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_follows_the_inverse_square_law() {
        let light = Light::point("p", DVec3::new(0.0, 0.0, 2.0), Rgb::ONE, 10.0);
        let at = light.incident(DVec3::new(1.0, 0.0, 0.0)).expect("lit");
        let e = at.on(DVec3::Z).0[0];
        // I cos / d^2 with cos = 2 / sqrt(5), d^2 = 5.
        assert!((e - 10.0 * 2.0 / 5f64.sqrt() / 5.0).abs() < 1e-12, "{e}");
        assert_eq!(at.on(DVec3::NEG_Z), Rgb::ZERO);
    }

    #[test]
    fn spot_falloff_is_one_inside_and_zero_outside() {
        assert_eq!(spot_falloff(0.2, 0.4, 0.1f64.cos()), 1.0);
        assert_eq!(spot_falloff(0.2, 0.4, 0.5f64.cos()), 0.0);
        let mid = spot_falloff(0.2, 0.4, 0.3f64.cos());
        assert!(mid > 0.0 && mid < 1.0);
    }

    #[test]
    fn bad_values_are_named() {
        let mut l = Light::point("lamp", DVec3::ZERO, Rgb::ONE, -1.0);
        let e = l.validate().unwrap_err().to_string();
        assert!(e.contains("lamp") && e.contains("intensity"), "{e}");
        l.intensity = 1.0;
        l.kind = LightKind::Spot {
            inner_cone: 0.5,
            outer_cone: 0.3,
        };
        let e = l.validate().unwrap_err().to_string();
        assert!(e.contains("innerConeAngle"), "{e}");
    }

    #[test]
    fn intensities_at_the_ends_of_floating_point_are_refused() {
        let light = |intensity: f64, colour: f64| {
            Light::point("lamp", DVec3::ZERO, Rgb::splat(colour), intensity).validate()
        };
        for (intensity, colour) in [(1e-310, 1.0), (1.0, 1e-320), (3.5e38, 1.0), (1e20, 1e19)] {
            let e = light(intensity, colour).unwrap_err().to_string();
            assert!(e.contains("lamp") && e.contains("the same factor"), "{e}");
        }
        // The smallest normal and the largest single-precision values pass,
        // as does a light of colour 0.
        assert!(light(f64::MIN_POSITIVE, 1.0).is_ok());
        assert!(light(f64::from(f32::MAX), 1.0).is_ok());
        assert!(light(1e300, 0.0).is_err());
        assert!(light(1.0, 0.0).is_ok());
    }
}
