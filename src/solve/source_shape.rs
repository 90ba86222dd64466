//! Unevenly lit sources seen from close by.
//!
//! A row holds one form factor per patch, and the gather multiplies it by the
//! patch's radiosity: the mean over the whole patch. A receiver close to a
//! patch that is lit unevenly sees mostly the near part of it, which may be
//! much darker or brighter than the mean: a bench's underside sees the floor
//! in the bench's own shadow, not the mean of a floor patch that runs out
//! into the sun. Refining the receiver does not help; only the source's own
//! detail does.
//!
//! That detail is known after a gather: the source patch's elements. So a
//! receiver near such a patch weighs the patch's parts by their unoccluded
//! form factors from the receiver, and gathers the patch's radiosity times
//! the ratio of that weighted mean to the patch's area mean, per band. The
//! parts are a cut of the patch's quadtree (its leaves when it has few), and
//! a receiver looks inside every part it is near (see [`OPEN`]), down to the
//! leaves: a receiver in a corner sees the leaves beside it, not the mean of
//! a part that also reaches round the far side of a pier. A part's value is
//! the radiosity of its exposed leaves, and its weight counts only its
//! exposed share, since what stands on a surface hides it from every
//! receiver. The ratio carries only the distribution over the patch; its
//! level still comes from the solved patch system, and the row's form factor
//! still says how much of the patch is visible. Where the row sees clearly
//! less of the patch than the parts' unoccluded form factors add up to,
//! something stands between, and the receiver's hemi-cube is drawn again
//! with the patch's parts in place of its polygons: each part then weighs
//! by the share of its pixels it won (see [`SEEN_SHARE`], [`VIEW_SHARE`]).
//! Each
//! patch's factors are finally corrected so that its receivers together
//! gather from it what it sends them: in a closed scene what they gathered
//! from its mean (the correction moves light between receivers and conserves
//! it), in an open one what its leaves send to reflecting surfaces by their
//! own rows (see [`SourceShapes::new`]). The difference goes to the receivers
//! whose weights are a guess (those that see part of the patch hidden, and
//! those too far to weigh its parts), not to those that see all of it (see
//! [`Correction`]).
//!
//! Moving light between receivers that reflect differently changes what
//! they pass on, so after each shaped gather the gathering solver solves the
//! patch system again with what the shapes changed in each patch's mean as
//! extra emission, and gathers again (see
//! `crate::pipeline`'s gathering solver): the result balances its light like
//! a plain gather. Each of those corrections also takes the ratios again
//! from the parts' new values, with the weights found the first time (see
//! [`SourceShapes::refresh`]): the first ratios came from a plain gather, in
//! which the dark side of a patch near its receivers was lit by the means
//! of the patches it sees, too brightly where two surfaces face each other
//! across a narrow gap. A receiver's ratio fades out towards the edge of its
//! reach, and the least important ones are left at the mean (see
//! [`SKIPPED_SHARE`]), both without a step. One shaped gather is the
//! gathering solver's default ([`crate::Settings::shaped_gathers`]).

use super::ragged::Ragged;
use super::Radiosity;
use crate::formfactor::{FormFactors, PartSources, RowScene, SourcePolygon};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

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

/// Parts of a shaped patch (indices into [`Shaped::parts`]) with weights,
/// in single precision: a receiver near many patches holds thousands.
type PartWeights = Vec<(u32, f32)>;

/// Leaves weighed in one parallel task: leaves near a lit patch weigh its
/// parts, the rest do nothing, and small tasks keep every worker busy to
/// the end.
const WEIGH_TASK: usize = 16;

/// Leaves whose factors one parallel task takes: taking them is cheap
/// (a weighted mean per near entry), so a task holds many.
const FACTOR_BLOCK: usize = 256;

/// A leaf's part views: per entry drawn, (leaf, index in its near entries,
/// the parts' weights by what it sees, or `None` where no pixel shows one).
type LeafViews = SmallVec<[(usize, usize, Option<PartWeights>); 2]>;

/// Part views are drawn this many receivers at a time, and their weights
/// handed over before the next batch is drawn.
const VIEW_BATCH: usize = 8192;

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
    near: Ragged<NearEntry>,
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
    fn kept_parts(&self, entry: &NearEntry) -> &[(u32, f32)] {
        &self.weights[entry.parts.start as usize..entry.parts.end as usize]
    }
}

/// How a shaped gather draws the hemi-cubes of receivers that look at a
/// patch part by part (see [`SEEN_SHARE`]).
pub(crate) struct PartViews<'a, 's> {
    /// Builds the scene they are drawn in (only when one is needed).
    pub scene: &'a dyn Fn() -> RowScene<'s>,
    /// Called with the views drawn so far and their number.
    pub progress: &'a (dyn Fn(usize, usize) + Sync),
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
struct NearEntry {
    /// Its index in the row.
    index: u32,
    /// How much of its ratio the receiver takes (see [`SourceShapes::important`]).
    weight: f64,
    /// Where in [`NearWeights::weights`] the parts it weighs lie, each with
    /// its weight: by their unoccluded form factors, or by what its
    /// hemi-cube shows of them where it looked (see
    /// [`SourceShapes::near_weights`]). Its ratio is their weighted mean
    /// over the patch's mean, whatever the parts' values. Empty when not
    /// `kept`: they are then weighed again from the geometry each time.
    parts: std::ops::Range<u32>,
    /// Whether `parts` holds the weights (see [`MAX_KEPT_WEIGHTS`]).
    kept: bool,
    /// Whether the receiver's row sees too little of the parts for those
    /// weights to hold, by enough to matter: its ratio is then taken from
    /// what its hemi-cube shows of each part (see [`SEEN_SHARE`]).
    look: bool,
    /// The share of the parts' unoccluded form factors that its row does
    /// not see, in 0..=1: how far its unoccluded weights can be off.
    hidden: f64,
}

/// A receiver counts as near a patch within this many times the patch's
/// bounding radius of its centre. Farther away every part of the patch
/// subtends about the same solid angle per area, and the ratio is near 1.
/// Measured with two shaped gathers (mean per-object error): at 2, the
/// atrium 2.72% and the Cornell box 0.267%; at 3, 2.57% and 0.236%; at 6,
/// 2.49% and 0.205%; with every receiver near, 2.49% and 0.204% for 1.1x
/// the CPU time of 6 on the atrium.
pub(crate) const NEAR: f64 = 6.0;

/// Within this many bounding radii a near receiver takes its ratio whole;
/// from here out to [`NEAR`] the ratio fades linearly to 1, so that a
/// receiver's result does not jump where rounding puts it just inside or
/// outside the reach (elements on a regular grid often lie exactly at it).
pub(crate) const FULLY_NEAR: f64 = 5.0;

/// Most parts a patch's cut has: its leaves, or the deepest cut of its
/// quadtree with at most this many nodes (receivers near a part look
/// inside it).
pub(crate) const MAX_PARTS: usize = 64;

/// A patch counts as unevenly lit when, in some band, its parts' radiosities
/// spread (largest minus smallest) by more than this fraction of their mean.
/// A patch just under it changes what any receiver gathers by less than
/// this fraction, so its being left out makes no step in the solution.
pub(crate) const SPREAD: f64 = 1e-5;

/// A receiver leaves its least important near entries at the patch mean as
/// long as together they could change what it gathers from shaped patches by
/// at most this fraction, in every band. An entry's bound is its form factor
/// times its patch's mean times the patch's largest relative departure of a
/// part from the mean (no weighted mean of the parts can depart further).
/// On the Cornell box this leaves out a third of the near entries (the
/// weakest, and those to patches lit almost evenly) and changes no surface's
/// mean by more than 0.03%.
pub(crate) const SKIPPED_SHARE: f64 = 1e-3;

/// A part weighs by the differential form factor at its centroid when its
/// bounding radius is under this fraction of its distance from the receiver,
/// by Lambert's formula when nearer.
pub(crate) const WEIGHT_FAR: f64 = 0.15;

/// How a shaped patch's factors are brought to what its receivers must
/// gather from it together (see [`SourceShapes::entry_factors`]).
///
/// A near receiver's ratio weighs the patch's parts by their unoccluded
/// form factors. Where its row sees the whole of them, those are the
/// weights it sees by, and the ratio holds. Where something hides part of
/// the patch, or the receiver is far and takes the mean, the weights are a
/// guess. So the difference between the target and what the ratios gather
/// goes first to the unsure share of each entry: its hidden share where it
/// is near, all of it where it takes the mean. Only where that share is too
/// small to take the difference within [`UNSURE_LIMIT`] is the rest spread
/// over every entry alike. Until 2026-12-03 every entry was scaled alike: a
/// receiver that sees the whole patch, whose ratio holds, then took a share
/// of what the guesses missed. Mean per-object error, scaled alike against
/// now: the Cornell box 0.155% against 0.139%, the Ferren sculpture 1.42%
/// against 1.09%, the Blender Cornell box 1.10% against 0.97%.
#[derive(Clone, Copy, Debug)]
struct Correction {
    /// Per band, the factor on the unsure share of a ratio.
    unsure: Rgb,
    /// Per band, the factor on every ratio after that.
    all: Rgb,
}

/// The factor on the unsure share of the ratios stays within
/// `1 / UNSURE_LIMIT` and `UNSURE_LIMIT`.
pub(crate) const UNSURE_LIMIT: f64 = 2.0;

impl Correction {
    /// The correction that brings `with` (what the ratios gather, per band)
    /// to `target`, `unsure` being the unsure part of `with`.
    fn of(target: Rgb, with: Rgb, unsure: Rgb) -> Self {
        let (mut on_unsure, mut all) = (Rgb::ONE, Rgb::ONE);
        for band in 0..3 {
            if unsure[band] > 0.0 {
                on_unsure.0[band] = (1.0 + (target[band] - with[band]) / unsure[band])
                    .clamp(1.0 / UNSURE_LIMIT, UNSURE_LIMIT);
            }
            let corrected = with[band] + (on_unsure[band] - 1.0) * unsure[band];
            if corrected > 0.0 {
                all.0[band] = target[band] / corrected;
            }
        }
        Correction {
            unsure: on_unsure,
            all,
        }
    }

    /// Ratio `r`, of which share `u` is unsure, corrected.
    fn apply(&self, r: Rgb, u: f64) -> Rgb {
        let mut out = r;
        for band in 0..3 {
            out.0[band] *= (1.0 + (self.unsure[band] - 1.0) * u) * self.all[band];
        }
        out
    }
}

impl Shaped {
    /// How much of its ratio a receiver at `eye` takes: 1 within
    /// [`FULLY_NEAR`] bounding radii of the centre, 0 beyond [`NEAR`], and
    /// linear between.
    fn nearness(&self, eye: DVec3) -> f64 {
        let d = (eye - self.centre).length();
        ((self.reach - d) / (self.reach - self.full)).clamp(0.0, 1.0)
    }
}

/// The unevenly lit patches of a solution and their parts.
#[derive(Debug, Default)]
pub(crate) struct SourceShapes {
    /// Per patch, its index in `shaped`, or `u32::MAX` when it is even.
    slot: Vec<u32>,
    shaped: Vec<Shaped>,
}

#[derive(Debug)]
struct Shaped {
    centre: DVec3,
    /// Distance from `centre` within which a receiver is near, and within
    /// which it is fully near (see [`FULLY_NEAR`]).
    reach: f64,
    full: f64,
    /// Area-weighted mean radiosity of the parts.
    mean: Rgb,
    /// Per band, the mean times the parts' largest relative departure from
    /// it: what the ratio can change, per unit of form factor, at most.
    swing: Rgb,
    /// Per band, in an open scene, the patch's leaves' radiosity weighted by
    /// what each sends to reflecting front faces (area times that part of its
    /// row), over `mean`: how much brighter the patch is where it sees its
    /// receivers than on average. 1 in a closed scene (see
    /// [`SourceShapes::new`]).
    sent: Rgb,
    /// The parts: the cut's nodes first (`parts[..top]`), then, below
    /// each, its children, so that a receiver near a part can look inside it.
    parts: Vec<Part>,
    /// How many of `parts` form the cut.
    top: usize,
    /// Per part, the radiosity of its exposed leaves (see
    /// [`exposed_power`]). Apart from `parts`: the ratios read only these,
    /// a few to a receiver's entry, and they share cache lines.
    values: Vec<Rgb>,
    /// Per part, its node of the patch's quadtree.
    keys: Vec<ElementKey>,
    /// The patch.
    patch: u32,
}

/// A node of a shaped patch's quadtree as a source.
#[derive(Debug)]
struct Part {
    source: SourcePolygon,
    /// Its area and area centroid, for its differential form factor.
    area_centroid: (f64, DVec3),
    /// Its exposed share of its area: what a receiver can see of it.
    share: f64,
    /// Its children among the patch's parts (empty for a leaf, and for
    /// children with nothing exposed).
    children: std::ops::Range<u32>,
}

impl SourceShapes {
    /// The unevenly lit patches of `mesh` by the element radiosities in
    /// `radiosity` (the last gather's). Only leaves with an exposed row take
    /// part: the others take no part in the exchange.
    ///
    /// In a `closed` scene each patch's receivers together gather from it
    /// what they gathered from its mean, so that no light is lost or created
    /// (there it would be multiplied by every bounce, and the patch system
    /// is not solved again). In an open scene they gather what its leaves
    /// send them by their own rows: where a patch's bright part looks out
    /// at the sky and its dark part at its receivers, they gather the dark.
    pub(crate) fn new(
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        closed: bool,
    ) -> Self {
        let mut slot = vec![u32::MAX; mesh.patches.len()];
        let mut shaped = Vec::new();
        let reflects: Vec<bool> = (0..mesh.patches.len())
            .map(|p| mesh.patch_reflectance(p as u32).max_band() > 0.0)
            .collect();
        for (p, patch) in mesh.patches.iter().enumerate() {
            let Some(parts) = cut(mesh, &patch.roots) else {
                continue;
            };
            let Some(tree) = PartTree::of(mesh, form_factors, radiosity, &parts) else {
                continue;
            };
            let PartTree {
                parts,
                values,
                top,
                keys,
                mean,
            } = tree;
            let uneven = (0..3).any(|band| {
                let (lo, hi) = values
                    .iter()
                    .map(|value| value[band])
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        (lo.min(v), hi.max(v))
                    });
                mean[band] > 0.0 && hi - lo > SPREAD * mean[band]
            });
            if !uneven {
                continue;
            }
            let swing = swing_of(&values, mean);
            let centre = patch.centroid;
            let radius = parts[..top]
                .iter()
                .flat_map(|part| part.source.corners().iter())
                .map(|v| (*v - centre).length())
                .fold(0.0, f64::max);
            let sent_ratio = if closed {
                Rgb::ONE
            } else {
                sent_ratio(mesh, form_factors, radiosity, p as u32, &reflects, mean)
            };
            slot[p] = shaped.len() as u32;
            shaped.push(Shaped {
                centre,
                reach: NEAR * radius,
                full: FULLY_NEAR * radius,
                mean,
                swing,
                sent: sent_ratio,
                parts,
                values,
                top,
                keys,
                patch: p as u32,
            });
        }
        SourceShapes { slot, shaped }
    }

    /// Takes the parts' values, the patches' means and what the patches send
    /// anew from `radiosity` (a later gather's), keeping the parts and which
    /// patches are shaped: what receivers weigh (see [`NearWeights`]) still
    /// holds, and [`Self::factors`] then gives the ratios of the new values.
    /// A shaped gather's receivers took their ratios from the values of the
    /// gather before, in which the dark side of a patch near them was lit by
    /// the means of the patches it sees; each refresh passes one more bounce
    /// of the detail between near patches.
    pub(crate) fn refresh(
        &mut self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        closed: bool,
    ) {
        let reflects: Vec<bool> = (0..mesh.patches.len())
            .map(|p| mesh.patch_reflectance(p as u32).max_band() > 0.0)
            .collect();
        self.shaped.par_iter_mut().for_each(|shaped| {
            let (mut area, mut power) = (0.0, Rgb::ZERO);
            for (n, (value, &k)) in shaped.values.iter_mut().zip(&shaped.keys).enumerate() {
                let (a, p) = exposed_power(mesh, form_factors, radiosity, k);
                if a > 0.0 {
                    *value = p * (1.0 / a);
                }
                if n < shaped.top {
                    area += a;
                    power += p;
                }
            }
            if area > 0.0 {
                shaped.mean = power * (1.0 / area);
            }
            shaped.swing = swing_of(&shaped.values, shaped.mean);
            if !closed {
                shaped.sent = sent_ratio(
                    mesh,
                    form_factors,
                    radiosity,
                    shaped.patch,
                    &reflects,
                    shaped.mean,
                );
            }
        });
    }

    /// How many patches are unevenly lit.
    pub(crate) fn len(&self) -> usize {
        self.shaped.len()
    }

    /// The factors on the patch radiosities that the rows of `leaves` gather:
    /// [`Self::near_weights`], then [`Self::factors`]. `None` when no patch
    /// is unevenly lit.
    #[cfg(test)]
    pub(crate) fn entry_factors<'s>(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        row_scale: impl Fn(usize) -> f64 + Sync,
        views: Option<&PartViews<'_, 's>>,
    ) -> Option<EntryFactors> {
        let near = self.near_weights(mesh, form_factors, leaves, views)?;
        Some(self.factors(mesh, form_factors, leaves, row_scale, &near))
    }

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
    fn near_weights_within<'s>(
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

    /// Per band, the ratio of what a receiver at `eye` facing `normal` sees
    /// of patch `j` to the patch's mean, weighing the parts by their
    /// unoccluded form factors, and the sum of those weights; `None` when the
    /// patch is even or the receiver sees none of the parts.
    #[cfg(test)]
    fn ratio(&self, j: u32, eye: DVec3, normal: DVec3) -> Option<(Rgb, f64)> {
        let mut parts = Vec::new();
        let weight = self.weights_into(j, eye, normal, &mut parts)?;
        let shaped = &self.shaped[self.slot[j as usize] as usize];
        Some((shaped.ratio_from(&parts)?, weight))
    }

    /// The parts of patch `j` a receiver at `eye` facing `normal` weighs,
    /// each by its unoccluded form factor times its exposed share, pushed
    /// onto `out`, and the sum of those weights; `None`, with nothing
    /// pushed, when the patch is even or the receiver sees none of the parts.
    fn weights_into(
        &self,
        j: u32,
        eye: DVec3,
        normal: DVec3,
        out: &mut Vec<(u32, f32)>,
    ) -> Option<f64> {
        let s = *self.slot.get(j as usize)?;
        if s == u32::MAX {
            return None;
        }
        let shaped = &self.shaped[s as usize];
        let start = out.len();
        let mut weight = 0.0;
        shaped.each_weighed_part(eye, normal, |part, w| {
            let w = w * shaped.parts[part as usize].share;
            weight += w;
            out.push((part, w as f32));
        });
        if weight > 0.0 {
            Some(weight)
        } else {
            out.truncate(start);
            None
        }
    }

    /// For the near entries of `near` (per leaf of `leaves`) whose rows see
    /// too little of the parts, the parts' weights by what the leaf sees:
    /// each part's unoccluded form factor times the share of its pixels that
    /// the leaf's hemi-cube, drawn with the patch part by part (see
    /// [`RowScene::with_part_views`]), shows, each handed to `take` as
    /// (leaf, index in its near entries, weights), in leaf order (none where
    /// no pixel shows a part). Returns the number of hemi-cubes drawn.
    fn seen_weights<'s>(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        near: &Ragged<NearEntry>,
        views: &PartViews<'_, 's>,
        mut take: impl FnMut(usize, usize, PartWeights),
    ) -> usize {
        let which: Vec<usize> = (0..leaves.len())
            .filter(|&n| near.row(n).iter().any(|x| x.look))
            .collect();
        if which.is_empty() {
            return 0;
        }
        let scene = (views.scene)();
        let keys: Vec<ElementKey> = which.iter().map(|&n| leaves[n]).collect();
        // In batches, each handed over before the next is drawn: all at
        // once, the weights of every view were held twice at the end.
        for (b, batch) in keys.chunks(VIEW_BATCH).enumerate() {
            let offset = b * VIEW_BATCH;
            let progress = |done: usize, _| (views.progress)(offset + done, keys.len());
            let seen = self.seen_batch(
                mesh,
                form_factors,
                leaves,
                near,
                &which[offset..],
                &scene,
                batch,
                &progress,
            );
            for (n, m, by_view) in seen.into_iter().flatten() {
                if let Some(parts) = by_view {
                    take(n, m, parts);
                }
            }
        }
        keys.len()
    }

    /// [`Self::seen_weights`] for the leaves `keys`, whose indices in
    /// `leaves` are `which` (from its start), drawn with `scene`.
    #[allow(clippy::too_many_arguments)]
    fn seen_batch<'s>(
        &self,
        mesh: &Mesh,
        form_factors: &FormFactors,
        leaves: &[ElementKey],
        near: &Ragged<NearEntry>,
        which: &[usize],
        scene: &RowScene<'s>,
        keys: &[ElementKey],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Vec<LeafViews> {
        scene.with_part_views(keys, progress, |index, view| {
            let n = which[index];
            let k = leaves[n];
            let e = &mesh.elements[k];
            let normal = mesh.surfaces()[e.surface as usize].normal;
            let row = form_factors.entries(k);
            // Per hidden entry: its index, its patch and the parts weighed.
            type Parts = SmallVec<[(u32, f64); 64]>;
            let mut drawn: SmallVec<[(usize, u32, &Shaped, Parts); 2]> = SmallVec::new();
            for (m, entry) in near.row(n).iter().enumerate() {
                if entry.look {
                    let j = row[entry.index as usize].0;
                    let shaped = &self.shaped[self.slot[j as usize] as usize];
                    let parts = shaped.weighed_parts(e.centroid, normal);
                    drawn.push((m, j, shaped, parts));
                }
            }
            let wanted: Vec<PartSources<'_>> = drawn
                .iter()
                .map(|(_, j, shaped, parts)| PartSources {
                    patch: *j,
                    parts: parts
                        .iter()
                        .map(|&(p, _)| &shaped.parts[p as usize].source)
                        .collect(),
                })
                .collect();
            let shown = view(&wanted);
            let mut at = 0;
            let mut out: LeafViews = SmallVec::new();
            for (m, _, shaped, parts) in &drawn {
                let shown = &shown[at..at + parts.len()];
                at += parts.len();
                out.push((n, *m, shaped.seen_weights(parts, shown)));
            }
            out
        })
    }
}

impl Shaped {
    /// The parts a receiver at `eye` facing `normal` weighs, with their
    /// unoccluded form factors: the cut's parts that face it, and inside
    /// every part it is near (see [`OPEN`]) that part's children instead.
    /// Together they tile what the receiver can see of the patch.
    fn weighed_parts(&self, eye: DVec3, normal: DVec3) -> SmallVec<[(u32, f64); 64]> {
        let mut out = SmallVec::new();
        self.each_weighed_part(eye, normal, |i, f| out.push((i, f)));
        out
    }

    /// [`Self::weighed_parts`], each handed to `weighed` in the same order
    /// (no list to build and move: receivers weigh hundreds of thousands).
    fn each_weighed_part(&self, eye: DVec3, normal: DVec3, mut weighed: impl FnMut(u32, f64)) {
        let mut stack: SmallVec<[u32; 64]> = (0..self.top as u32).rev().collect();
        while let Some(i) = stack.pop() {
            let part = &self.parts[i as usize];
            if !part.source.faces(eye) {
                continue;
            }
            let source = &part.source;
            if !part.children.is_empty() && source.radius > OPEN * (source.centre - eye).length() {
                stack.extend(part.children.clone().rev());
                continue;
            }
            let f = source.form_factor_within_given(eye, normal, WEIGHT_FAR, || part.area_centroid);
            weighed(i, f);
        }
    }

    /// Per band, the mean of the parts' values by `weights` over the
    /// patch's mean; `None` when the weights are 0.
    fn ratio_from(&self, weights: &[(u32, f32)]) -> Option<Rgb> {
        let (mut weight, mut seen) = (0.0, Rgb::ZERO);
        for &(p, w) in weights {
            let w = f64::from(w);
            weight += w;
            seen += self.values[p as usize] * w;
        }
        self.ratio_of(seen, weight)
    }

    /// Per band, `seen` over `weight` (a weighted sum of the parts' values
    /// and the sum of its weights) as a ratio to the mean; `None` when the
    /// weights are 0.
    fn ratio_of(&self, seen: Rgb, weight: f64) -> Option<Rgb> {
        if weight <= 0.0 {
            return None;
        }
        let mut ratio = Rgb::ONE;
        for band in 0..3 {
            if self.mean[band] > 0.0 {
                ratio.0[band] = seen[band] / weight / self.mean[band];
            }
        }
        Some(ratio)
    }

    /// The weights of the parts by what a receiver sees, `parts` being the
    /// parts it weighs with their unoccluded form factors and `shown`, per
    /// part, the delta form factors of the pixels it won and of all it
    /// covered in the receiver's hemi-cube drawn with those parts. Each part
    /// weighs its form factor times the share of its pixels it won (what
    /// stands on the surface hides its covered share in the pixels too, so
    /// that share is not counted twice). A part too small to cover a pixel
    /// centre takes the share of all the parts' pixels won, and its exposed
    /// share. `None` when no pixel shows a part.
    fn seen_weights(&self, parts: &[(u32, f64)], shown: &[(f64, f64)]) -> Option<PartWeights> {
        let (won, covered) = shown
            .iter()
            .fold((0.0, 0.0), |(w, c), s| (w + s.0, c + s.1));
        if won <= 0.0 {
            return None;
        }
        let overall = (won / covered).min(1.0);
        let mut weight = 0.0;
        let weights: PartWeights = parts
            .iter()
            .zip(shown)
            .map(|(&(p, form_factor), &(won, covered))| {
                let w = if covered > 0.0 {
                    form_factor * (won / covered).min(1.0)
                } else {
                    form_factor * self.parts[p as usize].share * overall
                };
                weight += w;
                (p, w as f32)
            })
            .collect();
        (weight > 0.0).then_some(weights)
    }
}

/// A receiver's ratio for a patch is taken from what its hemi-cube shows of
/// the patch's parts, not from their unoccluded form factors, where its row
/// has less than this share of those form factors' sum: something hides
/// part of the patch from it, and the unoccluded weights would count the
/// hidden parts.
pub(crate) const SEEN_SHARE: f64 = 0.95;

/// A receiver draws its hemi-cube again only for a patch whose hidden
/// parts could change what its row gathers from shaped patches by more
/// than this fraction in some band: the patch's largest departure of a part
/// from its mean, times its form factor and its ratio's weight, times the
/// hidden share of the parts' form factors over the seen share (at most
/// 1). Measured on the 10 000-triangle atrium (mean per-object error):
/// without this bound, 1.80% with views for 27 933 of 30 590 receivers; at
/// 0.003, 1.83% with 24 736 views at a third of the time; at 0.01, 1.91%.
pub(crate) const VIEW_SHARE: f64 = 0.003;

/// A receiver looks inside a part (at its children) when the part's
/// bounding radius exceeds this fraction of its distance from the part's
/// centre: near a part its detail matters, from afar only its mean.
/// Measured on the 100 000-triangle atrium (mean per-object error): never
/// looking inside, 1.50%; at 0.5, 1.32%; at 0.25, 1.31% for more time.
pub(crate) const OPEN: f64 = 0.5;

/// A shaped patch's parts (see [`Shaped::parts`]) and their mean.
struct PartTree {
    parts: Vec<Part>,
    values: Vec<Rgb>,
    top: usize,
    keys: Vec<ElementKey>,
    mean: Rgb,
}

impl PartTree {
    /// The parts under the nodes `cut` with anything exposed; `None` when
    /// fewer than two cut nodes have.
    fn of(
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        cut: &[ElementKey],
    ) -> Option<PartTree> {
        let part = |k: ElementKey| -> Option<(Part, Rgb, f64)> {
            let (area, power) = exposed_power(mesh, form_factors, radiosity, k);
            if area <= 0.0 {
                return None;
            }
            let e = &mesh.elements[k];
            let surface = &mesh.surfaces()[e.surface as usize];
            let polygon = surface.polygon(&e.cell);
            let source = SourcePolygon::new(&polygon, surface.normal, e.surface);
            let part = Part {
                area_centroid: source.area_and_centroid(),
                source,
                share: (area / e.area).min(1.0),
                children: 0..0,
            };
            Some((part, power * (1.0 / area), area))
        };
        let mut parts = Vec::new();
        let mut values = Vec::new();
        let mut keys = Vec::new();
        let mut below: Vec<(u32, ElementKey)> = Vec::new();
        let (mut area, mut power) = (0.0, Rgb::ZERO);
        for &k in cut {
            if let Some((p, value, a)) = part(k) {
                area += a;
                power += value * a;
                below.push((parts.len() as u32, k));
                parts.push(p);
                values.push(value);
                keys.push(k);
            }
        }
        let top = parts.len();
        if top < 2 {
            return None;
        }
        // Children after their parents, each node's contiguous.
        let mut next = 0;
        while next < below.len() {
            let (i, k) = below[next];
            next += 1;
            let start = parts.len() as u32;
            for &c in &mesh.elements[k].children {
                if let Some((p, value, _)) = part(c) {
                    below.push((parts.len() as u32, c));
                    parts.push(p);
                    values.push(value);
                    keys.push(c);
                }
            }
            parts[i as usize].children = start..parts.len() as u32;
        }
        Some(PartTree {
            parts,
            values,
            top,
            keys,
            mean: power * (1.0 / area),
        })
    }
}

/// The deepest cut of the quadtrees under `roots` with at most [`MAX_PARTS`]
/// nodes (the leaves when there are few enough), or `None` when even the
/// roots are too many.
fn cut(mesh: &Mesh, roots: &[ElementKey]) -> Option<Vec<ElementKey>> {
    if roots.len() > MAX_PARTS {
        return None;
    }
    let mut parts = roots.to_vec();
    loop {
        let next: Vec<ElementKey> = parts
            .iter()
            .flat_map(|k| {
                let e = &mesh.elements[*k];
                if e.is_leaf() {
                    std::slice::from_ref(k).to_vec()
                } else {
                    e.children.to_vec()
                }
            })
            .collect();
        if next.len() == parts.len() || next.len() > MAX_PARTS {
            return Some(parts);
        }
        parts = next;
    }
}

/// Per band, `mean` times the parts' largest relative departure from it.
fn swing_of(values: &[Rgb], mean: Rgb) -> Rgb {
    let mut swing = Rgb::ZERO;
    for value in values {
        for band in 0..3 {
            swing.0[band] = swing.0[band].max((value[band] - mean[band]).abs());
        }
    }
    swing
}

/// Per band, what patch `p` sends to reflecting surfaces (see [`sent_mean`])
/// over its `mean`; 1 where either is unknown.
fn sent_ratio(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    p: u32,
    reflects: &[bool],
    mean: Rgb,
) -> Rgb {
    let mut ratio = Rgb::ONE;
    if let Some(sent) = sent_mean(mesh, form_factors, radiosity, p, reflects) {
        for band in 0..3 {
            if mean[band] > 0.0 {
                ratio.0[band] = sent[band] / mean[band];
            }
        }
    }
    ratio
}

/// The radiosity of patch `p`'s exposed leaves weighted by what each sends
/// to the front faces of patches that reflect (`reflects`): its area times
/// that part of its row, over its visible share (a partly covered leaf's
/// radiosity is its whole area's mean). `None` when they send nothing.
fn sent_mean(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    p: u32,
    reflects: &[bool],
) -> Option<Rgb> {
    let (mut weight, mut power) = (0.0, Rgb::ZERO);
    for k in mesh.patch_leaves(p) {
        if !form_factors.is_exposed(k) {
            continue;
        }
        let visible = form_factors.view(k).map_or(1.0, |v| v.visible());
        let seen: f64 = form_factors
            .entries(k)
            .iter()
            .filter(|(j, _)| reflects[*j as usize])
            .map(|(_, f)| f64::from(*f))
            .sum();
        let w = mesh.elements[k].area * seen / visible;
        weight += w;
        power += radiosity.element(k) * w;
    }
    (weight > 0.0).then(|| power * (1.0 / weight))
}

/// The exposed area under node `k` and the power per unit of radiosity it
/// sends: sums of `A_e` and `A_e B_e` over its leaves with an exposed row.
/// Hidden leaves (under an object standing on the surface) send nothing,
/// and an interior node's stored mean would count them; a partly covered
/// leaf counts its visible part's area.
fn exposed_power(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    k: ElementKey,
) -> (f64, Rgb) {
    let e = &mesh.elements[k];
    if e.is_leaf() {
        if !form_factors.is_exposed(k) {
            return (0.0, Rgb::ZERO);
        }
        // A leaf that objects standing on it cover in part has the mean
        // radiosity of its whole area, dark where covered; it sends that
        // power from its visible part alone.
        let visible = form_factors.view(k).map_or(1.0, |v| v.visible());
        return (e.area * visible, radiosity.element(k) * e.area);
    }
    e.children
        .iter()
        .map(|c| exposed_power(mesh, form_factors, radiosity, *c))
        .fold((0.0, Rgb::ZERO), |(a, p), (ca, cp)| (a + ca, p + cp))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Scene, SceneBuilder};
    use crate::solution::Solution;
    use crate::Settings;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// A 4 m floor of one patch lit by a lamp over its west end, and a panel
    /// standing on its east half.
    fn scene() -> Scene {
        let mut b = SceneBuilder::new("floor");
        let grey = b.material("grey", Rgb::splat(0.8), Rgb::ZERO).unwrap();
        let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
        b.object("floor");
        b.quad(
            grey,
            v(0., 0., 0.),
            v(0., 0., 4.),
            v(4., 0., 4.),
            v(4., 0., 0.),
        )
        .unwrap();
        b.object("lamp");
        b.quad(
            lamp,
            v(0.5, 2., 1.5),
            v(1.5, 2., 1.5),
            v(1.5, 2., 2.5),
            v(0.5, 2., 2.5),
        )
        .unwrap();
        b.object("panel");
        b.quad(
            grey,
            v(2.5, 0., 1.5),
            v(2.5, 0.6, 1.5),
            v(2.5, 0.6, 2.5),
            v(2.5, 0., 2.5),
        )
        .unwrap();
        b.build().unwrap()
    }

    fn solved() -> Solution {
        solved_scene(&scene())
    }

    fn solved_scene(scene: &Scene) -> Solution {
        let settings = Settings {
            patch_size: Some(4.0),
            shaped_gathers: Some(0),
            ..Settings::default()
        };
        crate::solve(scene, &settings, &|_| {}).unwrap()
    }

    /// The lit floor of [`scene`] without the panel, a small shelf facing
    /// it 0.5 m over its middle, and a blind halfway between them that hides
    /// the floor's west half from the middle of the shelf: a ray from
    /// (x, 0.5, z) to the floor crosses the blind's height at the mean of
    /// the two x.
    fn blinded_scene() -> Scene {
        let mut b = SceneBuilder::new("blinded");
        let grey = b.material("grey", Rgb::splat(0.8), Rgb::ZERO).unwrap();
        let lamp = b.material("lamp", Rgb::ZERO, Rgb::splat(5.0)).unwrap();
        b.object("floor");
        b.quad(
            grey,
            v(0., 0., 0.),
            v(0., 0., 4.),
            v(4., 0., 4.),
            v(4., 0., 0.),
        )
        .unwrap();
        let down = |b: &mut SceneBuilder, m, y: f64, x: [f64; 2], z: [f64; 2]| {
            b.quad(
                m,
                v(x[0], y, z[0]),
                v(x[1], y, z[0]),
                v(x[1], y, z[1]),
                v(x[0], y, z[1]),
            )
            .unwrap();
        };
        b.object("lamp");
        down(&mut b, lamp, 2.0, [0.5, 1.5], [1.5, 2.5]);
        b.object("shelf");
        down(&mut b, grey, 0.5, [1.9, 2.1], [1.9, 2.1]);
        b.object("blind");
        down(&mut b, grey, 0.25, [0.9, 2.0], [0.9, 3.1]);
        b.build().unwrap()
    }

    /// Through the whole solve: with part views the shelf, which the blind
    /// keeps from the floor's west half, gathers more (the test below finds
    /// what it sees of the floor brighter than the mean of every part), the
    /// views are counted, and the energy balance stays as it was.
    #[test]
    fn part_views_brighten_the_blinded_shelf_and_keep_the_balance() {
        let scene = blinded_scene();
        let solve = |part_views: bool| {
            let settings = Settings {
                patch_size: Some(4.0),
                part_views: Some(part_views),
                ..Settings::default()
            };
            crate::solve(&scene, &settings, &|_| {}).unwrap()
        };
        let (plain, viewed) = (solve(false), solve(true));
        assert_eq!(plain.stats.shaped_views, vec![0]);
        assert!(
            viewed.stats.shaped_views[0] >= 1,
            "{:?}",
            viewed.stats.shaped_views
        );
        let shelf = |sol: &Solution| {
            let (mut area, mut power) = (0.0, 0.0);
            for k in sol.mesh.leaves() {
                let e = &sol.mesh.elements[k];
                if (e.centroid.y - 0.5).abs() < 1e-9 && e.centroid.x > 1.8 {
                    area += e.area;
                    power += sol.radiosity.element(k)[0] * e.area;
                }
            }
            power / area
        };
        let (before, after) = (shelf(&plain), shelf(&viewed));
        assert!(after > before * 1.02, "shelf {before} -> {after}");
        let (a, b) = (
            plain.stats.energy.relative_difference,
            viewed.stats.energy.relative_difference,
        );
        assert!((a - b).abs() < 1e-3, "energy balance {a} -> {b}");
    }

    /// A receiver with part of an unevenly lit patch hidden from it weighs
    /// the parts its hemi-cube shows, not all of them: its ratio comes out
    /// near the one weighing only the parts the geometry leaves in sight,
    /// far from the one weighing every part.
    #[test]
    fn a_receiver_weighs_only_the_parts_its_hemicube_shows() {
        let sol = solved_scene(&blinded_scene());
        let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        let floor = floor_patch(&sol);
        let s = shapes.slot[floor as usize];
        assert!(s != u32::MAX, "the floor is uneven");
        let shaped = &shapes.shaped[s as usize];
        let mesh = &sol.mesh;
        // The shelf's leaf nearest its middle.
        let shelf = mesh
            .leaves()
            .into_iter()
            .filter(|&k| {
                let e = &mesh.elements[k];
                (e.centroid.y - 0.5).abs() < 1e-9
                    && mesh.surfaces()[e.surface as usize].normal.y < -0.9
                    && e.centroid.x > 1.8
            })
            .min_by(|&a, &b| {
                let d = |k: ElementKey| (mesh.elements[k].centroid - v(2.0, 0.5, 2.0)).length();
                d(a).total_cmp(&d(b))
            })
            .expect("a shelf leaf");
        let e = &mesh.elements[shelf];
        let entries = sol.form_factors.entries(shelf);
        let i = entries.iter().position(|x| x.0 == floor).unwrap() as u32;
        let (all, _) = shapes.ratio(floor, e.centroid, DVec3::NEG_Y).unwrap();
        // The floor in sight: beyond x = 4 - eye x, where rays pass the
        // blind's east edge at x = 2.
        let cut = 4.0 - e.centroid.x;
        let (mut weight, mut seen) = (0.0, Rgb::ZERO);
        for (p, f) in shaped.weighed_parts(e.centroid, DVec3::NEG_Y) {
            let part = &shaped.parts[p as usize];
            if part.source.centre.x > cut {
                weight += f * part.share;
                seen += shaped.values[p as usize] * (f * part.share);
            }
        }
        let in_sight = shaped.ratio_of(seen, weight).unwrap();
        let sources = crate::formfactor::Sources::from_mesh(mesh);
        let settings = crate::formfactor::RowSettings {
            table: std::sync::Arc::new(crate::formfactor::hemicube::DeltaTable::new(64)),
            seed: 1,
            method: crate::formfactor::FormFactorMethod::Hybrid,
            emitter_sampling: crate::formfactor::EmitterSampling::default(),
            level_of_detail: true,
        };
        let skips = crate::formfactor::RowSkips::default();
        let mut near = Ragged::default();
        near.push_row([NearEntry {
            index: i,
            weight: 1.0,
            parts: 0..0,
            kept: false,
            look: true,
            hidden: 0.5,
        }]);
        let scene = || RowScene::new(mesh, &sources, &settings, &skips);
        let views = PartViews {
            scene: &scene,
            progress: &|_, _| {},
        };
        let mut weights = Vec::new();
        let views = shapes.seen_weights(
            mesh,
            &sol.form_factors,
            &[shelf],
            &near,
            &views,
            |n, m, w| {
                weights.push((n, m, w));
            },
        );
        assert_eq!(views, 1);
        assert_eq!(weights.len(), 1, "the shelf sees part of the floor");
        let by_view = shaped.ratio_from(&weights[0].2).unwrap();
        let (all, in_sight, by_view) = (all[0], in_sight[0], by_view[0]);
        eprintln!("every part {all:.4}, in sight {in_sight:.4}, by the hemi-cube {by_view:.4}");
        assert!(
            (all - in_sight).abs() > 0.1 * in_sight,
            "hiding the west half matters: {all} against {in_sight}"
        );
        assert!(
            (by_view - in_sight).abs() < 0.2 * (all - in_sight).abs(),
            "by its hemi-cube {by_view}, in sight {in_sight}, every part {all}"
        );
    }

    fn floor_patch(sol: &Solution) -> u32 {
        let floor = sol
            .mesh
            .patches
            .iter()
            .position(|p| sol.mesh.surfaces()[p.surface as usize].normal.y > 0.9)
            .unwrap();
        floor as u32
    }

    #[test]
    fn a_receiver_over_the_dark_end_sees_less_than_the_mean_and_one_over_the_lit_end_more() {
        let sol = solved();
        let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        let floor = floor_patch(&sol);
        assert!(
            shapes.slot[floor as usize] != u32::MAX,
            "the floor is uneven"
        );
        let down = DVec3::NEG_Y;
        let dark = shapes.ratio(floor, v(3.9, 0.1, 0.1), down).unwrap().0;
        let lit = shapes.ratio(floor, v(1.0, 0.1, 2.0), down).unwrap().0;
        for band in 0..3 {
            assert!(dark[band] < 0.7, "{dark:?}");
            assert!(lit[band] > 1.2, "{lit:?}");
        }
        // Far away every part weighs by its area: no correction.
        let shaped = &shapes.shaped[shapes.slot[floor as usize] as usize];
        assert_eq!(shaped.nearness(v(2.0, 50.0, 2.0)), 0.0);
        assert_eq!(shaped.nearness(v(3.9, 0.1, 0.1)), 1.0);
        // The floor's back sees none of it.
        assert!(shapes.ratio(floor, v(2.0, -0.1, 2.0), down).is_none());
    }

    #[test]
    fn a_correction_leaves_sure_ratios_alone_while_the_unsure_share_can_take_the_difference() {
        // Three receivers of one patch, weights w, ratios r, unsure shares u.
        let w = [2.0, 1.0, 3.0];
        let r = [Rgb::splat(0.5), Rgb::splat(1.2), Rgb::ONE];
        let u = [0.0, 0.5, 1.0];
        let gathered =
            |c: &Correction| -> f64 { (0..3).map(|i| c.apply(r[i], u[i])[0] * w[i]).sum() };
        let with: f64 = (0..3).map(|i| r[i][0] * w[i]).sum(); // 5.2
        let unsure: f64 = (0..3).map(|i| r[i][0] * w[i] * u[i]).sum(); // 3.6
        for target in [5.6, 4.9] {
            let c = Correction::of(Rgb::splat(target), Rgb::splat(with), Rgb::splat(unsure));
            assert!(
                (gathered(&c) - target).abs() < 1e-12,
                "{target}: {}",
                gathered(&c)
            );
            // The sure receiver keeps its ratio; the far one takes the most.
            assert_eq!(c.apply(r[0], u[0]), r[0]);
            let factor = 1.0 + (target - with) / unsure;
            assert!((c.apply(r[2], u[2])[0] - factor).abs() < 1e-12);
        }
        // A difference the unsure share cannot take within the limit: the
        // rest is spread over every ratio alike, and the total still holds.
        let target = 20.0;
        let c = Correction::of(Rgb::splat(target), Rgb::splat(with), Rgb::splat(unsure));
        assert_eq!(c.unsure[0], UNSURE_LIMIT);
        assert!(c.all[0] > 1.0);
        assert!((gathered(&c) - target).abs() < 1e-9);
        // Nothing unsure: the old scaling, every ratio alike.
        let c = Correction::of(Rgb::splat(6.0), Rgb::splat(with), Rgb::ZERO);
        assert_eq!(c.unsure, Rgb::ONE);
        assert!((c.apply(r[0], 0.0)[0] - 0.5 * 6.0 / with).abs() < 1e-15);
    }

    /// Refreshing a patch's values from another radiosity gives what
    /// building the shapes from that radiosity gives: the parts' values,
    /// the means, the swings and what the patches send, while what the
    /// receivers weigh stays as it was.
    #[test]
    fn a_refresh_takes_the_values_a_new_build_would() {
        let sol = solved();
        let mut shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        assert!(shapes.len() >= 1);
        // Another radiosity: every leaf brighter the farther east it lies.
        let mut other = sol.radiosity.clone();
        for k in sol.mesh.leaves() {
            let x = sol.mesh.elements[k].centroid.x;
            other.set_element(k, sol.radiosity.element(k) * (1.0 + 0.25 * x));
        }
        shapes.refresh(&sol.mesh, &sol.form_factors, &other, false);
        let fresh = SourceShapes::new(&sol.mesh, &sol.form_factors, &other, false);
        // The patches shaped before are compared (the new values may make
        // others uneven too, which a refresh does not add).
        let close = |a: Rgb, b: Rgb| (a - b).abs().max_band() <= 1e-12 * b.max_band().max(1e-300);
        for (p, &s) in shapes.slot.iter().enumerate() {
            if s == u32::MAX {
                continue;
            }
            assert!(fresh.slot[p] != u32::MAX, "patch {p} is still uneven");
            let a = &shapes.shaped[s as usize];
            let b = &fresh.shaped[fresh.slot[p] as usize];
            assert!(
                close(a.mean, b.mean),
                "mean {:?} against {:?}",
                a.mean,
                b.mean
            );
            assert!(
                close(a.swing, b.swing),
                "swing {:?} against {:?}",
                a.swing,
                b.swing
            );
            assert!(
                close(a.sent, b.sent),
                "sent {:?} against {:?}",
                a.sent,
                b.sent
            );
            assert_eq!(a.values.len(), b.values.len());
            for (p, q) in a.values.iter().zip(&b.values) {
                assert!(close(*p, *q), "part {p:?} against {q:?}");
            }
        }
        // The scaling moved the patch's light east: a ratio changed.
        let unchanged = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        let moved = shapes
            .shaped
            .iter()
            .zip(&unchanged.shaped)
            .flat_map(|(a, b)| a.values.iter().zip(&b.values).map(|(p, q)| (*p, *q)))
            .any(|(p, q)| (p[0] / q[0] - 1.0).abs() > 0.01);
        assert!(moved, "the refresh took the new values");
    }

    /// Receivers past the budget weigh their parts again each time: the
    /// factors are the same bits as with every weight kept.
    #[test]
    fn weights_not_kept_give_the_same_factors() {
        let sol = solved();
        let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        let leaves = sol.mesh.leaves();
        let (mesh, ff) = (&sol.mesh, &sol.form_factors);
        let all = shapes
            .near_weights_within(mesh, ff, &leaves, None, usize::MAX)
            .unwrap();
        let none = shapes
            .near_weights_within(mesh, ff, &leaves, None, 0)
            .unwrap();
        let kept = |w: &NearWeights| w.near.rows().flatten().filter(|e| e.kept).count();
        assert!(kept(&all) > 0);
        assert_eq!(kept(&none), 0);
        let a = shapes.factors(mesh, ff, &leaves, |_| 1.0, &all);
        let b = shapes.factors(mesh, ff, &leaves, |_| 1.0, &none);
        assert_eq!(a.near, b.near);
        assert_eq!(a.patch, b.patch);
    }

    #[test]
    fn the_factors_keep_what_the_receivers_gather_from_each_patch() {
        let sol = solved();
        let shapes = SourceShapes::new(&sol.mesh, &sol.form_factors, &sol.radiosity, false);
        assert!(shapes.len() >= 1);
        let leaves = sol.mesh.leaves();
        let factors = shapes
            .entry_factors(&sol.mesh, &sol.form_factors, &leaves, |_| 1.0, None)
            .unwrap();
        let patches = sol.mesh.patches.len();
        let (mut with, mut without) = (vec![Rgb::ZERO; patches], vec![0.0; patches]);
        let mut moved = 0.0f64;
        for (n, &k) in leaves.iter().enumerate() {
            let e = &sol.mesh.elements[k];
            let reflects = e.reflectance.max_band() > 0.0;
            let mut near = factors.near.row(n).iter().peekable();
            for (i, &(j, f)) in sol.form_factors.entries(k).iter().enumerate() {
                let r = factors.factor(&mut near, i, j, reflects);
                if !reflects {
                    // Receivers that reflect nothing (the lamp) gather means.
                    assert_eq!(r, Rgb::ONE);
                    continue;
                }
                let w = e.area * f64::from(f);
                with[j as usize] += r * w;
                without[j as usize] += w;
                moved = moved.max((r[0] - 1.0).abs());
            }
        }
        assert!(moved > 0.1, "the factors change something: {moved}");
        // Each patch's receivers gather its mean times its `sent` ratio; an
        // even patch's gather is unchanged.
        for j in 0..patches {
            let sent = match shapes.slot[j] {
                u32::MAX => Rgb::ONE,
                s => shapes.shaped[s as usize].sent,
            };
            for band in 0..3 {
                let (a, b) = (with[j][band], without[j] * sent[band]);
                assert!(
                    (a - b).abs() <= 1e-12 * b.max(1e-300),
                    "patch {j}: {a} vs {b}"
                );
            }
        }
    }
}
