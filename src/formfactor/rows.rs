//! Element-to-patch rows for many receivers at once, in parallel.

use super::hemicube::{DeltaTable, Hemicube, HemicubeStats};
use super::{element_samples, EmitterVisibility, Occluders, Row, Samples, Sources};
use crate::mesh::{Cell, ElementKey, Mesh};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;

/// How rows are computed.
#[derive(Clone, Debug)]
pub struct RowSettings {
    /// The delta form-factor table (its resolution is the hemi-cube's).
    pub table: Arc<DeltaTable>,
    /// Seed of the per-receiver random rotations.
    pub seed: u64,
    /// How pixels become form factors.
    pub method: super::FormFactorMethod,
    /// Ray cast the visibility of emitters the item buffer saw only in part
    /// (hybrid method only).
    pub emitter_rays: bool,
    /// Make an emitter's entry the receiving element's mean form factor (Gauss
    /// points over the element) rather than its centre's.
    pub emitter_element_mean: bool,
}

/// A well-mixed 64-bit hash (SplitMix64 finaliser).
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A seed for one element from stable ids (the run seed, its surface and its
/// lattice cell), so that its hemi-cube rotation does not depend on the order
/// in which elements were created or on the thread that computes it.
#[must_use]
pub fn element_seed(seed: u64, surface: u32, cell: &Cell) -> u64 {
    let (a, b, s, kind) = match *cell {
        Cell::Quad { u, v, size } => (u, v, size, 0u64),
        Cell::Tri { a, b, size, up } => (a, b, size, 1 + u64::from(up)),
    };
    let mut h = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
    for x in [
        u64::from(surface),
        u64::from(a),
        u64::from(b),
        u64::from(s),
        kind,
    ] {
        h = mix(h ^ x);
    }
    h
}

/// Computes the hemi-cube row of each element in `keys` (in parallel, one
/// reusable hemi-cube per worker). Results are in the order of `keys` and do
/// not depend on the thread count. `progress` is called with the number of rows
/// finished so far.
pub fn compute_rows(
    mesh: &Mesh,
    sources: &Sources,
    keys: &[ElementKey],
    settings: &RowSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> (Vec<Row>, HemicubeStats) {
    let done = AtomicUsize::new(0);
    let polygons = AtomicU64::new(0);
    let pixels = AtomicU64::new(0);
    let patches = mesh.patches.len();
    let occluders = (settings.emitter_rays
        && settings.method == super::FormFactorMethod::Hybrid
        && !sources.emitters.is_empty())
    .then(|| Occluders::new(sources));
    let rows = keys
        .par_iter()
        .map_init(
            || Hemicube::new(Arc::clone(&settings.table), patches),
            |cube, &key| {
                let e = &mesh.elements[key];
                let lattice = &mesh.surfaces[e.surface as usize];
                let h = element_seed(settings.seed, e.surface, &e.cell);
                let angle = (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64) * std::f64::consts::TAU;
                // Lift the eye off the surface by a distance relative to the
                // element's own size, so that the offset is scale invariant.
                let eye = e.centroid + lattice.normal * (1e-6 * e.area.sqrt());
                let before = cube.stats;
                let lift = lattice.normal * (1e-6 * e.area.sqrt());
                let samples = match &occluders {
                    Some(_) if settings.emitter_element_mean => {
                        element_samples(&lattice.polygon(&e.cell), lift)
                    }
                    Some(_) => Samples::from_buf_and_len([(eye, 1.0); 4], 1),
                    None => Samples::new(),
                };
                let rays = occluders.as_ref().map(|o| EmitterVisibility {
                    occluders: o,
                    seed: h,
                    samples: &samples,
                });
                let row = cube.row(
                    sources,
                    eye,
                    lattice.normal,
                    angle,
                    e.surface,
                    settings.method,
                    rays,
                );
                polygons.fetch_add(
                    cube.stats.polygons_rasterized - before.polygons_rasterized,
                    Ordering::Relaxed,
                );
                pixels.fetch_add(
                    cube.stats.pixels_tested - before.pixels_tested,
                    Ordering::Relaxed,
                );
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_multiple_of(64) || n == keys.len() {
                    progress(n);
                }
                row
            },
        )
        .collect();
    let stats = HemicubeStats {
        hemicubes: keys.len() as u64,
        polygons_rasterized: polygons.into_inner(),
        pixels_tested: pixels.into_inner(),
    };
    (rows, stats)
}
