//! The words for overlaps: one warning when they are resolved, one error when
//! they are refused, each with the number of pairs and the first few by name.

use super::pairs::Found;
use crate::error::{Error, GeometryFault};
use crate::scene::Scene;

/// Pairs of objects spelled out in one message.
const NAMED: usize = 5;

/// `object 'name'`, else the object's index.
fn object_name(scene: &Scene, surface: usize) -> String {
    let s = &scene.surfaces[surface];
    scene.objects.get(s.object as usize).map_or_else(
        || format!("object {}", s.object),
        |o| format!("'{}'", o.name),
    )
}

/// The distinct `(on top, below)` object pairs with their counts, in the
/// order first met.
fn object_pairs(scene: &Scene, found: &Found) -> Vec<(String, String, usize)> {
    let mut pairs: Vec<(String, String, usize)> = Vec::new();
    let all = found
        .pairs
        .iter()
        .chain(&found.duplicates)
        .map(|&(below, on_top)| (object_name(scene, on_top), object_name(scene, below)));
    for (top, below) in all {
        match pairs.iter_mut().find(|(t, b, _)| *t == top && *b == below) {
            Some(p) => p.2 += 1,
            None => pairs.push((top, below, 1)),
        }
    }
    pairs
}

fn listing(scene: &Scene, found: &Found, joiner: &str) -> String {
    let pairs = object_pairs(scene, found);
    let mut text = pairs
        .iter()
        .take(NAMED)
        .map(|(top, below, n)| {
            let times = if *n > 1 {
                format!(" ({n} pairs)")
            } else {
                String::new()
            };
            format!("{top}{joiner}{below}{times}")
        })
        .collect::<Vec<_>>()
        .join(", ");
    if pairs.len() > NAMED {
        text.push_str(&format!(
            ", and {} more pairs of objects",
            pairs.len() - NAMED
        ));
    }
    text
}

/// The warning for overlaps that were resolved.
pub(super) fn resolved(scene: &Scene, found: &Found) -> String {
    let mut text = format!(
        "{} pairs of surfaces overlapped in one plane, facing the same way; the one on top \
         (the smaller object's, else the smaller, else the later) now covers its footprint, \
         cut out of the one below: {}",
        found.pairs.len() + found.duplicates.len(),
        listing(scene, found, " over ")
    );
    if !found.duplicates.is_empty() {
        text.push_str(&format!(
            "; {} of them were coincident duplicates, counted once",
            found.duplicates.len()
        ));
    }
    text
}

/// The error for overlaps that are refused.
pub(super) fn refusal(scene: &Scene, found: &Found) -> Error {
    Error::geometry(
        GeometryFault::Overlap,
        format!(
            "{} pairs of surfaces with different materials overlap in one plane, facing the same \
         way: {}. The hemi-cube cannot tell which is in front, so one would hide the other \
         from the whole scene. Let the importer resolve them (`overlaps` resolve, the \
         default: the smaller layer covers the larger), or move one \
         off the other by at least {:.3e} m (1e-4 of the scene's size), or cut a hole for it",
            found.pairs.len() + found.duplicates.len(),
            listing(scene, found, " and "),
            1e-4 * scene.extent()
        ),
    )
}
