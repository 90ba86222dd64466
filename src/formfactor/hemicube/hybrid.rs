//! The hybrid form-factor policy: the item buffer decides what is seen, and
//! Lambert's exact formula how much.

use super::{Hemicube, BACK_FACE, NOTHING};
use crate::formfactor::visibility::crosses;
use crate::formfactor::{point_to_polygon, EmitterVisibility, Row, Sources};
use glam::DVec3;

impl Hemicube {
    /// Replaces each won pixel sum by the exact unoccluded form factor times the
    /// fraction of the patch's covered pixels it won.
    ///
    /// A patch whose projection falls between pixel centres covers no pixel and
    /// would get no form factor at all; in a closed scene those losses add up
    /// (row sums 1 - 2e-3 next to a wall, a furnace 2% dark at rho = 0.999). Its
    /// visibility is instead sampled along the ray to its centroid, against what
    /// won the pixel that ray falls in: it gets its exact form factor unless that
    /// is nearer.
    ///
    /// The row then keeps the front faces' share of the view that the pixels
    /// give (`front`, the delta form factors of every pixel a front face won).
    /// Exact magnitudes times pixel fractions do not add up to it: behind a
    /// small occluder, the part of the patches it hides is its outline in
    /// pixels, about 10% off at 6 pixels across, while the occluder itself
    /// gets its exact form factor, so rows lost 1e-4 on average and up to 1e-3
    /// in a closed room with a lamp under the ceiling (1% of the light at
    /// rho = 0.99). Only the partly hidden patches are approximate, so they
    /// take up the difference (see [`close_row`]); patches seen whole and
    /// emitters, whose visible form factor is exact, keep theirs.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn hybrid(
        &mut self,
        row: Row,
        front: f64,
        open: f64,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        own_surface: u32,
        emitter_rays: Option<EmitterVisibility<'_>>,
    ) -> Row {
        // (patch, form factor, partly hidden)
        let mut entries: Vec<(u32, f64, bool)> = row
            .entries()
            .iter()
            .map(|&(id, won)| {
                let exact = sources.exact_form_factor(id, eye, normal);
                let covered = self.covered[id as usize];
                let won = f64::from(won);
                let visible = if covered > 0.0 {
                    (won / covered).min(1.0)
                } else {
                    0.0
                };
                (id, exact * visible, won < covered * (1.0 - 1e-6))
            })
            .collect();
        let subpixel = std::mem::take(&mut self.subpixel);
        let before = entries.len();
        for &(q, centroid, world) in &subpixel {
            let poly = &sources.polygons[q as usize];
            // A cluster with pixels of its own has its entry from them.
            if self.covered[poly.patch as usize] > 0.0 {
                continue;
            }
            if self.sample_visible(sources, q, eye, centroid, world) {
                let exact = point_to_polygon(eye, normal, poly.corners());
                entries.push((poly.patch, exact, false));
            }
        }
        self.subpixel = subpixel; // keeps its capacity; cleared per row
        let minor = std::mem::take(&mut self.minor);
        for m in &minor {
            if self.covered[m.patch as usize] == 0.0 && self.minor_visible(m) {
                entries.push((m.patch, m.form_factor, false));
            }
        }
        self.minor = minor;

        if entries.len() > before {
            entries.sort_unstable_by_key(|e| e.0);
            // Sub-pixel polygons of one cluster add up.
            entries.dedup_by(|b, a| {
                let same = a.0 == b.0;
                if same {
                    a.1 += b.1;
                }
                same
            });
        }
        if let Some(visibility) = emitter_rays {
            self.emitter_entries(
                &row,
                &mut entries,
                sources,
                eye,
                normal,
                own_surface,
                &visibility,
            );
        }
        if open <= OPEN_CLOSURE {
            close_row(&mut entries, front);
        }
        let sum: f64 = entries.iter().map(|e| e.1).sum();
        if sum > 1.0 {
            for e in &mut entries {
                e.1 /= sum;
            }
        }
        Row::from_sorted(entries.into_iter().map(|(i, f, _)| (i, f as f32)).collect())
    }

    /// Whether the patch part `m` under a sample is in view: unless what
    /// its pixel holds lies nearer than it by more than the sample's reach.
    /// Within the reach, what is in front is not known (the sample's own
    /// patches are not drawn apart): it counts as seen, as scan conversion
    /// would show part of it.
    fn minor_visible(&self, m: &super::cull::Minor) -> bool {
        let Some((fi, face, px)) = self.pixel_of(m.local) else {
            return false;
        };
        if self.items[fi][px] == NOTHING {
            return true;
        }
        let z = face.map(m.local).z;
        let stored = f64::from(self.depth[fi][px]);
        1.0 / (z - m.reach).max(z * 1e-3) >= stored
    }

    /// Whether the polygon `id`, whose centroid is `local` in the hemi-cube's
    /// frame and `world` in the scene, is visible from `eye` along the ray to
    /// its centroid: true if the pixel that ray falls in holds nothing, a patch of
    /// the same (planar) surface, or a patch (or face cluster) none of whose
    /// polygons the ray passes through between the eye and the centroid. A
    /// back face, whose polygon is not kept, is compared by the depth stored at
    /// the pixel centre.
    fn sample_visible(
        &self,
        sources: &Sources,
        id: u32,
        eye: DVec3,
        local: DVec3,
        world: DVec3,
    ) -> bool {
        let Some((fi, face, px)) = self.pixel_of(local) else {
            return false; // behind the eye or below the horizon
        };
        let p = face.map(local);
        let n = self.table.n;
        let winner = self.items[fi][px];
        if winner == NOTHING {
            return true;
        }
        if winner == BACK_FACE {
            // A back face, whose plane is not kept: by depth. The stored
            // value carries up to a span of single-precision steps.
            let stored = f64::from(self.depth[fi][px]);
            return 1.0 / p.z >= stored * (1.0 - 4.0 * n as f64 * f64::from(f32::EPSILON));
        }
        let polygon = &sources.polygons[id as usize];
        let won = sources.patch(winner);
        if won.iter().any(|w| w.surface == polygon.surface) {
            return true;
        }
        // Hidden only if the ray itself passes through a polygon of the
        // winner before the centroid. The winner's plane alone is not
        // enough: on a tessellated convex mesh every facet's centroid lies
        // behind its front-facing neighbours' planes, and a sub-pixel facet
        // whose pixel centre a neighbour won would be lost (a sphere of
        // pixel-sized facets seen from 2 m kept 45% of its form factor).
        let (along, length) = ((world - eye).normalize_or_zero(), (world - eye).length());
        !won.iter()
            .any(|w| crosses(w.corners(), w.normal, eye, along, length))
    }
}

/// The largest change [`close_row`] makes to the partly hidden entries of a
/// row, as a factor either way. Larger corrections come from the pixel
/// outlines of open sky or back faces, not from the hidden parts themselves.
const MAX_CLOSURE: f64 = 1.5;

/// Rows are closed (see [`close_row`]) only where at most this form factor
/// of the view is open sky: a few pixels' worth, as cracks between polygons
/// leave. Where the sky fills more, the aliasing of its outline would move
/// the partly hidden entries by more than it corrects them.
const OPEN_CLOSURE: f64 = 1e-3;

/// Scales the partly hidden entries of a hybrid row (`(patch, form factor,
/// partly hidden)`) so that the row sums to `front`, the front faces' share of
/// the view in pixels, within a factor of [`MAX_CLOSURE`] either way.
///
/// In a closed scene with no back face in view the pixels' share is exactly
/// 1: every pixel is won by some front face, and the delta form factors sum
/// to 1. The entries of patches seen whole are exact, so the partly hidden
/// ones together must make up the rest; what the pixel fractions gave them
/// is only an estimate of how much is hidden. Elsewhere the pixels' share
/// carries the aliasing of the outlines of back faces and open sky, which
/// the partly hidden entries then take on (a few per cent of their value).
fn close_row(entries: &mut [(u32, f64, bool)], front: f64) {
    let (mut partial, mut whole) = (0.0, 0.0);
    for e in entries.iter() {
        if e.2 {
            partial += e.1;
        } else {
            whole += e.1;
        }
    }
    if partial <= 0.0 {
        return;
    }
    let scale = ((front - whole) / partial).clamp(1.0 / MAX_CLOSURE, MAX_CLOSURE);
    for e in entries.iter_mut().filter(|e| e.2) {
        e.1 *= scale;
    }
}
