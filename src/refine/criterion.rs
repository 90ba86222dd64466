//! The subdivision criterion: radiosity differences between edge neighbours.

use super::Contrast;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;

/// The result of one pass of the criterion.
#[derive(Clone, Debug, Default)]
pub(crate) struct Marks {
    /// Leaves to split, in a deterministic order.
    pub split: Vec<ElementKey>,
    /// The largest neighbour difference found, relative to its scale
    /// (see [`Contrast`]).
    pub max_difference: f64,
    /// Leaves that exceed the tolerance but may not split (depth, size, budget).
    pub blocked: usize,
    /// Of the blocked leaves, those that only the budget kept whole.
    pub over_budget: usize,
    /// Of the leaves to split, those split because a facing surface stands
    /// close to them (see `crate::refine::mark_facing`), not by contrast.
    pub facing: usize,
}

/// Where to split and how much room there is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SplitLimits {
    /// Split where neighbours differ by more than this fraction (see [`Contrast`]).
    pub tolerance: f64,
    /// The local scale's floor, as a fraction of the brightest reflected radiosity.
    pub floor: f64,
    /// The same floor where either leaf of a pair sees surfaces close by
    /// (see [`crate::refine::RefineSettings::near_floor`]); the lower of the
    /// two applies.
    pub near_floor: f64,
    /// Leaves at this depth do not split.
    pub max_depth: u8,
    /// Children smaller than this (square metres) are not made.
    pub min_area: f64,
    /// Most new leaves.
    pub room: usize,
}

/// Marks leaves whose radiosity differs from an edge neighbour's by more than
/// the tolerance, measured by [`Contrast`], with the near floor where
/// `is_near` says either leaf sees surfaces close by. Both sides of such an
/// edge are marked, if they may split: depth below the limit, children no
/// smaller than the least area, and the largest differences first until the
/// budget of new leaves is used up.
#[must_use]
pub(crate) fn mark_for_split(
    mesh: &Mesh,
    radiosity: &Radiosity,
    limits: SplitLimits,
    is_near: &dyn Fn(ElementKey) -> bool,
) -> Marks {
    let SplitLimits {
        tolerance,
        floor,
        near_floor,
        max_depth,
        min_area,
        room,
    } = limits;
    let leaves = mesh.leaves();
    let mut marks = Marks::default();
    let Some(contrast) = Contrast::of_scene(mesh, radiosity, floor) else {
        return marks;
    };
    // At a near floor no lower than the floor, nearness changes nothing:
    // neither the second scale nor the rows' shares are looked at.
    let (near_contrast, near): (Contrast, Vec<bool>) = if near_floor < floor {
        (
            Contrast::of_scene(mesh, radiosity, near_floor).unwrap_or(contrast),
            leaves.iter().map(|&k| is_near(k)).collect(),
        )
    } else {
        (contrast, vec![false; leaves.len()])
    };
    let order: std::collections::HashMap<ElementKey, usize> =
        leaves.iter().enumerate().map(|(i, k)| (*k, i)).collect();
    let mut worst: Vec<f64> = vec![0.0; leaves.len()];
    for (i, &k) in leaves.iter().enumerate() {
        for n in mesh.edge_neighbours(k).into_iter().flatten() {
            if !mesh.elements[n].is_leaf() {
                continue;
            }
            let j = order.get(&n).copied();
            let close = near[i] || j.is_some_and(|j| near[j]);
            let d = if close { near_contrast } else { contrast }.between(mesh, radiosity, k, n);
            worst[i] = worst[i].max(d);
            if let Some(j) = j {
                worst[j] = worst[j].max(d);
            }
        }
    }
    marks.max_difference = worst.iter().copied().fold(0.0, f64::max);
    let mut candidates: Vec<(usize, f64)> = worst
        .iter()
        .enumerate()
        .filter(|(_, d)| **d > tolerance)
        .map(|(i, d)| (i, *d))
        .collect();
    candidates.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut budget = room;
    for (i, _) in candidates {
        let e = &mesh.elements[leaves[i]];
        if e.depth >= max_depth || e.area * 0.25 < min_area {
            marks.blocked += 1;
            continue;
        }
        if budget < 3 {
            marks.blocked += 1;
            marks.over_budget += 1;
            continue;
        }
        budget -= 3;
        marks.split.push(leaves[i]);
    }
    marks
}
