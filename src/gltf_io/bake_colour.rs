//! Scales of baked values, and how bakes before light groups (version 1)
//! stored their radiosity: `COLOR_0` times a power of two kept in each
//! primitive's `extras` as `radiosityScale`, on unlit white materials (the
//! radiosity) or on the scene's own (the irradiance, with the emission on the
//! material). [`load_baked`](super::load_baked) still reads those.
//!
//! Dividing by a power of two loses nothing, so the only rounding of a
//! scaled value is its final `f32`.

use crate::math::Rgb;

/// The key of a primitive's `extras` that held its colour scale in a
/// version 1 bake.
pub(super) const SCALE_KEY: &str = "radiosityScale";

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

    #[test]
    fn radiosity_comes_back_from_either_version_1_material() {
        // Unlit white: the colour times the scale is the radiosity.
        let b = radiosity_from(Rgb::new(0.5, 0.25, 1.0), 8.0, Rgb::ONE, Rgb::ZERO, true);
        assert_eq!(b.0, [4.0, 2.0, 8.0]);
        // Lit: base colour times the irradiance, plus the emission.
        let b = radiosity_from(
            Rgb::splat(0.5),
            8.0,
            Rgb::splat(0.5),
            Rgb::splat(1.0),
            false,
        );
        assert_eq!(b.0, [3.0; 3]);
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
}
