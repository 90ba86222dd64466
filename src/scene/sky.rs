//! Daylight for scenes that bring none: a sky over the whole scene, and a
//! sun.
//!
//! A sky is a source at infinity: radiance `L(w)` arriving from every
//! direction `w` above the horizon (world +Y is up, as in glTF), none from
//! below (a black ground). What reaches a point is the sky it sees past the
//! scene's own surfaces, so the sky needs no patch and cannot leak round a
//! giant dome's edges; the solver finds each element's unobstructed part by
//! rays, the reference path tracer by paths that escape.
//!
//! Two standard models (CIE S 011/E:2003):
//!
//! - **uniform**: `L(w) = L_z` everywhere above the horizon; an unobstructed
//!   horizontal surface receives `E_h = pi L_z`;
//! - **overcast** (CIE standard overcast sky, Moon and Spencer 1942):
//!   `L(w) = L_z (1 + 2 cos theta) / 3` with `theta` the zenith angle, three
//!   times brighter at the zenith than at the horizon; `E_h = 7 pi L_z / 9`.
//!
//! Units are those of the rest of the scene: `L_z` in cd/m², illuminance in
//! lux (lm/m²).

use super::{Light, LightKind};
use crate::error::{Error, Result};
use crate::math::Rgb;
use glam::DVec3;
use std::f64::consts::PI;

/// The up direction of the sky: glTF's +Y.
pub(crate) const UP: DVec3 = DVec3::Y;

/// How the sky's radiance varies with the zenith angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkyModel {
    /// The same radiance from every direction above the horizon.
    Uniform,
    /// The CIE standard overcast sky: `(1 + 2 cos theta) / 3` of the zenith.
    Overcast,
}

/// A sky over the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky {
    /// How radiance varies over the sky.
    pub model: SkyModel,
    /// Radiance at the zenith, per band, in cd/m².
    pub zenith: Rgb,
}

impl Sky {
    /// A white sky of `model` whose zenith radiance is `luminance` cd/m².
    #[must_use]
    pub fn with_zenith_luminance(model: SkyModel, luminance: f64) -> Sky {
        Sky {
            model,
            zenith: Rgb::splat(luminance),
        }
    }

    /// A white sky of `model` that gives an unobstructed horizontal surface
    /// `illuminance` lux.
    #[must_use]
    pub fn with_horizontal_illuminance(model: SkyModel, illuminance: f64) -> Sky {
        let per_zenith = Sky::with_zenith_luminance(model, 1.0).horizontal_illuminance();
        Sky::with_zenith_luminance(model, illuminance / per_zenith.0[0])
    }

    /// Fails unless the zenith radiance is finite, non-negative and above 0
    /// in some band, and within the range an emission may have (an
    /// exitance `pi L` that is a normal, finite double).
    pub fn validate(&self) -> Result<()> {
        let ok = self.zenith.0.iter().all(|v| v.is_finite() && *v >= 0.0)
            && self.zenith.max_band() > 0.0
            && (self.zenith.max_band() * PI * 3.0).is_finite()
            && self.zenith.max_band() * PI >= f64::MIN_POSITIVE;
        if ok {
            Ok(())
        } else {
            Err(Error::Setting {
                name: "sky",
                message: format!(
                    "the sky's zenith luminance must be a positive finite number of cd/m² \
                     (at most 1e300), got {:?}",
                    self.zenith.0
                ),
            })
        }
    }

    /// The sky's radiance from direction `w` (unit, pointing away from the
    /// receiver towards the sky) as a fraction of the zenith's: 0 at or
    /// below the horizon.
    #[inline]
    #[must_use]
    pub(crate) fn relative_radiance(&self, w: DVec3) -> f64 {
        let c = w.dot(UP);
        if c <= 0.0 {
            return 0.0;
        }
        match self.model {
            SkyModel::Uniform => 1.0,
            SkyModel::Overcast => (1.0 + 2.0 * c) / 3.0,
        }
    }

    /// The radiance arriving from direction `w`, per band.
    #[must_use]
    pub fn radiance(&self, w: DVec3) -> Rgb {
        self.zenith * self.relative_radiance(w)
    }

    /// The irradiance the whole sky gives a point whose unit `normal` nothing
    /// hides it from: `integral L(w) max(0, n.w) dw` over the upper
    /// hemisphere, in closed form. With `b` the angle between the normal and
    /// the zenith, the upper half of the receiver's hemisphere gives
    /// `integral max(0, n.w) dw = pi (1 + cos b) / 2` and
    /// `integral max(0, n.w) cos theta dw = 2/3 ((pi - b) cos b + sin b)`.
    #[must_use]
    pub(crate) fn unobstructed_irradiance(&self, normal: DVec3) -> Rgb {
        let cos_b = normal.dot(UP).clamp(-1.0, 1.0);
        let b = cos_b.acos();
        let flat = PI * (1.0 + cos_b) / 2.0;
        let relative = match self.model {
            SkyModel::Uniform => flat,
            SkyModel::Overcast => {
                let weighted = 2.0 / 3.0 * ((PI - b) * cos_b + b.sin());
                (flat + 2.0 * weighted) / 3.0
            }
        };
        self.zenith * relative.max(0.0)
    }

    /// The illuminance of an unobstructed horizontal surface facing up.
    #[must_use]
    pub(crate) fn horizontal_illuminance(&self) -> Rgb {
        self.unobstructed_irradiance(UP)
    }
}

/// A sun: a directional light from `azimuth` degrees (clockwise from north,
/// taken as -Z, towards east, +X) at `elevation` degrees above the horizon,
/// giving `illuminance` lux on a surface that faces it. It is the sky's
/// companion for a daylit model; its light is a punctual light's (sharp
/// shadows, exact).
///
/// Fails on an elevation outside (0, 90], an azimuth or illuminance that is
/// not finite, or a negative illuminance.
pub fn sun(azimuth: f64, elevation: f64, illuminance: f64) -> Result<Light> {
    let bad = |message: String| {
        Err(Error::Setting {
            name: "sun",
            message,
        })
    };
    if !(azimuth.is_finite() && elevation.is_finite() && illuminance.is_finite()) {
        return bad(format!(
            "azimuth, elevation and illuminance must be finite, got {azimuth}, {elevation}, \
             {illuminance}"
        ));
    }
    if !(elevation > 0.0 && elevation <= 90.0) {
        return bad(format!(
            "the elevation must lie above the horizon, in (0, 90] degrees, got {elevation}"
        ));
    }
    if illuminance <= 0.0 {
        return bad(format!(
            "the illuminance must be positive (lux), got {illuminance}"
        ));
    }
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    let towards = DVec3::new(a.sin() * e.cos(), e.sin(), -a.cos() * e.cos());
    let light = Light {
        name: format!("sun (azimuth {azimuth} deg, elevation {elevation} deg)"),
        kind: LightKind::Directional,
        colour: Rgb::splat(1.0),
        intensity: illuminance,
        range: None,
        position: DVec3::ZERO,
        direction: -towards,
    };
    light.validate()?;
    Ok(light)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_shines_from_its_azimuth_and_elevation() {
        // Due south (azimuth 180) at 30 degrees: light travels north (-z is
        // north, so towards -z... from +z) and down.
        let s = sun(180.0, 30.0, 50_000.0).unwrap();
        let towards = -s.direction;
        assert!((towards - DVec3::new(0.0, 0.5, 0.75f64.sqrt())).length() < 1e-12);
        // East at the zenith's edge, then straight overhead.
        let east = sun(90.0, 45.0, 1.0).unwrap();
        assert!(-east.direction.x > 0.7 && east.direction.z.abs() < 1e-12);
        let overhead = sun(10.0, 90.0, 1.0).unwrap();
        assert!((overhead.direction + UP).length() < 1e-12);
        // A horizontal floor under it gets the illuminance times sin(elevation).
        let lit = s.incident(DVec3::ZERO).unwrap().on(UP);
        assert!((lit.0[0] - 25_000.0).abs() < 1e-6);
        for (a, e, l) in [
            (0.0, 0.0, 1.0),
            (0.0, -5.0, 1.0),
            (0.0, 95.0, 1.0),
            (f64::NAN, 10.0, 1.0),
            (0.0, 10.0, 0.0),
            (0.0, 10.0, f64::INFINITY),
        ] {
            assert!(sun(a, e, l).is_err(), "{a} {e} {l}");
        }
    }

    /// A plain midpoint sum over the sphere, independent of the closed forms.
    fn numeric_irradiance(sky: &Sky, normal: DVec3) -> f64 {
        let (nt, np) = (800, 1600);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) * PI / nt as f64;
            let ring = theta.sin() * (PI / nt as f64) * (2.0 * PI / np as f64);
            for j in 0..np {
                let phi = (j as f64 + 0.5) * 2.0 * PI / np as f64;
                let w = DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                sum += sky.relative_radiance(w) * normal.dot(w).max(0.0) * ring;
            }
        }
        sum
    }

    #[test]
    fn a_horizontal_surface_receives_pi_l_under_a_uniform_sky_and_seven_ninths_of_it_under_an_overcast_one(
    ) {
        let uniform = Sky::with_zenith_luminance(SkyModel::Uniform, 1000.0);
        assert!((uniform.horizontal_illuminance().0[0] - PI * 1000.0).abs() < 1e-9);
        let overcast = Sky::with_zenith_luminance(SkyModel::Overcast, 1000.0);
        let expected = 7.0 * PI * 1000.0 / 9.0;
        assert!((overcast.horizontal_illuminance().0[0] - expected).abs() < 1e-9);
        // Given by its illuminance, the sky has the zenith radiance that
        // gives it.
        let given = Sky::with_horizontal_illuminance(SkyModel::Overcast, 10_000.0);
        assert!((given.zenith.0[0] - 10_000.0 * 9.0 / (7.0 * PI)).abs() < 1e-9);
    }

    #[test]
    fn tilted_surfaces_receive_what_a_sum_over_the_sphere_gives() {
        for model in [SkyModel::Uniform, SkyModel::Overcast] {
            let sky = Sky::with_zenith_luminance(model, 1.0);
            for tilt in [0.0f64, 0.4, 1.2, 0.5 * PI, 2.3, 3.0, PI] {
                let normal = DVec3::new(tilt.sin(), tilt.cos(), 0.0);
                let closed = sky.unobstructed_irradiance(normal).0[0];
                let numeric = numeric_irradiance(&sky, normal);
                assert!(
                    (closed - numeric).abs() < 1e-4 * (1.0 + numeric),
                    "{model:?} tilt {tilt}: {closed} against {numeric}"
                );
            }
        }
    }

    #[test]
    fn nothing_comes_from_below_the_horizon() {
        let sky = Sky::with_zenith_luminance(SkyModel::Overcast, 1.0);
        assert_eq!(sky.relative_radiance(-UP), 0.0);
        assert_eq!(sky.relative_radiance(DVec3::X), 0.0);
        assert!(sky.unobstructed_irradiance(-UP).0[0].abs() < 1e-12);
        assert!((sky.relative_radiance(UP) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn a_sky_without_light_or_beyond_the_range_of_numbers_is_refused() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e308, 1e-320] {
            let sky = Sky::with_zenith_luminance(SkyModel::Uniform, bad);
            assert!(sky.validate().is_err(), "{bad}");
        }
        assert!(Sky::with_zenith_luminance(SkyModel::Uniform, 1e4)
            .validate()
            .is_ok());
    }
}
