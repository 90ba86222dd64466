//! The factors a shaped gather puts on the entries of its rows: each near
//! entry's ratio and each patch's correction.

use super::correction::Correction;
use super::{NearWeights, SourceShapes};
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::ragged::Ragged;
use rayon::prelude::*;

/// The factors a shaped gather puts on patch radiosities.
#[derive(Debug, Default)]
pub(crate) struct EntryFactors {
    /// Per leaf, the entries of its row to unevenly lit patches it is near,
    /// as (index in the row, factor), in row order.
    pub near: Ragged<(u32, Rgb)>,
    /// Per patch, the factor of every other receiver's entry (1 for an even
    /// patch, and for every patch on a receiver that reflects nothing).
    pub patch: Vec<Rgb>,
}

impl EntryFactors {
    /// The factor on entry `i` (to patch `j`) of a row whose receiver
    /// `reflects` or not, `near` being that row's near factors not yet
    /// passed (entries must be asked for in row order).
    #[inline]
    pub(crate) fn factor(
        &self,
        near: &mut std::iter::Peekable<std::slice::Iter<'_, (u32, Rgb)>>,
        i: usize,
        j: u32,
        reflects: bool,
    ) -> Rgb {
        match near.peek() {
            Some((at, r)) if *at as usize == i => {
                near.next();
                *r
            }
            _ if reflects => self.patch[j as usize],
            _ => Rgb::ONE,
        }
    }
}

/// Leaves whose factors one parallel task takes: taking them is cheap
/// (a weighted mean per near entry), so a task holds many.
const FACTOR_BLOCK: usize = 256;

impl SourceShapes {
    /// The factors on the patch radiosities that the rows of `leaves` gather
    /// (see [`EntryFactors`]), by what they weigh of the shaped patches
    /// (`near`, from [`Self::near_weights`]) and the parts' present values,
    /// each patch's corrected (see [`Correction`])
    /// so that its receivers
    /// (leaf `n`'s row scaled by `row_scale(n)`, as the gather scales it)
    /// together gather from it, per band, what they gathered from its mean
    /// times `Shaped::sent` (1 in a closed scene, where the correction then
    /// moves a patch's light between receivers and neither creates nor
    /// loses any).
    pub(crate) fn factors(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        row_scale: impl Fn(usize) -> f64 + Sync,
        near: &NearWeights,
    ) -> EntryFactors {
        // Per near entry, its factor, and how unsure its ratio is (see
        // `unsure` below).
        let mut rows = Ragged::from_par_rows(leaves.len(), FACTOR_BLOCK, |n, out| {
            let k = leaves[n];
            let entries = form_factors.entries(k);
            let e = &mesh.elements[k];
            let normal = mesh.surfaces()[e.surface as usize].normal;
            let mut weighed = Vec::new();
            for entry in near.near.row(n) {
                let j = entries[entry.index as usize].0;
                let shaped = &self.shaped[self.slot[j as usize] as usize];
                let parts = if entry.kept {
                    near.kept_parts(entry)
                } else {
                    weighed.clear();
                    self.weights_into(j, e.centroid, normal, &mut weighed);
                    &weighed[..]
                };
                let r = shaped.ratio_from(parts).unwrap_or(Rgb::ONE);
                let weight = entry.weight;
                // The share of the mean it keeps is as unsure as a far
                // receiver's.
                let unsure = weight * entry.hidden + (1.0 - weight);
                out.push((entry.index, Rgb::ONE + (r - Rgb::ONE) * weight, unsure));
            }
        });
        // Per shaped patch, what its receivers gather from it with and
        // without the ratios, and with the ratios times how unsure each
        // is, summed in leaf order (the same bits at any thread count).
        // Receivers that are not near it gather its mean, wholly unsure.
        let without = self.gathered_from_means(mesh, form_factors, leaves, &row_scale);
        // Receivers gather by the ratios what they gathered from the means,
        // plus each near entry's departure from its mean.
        let mut with: Vec<Rgb> = without.iter().map(|&w| Rgb::splat(w)).collect();
        let mut with_unsure = with.clone();
        for (n, (&k, near)) in leaves.iter().zip(rows.rows()).enumerate() {
            let e = &mesh.elements[k];
            if near.is_empty() || e.reflectance.max_band() <= 0.0 {
                continue;
            }
            let area = e.area * row_scale(n);
            let entries = form_factors.entries(k);
            for &(i, ratio, u) in near {
                let (j, f) = entries[i as usize];
                let s = self.slot[j as usize] as usize;
                let w = area * f64::from(f);
                with[s] += (ratio - Rgb::ONE) * w;
                with_unsure[s] += (ratio * u - Rgb::ONE) * w;
            }
        }
        let corrections: Vec<Correction> = (0..self.shaped.len())
            .map(|s| {
                let target = self.shaped[s].sent * without[s];
                Correction::of(target, with[s], with_unsure[s])
            })
            .collect();
        for (n, &k) in leaves.iter().enumerate() {
            let entries = form_factors.entries(k);
            for (i, r, u) in rows.row_mut(n) {
                let j = entries[*i as usize].0;
                *r = corrections[self.slot[j as usize] as usize].apply(*r, *u);
            }
        }
        let factors = rows.map(|(i, r, _)| (i, r));
        // Receivers not near a shaped patch gather its mean, wholly unsure.
        let mut patch = vec![Rgb::ONE; self.slot.len()];
        for (p, s) in self.slot.iter().enumerate() {
            if *s != u32::MAX {
                patch[p] = corrections[*s as usize].apply(Rgb::ONE, 1.0);
            }
        }
        EntryFactors {
            near: factors,
            patch,
        }
    }

    /// Per shaped patch, what the reflecting receivers among `leaves` (leaf
    /// `n`'s row scaled by `row_scale(n)`) gather from its mean per unit
    /// radiosity: the sum of area times form factor. Summed in fixed blocks
    /// of leaves, in parallel, and the blocks in order: the same bits at
    /// any thread count.
    fn gathered_from_means(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        row_scale: &(impl Fn(usize) -> f64 + Sync),
    ) -> Vec<f64> {
        const BLOCK: usize = 1024;
        let blocks: Vec<Vec<f64>> = leaves
            .par_chunks(BLOCK)
            .enumerate()
            .map(|(b, block)| {
                let mut sums = vec![0.0; self.shaped.len()];
                for (m, &k) in block.iter().enumerate() {
                    let e = &mesh.elements[k];
                    if e.reflectance.max_band() <= 0.0 {
                        continue;
                    }
                    let area = e.area * row_scale(b * BLOCK + m);
                    for &(j, f) in form_factors.entries(k) {
                        let s = self.slot[j as usize];
                        if s != u32::MAX {
                            sums[s as usize] += area * f64::from(f);
                        }
                    }
                }
                sums
            })
            .collect();
        let mut total = vec![0.0; self.shaped.len()];
        for sums in &blocks {
            for (t, x) in total.iter_mut().zip(sums) {
                *t += x;
            }
        }
        total
    }
}
