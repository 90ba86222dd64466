//! Balancing element-to-patch rows so that no light is lost or created.
//!
//! Patch `j` sends `B_j W_j` to front faces, where its exposure `W_j = sum_e
//! A_e s_e` sums, over its elements, their areas times their row sums `s_e =
//! sum_k F_ek` (see [`crate::solve::PatchSystem`]). The receivers gather `B_j
//! C_j` of it, with `C_j = sum_e A_e F_ej` over every receiving element. Both
//! estimate the same integral (reciprocity), but `C_j` is a midpoint rule over
//! the receivers, each sampled at its centre, and it is blind to what no
//! receiver resolves: measured in a closed room with a lamp 1 mm under the
//! ceiling, the lamp was seen 0.19% more than it sends, the ceiling patches
//! around it 3.4% more (the lamp's back hides a 1 mm strip around it from the
//! ceiling's own elements, which no receiver's hemi-cube resolves), wall patches
//! by their corners up to 0.8% less. In a closed room whatever such differences
//! lose or create is multiplied by `1 / (1 - rho)`: 0.3% of the light at
//! rho = 0.9.
//!
//! The rows are therefore balanced: each receiver's row is scaled by `r_e`
//! and each patch's column by `c_j`, `F'_ej = r_e F_ej c_j`, so that every
//! column gathers what its patch sends (`sum_e A_e F'_ej = W_j`) and every row
//! keeps its own sum (`sum_j F'_ej = s_e`: a receiver sees as much of the front
//! faces as its hemi-cube found). Both sets of sums have the same total, so
//! scales meeting both exist; they are found by iterative proportional fitting
//! (alternately matching the columns and the rows; Deming and Stephan 1940,
//! Sinkhorn 1964), which changes the rows as little as it can in the sense of
//! relative entropy. The scales are within a percent of 1 in practice. A patch
//! whose ratio `W_j / C_j` lies beyond [`MAX_SCALE`] is not a quadrature error
//! but a patch too small for its receivers to resolve, and its column is left
//! alone.

use crate::formfactor::RowView;

/// A scene counts as closed when its elements' rows see open sky over at
/// most this fraction of their views, area weighted: a few pixels' worth, as
/// cracks between polygons leave.
pub const CLOSED_OPEN_SKY: f64 = 1e-3;

/// Whether the scene whose leaves have the given areas, rows and emission
/// (whether each emits) is closed: whether the area-weighted mean of the
/// rows' open sky is at most [`CLOSED_OPEN_SKY`]. Only leaves that see some
/// front face or emit count: light reaches and leaves the others only as
/// their emission, so where they look does not matter (the bottom of a box
/// standing on the floor looks down through the floor's back into the void,
/// and nothing ever lights it).
///
/// Only a closed scene is balanced, and weighs its elements by exposure (see
/// [`crate::solve::PatchSystem`]). There light stays until it is absorbed, so
/// an error of `d` a bounce in what the form factors conserve becomes about
/// `d / (1 - rho)` of the solution, and conservation decides the accuracy.
/// Where light escapes it is not multiplied so, and what decides the accuracy
/// is how well each element's centre stands for it, which a correction spread
/// over whole rows and columns can make worse: on the penumbra scenes (a
/// black light and occluder over a floor) balancing raised the mean element
/// error against the exact oracle fivefold, and on the Cornell box (open at
/// the front) it and the exposure weights moved the surfaces by up to 0.4%
/// either way.
#[must_use]
pub fn is_closed(leaves: impl Iterator<Item = (f64, RowView, bool)>) -> bool {
    let (mut open, mut total) = (0.0, 0.0);
    for (area, view, emits) in leaves {
        if view.sum > 0.0 || emits {
            open += area * view.open;
            total += area;
        }
    }
    total > 0.0 && open <= CLOSED_OPEN_SKY * total
}

/// One receiving element: its patch, its area and its row.
#[derive(Clone, Copy, Debug)]
pub struct Receiver<'a> {
    /// The patch it belongs to.
    pub patch: u32,
    /// Its area.
    pub area: f64,
    /// Its row: `(patch, F_ej)` pairs.
    pub entries: &'a [(u32, f32)],
}

/// The scales of a balanced set of rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Balance {
    /// Per patch, `c_j`: how much brighter receivers see it than its
    /// radiosity (empty when all are 1).
    pub seen: Vec<f64>,
    /// Per receiver, in the order given, `r_e` (empty when all are 1).
    pub receiver: Vec<f64>,
    /// Rounds of fitting done.
    pub rounds: usize,
    /// The largest relative difference left between what a balanced patch
    /// sends and what its receivers gather.
    pub residual: f64,
    /// Per patch, whether it took no part (see [`balance`]; empty: all did).
    pub excluded: Vec<bool>,
}

/// The largest scale either way: a patch whose receivers gather more than
/// this factor from it, or less than its inverse, is left alone.
pub const MAX_SCALE: f64 = 1.25;

/// Most rounds of fitting.
pub(crate) const MAX_ROUNDS: usize = 32;

/// Fitting stops once every balanced column is within this relative
/// difference of its patch's exposure (single-precision rows carry about
/// `1e-7`).
pub(crate) const TOLERANCE: f64 = 1e-6;

impl Balance {
    /// The scale of patch `j` as its receivers see it.
    #[inline]
    #[must_use]
    pub fn seen(&self, j: usize) -> f64 {
        self.seen.get(j).copied().unwrap_or(1.0)
    }

    /// The scale of receiver `i`'s row.
    #[inline]
    #[must_use]
    pub fn receiver(&self, i: usize) -> f64 {
        self.receiver.get(i).copied().unwrap_or(1.0)
    }

    /// Whether patch `j` took no part.
    #[inline]
    #[must_use]
    pub(crate) fn is_excluded(&self, j: usize) -> bool {
        self.excluded.get(j).copied().unwrap_or(false)
    }

    /// The scale of the entry to patch `j` of the row of receiver `i`, of
    /// patch `p`: `r_i c_j`, or 1 where either patch took no part.
    #[inline]
    #[must_use]
    pub fn entry(&self, i: usize, p: usize, j: usize) -> f64 {
        if self.is_excluded(p) || self.is_excluded(j) {
            1.0
        } else {
            self.receiver(i) * self.seen(j)
        }
    }
}

/// The scales that balance the rows of `receivers` over `patches` patches
/// (see the module notes). Patches marked in `excluded` (empty: none) take no
/// part: they carry no light (they neither emit nor reflect), so what they
/// gather is only absorbed, and the gather counts it by reciprocity from the
/// other side (as it must when they have no rows; see
/// [`crate::pipeline::Skips::zero_reflectance`]). Their rows are ignored, the
/// entries of other rows to them keep their values, and what a patch sends
/// them is no part of what its balanced receivers must gather.
#[must_use]
pub fn balance(receivers: &[Receiver<'_>], patches: usize, excluded: &[bool]) -> Balance {
    let out_of = |j: u32| excluded.get(j as usize).copied().unwrap_or(false);
    // Per receiver: the sum of its entries to balanced patches (its row's
    // target), zero for a receiver of an excluded patch.
    let sums: Vec<f64> = receivers
        .iter()
        .map(|r| {
            if out_of(r.patch) {
                return 0.0;
            }
            r.entries
                .iter()
                .filter(|e| !out_of(e.0))
                .map(|e| f64::from(e.1))
                .sum()
        })
        .collect();
    let mut target = vec![0.0; patches];
    for (r, s) in receivers.iter().zip(&sums) {
        target[r.patch as usize] += r.area * s;
    }
    let mut receiver = vec![1.0; receivers.len()];
    let mut gathered = vec![0.0; patches];
    gather(receivers, &receiver, &sums, excluded, &mut gathered);
    // A patch left alone keeps what its receivers gather now as its target.
    // What it sends beyond that (or short of it) is then light the rows
    // cannot conserve, and the row sums give way by that much, all in
    // proportion, so that rows and columns still have the same total.
    let mut moved = false;
    for (j, (t, &c)) in target.iter_mut().zip(&gathered).enumerate() {
        let balanced = !out_of(j as u32)
            && *t > 0.0
            && c > 0.0
            && (1.0 / MAX_SCALE..=MAX_SCALE).contains(&(*t / c));
        if !balanced {
            *t = c;
        }
        moved |= balanced && *t != c;
    }
    let mut out = Balance::default();
    if !moved {
        return out;
    }
    let rows_total: f64 = receivers.iter().zip(&sums).map(|(r, s)| r.area * s).sum();
    let give = target.iter().sum::<f64>() / rows_total;
    let mut seen = vec![1.0; patches];
    for round in 1..=MAX_ROUNDS {
        let mut residual: f64 = 0.0;
        for j in 0..patches {
            if gathered[j] > 0.0 {
                let c = target[j] / gathered[j];
                residual = residual.max((c / seen[j] - 1.0).abs());
                seen[j] = c;
            }
        }
        out.rounds = round;
        out.residual = residual;
        if residual <= TOLERANCE {
            // The columns were just matched, and the rows the round before.
            break;
        }
        for ((r, s), scale) in receivers.iter().zip(&sums).zip(&mut receiver) {
            let seen_sum: f64 = r
                .entries
                .iter()
                .filter(|e| !out_of(e.0))
                .map(|&(j, f)| f64::from(f) * seen[j as usize])
                .sum();
            if *s > 0.0 && seen_sum > 0.0 {
                *scale = s * give / seen_sum;
            }
        }
        gather(receivers, &receiver, &sums, excluded, &mut gathered);
    }
    out.seen = seen;
    out.receiver = receiver;
    out.excluded = excluded.to_vec();
    out
}

/// What every patch's receivers gather from it, rows scaled by `receiver`:
/// `sum_e A_e r_e F_ej`, over the receivers that take part (a row target in
/// `sums` above 0) and their entries to patches that take part (not marked
/// in `excluded`).
fn gather(
    receivers: &[Receiver<'_>],
    receiver: &[f64],
    sums: &[f64],
    excluded: &[bool],
    gathered: &mut [f64],
) {
    gathered.fill(0.0);
    for ((r, scale), s) in receivers.iter().zip(receiver).zip(sums) {
        if *s <= 0.0 {
            continue;
        }
        let w = r.area * scale;
        for &(j, f) in r.entries {
            if !excluded.get(j as usize).copied().unwrap_or(false) {
                gathered[j as usize] += w * f64::from(f);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balanced_rows_keep_their_sums_and_columns_gather_what_patches_send() {
        // Four unit patches of one receiver each, rows summing to 1 (a closed
        // scene) but not quite reciprocal: F_01 = 0.36 while F_10 = 0.33, so
        // that the receivers gather 0.99, 1.02, 1 and 0.99 of what each patch
        // sends.
        let rows: [&[(u32, f32)]; 4] = [
            &[(1, 0.36), (2, 0.32), (3, 0.32)],
            &[(0, 0.33), (2, 0.34), (3, 0.33)],
            &[(0, 0.33), (1, 0.33), (3, 0.34)],
            &[(0, 0.33), (1, 0.33), (2, 0.34)],
        ];
        let areas = [1.0; 4];
        let receivers: Vec<Receiver<'_>> = (0..4)
            .map(|i| Receiver {
                patch: i as u32,
                area: areas[i],
                entries: rows[i],
            })
            .collect();
        let b = balance(&receivers, 4, &[]);
        assert!(b.residual <= TOLERANCE, "{b:?}");
        for (i, row) in rows.iter().enumerate() {
            let sum: f64 = row
                .iter()
                .map(|&(j, f)| b.receiver(i) * f64::from(f) * b.seen(j as usize))
                .sum();
            assert!((sum - 1.0).abs() < 1e-5, "row {i} sums to {sum}");
        }
        for j in 0..4 {
            let gathered: f64 = rows
                .iter()
                .enumerate()
                .flat_map(|(i, row)| row.iter().map(move |&(k, f)| (i, k, f)))
                .filter(|&(_, k, _)| k as usize == j)
                .map(|(i, _, f)| areas[i] * b.receiver(i) * f64::from(f) * b.seen(j))
                .sum();
            assert!(
                (gathered - areas[j]).abs() < 1e-5 * areas[j],
                "patch {j} sends {} but its receivers gather {gathered}",
                areas[j]
            );
        }
    }

    #[test]
    fn reciprocal_rows_are_left_alone() {
        // Two facing unit squares seeing each other with F = 0.2: nothing to
        // balance.
        let rows: [&[(u32, f32)]; 2] = [&[(1, 0.2)], &[(0, 0.2)]];
        let receivers: Vec<Receiver<'_>> = (0..2)
            .map(|i| Receiver {
                patch: i as u32,
                area: 1.0,
                entries: rows[i],
            })
            .collect();
        let b = balance(&receivers, 2, &[]);
        assert!(b.seen.is_empty() && b.receiver.is_empty(), "{b:?}");
        assert_eq!(b.rounds, 0);
    }

    #[test]
    fn a_patch_seen_far_less_than_it_sends_is_left_alone() {
        // Patch 1 sends 1 but is gathered 0.1: beyond any quadrature error.
        let rows: [&[(u32, f32)]; 2] = [&[(1, 0.1)], &[(0, 1.0)]];
        let receivers: Vec<Receiver<'_>> = (0..2)
            .map(|i| Receiver {
                patch: i as u32,
                area: 1.0,
                entries: rows[i],
            })
            .collect();
        let b = balance(&receivers, 2, &[]);
        assert_eq!(b.seen(1), 1.0, "{b:?}");
    }
}
