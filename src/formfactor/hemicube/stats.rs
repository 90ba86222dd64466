//! Counters of the work a hemi-cube buffer has done.

/// Counters of the work one hemi-cube buffer has done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HemicubeStats {
    /// Hemi-cubes rendered.
    pub hemicubes: u64,
    /// Polygon-face pairs projected and scan converted.
    pub polygons_rasterized: u64,
    /// Pixels written (depth test passed or not).
    pub pixels_tested: u64,
    /// Faces nothing was drawn into, which were neither read out nor cleared.
    pub empty_faces: u64,
    /// Pixels outside the rectangle drawn into on their face (empty faces
    /// included), which were neither read out nor cleared.
    pub pixels_skipped: u64,
    /// Source polygons dropped before projection: on the receiver's own
    /// surface, wholly behind or on its plane, or seen edge-on.
    pub polygons_culled: u64,
    /// Source polygons under BVH nodes that the depth buffer already hid
    /// wholly (see `occlusion.rs`), never drawn.
    pub polygons_hidden: u64,
    /// Back faces not drawn because front faces of their own closed object
    /// hide them (see `crate::formfactor::ClosedObjects`).
    pub back_faces_skipped: u64,
    /// Rows given by the exact unoccluded form factor with no hemi-cube at all
    /// (a convex enclosure; see `crate::formfactor::is_convex_enclosure`).
    pub exact_rows: u64,
    /// Emitter polygons whose visibility was found exactly: by clipping the
    /// shaft, else by shadow rays (summed over rows).
    pub emitters_exact: u64,
    /// Emitter polygons seen as less than a pixel by a row that sees many,
    /// given one shadow ray each (see `emitters.rs`).
    pub emitters_one_ray: u64,
    /// Emitter polygons of patches the pixels saw whole or hidden, in a row
    /// that sees many, taken as the pixels saw them (see `emitters.rs`).
    pub emitters_by_pixels: u64,
}

impl HemicubeStats {
    /// Every counter, in declaration order, for element-wise arithmetic.
    fn counters(&mut self) -> [&mut u64; 12] {
        [
            &mut self.hemicubes,
            &mut self.polygons_rasterized,
            &mut self.pixels_tested,
            &mut self.empty_faces,
            &mut self.pixels_skipped,
            &mut self.polygons_culled,
            &mut self.polygons_hidden,
            &mut self.back_faces_skipped,
            &mut self.exact_rows,
            &mut self.emitters_exact,
            &mut self.emitters_one_ray,
            &mut self.emitters_by_pixels,
        ]
    }
}

impl std::ops::AddAssign for HemicubeStats {
    fn add_assign(&mut self, mut other: HemicubeStats) {
        for (a, b) in self.counters().into_iter().zip(other.counters()) {
            *a += *b;
        }
    }
}

impl std::ops::Sub for HemicubeStats {
    type Output = HemicubeStats;

    /// The counters gained since `before` (an earlier copy of these).
    fn sub(mut self, mut before: HemicubeStats) -> HemicubeStats {
        for (a, b) in self.counters().into_iter().zip(before.counters()) {
            *a -= *b;
        }
        self
    }
}
