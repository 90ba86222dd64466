//! How much of each receiving leaf a shooter's eye sees, from its item buffer.
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

/// The visible fraction of every leaf of every patch that the item buffer
/// touched, as `(leaf index, fraction)` in increasing leaf order, leaving out
/// leaves with nothing visible. `coverage` must be sorted by id (as
/// [`crate::formfactor::hemicube::Hemicube::coverage`] returns it).
#[must_use]
pub fn visible_fractions(
    mesh: &Mesh,
    receivers: &Receivers,
    coverage: &[Coverage],
) -> Vec<(u32, f64)> {
    let mut out = Vec::new();
    let mut last_patch = None;
    for c in coverage {
        let patch = mesh.elements[receivers.leaves[c.id as usize]].patch;
        // Leaves are stored patch by patch, so each patch comes up in one run.
        if last_patch == Some(patch) {
            continue;
        }
        last_patch = Some(patch);
        let root = mesh.patches[patch as usize].root;
        assign(mesh, receivers, coverage, root, None, true, &mut out);
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
