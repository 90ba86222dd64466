//! What a receiver sees of a few patches, part by part.
//!
//! A row holds one form factor per patch. Where a patch is lit unevenly, a
//! receiver near it needs to know which of its parts it sees: an occluder
//! between them may hide the bright half and leave the dark one (see
//! `crate::solve::source_shape`). The item buffer knows: drawn with those
//! patches' parts in place of their polygons, each pixel names the part it
//! shows. The parts tile their patch, so everything else in the picture,
//! and the depth test, is as in the row.

use super::{Hemicube, RowRequest, BACK_FACE};
use crate::formfactor::SourcePolygon;

/// A patch to draw part by part.
#[derive(Clone, Debug)]
pub(crate) struct PartSources<'a> {
    /// The patch whose polygons the parts replace.
    pub(crate) patch: u32,
    /// Its parts: polygons that tile what the patch shows.
    pub(crate) parts: Vec<&'a SourcePolygon>,
}

impl Hemicube {
    /// The hemi-cube of `request` drawn with the patches of `wanted` part by
    /// part: per part, in the order of `wanted` and of its parts, the delta
    /// form factors of the pixels its front face won and of all those it
    /// covered, won or not. `request`'s method and reach do not matter;
    /// parts that cover no pixel centre win nothing.
    pub(crate) fn part_view(
        &mut self,
        request: &RowRequest<'_>,
        wanted: &[PartSources<'_>],
    ) -> Vec<(f64, f64)> {
        self.render::<true>(
            request.sources,
            request.hidden_back,
            request.eye,
            request.normal,
            request.angle,
            request.own_surface,
            false,
            request.cull.as_ref(),
            wanted,
        );
        self.sum_won(0.0);
        let first = request.sources.patch_count();
        let mut shown = vec![(0.0, 0.0); wanted.iter().map(|w| w.parts.len()).sum()];
        for id in self.touched.drain(..) {
            let v = std::mem::take(&mut self.accumulator[id as usize]);
            if (id as usize) >= first && id < BACK_FACE {
                shown[id as usize - first].0 = v;
            }
        }
        for id in self.covered_touched.drain(..) {
            let v = std::mem::take(&mut self.covered[id as usize]);
            self.covered_pixels[id as usize] = 0;
            if (id as usize) >= first && id < BACK_FACE {
                shown[id as usize - first].1 = v;
            }
        }
        shown
    }
}

#[cfg(test)]
mod tests {
    use super::super::DeltaTable;
    use super::*;
    use crate::formfactor::{point_to_polygon, FormFactorMethod, Sources};
    use glam::DVec3;
    use std::sync::Arc;

    fn quad(corners: [[f64; 3]; 4]) -> Vec<DVec3> {
        corners.iter().map(|c| DVec3::from_array(*c)).collect()
    }

    /// A ceiling of two halves over a receiver, and a blind halfway up under
    /// the west half: the receiver sees only the east half, and each half's
    /// won share is its exact form factor when nothing hides it.
    #[test]
    fn each_part_wins_what_the_receiver_sees_of_it() {
        let down = -DVec3::Y;
        let ceiling = quad([[-2., 1., -2.], [-2., 1., 2.], [2., 1., 2.], [2., 1., -2.]]);
        let west = quad([[-2., 1., -2.], [-2., 1., 2.], [0., 1., 2.], [0., 1., -2.]]);
        let east = quad([[0., 1., -2.], [0., 1., 2.], [2., 1., 2.], [2., 1., -2.]]);
        let blind = quad([
            [-2., 0.5, -2.],
            [-2., 0.5, 2.],
            [0., 0.5, 2.],
            [0., 0.5, -2.],
        ]);
        let parts = [
            SourcePolygon::new(&west, down, 1),
            SourcePolygon::new(&east, down, 1),
        ];
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(256)), 2);
        let view = |cube: &mut Hemicube, with_blind: bool| {
            let mut polygons = vec![SourcePolygon::new(&ceiling, down, 1)];
            if with_blind {
                polygons.push(SourcePolygon::new(&blind, down, 2));
            }
            let sources = Sources::one_per_patch(polygons);
            let request = RowRequest {
                sources: &sources,
                hidden_back: None,
                eye: DVec3::ZERO,
                normal: DVec3::Y,
                angle: 0.3,
                own_surface: 0,
                method: FormFactorMethod::Hemicube,
                emitter_rays: None,
                cull: None,
                reach: 0.0,
            };
            let shown = cube.part_view(
                &request,
                &[PartSources {
                    patch: 0,
                    parts: parts.iter().collect(),
                }],
            );
            for (won, covered) in &shown {
                // Summed pixel by pixel and by prefix sums: equal but for
                // rounding.
                assert!(
                    *won <= covered * (1.0 + 1e-9),
                    "a part wins at most what it covers: {won} of {covered}"
                );
            }
            shown.iter().map(|x| x.0).collect::<Vec<f64>>()
        };
        let open = view(&mut cube, false);
        for (won, part) in open.iter().zip([&west, &east]) {
            let exact = point_to_polygon(DVec3::ZERO, DVec3::Y, part);
            assert!((won - exact).abs() < 0.01 * exact, "{won} against {exact}");
        }
        let blinded = view(&mut cube, true);
        assert!(
            blinded[0] < 0.01 * open[0],
            "the blind hides the west half: {} of {}",
            blinded[0],
            open[0]
        );
        assert!(
            (blinded[1] - open[1]).abs() < 0.01 * open[1],
            "the east half is seen whole: {} against {}",
            blinded[1],
            open[1]
        );
    }
}
