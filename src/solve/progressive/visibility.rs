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
//! from the shooter are) cannot be judged from its own pixels: taking them at
//! face value would light it fully or not at all at random. Such a leaf takes
//! the fraction of its nearest ancestor in the patch quadtree that covers
//! enough pixels, which is the finest scale the item buffer resolves.

use super::Receivers;
use crate::formfactor::hemicube::Coverage;
use crate::mesh::{ElementKey, Mesh};

/// Pixels a quadtree node must cover for its own visible fraction to count.
pub const RESOLVED_PIXELS: u32 = 4;

#[derive(Clone, Copy, Default)]
struct Sums {
    won: f64,
    covered: f64,
    pixels: u32,
}

/// A patch whose won pixels add up to at least this fraction of its covered
/// ones counts as fully visible (the sums differ only by rounding then).
const WHOLE: f64 = 1.0 - 1e-9;

/// The patches of a patch-level item buffer that are partly visible, by
/// increasing id.
#[must_use]
pub fn partly_visible(patches: &[Coverage]) -> Vec<u32> {
    patches
        .iter()
        .filter(|c| c.won > 0.0 && c.won < WHOLE * c.covered)
        .map(|c| c.id)
        .collect()
}

/// The visible fraction of every leaf of every patch seen, as `(leaf index,
/// fraction)` in increasing leaf order, leaving out leaves with nothing
/// visible. `patches` is the patch-level coverage, `leaves` the leaf-level
/// coverage of the [`partly_visible`] patches (ids are leaf indices); both
/// sorted by id.
#[must_use]
pub fn visible_fractions(
    mesh: &Mesh,
    receivers: &Receivers,
    patches: &[Coverage],
    leaves: &[Coverage],
) -> Vec<(u32, f64)> {
    let mut out = Vec::new();
    for c in patches {
        if c.won <= 0.0 {
            continue;
        }
        if c.won >= WHOLE * c.covered {
            out.extend(
                receivers.patch_leaves[c.id as usize]
                    .clone()
                    .map(|i| (i, 1.0)),
            );
        } else {
            let root = mesh.patches[c.id as usize].root;
            assign(mesh, receivers, leaves, root, None, true, &mut out);
        }
    }
    out
}

fn leaf_sums(receivers: &Receivers, coverage: &[Coverage], key: ElementKey) -> Sums {
    let Some(&i) = receivers.index.get(key) else {
        return Sums::default();
    };
    match coverage.binary_search_by_key(&i, |c| c.id) {
        Ok(j) => Sums {
            won: coverage[j].won,
            covered: coverage[j].covered,
            pixels: coverage[j].pixels,
        },
        Err(_) => Sums::default(),
    }
}

fn sums(mesh: &Mesh, receivers: &Receivers, coverage: &[Coverage], key: ElementKey) -> Sums {
    let e = &mesh.elements[key];
    if e.is_leaf() {
        return leaf_sums(receivers, coverage, key);
    }
    let mut s = Sums::default();
    for &c in &e.children {
        let t = sums(mesh, receivers, coverage, c);
        s.won += t.won;
        s.covered += t.covered;
        s.pixels += t.pixels;
    }
    s
}

fn assign(
    mesh: &Mesh,
    receivers: &Receivers,
    coverage: &[Coverage],
    key: ElementKey,
    inherited: Option<f64>,
    is_root: bool,
    out: &mut Vec<(u32, f64)>,
) {
    let s = sums(mesh, receivers, coverage, key);
    let own = (s.covered > 0.0).then(|| (s.won / s.covered).min(1.0));
    // The patch root always trusts its own pixels: there is nothing coarser.
    let fraction = if is_root || s.pixels >= RESOLVED_PIXELS {
        own
    } else {
        inherited
    };
    let e = &mesh.elements[key];
    if e.is_leaf() {
        if let (Some(f), Some(&i)) = (fraction, receivers.index.get(key)) {
            if f > 0.0 {
                out.push((i, f));
            }
        }
        return;
    }
    for &c in &e.children {
        assign(mesh, receivers, coverage, c, fraction, false, out);
    }
}
