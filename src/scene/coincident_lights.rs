//! Punctual lights at the same place merged into one.
//!
//! Direct light costs a shadow ray per light per sample point, so a file
//! with a hundred thousand lights at one point (a scattering tool run wild,
//! a light instanced on every copy of a mesh flattened into one place) took
//! minutes for the light of one lamp. Lights of one kind that share their
//! position, direction, range and cones light every point alike up to their
//! colour and intensity, and their light adds: one light with the summed
//! power per band gives the same irradiance everywhere.

use super::{Light, LightKind};
use crate::math::Rgb;
use std::collections::HashMap;

/// What makes two lights the same source up to their power: the kind and
/// the bits of every parameter that matters to the kind.
fn key(light: &Light) -> Vec<u64> {
    let mut k = Vec::with_capacity(10);
    let mut push = |x: f64| k.push(x.to_bits());
    match light.kind {
        LightKind::Point => {
            push(0.0);
            light.position.to_array().into_iter().for_each(&mut push);
            push(light.range.unwrap_or(-1.0));
        }
        LightKind::Spot {
            inner_cone,
            outer_cone,
        } => {
            push(1.0);
            light.position.to_array().into_iter().for_each(&mut push);
            light.direction.to_array().into_iter().for_each(&mut push);
            push(light.range.unwrap_or(-1.0));
            push(inner_cone);
            push(outer_cone);
        }
        LightKind::Directional => {
            push(2.0);
            light.direction.to_array().into_iter().for_each(&mut push);
        }
    }
    k
}

/// `lights` with every group of lights at the same place (and of the same
/// kind, direction, range and cones) merged into its first, which takes the
/// group's summed power per band and a name that counts the others. The
/// order of the first lights is kept. Returns the lights and how many were
/// merged away.
#[must_use]
pub(crate) fn merge_coincident_lights(lights: Vec<Light>) -> (Vec<Light>, usize) {
    let mut first: HashMap<Vec<u64>, usize> = HashMap::new();
    let mut power: Vec<Rgb> = Vec::new();
    let mut count: Vec<usize> = Vec::new();
    let mut out: Vec<Light> = Vec::new();
    for light in lights {
        let p = light.colour * light.intensity;
        match first.get(&key(&light)) {
            Some(&i) => {
                power[i] += p;
                count[i] += 1;
            }
            None => {
                first.insert(key(&light), out.len());
                power.push(p);
                count.push(1);
                out.push(light);
            }
        }
    }
    let mut merged = 0;
    for ((light, p), n) in out.iter_mut().zip(power).zip(count) {
        if n == 1 {
            continue;
        }
        merged += n - 1;
        let intensity = p.max_band();
        light.intensity = intensity;
        light.colour = if intensity > 0.0 {
            p / intensity
        } else {
            Rgb::ZERO
        };
        light.name = format!("{} and {} more at the same place", light.name, n - 1);
    }
    (out, merged)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn lights_at_one_place_add_their_power_per_band() {
        let at = DVec3::new(1.0, 2.0, 3.0);
        let lights = vec![
            Light::point("a", at, Rgb::new(1.0, 0.0, 0.0), 10.0),
            Light::point("b", DVec3::ZERO, Rgb::ONE, 1.0),
            Light::point("c", at, Rgb::new(0.0, 0.5, 0.0), 4.0),
            Light::point("d", at, Rgb::new(0.0, 0.0, 1.0), 10.0),
        ];
        let here = DVec3::new(1.0, 0.0, 3.0);
        let before: Rgb = lights
            .iter()
            .map(|l| l.incident(here).unwrap().normal_irradiance)
            .fold(Rgb::ZERO, |a, b| a + b);
        let (merged, gone) = merge_coincident_lights(lights);
        assert_eq!(gone, 2);
        assert_eq!(merged.len(), 2);
        assert!(merged[0].name.starts_with("a and 2 more"));
        assert_eq!(merged[1].name, "b");
        let after: Rgb = merged
            .iter()
            .map(|l| l.incident(here).unwrap().normal_irradiance)
            .fold(Rgb::ZERO, |a, b| a + b);
        for k in 0..3 {
            assert!((after[k] - before[k]).abs() <= 1e-12 * before[k].max(1.0));
        }
    }

    #[test]
    fn lights_that_differ_in_anything_but_power_stay_apart() {
        let at = DVec3::ZERO;
        let mut ranged = Light::point("r", at, Rgb::ONE, 1.0);
        ranged.range = Some(2.0);
        let lights = vec![
            Light::point("p", at, Rgb::ONE, 1.0),
            ranged,
            Light::spot("s", at, DVec3::NEG_Y, (0.1, 0.2), Rgb::ONE, 1.0),
            Light::spot("t", at, DVec3::NEG_Y, (0.1, 0.3), Rgb::ONE, 1.0),
            Light::directional("sun", DVec3::NEG_Y, Rgb::ONE, 1.0),
        ];
        let (merged, gone) = merge_coincident_lights(lights);
        assert_eq!((merged.len(), gone), (5, 0));
    }
}
