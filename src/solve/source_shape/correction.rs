//! How a shaped patch's factors are brought to what its receivers must
//! gather from it together.

use crate::math::Rgb;

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
///
/// [`SourceShapes::entry_factors`]: super::SourceShapes::entry_factors
#[derive(Clone, Copy, Debug)]
pub(super) struct Correction {
    /// Per band, the factor on the unsure share of a ratio.
    pub(super) unsure: Rgb,
    /// Per band, the factor on every ratio after that.
    pub(super) all: Rgb,
}

/// The factor on the unsure share of the ratios stays within
/// `1 / UNSURE_LIMIT` and `UNSURE_LIMIT`.
pub(crate) const UNSURE_LIMIT: f64 = 2.0;

impl Correction {
    /// The correction that brings `with` (what the ratios gather, per band)
    /// to `target`, `unsure` being the unsure part of `with`.
    pub(super) fn of(target: Rgb, with: Rgb, unsure: Rgb) -> Self {
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
    pub(super) fn apply(&self, r: Rgb, u: f64) -> Rgb {
        let mut out = r;
        for band in 0..3 {
            out.0[band] *= (1.0 + (self.unsure[band] - 1.0) * u) * self.all[band];
        }
        out
    }
}
