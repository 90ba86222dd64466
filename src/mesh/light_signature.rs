//! What lights a facet before anything is solved: which punctual lights it
//! sees, and how much of the sky, found by rays through the scene's surfaces.
//!
//! A face cluster is one source of one radiosity in the patch system. Where
//! its facets are lit differently (one in a shaft of sky light through a
//! window, its neighbour on the same wall inside), the patch system sees
//! their mean: surfaces facing the cluster gather the mean, and the shaped
//! gather, which corrects the elements afterwards one bounce at a time,
//! cannot bring the light of many bounces back (on a 20 000-triangle cut of
//! a game level, two facing corridor walls came out at a third and at a half
//! of what they get with every facet a patch of its own; see
//! `papers/performance.md`). So facets join a cluster only where their
//! signatures agree ([`LightSignature::alike`]): the same punctual lights in
//! view, and about the same share of the sky. That catches differences in
//! direct light only: the corridor above, whose bright facet is lit by light
//! reflected from outside, stays as it was.
//!
//! Emitting surfaces are not looked at: their light on a facet needs form
//! factors, which come later; their receivers still split where the light
//! changes, through the element refinement.

use crate::scene::{Scene, Target, Tracer};
use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

/// Directions cast at the sky from each facet: a stratified pattern of
/// cosine-weighted directions, the same for every facet, turned into its
/// frame.
const SKY_RAYS: usize = 32;

/// Two facets see the sky alike when their shares differ by at most this
/// fraction of the larger plus [`SKY_FLOOR`]. A factor of two in the sky's
/// direct light is as far as a constant source stays fair to both.
const SKY_RATIO: f64 = 0.5;

/// Shares of the sky below this fraction of an open horizontal surface's
/// count as none: interior facets that catch a ray or two are lit mostly by
/// the rooms around them.
const SKY_FLOOR: f64 = 0.01;

/// How one facet is lit directly, before the solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LightSignature {
    /// Bit `k` set when punctual light `k` shines on the facet's front,
    /// unblocked.
    lights: SmallVec<[u64; 1]>,
    /// The sky's direct light on the facet, as a fraction of what an open
    /// horizontal surface gets (0 without a sky).
    sky: f64,
}

impl LightSignature {
    /// Whether one constant source may stand for facets signed `self` and
    /// `other`.
    pub(crate) fn alike(&self, other: &LightSignature) -> bool {
        if self.lights != other.lights {
            return false;
        }
        let (lo, hi) = if self.sky < other.sky {
            (self.sky, other.sky)
        } else {
            (other.sky, self.sky)
        };
        hi < SKY_FLOOR || hi - lo <= SKY_RATIO * hi + SKY_FLOOR
    }
}

/// The signatures of the surfaces of `scene` marked in `wanted` (`None` for
/// the rest), or `None` when the scene has neither punctual lights nor a sky
/// (nothing to tell facets apart by, and no rays cast).
pub(crate) fn light_signatures(
    scene: &Scene,
    wanted: &[bool],
) -> Option<Vec<Option<LightSignature>>> {
    let lights: Vec<usize> = (0..scene.lights.len())
        .filter(|&k| scene.lights[k].shines())
        .collect();
    if lights.is_empty() && scene.sky.is_none() {
        return None;
    }
    let (lo, hi) = scene.bounds();
    let surfaces: Vec<_> = scene.surfaces.iter().collect();
    let tracer = Tracer::new(scene, &surfaces, lo, hi);
    // Off the surface by a step that clears its own plane (and a
    // back-to-back twin) at the scene's scale.
    let lift = 1e-6 * (hi - lo).length().max(1e-9);
    let pattern = cosine_pattern();
    let open = scene.sky.as_ref().map(|sky| {
        pattern
            .iter()
            .map(|d| sky.relative_radiance(DVec3::new(d.x, d.z, d.y)))
            .sum::<f64>()
    });
    let signatures = scene
        .surfaces
        .par_iter()
        .zip(wanted.par_iter())
        .map(|(s, &wanted)| {
            if !wanted {
                return None;
            }
            let n = s.vertices.len() as f64;
            let centre = s.vertices.iter().copied().sum::<DVec3>() / n;
            let eye = centre + s.normal * lift;
            let mut bits: SmallVec<[u64; 1]> = SmallVec::from_elem(0, lights.len().div_ceil(64));
            for (bit, &k) in lights.iter().enumerate() {
                let Some(incident) = scene.lights[k].incident(eye) else {
                    continue;
                };
                if incident.towards.dot(s.normal) <= 0.0 {
                    continue;
                }
                let seen = match incident.target {
                    Target::Point(p) => tracer.sees(eye, p),
                    Target::Infinity(d) => tracer.first(eye, d).is_none(),
                };
                if seen {
                    bits[bit / 64] |= 1 << (bit % 64);
                }
            }
            let sky = match (&scene.sky, open) {
                (Some(sky), Some(open)) if open > 0.0 => {
                    let (t, b) = s.normal.any_orthonormal_pair();
                    let seen: f64 = pattern
                        .iter()
                        .map(|d| t * d.x + b * d.y + s.normal * d.z)
                        .filter(|&w| w.y > 0.0 && tracer.first(eye, w).is_none())
                        .map(|w| sky.relative_radiance(w))
                        .sum();
                    seen / open
                }
                _ => 0.0,
            };
            Some(LightSignature { lights: bits, sky })
        })
        .collect();
    Some(signatures)
}

/// [`SKY_RAYS`] unit directions about +Z with the cosine's density: the
/// centres of strata of equal area on the unit disc (4 rings of 8
/// sectors, each ring turned half a sector from the last), lifted onto the
/// hemisphere.
fn cosine_pattern() -> Vec<DVec3> {
    const RINGS: usize = 4;
    const SECTORS: usize = SKY_RAYS / RINGS;
    let mut out = Vec::with_capacity(SKY_RAYS);
    for ring in 0..RINGS {
        let r = ((ring as f64 + 0.5) / RINGS as f64).sqrt();
        for sector in 0..SECTORS {
            let turn = (sector as f64 + 0.5 * (ring % 2) as f64 + 0.5) / SECTORS as f64;
            let phi = std::f64::consts::TAU * turn;
            out.push(DVec3::new(
                r * phi.cos(),
                r * phi.sin(),
                (1.0 - r * r).max(0.0).sqrt(),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::{Light, SceneBuilder, Sky, SkyModel};

    #[test]
    fn the_pattern_is_unit_cosine_weighted_and_covers_the_hemisphere() {
        let p = cosine_pattern();
        assert_eq!(p.len(), SKY_RAYS);
        for d in &p {
            assert!((d.length() - 1.0).abs() < 1e-12 && d.z > 0.0);
        }
        // Under the cosine's density the mean cosine is 2/3; four rings
        // come within 1% of it.
        let mean_z: f64 = p.iter().map(|d| d.z).sum::<f64>() / p.len() as f64;
        assert!((mean_z - 2.0 / 3.0).abs() < 0.02, "{mean_z}");
    }

    /// A floor of unit squares along x at y = 0, facing up.
    fn squares(b: &mut SceneBuilder, grey: u32, n: usize) {
        b.object("floor");
        for i in 0..n {
            let x = i as f64;
            b.quad(
                grey,
                DVec3::new(x, 0.0, 0.0),
                DVec3::new(x, 0.0, 1.0),
                DVec3::new(x + 1.0, 0.0, 1.0),
                DVec3::new(x + 1.0, 0.0, 0.0),
            )
            .unwrap();
        }
    }

    #[test]
    fn a_shaded_floor_and_an_open_one_are_told_apart_by_the_sky() {
        // Two squares of floor; a low roof over the second one only.
        let mut b = SceneBuilder::new("floor");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        squares(&mut b, grey, 2);
        b.object("roof");
        b.quad(
            grey,
            DVec3::new(0.9, 0.05, -2.0),
            DVec3::new(3.0, 0.05, -2.0),
            DVec3::new(3.0, 0.05, 3.0),
            DVec3::new(0.9, 0.05, 3.0),
        )
        .unwrap();
        let mut scene = b.build().unwrap();
        scene.sky = Some(Sky::with_horizontal_illuminance(SkyModel::Uniform, 1000.0));
        let s = light_signatures(&scene, &[true, true, false]).unwrap();
        let (open, shut) = (s[0].clone().unwrap(), s[1].clone().unwrap());
        // The open square sees nearly all the sky (the roof hides a strip
        // a few degrees high); the one under the roof sees none.
        assert!(open.sky > 0.9 && shut.sky < SKY_FLOOR, "{open:?} {shut:?}");
        assert!(!open.alike(&shut));
        assert!(open.alike(&open.clone()));
        assert!(s[2].is_none());
    }

    #[test]
    fn a_facet_behind_an_occluder_does_not_share_a_lights_bit() {
        // A shade under a bulb hides the first square of floor, not the
        // second.
        let mut b = SceneBuilder::new("shade");
        let grey = b.material("grey", Rgb::splat(0.5), Rgb::ZERO).unwrap();
        squares(&mut b, grey, 2);
        b.object("shade");
        b.quad(
            grey,
            DVec3::new(0.2, 0.5, 0.2),
            DVec3::new(0.8, 0.5, 0.2),
            DVec3::new(0.8, 0.5, 0.8),
            DVec3::new(0.2, 0.5, 0.8),
        )
        .unwrap();
        b.light(Light::point(
            "bulb",
            DVec3::new(0.5, 1.0, 0.5),
            Rgb::splat(1.0),
            10.0,
        ))
        .unwrap();
        let scene = b.build().unwrap();
        let s = light_signatures(&scene, &[true, true, false]).unwrap();
        let (hidden, lit) = (s[0].clone().unwrap(), s[1].clone().unwrap());
        assert_eq!(hidden.lights[0], 0);
        assert_eq!(lit.lights[0], 1);
        assert!(!hidden.alike(&lit));
        assert!(lit.sky == 0.0 && hidden.sky == 0.0);
    }

    #[test]
    fn without_lights_or_sky_no_rays_are_cast() {
        let scene = crate::scenes::cornell_box();
        let mut dark = scene.clone();
        dark.lights.clear();
        dark.sky = None;
        assert!(light_signatures(&dark, &vec![true; dark.surfaces.len()]).is_none());
    }
}
