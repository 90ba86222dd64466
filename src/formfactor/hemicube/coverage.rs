//! What a shooter's item buffer of leaves needs: for every polygon, the
//! pixels it won and the pixels it covered.

use super::Hemicube;
use crate::formfactor::Sources;
use glam::DVec3;

/// What a hemi-cube saw of one source polygon (see [`Hemicube::coverage`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coverage {
    /// The polygon's index in its [`Sources`].
    pub(crate) id: u32,
    /// Delta form factors of the pixels it won the depth test for: its
    /// classic hemi-cube form factor.
    pub(crate) won: f64,
    /// Delta form factors of every pixel its front face covered, won or not.
    pub(crate) covered: f64,
    /// Number of pixels its front face covered.
    pub(crate) pixels: u32,
}

/// What a hemi-cube saw from one eye (see [`Hemicube::coverage`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ItemCoverage {
    /// Every source polygon whose front face covered a pixel, by increasing id.
    pub(crate) polygons: Vec<Coverage>,
    /// The form factor of the back faces won (0 to 1): near 1 when the eye is
    /// shut inside a closed object, such as a point of the floor under a box.
    pub(crate) back_faces: f64,
}

impl Hemicube {
    /// Renders the item buffer like [`Hemicube::row`] and reports, for every
    /// polygon of `sources` whose front face covers at least one pixel centre,
    /// what it won and what it covered, in increasing id order, and how much of
    /// the view back faces fill. The sources may be any polygons with any ids
    /// (patches, or leaf elements for a shooting patch's item buffer); what to
    /// make of the pixels is the caller's choice.
    /// `hidden_back` marks surfaces whose back faces are not drawn (see
    /// [`Hemicube::render`]).
    pub(crate) fn coverage(
        &mut self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
        hidden_back: Option<&[bool]>,
    ) -> ItemCoverage {
        self.render::<true>(
            sources,
            hidden_back,
            eye,
            normal,
            angle,
            own_surface,
            false,
            None,
            &[],
        );
        let (back_faces, _) = self.sum_won(0.0);
        self.covered_touched.sort_unstable();
        let polygons = self
            .covered_touched
            .iter()
            .map(|&id| {
                let i = id as usize;
                Coverage {
                    id,
                    won: std::mem::take(&mut self.accumulator[i]),
                    covered: std::mem::take(&mut self.covered[i]),
                    pixels: std::mem::take(&mut self.covered_pixels[i]),
                }
            })
            .collect();
        for id in self.touched.drain(..) {
            self.accumulator[id as usize] = 0.0;
        }
        self.covered_touched.clear();
        ItemCoverage {
            polygons,
            back_faces,
        }
    }
}
