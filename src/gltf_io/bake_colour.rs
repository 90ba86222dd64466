//! What the vertex colour of a baked solution means, in both directions: from a
//! vertex radiosity to the stored `COLOR_0`, and from `COLOR_0` and its material
//! back to the radiosity.
//!
//! glTF requires every `COLOR_0` component to lie in `[0, 1]` (the Khronos
//! validator reports anything else as the error `ACCESSOR_NON_CLAMPED`), while
//! radiosities are unbounded. So each primitive stores its values divided by a
//! *scale*, a power of two written in the primitive's `extras` as
//! `radiosityScale`; dividing by a power of two loses nothing, so the only
//! rounding is the final `f32`.

use crate::math::Rgb;
use crate::scene::Material;
use std::fmt;
use std::str::FromStr;

/// The key of a primitive's `extras` that holds its colour scale.
pub(super) const SCALE_KEY: &str = "radiosityScale";

/// What the `COLOR_0` of a baked file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BakeColour {
    /// The light arriving: the irradiance `H = (B - E) / rho` per band, on the
    /// surface's original (lit, PBR) material, so that base colour times vertex
    /// colour (times the scale) is the *reflected* radiosity `rho H`, and the
    /// material's emission adds the rest. Meant as a light map for engines that
    /// keep their own materials.
    ///
    /// - Emitters: only the reflected part goes into the colour; the emission
    ///   stays on the material (`emissiveFactor`), as in the source scene, so
    ///   nothing is counted twice.
    /// - A band whose reflectance is 0 reflects nothing, so its irradiance cannot
    ///   be recovered from `B`; it is stored as 0 (the product with the base
    ///   colour is 0 either way).
    Light,
    /// The radiosity `B` itself (emission included) on an unlit
    /// (`KHR_materials_unlit`) white material without emission: what a viewer
    /// shows is the solution.
    Radiosity,
}

impl BakeColour {
    /// The name used on the command line and in the file: `light` or `radiosity`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BakeColour::Light => "light",
            BakeColour::Radiosity => "radiosity",
        }
    }

    /// The unscaled colour stored for a vertex of radiosity `b` on `material`.
    /// Never negative: `B - E` that rounding took below 0 becomes 0.
    #[must_use]
    pub fn colour_of(self, b: Rgb, material: &Material) -> Rgb {
        match self {
            BakeColour::Radiosity => b.max(Rgb::ZERO),
            BakeColour::Light => {
                let mut h = Rgb::ZERO;
                for k in 0..3 {
                    let rho = material.reflectance[k];
                    if rho > 0.0 {
                        h[k] = ((b[k] - material.emission[k]) / rho).max(0.0);
                    }
                }
                h
            }
        }
    }
}

impl fmt::Display for BakeColour {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for BakeColour {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "light" => Ok(BakeColour::Light),
            "radiosity" => Ok(BakeColour::Radiosity),
            other => Err(format!(
                "unknown bake colour '{other}' (expected light or radiosity)"
            )),
        }
    }
}

/// The smallest power of two at least `max` (1 when `max` is 0 or not finite),
/// so that values up to `max` divided by it lie in `[0, 1]`, the largest above
/// one half.
pub(super) fn scale_for(max: f64) -> f64 {
    if !(max.is_finite() && max > 0.0) {
        return 1.0;
    }
    let mut scale = 2f64.powi(max.log2().ceil() as i32);
    // `log2` may round across a power of two either way.
    while scale < max {
        scale *= 2.0;
    }
    while scale / 2.0 >= max {
        scale /= 2.0;
    }
    scale
}

/// The radiosity a baked vertex stands for: `scale * base * colour`, plus the
/// material's emitted exitance unless the material is unlit (an unlit material's
/// colour already holds the emission).
pub(super) fn radiosity_from(
    colour: Rgb,
    scale: f64,
    base_colour: Rgb,
    emission: Rgb,
    unlit: bool,
) -> Rgb {
    let reflected = base_colour * colour * scale;
    if unlit {
        reflected
    } else {
        reflected + emission
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(rho: Rgb, emission: Rgb) -> Material {
        Material {
            name: "m".to_string(),
            reflectance: rho,
            base_texture: None,
            emission,
            emissive_texture: None,
            double_sided: false,
        }
    }

    #[test]
    fn light_is_irradiance_and_round_trips() {
        let m = material(Rgb::new(0.5, 0.25, 0.0), Rgb::new(2.0, 0.0, 1.0));
        // B = E + rho H with H = (4, 8, unknown): B = (4, 2, 1).
        let b = Rgb::new(4.0, 2.0, 1.0);
        let c = BakeColour::Light.colour_of(b, &m);
        assert_eq!(c.0, [4.0, 8.0, 0.0]);
        let back = radiosity_from(c / 8.0, 8.0, m.reflectance, m.emission, false);
        assert_eq!(back.0, b.0);
    }

    #[test]
    fn radiosity_round_trips_on_unlit_white() {
        let m = material(Rgb::splat(0.7), Rgb::splat(3.0));
        let b = Rgb::new(5.0, 4.0, 3.5);
        let c = BakeColour::Radiosity.colour_of(b, &m);
        assert_eq!(c.0, b.0);
        let back = radiosity_from(c / 8.0, 8.0, Rgb::ONE, Rgb::ZERO, true);
        assert_eq!(back.0, b.0);
    }

    #[test]
    fn rounding_below_the_emission_is_not_negative() {
        let m = material(Rgb::splat(0.5), Rgb::splat(1.0));
        let c = BakeColour::Light.colour_of(Rgb::splat(1.0 - 1e-15), &m);
        assert_eq!(c.0, [0.0; 3]);
    }

    #[test]
    fn scales_are_tight_powers_of_two() {
        assert_eq!(scale_for(0.0), 1.0);
        assert_eq!(scale_for(f64::NAN), 1.0);
        assert_eq!(scale_for(1.0), 1.0);
        assert_eq!(scale_for(1.5), 2.0);
        assert_eq!(scale_for(53.4), 64.0);
        assert_eq!(scale_for(0.3), 0.5);
        assert_eq!(scale_for(0.25), 0.25);
        for max in [1e-300, 3e-7, 0.999_999, 7.0, 1e300] {
            let s = scale_for(max);
            assert!(max / s <= 1.0 && max / s > 0.5, "{max} {s}");
        }
    }

    #[test]
    fn names_parse_back() {
        for c in [BakeColour::Light, BakeColour::Radiosity] {
            assert_eq!(c.name().parse::<BakeColour>(), Ok(c));
        }
        assert!("irradiance".parse::<BakeColour>().is_err());
    }
}
