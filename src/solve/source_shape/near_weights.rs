//! What the near receivers of the shaped patches weigh: per important
//! entry of a row, the parts of its patch and their weights.

use super::part_views::{SEEN_SHARE, VIEW_SHARE};
use super::{PartViews, SourceShapes};
use crate::formfactor::FormFactors;
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::ragged::Ragged;
use glam::DVec3;
use rayon::prelude::*;

/// Leaves weighed in one parallel task: leaves near a lit patch weigh its
/// parts, the rest do nothing, and small tasks keep every worker busy to
/// the end.
const WEIGH_TASK: usize = 16;

/// Most part weights [`NearWeights`] keeps (8 bytes each: 256 MB); past
/// them, in leaf order, receivers weigh the parts again each time the
/// ratios are taken (the same weights, bit for bit, for more CPU). Kept
/// whole, the 100 000-triangle atrium's took about 1.3 GB; the Cornell
/// box's fit.
pub(crate) const MAX_KEPT_WEIGHTS: usize = 32 << 20;

/// Leaves weighed together before [`MAX_KEPT_WEIGHTS`] is checked again.
const WEIGH_BATCH: usize = 4096;

/// What the near receivers of the shaped patches weigh (see
/// [`SourceShapes::near_weights`]): geometry alone, so that it holds while
/// the parts' values change (see [`SourceShapes::refresh`]).
#[derive(Debug)]
pub(crate) struct NearWeights {
    /// Per leaf, its entries to shaped patches it is near, in row order.
    pub(super) near: Ragged<NearEntry>,
    /// The part weights the entries keep (see [`NearEntry::parts`]).
    weights: Vec<(u32, f32)>,
    /// How many receivers drew a hemi-cube again to see a patch part by part.
    views: usize,
}

impl NearWeights {
    /// How many receivers drew a hemi-cube again to see a patch part by part.
    pub(crate) fn views(&self) -> usize {
        self.views
    }

    /// The part weights that `entry` keeps.
    pub(super) fn kept_parts(&self, entry: &NearEntry) -> &[(u32, f32)] {
        &self.weights[entry.parts.start as usize..entry.parts.end as usize]
    }
}

/// Lists [`SourceShapes::important`] fills, kept from one leaf to the next
/// (a receiver is near dozens of patches: lists of their own would be
/// allocated, grown and freed per leaf).
#[derive(Default)]
struct ImportantScratch {
    /// The entries near enough to weigh: (share, index in the row,
    /// weight, swing times form factor and weight).
    order: Vec<(f64, u32, f64, Rgb)>,
    /// The entries kept, with their weights, in row order.
    kept: Vec<(u32, f64)>,
}

/// An entry of a receiver's row to a shaped patch it is near.
#[derive(Clone, Debug)]
pub(super) struct NearEntry {
    /// Its index in the row.
    pub(super) index: u32,
    /// How much of its ratio the receiver takes (see [`SourceShapes::important`]).
    pub(super) weight: f64,
    /// Where in [`NearWeights::weights`] the parts it weighs lie, each with
    /// its weight: by their unoccluded form factors, or by what its
    /// hemi-cube shows of them where it looked (see
    /// [`SourceShapes::near_weights`]). Its ratio is their weighted mean
    /// over the patch's mean, whatever the parts' values. Empty when not
    /// `kept`: they are then weighed again from the geometry each time.
    pub(super) parts: std::ops::Range<u32>,
    /// Whether `parts` holds the weights (see [`MAX_KEPT_WEIGHTS`]).
    pub(super) kept: bool,
    /// Whether the receiver's row sees too little of the parts for those
    /// weights to hold, by enough to matter: its ratio is then taken from
    /// what its hemi-cube shows of each part (see [`SEEN_SHARE`]).
    pub(super) look: bool,
    /// The share of the parts' unoccluded form factors that its row does
    /// not see, in 0..=1: how far its unoccluded weights can be off.
    pub(super) hidden: f64,
}

/// A receiver leaves its least important near entries at the patch mean as
/// long as together they could change what it gathers from shaped patches by
/// at most this fraction, in every band. An entry's bound is its form factor
/// times its patch's mean times the patch's largest relative departure of a
/// part from the mean (no weighted mean of the parts can depart further).
/// On the Cornell box this leaves out a third of the near entries (the
/// weakest, and those to patches lit almost evenly) and changes no surface's
/// mean by more than 0.03%.
pub(crate) const SKIPPED_SHARE: f64 = 1e-3;

impl SourceShapes {
    /// What each of `leaves` weighs of the shaped patches it is near: per
    /// important entry of its row (see [`Self::important`]), the parts and
    /// their unoccluded form factors, or, where its row sees too little of
    /// them and that could matter (and `views` is given), the share of each
    /// that its hemi-cube, drawn with the patch part by part, shows (see
    /// [`SEEN_SHARE`], [`VIEW_SHARE`]). `None` when no patch is unevenly lit.
    pub(crate) fn near_weights<'s>(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        views: Option<&PartViews<'_, 's>>,
    ) -> Option<NearWeights> {
        self.near_weights_within(mesh, form_factors, leaves, views, MAX_KEPT_WEIGHTS)
    }

    /// [`Self::near_weights`], keeping at most about `budget` part weights.
    pub(super) fn near_weights_within<'s>(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        views: Option<&PartViews<'_, 's>>,
        budget: usize,
    ) -> Option<NearWeights> {
        if self.shaped.is_empty() {
            return None;
        }
        let can_look = views.is_some();
        // In batches of leaves, so that what is kept stops at the budget
        // at the same leaf on any number of threads. A batch is a whole
        // number of tasks, so that leaf `n` lies in task `n / WEIGH_TASK`.
        const { assert!(WEIGH_BATCH.is_multiple_of(WEIGH_TASK)) };
        let mut near: Ragged<NearEntry> = Ragged::default();
        let mut blocks: Vec<Vec<(u32, f32)>> = Vec::with_capacity(leaves.len() / WEIGH_TASK + 1);
        let mut kept_count = 0;
        for batch in leaves.chunks(WEIGH_BATCH) {
            let keep = kept_count < budget;
            // Per task, its leaves' entries and the weights they keep.
            type Weighed = (Ragged<NearEntry>, Vec<(u32, f32)>);
            let tasks: Vec<Weighed> = batch
                .par_chunks(WEIGH_TASK)
                .map_init(ImportantScratch::default, |scratch, task| {
                    let (mut entries, mut kept) = (Ragged::default(), Vec::new());
                    for &k in task {
                        entries.push_row_with(|out| {
                            self.near_entries(
                                mesh,
                                form_factors,
                                k,
                                can_look,
                                keep,
                                &mut kept,
                                out,
                                scratch,
                            );
                        });
                    }
                    (entries, kept)
                })
                .collect();
            for (entries, kept) in tasks {
                kept_count += kept.len();
                blocks.push(kept);
                near.append(entries);
            }
        }
        // The tasks' blocks in one vector, sized once (joined as they came,
        // it grew by doubling, copying what it held each time), with each
        // entry's range moved by where its task's block now starts.
        let mut weights: Vec<(u32, f32)> = Vec::with_capacity(kept_count);
        for (t, block) in blocks.into_iter().enumerate() {
            let offset = weights.len() as u32;
            weights.extend(block);
            let leaves_of_task = t * WEIGH_TASK..((t + 1) * WEIGH_TASK).min(leaves.len());
            for n in leaves_of_task {
                for entry in near.row_mut(n) {
                    entry.parts = entry.parts.start + offset..entry.parts.end + offset;
                }
            }
        }
        // Per entry weighed by what its leaf sees: (leaf, entry, its weights).
        let mut seen: Vec<(usize, usize, std::ops::Range<u32>)> = Vec::new();
        let views = match views {
            Some(scene) => {
                self.seen_weights(mesh, form_factors, leaves, &near, scene, |n, m, parts| {
                    let start = weights.len() as u32;
                    weights.extend(parts);
                    seen.push((n, m, start..weights.len() as u32));
                })
            }
            None => 0,
        };
        for (n, m, parts) in seen {
            // Weighed by what it sees: sure.
            let entry = &mut near.row_mut(n)[m];
            entry.parts = parts;
            entry.kept = true;
            entry.hidden = 0.0;
        }
        Some(NearWeights {
            near,
            weights,
            views,
        })
    }

    /// The near entries of leaf `k`'s row (see [`Self::near_weights`]),
    /// pushed onto `out`, their weights kept, when `keep`, at the end of
    /// `kept` (the entries' ranges index it).
    #[allow(clippy::too_many_arguments)]
    fn near_entries(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        k: ElementKey,
        can_look: bool,
        keep: bool,
        kept: &mut Vec<(u32, f32)>,
        out: &mut Vec<NearEntry>,
        scratch: &mut ImportantScratch,
    ) {
        let e = &mesh.elements[k];
        // A receiver that reflects nothing passes no light on: it
        // gathers patch means and stays out of the sums, so that
        // skipping its row (see `crate::pipeline::Skips`) changes
        // nothing.
        if e.reflectance.max_band() <= 0.0 {
            return;
        }
        let normal = mesh.surfaces()[e.surface as usize].normal;
        let entries = form_factors.entries(k);
        let gathered = self.important(entries, e.centroid, scratch);
        for &(i, weight) in &scratch.kept {
            let (j, f) = entries[i as usize];
            let start = kept.len();
            let Some(unoccluded) = self.weights_into(j, e.centroid, normal, kept) else {
                continue;
            };
            if !keep {
                kept.truncate(start);
            }
            let f = f64::from(f);
            let hidden = 1.0 - f / unoccluded;
            // What weighing the hidden parts could change at
            // most, as a share of what the row gathers.
            let shaped = &self.shaped[self.slot[j as usize] as usize];
            let bound = shaped.swing * (f * weight * (hidden / (1.0 - hidden)).min(1.0));
            let matters = (0..3).any(|band| bound[band] > VIEW_SHARE * gathered[band]);
            let look = f < SEEN_SHARE * unoccluded && matters;
            out.push(NearEntry {
                index: i,
                weight,
                kept: keep,
                parts: start as u32..kept.len() as u32,
                look: look && can_look,
                hidden: hidden.clamp(0.0, 1.0),
            });
        }
    }

    /// The entries of a row at `eye`, in row order, whose ratios are worth
    /// weighing, with the weight each ratio takes: those to shaped patches
    /// the eye is near (weighed down towards the edge of the reach), less
    /// the least important ones while together they could change what the
    /// row gathers from shaped patches by at most [`SKIPPED_SHARE`] in any
    /// band. The entry that crosses that budget is weighed by the part of it
    /// left over, so that nothing jumps when rounding reorders two entries
    /// or moves one across the budget. They are left in `scratch.kept`;
    /// returned is what the row gathers from the shaped patches' means.
    fn important(&self, entries: &[(u32, f32)], eye: DVec3, scratch: &mut ImportantScratch) -> Rgb {
        let ImportantScratch { order, kept } = scratch;
        order.clear();
        kept.clear();
        let mut gathered = Rgb::ZERO;
        for (i, &(j, f)) in entries.iter().enumerate() {
            let s = self.slot[j as usize];
            if s == u32::MAX {
                continue;
            }
            let shaped = &self.shaped[s as usize];
            let f = f64::from(f);
            gathered += shaped.mean * f;
            let weight = shaped.nearness(eye);
            if weight > 0.0 {
                // Its share is set below, once `gathered` is whole.
                order.push((0.0, i as u32, weight, shaped.swing * (f * weight)));
            }
        }
        let share = |swing: &Rgb| {
            (0..3)
                .filter(|&band| gathered[band] > 0.0)
                .map(|band| swing[band] / gathered[band])
                .fold(0.0, f64::max)
        };
        for entry in order.iter_mut() {
            entry.0 = share(&entry.3);
        }
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut skipped = Rgb::ZERO;
        for (n, &(own, i, weight, swing)) in order.iter().enumerate() {
            if share(&(skipped + swing)) <= SKIPPED_SHARE {
                skipped += swing;
                continue;
            }
            let left = (SKIPPED_SHARE - share(&skipped)).max(0.0);
            let taken = if own > 0.0 { 1.0 - left / own } else { 1.0 };
            kept.push((i, weight * taken.clamp(0.0, 1.0)));
            kept.extend(order[n + 1..].iter().map(|x| (x.1, x.2)));
            break;
        }
        kept.sort_unstable_by_key(|x| x.0);
        gathered
    }
}
