//! Rows out of the item buffer: the entry points that render it and sum the
//! delta form factors each patch won.

use super::{Cull, Drawn, Hemicube, BACK_FACE};
use crate::formfactor::{EmitterVisibility, FormFactorMethod, Row, Sources};
use glam::DVec3;
use std::sync::Arc;

/// Everything one row needs: what [`Hemicube::row`] takes, and what the
/// pipeline adds.
#[derive(Clone, Copy)]
pub(crate) struct RowRequest<'a> {
    /// The patches' polygons.
    pub(crate) sources: &'a Sources,
    /// Per surface of the sources, whether its back face is not drawn: back
    /// faces that front faces of their own object hide from `eye`, as
    /// `crate::formfactor::ClosedObjects::hidden_from` finds them. The row
    /// is then the same but where a back face would have won a silhouette
    /// pixel from the front face at equal depth.
    pub(crate) hidden_back: Option<&'a [bool]>,
    /// The receiving point.
    pub(crate) eye: DVec3,
    /// The receiver's unit normal.
    pub(crate) normal: DVec3,
    /// The rotation of the faces about the normal.
    pub(crate) angle: f64,
    /// The receiver's own surface, which it cannot see.
    pub(crate) own_surface: u32,
    /// How pixels become form factors.
    pub(crate) method: FormFactorMethod,
    /// With the occluders and a seed, the hybrid method finds the visibility
    /// of emitters that the item buffer saw only in part from the occluders
    /// themselves.
    pub(crate) emitter_rays: Option<EmitterVisibility<'a>>,
    /// How to find what to draw (see `cull.rs`); `None` draws every polygon.
    pub(crate) cull: Option<Cull<'a>>,
    /// Surfaces nearer than this along a face's axis count as near (see
    /// [`Row::near`]); 0 measures nothing.
    pub(crate) reach: f64,
}

impl Hemicube {
    /// The form factors from a differential area at `eye` with unit `normal` to
    /// every patch of `sources`, skipping patches on `own_surface` (a planar
    /// surface cannot see itself). `angle` rotates the hemi-cube about the normal,
    /// which decorrelates the aliasing of neighbouring receivers. `method` says
    /// how pixels become form factors. Emitters are treated as every other
    /// patch: their visibility is the item buffer's.
    pub fn row(
        &mut self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
        method: FormFactorMethod,
    ) -> Row {
        self.row_for(&RowRequest {
            sources,
            hidden_back: None,
            eye,
            normal,
            angle,
            own_surface,
            method,
            emitter_rays: None,
            cull: None,
            reach: 0.0,
        })
    }

    /// The row `request` asks for (see [`RowRequest`]).
    pub(crate) fn row_for(&mut self, request: &RowRequest<'_>) -> Row {
        let &RowRequest {
            sources,
            hidden_back,
            eye,
            normal,
            angle,
            own_surface,
            method,
            emitter_rays,
            cull,
            reach,
        } = request;
        let hybrid = method == FormFactorMethod::Hybrid;
        self.render::<true>(
            sources,
            hidden_back,
            eye,
            normal,
            angle,
            own_surface,
            hybrid,
            cull.as_ref(),
            &[],
        );
        let (mut row, front, back, near) = self.accumulate(reach);
        // The delta form factors sum to exactly 1, so what neither a front
        // nor a back face won is open sky.
        let open = (1.0 - front - back).max(0.0);
        if hybrid {
            row = self.hybrid(
                row,
                front,
                open,
                sources,
                eye,
                normal,
                own_surface,
                emitter_rays,
            );
        }
        for id in self.covered_touched.drain(..) {
            self.covered[id as usize] = 0.0;
            self.covered_pixels[id as usize] = 0;
        }
        row.with_hidden(back, open).with_near(near)
    }

    /// Benchmark hook, not for use: renders the item buffer as
    /// [`Hemicube::row`] does with the classic method, but with `FILL` false
    /// stops each polygon after it is transformed, culled, clipped and
    /// projected and its rows found (no edge walk, no pixel), so that a bench
    /// can time the stages apart.
    #[doc(hidden)]
    pub fn render_stage<const FILL: bool>(
        &mut self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
    ) {
        self.render::<FILL>(
            sources,
            None,
            eye,
            normal,
            angle,
            own_surface,
            false,
            None,
            &[],
        );
        for id in self.covered_touched.drain(..) {
            self.covered[id as usize] = 0.0;
            self.covered_pixels[id as usize] = 0;
        }
    }

    /// Sums delta form factors per patch and returns the sparse row, with
    /// the delta form factors of all the pixels front faces won, of those
    /// back faces won, and of those either won nearer than `reach`.
    pub(super) fn accumulate(&mut self, reach: f64) -> (Row, f64, f64, f64) {
        let (back, near) = self.sum_won(reach);
        self.touched.sort_unstable();
        let mut front = 0.0;
        let entries = self
            .touched
            .iter()
            .map(|&id| {
                let v = std::mem::take(&mut self.accumulator[id as usize]);
                front += v;
                (id, v as f32)
            })
            .collect();
        self.touched.clear();
        (Row::from_sorted(entries), front, back, near)
    }

    /// Adds the delta form factor of every won pixel to its polygon's slot of
    /// the accumulator, listing the slots touched. Returns the delta form
    /// factors of the pixels won by back faces, and of the pixels whose
    /// surface (front or back) lies nearer than `reach` along the face's
    /// axis (none when `reach` is 0).
    ///
    /// When skipping, only each face's drawn rectangle is read: the pixels
    /// outside it hold nothing, and the ones inside are visited in the same
    /// order as a whole-face pass, so every sum is the same bits.
    pub(super) fn sum_won(&mut self, reach: f64) -> (f64, f64) {
        let table = Arc::clone(&self.table);
        let n = table.n;
        let mut back = 0.0;
        let mut near = 0.0;
        // The depth buffers hold 1/depth, 0 where nothing was drawn.
        let least_inverse = if reach > 0.0 {
            (1.0 / reach) as f32
        } else {
            f32::INFINITY
        };
        // The slots touched are listed in a buffer with room for every
        // slot (a slot is listed when its first pixel is added, and every
        // delta form factor is positive, so at most once), kept between
        // hemi-cubes so that it is not filled anew each time: a push that
        // may grow the list is a call, and a call in this loop made the
        // compiler keep the running sums in memory, each pixel waiting for
        // the store of the one before.
        if self.listing.len() < self.accumulator.len() {
            self.listing.resize(self.accumulator.len(), 0);
        }
        let mut count = 0;
        for f in 0..5 {
            let weights = if f == 0 { &table.top } else { &table.side };
            let height = if f == 0 { n } else { n / 2 };
            let d = if self.skip_empty {
                let d = self.drawn[f];
                self.stats.empty_faces += u64::from(d.is_empty());
                self.stats.pixels_skipped += (n * height - d.pixels()) as u64;
                d
            } else {
                Drawn {
                    j0: 0,
                    j1: height,
                    i0: 0,
                    i1: n,
                }
            };
            if d.is_empty() {
                continue;
            }
            for j in d.j0..d.j1 {
                let span = j * n + d.i0..j * n + d.i1;
                // A face where nothing drawn lies nearer than `reach` (every
                // face when `reach` is 0) adds nothing to `near`: its depths
                // are not read.
                if self.nearest[f] > least_inverse {
                    for (&z, &w) in self.depth[f][span.clone()]
                        .iter()
                        .zip(&weights[span.clone()])
                    {
                        if z > least_inverse {
                            near += w;
                        }
                    }
                }
                for (&id, &w) in self.items[f][span.clone()].iter().zip(&weights[span]) {
                    if id < BACK_FACE {
                        let slot = &mut self.accumulator[id as usize];
                        if *slot == 0.0 {
                            if let Some(free) = self.listing.get_mut(count) {
                                *free = id;
                                count += 1;
                            }
                        }
                        *slot += w;
                    } else if id == BACK_FACE {
                        back += w;
                    }
                }
            }
        }
        self.touched.extend_from_slice(&self.listing[..count]);
        (back, near)
    }
}

#[cfg(test)]
mod tests {
    use super::super::DeltaTable;
    use super::*;
    use crate::formfactor::{point_to_polygon, SourcePolygon};

    /// The square of half-side `half` at `height` above the origin, facing
    /// down, with its edges along the axes of a hemi-cube on the normal +y
    /// at angle 0.
    fn ceiling(height: f64, half: f64) -> Vec<DVec3> {
        let up = DVec3::Y;
        let t = up.any_orthonormal_vector();
        let b = up.cross(t);
        let c = up * height;
        vec![
            c - t * half - b * half,
            c - t * half + b * half,
            c + t * half + b * half,
            c + t * half - b * half,
        ]
    }

    /// Under a wide ceiling at height h, a hemi-cube's top face sees it at
    /// depth h and each side face at depth equal to the point's offset along
    /// that face's axis; so what lies nearer than a reach r > h is the
    /// coaxial square of half-side r, and its share is that square's exact
    /// form factor. Nearer than h nothing is near.
    #[test]
    fn near_is_the_form_factor_of_what_lies_within_reach() {
        let height = 0.5;
        let wide = ceiling(height, 8.0);
        let sources = Sources::one_per_patch(vec![SourcePolygon::new(&wide, -DVec3::Y, 1)]);
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(256)), 1);
        let near = |cube: &mut Hemicube, reach: f64| {
            cube.row_for(&RowRequest {
                sources: &sources,
                hidden_back: None,
                eye: DVec3::ZERO,
                normal: DVec3::Y,
                angle: 0.0,
                own_surface: 0,
                method: FormFactorMethod::Hemicube,
                emitter_rays: None,
                cull: None,
                reach,
            })
            .near()
        };
        assert_eq!(near(&mut cube, 0.0), 0.0, "no reach, nothing measured");
        assert_eq!(near(&mut cube, 0.45), 0.0, "all of it is farther");
        for reach in [0.75, 1.0, 2.0] {
            let exact = point_to_polygon(DVec3::ZERO, DVec3::Y, &ceiling(height, reach));
            let found = near(&mut cube, reach);
            assert!(
                (found - exact).abs() < 0.01 * exact,
                "reach {reach}: {found} against {exact}"
            );
        }
    }
}
