//! How much of each receiving leaf a shooter's eye sees, from its item buffer.
//!
//! The item buffer is rendered twice. First with one polygon per patch: a
//! patch whose pixels all won is fully visible, and so is every leaf of it;
//! one that won none is hidden. Only the partly visible patches are then
//! rendered leaf by leaf, among the other patches as whole polygons that can
//! hide them. Most patches are seen whole or not at all, so most leaves never
//! reach the rasterizer.
//!
//! A leaf that covers many pixels gets its own fraction `won / covered`. A leaf
//! that covers only a few (or none: smaller than a pixel, as deep elements far
//! from the shooter or seen edge-on are) cannot be judged from its own pixels:
//! taking them at face value would light it fully or not at all at random.
//! Such a leaf is judged by shadow rays from the eye to points spread over it
//! instead. (Taking the fraction of its patch, as this once did, darkened the
//! whole of a ceiling patch seen edge-on from a wall whenever the light hanging
//! below part of it hid that part: the Cornell box's ceiling came out 2.5%
//! darker than with gathering at uniform depth 1.)

use super::Receivers;
use crate::formfactor::hemicube::Coverage;
use crate::formfactor::Occluders;
use glam::DVec3;

/// Pixels a quadtree node must cover for its own visible fraction to count.
pub(super) const RESOLVED_PIXELS: u32 = 4;

/// A patch whose won pixels add up to at least this fraction of its covered
/// ones counts as fully visible (the sums differ only by rounding then).
const WHOLE: f64 = 1.0 - 1e-9;

/// The patches of a patch-level item buffer that are partly visible, by
/// increasing id.
#[must_use]
pub(super) fn partly_visible(patches: &[Coverage]) -> Vec<u32> {
    patches
        .iter()
        .filter(|c| c.won > 0.0 && c.won < WHOLE * c.covered)
        .map(|c| c.id)
        .collect()
}

/// The shooter's eye, for the shadow rays to leaves too small in its item
/// buffer to judge by their pixels.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShooterEye<'a> {
    /// Every patch as an occluder.
    pub occluders: &'a Occluders,
    /// Where the eye is.
    pub point: DVec3,
    /// The shooter's surface (its rays never stop on it).
    pub surface: u32,
}

/// The visible fraction of every leaf of every patch seen, as `(leaf index,
/// fraction)` in increasing leaf order, leaving out leaves with nothing
/// visible. `patches` is the patch-level coverage, `leaves` the leaf-level
/// coverage of the [`partly_visible`] patches (ids are leaf indices); both
/// sorted by id.
#[must_use]
pub(super) fn visible_fractions(
    receivers: &Receivers,
    patches: &[Coverage],
    leaves: &[Coverage],
    eye: &ShooterEye<'_>,
) -> Vec<(u32, f64)> {
    let mut out = Vec::new();
    for c in patches {
        if c.won <= 0.0 {
            continue;
        }
        let range = receivers.patch_leaves[c.id as usize].clone();
        if c.won >= WHOLE * c.covered {
            out.extend(range.map(|i| (i, 1.0)));
            continue;
        }
        for i in range {
            let own = match leaves.binary_search_by_key(&i, |l| l.id) {
                Ok(j) if leaves[j].pixels >= RESOLVED_PIXELS => {
                    (leaves[j].won / leaves[j].covered).min(1.0)
                }
                _ => ray_fraction(receivers, i, eye),
            };
            if own > 0.0 {
                out.push((i, own));
            }
        }
    }
    out
}

/// The fraction of shadow rays from the eye to points spread over leaf `i`
/// (its centroid, and halfway from there to each corner) that nothing blocks.
pub(super) fn ray_fraction(receivers: &Receivers, i: u32, eye: &ShooterEye<'_>) -> f64 {
    let poly = &receivers.sources.polygons[i as usize];
    let corners = &poly.vertices[..poly.count as usize];
    let centroid = corners.iter().copied().sum::<DVec3>() / corners.len() as f64;
    let skip = [eye.surface, poly.surface];
    let sources = &receivers.patch_sources;
    let clear = |p: DVec3| eye.occluders.clear(sources, eye.point, p, skip);
    let points = std::iter::once(centroid).chain(corners.iter().map(|v| (centroid + *v) * 0.5));
    let (mut open, mut total) = (0usize, 0usize);
    for p in points {
        total += 1;
        open += usize::from(clear(p));
    }
    open as f64 / total as f64
}
