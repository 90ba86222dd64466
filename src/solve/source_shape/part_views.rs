//! Hemi-cubes drawn again with a shaped patch part by part, for receivers
//! whose rows see too little of the parts for their unoccluded weights.

use super::near_weights::NearEntry;
use super::{Shaped, SourceShapes};
use crate::formfactor::{FormFactors, PartSources, RowScene};
use crate::mesh::{ElementKey, Mesh};
use crate::solve::ragged::Ragged;
use smallvec::SmallVec;

/// How a shaped gather draws the hemi-cubes of receivers that look at a
/// patch part by part (see [`SEEN_SHARE`]).
pub(crate) struct PartViews<'a, 's> {
    /// Builds the scene they are drawn in (only when one is needed).
    pub scene: &'a dyn Fn() -> RowScene<'s>,
    /// Called with the views drawn so far and their number.
    pub progress: &'a (dyn Fn(usize, usize) + Sync),
}

/// Parts of a shaped patch (indices into [`Shaped::parts`]) with weights,
/// in single precision: a receiver near many patches holds thousands.
type PartWeights = Vec<(u32, f32)>;

/// A leaf's part views: per entry drawn, (leaf, index in its near entries,
/// the parts' weights by what it sees, or `None` where no pixel shows one).
type LeafViews = SmallVec<[(usize, usize, Option<PartWeights>); 2]>;

/// Part views are drawn this many receivers at a time, and their weights
/// handed over before the next batch is drawn.
const VIEW_BATCH: usize = 8192;

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

impl SourceShapes {
    /// For the near entries of `near` (per leaf of `leaves`) whose rows see
    /// too little of the parts, the parts' weights by what the leaf sees:
    /// each part's unoccluded form factor times the share of its pixels that
    /// the leaf's hemi-cube, drawn with the patch part by part (see
    /// [`RowScene::with_part_views`]), shows, each handed to `take` as
    /// (leaf, index in its near entries, weights), in leaf order (none where
    /// no pixel shows a part). Returns the number of hemi-cubes drawn.
    pub(super) fn seen_weights<'s>(
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
