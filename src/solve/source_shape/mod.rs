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
//!
//! [`OPEN`]: part_weights::OPEN
//! [`SEEN_SHARE`]: part_views::SEEN_SHARE
//! [`VIEW_SHARE`]: part_views::VIEW_SHARE
//! [`Correction`]: correction::Correction
//! [`SKIPPED_SHARE`]: near_weights::SKIPPED_SHARE

mod correction;
mod entry_factors;
mod near_weights;
mod part_tree;
mod part_views;
mod part_weights;
#[cfg(test)]
mod tests;

use super::Radiosity;
use crate::formfactor::{FormFactors, SourcePolygon};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;
use part_tree::{cut, exposed_power, PartTree};
use rayon::prelude::*;

pub(crate) use entry_factors::EntryFactors;
pub(crate) use near_weights::NearWeights;
pub(crate) use part_views::PartViews;

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

/// A patch counts as unevenly lit when, in some band, its parts' radiosities
/// spread (largest minus smallest) by more than this fraction of their mean.
/// A patch just under it changes what any receiver gathers by less than
/// this fraction, so its being left out makes no step in the solution.
pub(crate) const SPREAD: f64 = 1e-5;

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

impl Shaped {
    /// How much of its ratio a receiver at `eye` takes: 1 within
    /// [`FULLY_NEAR`] bounding radii of the centre, 0 beyond [`NEAR`], and
    /// linear between.
    fn nearness(&self, eye: DVec3) -> f64 {
        let d = (eye - self.centre).length();
        ((self.reach - d) / (self.reach - self.full)).clamp(0.0, 1.0)
    }
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
