//! The hemi-cube of Cohen & Greenberg (1985): five faces of a unit half-cube around
//! a receiving point, an item buffer of patch ids with a depth test, and a table of
//! delta form factors that turns covered pixels into form factors.
//!
//! One concept a file: the buffers and their read-out ([`Hemicube::row`],
//! `row.rs`), scan conversion (`raster.rs`), the hybrid form-factor policy
//! (`hybrid.rs`) and its emitter entries (`emitters.rs`), what a shooter's
//! item buffer needs (`coverage.rs`), what a receiver sees of a patch part
//! by part (`parts.rs`), the rectangles drawn into (`drawn.rs`), the
//! polygons found to draw, in id order (`id_set.rs`), and the work counters
//! (`stats.rs`).

mod coverage;
mod cull;
mod drawn;
mod emitters;
mod faces;
mod hybrid;
mod id_set;
mod occlusion;
mod parts;
mod raster;
mod row;
mod stats;
mod table;

pub(crate) use coverage::Coverage;
pub(crate) use cull::Cull;
pub(crate) use emitters::emitter_form_factors;
pub(crate) use parts::PartSources;
pub(crate) use row::RowRequest;
pub use stats::HemicubeStats;
pub use table::DeltaTable;

use drawn::Drawn;
use glam::DVec3;
use std::sync::Arc;

/// An empty pixel.
const NOTHING: u32 = u32::MAX;
/// The back of a single-sided surface: it hides what lies behind it but neither
/// emits nor reflects, so its pixels count for no patch.
const BACK_FACE: u32 = u32::MAX - 1;

/// A reusable hemi-cube: item and depth buffers for the five faces, and dense
/// accumulators over source polygons (grown on demand). One per thread; no
/// allocation per hemi-cube.
#[derive(Clone, Debug)]
pub struct Hemicube {
    table: Arc<DeltaTable>,
    items: [Vec<u32>; 5],
    depth: [Vec<f32>; 5],
    accumulator: Vec<f64>,
    touched: Vec<u32>,
    /// Room for one entry per accumulator slot, kept between hemi-cubes:
    /// where the pixel sums list the slots they touch (see `row.rs`).
    listing: Vec<u32>,
    /// Delta form factors of every pixel a front face covered, won or not.
    covered: Vec<f64>,
    /// Pixel counts of the same coverage.
    covered_pixels: Vec<u32>,
    covered_touched: Vec<u32>,
    /// Front faces that covered no pixel centre (hybrid method only): polygon
    /// index and its vertex mean in local and in world coordinates.
    subpixel: Vec<(u32, DVec3, DVec3)>,
    /// Front-facing patches under samples that did not take the pixel
    /// (hybrid method only; see `cull.rs`).
    minor: Vec<cull::Minor>,
    /// Per-row span limits of the polygon being scan converted.
    span_left: Vec<f64>,
    span_right: Vec<f64>,
    /// Per face, the rectangle drawn into since the last clear.
    drawn: [Drawn; 5],
    /// Per face, at least the largest 1/depth drawn since the last clear:
    /// the pixel sums skip looking for near surfaces on a face where none
    /// can be (see `row.rs`).
    nearest: [f32; 5],
    /// The polygons to draw this time and the BVH nodes to draw as one sample
    /// (reused buffers; see `cull.rs`).
    candidates: Vec<u32>,
    splats: Vec<u32>,
    /// The polygons found to draw, before they are listed in order.
    found: id_set::IdSet,
    /// BVH nodes the depth buffer hid this time (see `occlusion.rs`).
    hidden_nodes: Vec<u32>,
    /// Clear and read out only the drawn rectangles (true by default); false
    /// treats every face as wholly drawn, as a check that skipping changes
    /// nothing.
    skip_empty: bool,
    /// Work counters.
    pub stats: HemicubeStats,
}

impl Hemicube {
    /// A hemi-cube with the given delta table, for a scene of `patches` patches.
    #[must_use]
    pub fn new(table: Arc<DeltaTable>, patches: usize) -> Self {
        let n = table.n;
        let face = |top: bool| if top { n * n } else { n * n / 2 };
        let items = std::array::from_fn(|f| vec![NOTHING; face(f == 0)]);
        let depth = std::array::from_fn(|f| vec![0.0f32; face(f == 0)]);
        Hemicube {
            table,
            items,
            depth,
            accumulator: vec![0.0; patches],
            touched: Vec::new(),
            listing: Vec::new(),
            covered: vec![0.0; patches],
            covered_pixels: vec![0; patches],
            covered_touched: Vec::new(),
            subpixel: Vec::new(),
            minor: Vec::new(),
            span_left: vec![f64::INFINITY; n],
            span_right: vec![f64::NEG_INFINITY; n],
            drawn: [Drawn::EMPTY; 5],
            nearest: [0.0; 5],
            candidates: Vec::new(),
            splats: Vec::new(),
            found: id_set::IdSet::default(),
            hidden_nodes: Vec::new(),
            skip_empty: true,
            stats: HemicubeStats::default(),
        }
    }

    /// Whether clearing and reading out the buffers stops at the rectangle
    /// of each face that polygons were drawn into (on by default). Either way
    /// the rows are the same bits; off, every pixel of every face is visited.
    pub fn set_skip_empty_faces(&mut self, on: bool) {
        self.skip_empty = on;
    }
}
