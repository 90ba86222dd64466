//! Element-to-patch rows for many receivers at once, in parallel.

use super::contacts::Contacts;
use super::hemicube::{Cull, DeltaTable, Hemicube, HemicubeStats, RowRequest};
use super::{
    element_samples, eye_lift, unoccluded_row, ClosedObjects, EmitterSampling, EmitterVisibility,
    Occluders, Row, Samples, Sources,
};
use crate::mesh::{Cell, ElementKey, Mesh};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
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
    /// How the visibility of emitters the item buffer saw only in part is
    /// found (hybrid method only).
    pub emitter_sampling: super::EmitterSampling,
    /// Draw BVH subtrees that would cover less than a pixel as one sample
    /// each (see [`crate::pipeline::Settings::level_of_detail`]).
    pub level_of_detail: bool,
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
pub(crate) fn element_seed(seed: u64, surface: u32, cell: &Cell) -> u64 {
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

/// Work `compute_rows_with` may leave out. `empty_faces` gives the same
/// bits as the full work; `hidden_back_faces` the same but for silhouette
/// pixels a back face won by rounding; `unoccluded` gives exact rows where
/// the hemi-cube approximates, and is right only for convex enclosures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RowSkips {
    /// The scene is a convex enclosure ([`super::is_convex_enclosure`]
    /// holds), so hybrid rows are the exact unoccluded form factors, with no
    /// hemi-cube. Off by default: elsewhere such rows would ignore occlusion.
    pub unoccluded: bool,
    /// Hemi-cubes do not draw the back faces of closed convex objects seen
    /// from outside them ([`ClosedObjects`]). On by default.
    pub hidden_back_faces: bool,
    /// Hemi-cubes clear and read out only the rectangle of each face that was
    /// drawn into. On by default.
    pub empty_faces: bool,
}

impl Default for RowSkips {
    fn default() -> Self {
        RowSkips {
            unoccluded: false,
            hidden_back_faces: true,
            empty_faces: true,
        }
    }
}

/// Computes the hemi-cube row of each element in `keys` (in parallel, one
/// reusable hemi-cube per worker). Results are in the order of `keys` and do
/// not depend on the thread count. `progress` is called with the number of rows
/// finished so far. The same as `compute_rows_with` and the default
/// `RowSkips`.
pub fn compute_rows(
    mesh: &Mesh,
    sources: &Sources,
    keys: &[ElementKey],
    settings: &RowSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> (Vec<Row>, HemicubeStats) {
    compute_rows_with(
        mesh,
        sources,
        keys,
        settings,
        &RowSkips::default(),
        progress,
    )
}

/// [`compute_rows`], leaving out the work `skips` allows.
pub(crate) fn compute_rows_with(
    mesh: &Mesh,
    sources: &Sources,
    keys: &[ElementKey],
    settings: &RowSettings,
    skips: &RowSkips,
    progress: &(dyn Fn(usize) + Sync),
) -> (Vec<Row>, HemicubeStats) {
    let done = AtomicUsize::new(0);
    let patches = mesh.patches.len();
    let exact = skips.unoccluded && settings.method == super::FormFactorMethod::Hybrid;
    // The BVH over the polygons: what each hemi-cube draws is found through
    // it, and so is the visibility of emitters.
    let occluders = (!exact).then(|| Occluders::new(sources));
    let emitters_exact = !exact
        && settings.emitter_sampling != EmitterSampling::Pixels
        && settings.method == super::FormFactorMethod::Hybrid
        && !sources.emitters.is_empty();
    // Where other objects touch a surface, the elements they cover in part.
    let contacts = occluders
        .as_ref()
        .map(|o| Contacts::new(mesh, sources, o))
        .filter(|c| !c.is_empty());
    let closed = (skips.hidden_back_faces && !exact)
        .then(|| ClosedObjects::new(mesh))
        .filter(|c| !c.is_empty());
    let results: Vec<(Row, HemicubeStats)> = keys
        .par_iter()
        .map_init(
            || {
                let mut cube = Hemicube::new(Arc::clone(&settings.table), patches);
                cube.set_skip_empty_faces(skips.empty_faces);
                (cube, Vec::new())
            },
            |(cube, hidden), &key| {
                let e = &mesh.elements[key];
                let lattice = &mesh.surfaces[e.surface as usize];
                let h = element_seed(settings.seed, e.surface, &e.cell);
                let angle = (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64) * std::f64::consts::TAU;
                let lift = eye_lift(lattice.normal, e.area);
                let mut eye = e.centroid + lift;
                let coverage = match (&contacts, &occluders) {
                    (Some(c), Some(o)) => {
                        let polygon = lattice.polygon(&e.cell);
                        c.touching(e.surface, &polygon, lattice.normal)
                            .and_then(|size| {
                                o.coverage(
                                    sources,
                                    &polygon,
                                    lattice.normal,
                                    e.surface,
                                    lift,
                                    h,
                                    size,
                                )
                            })
                    }
                    _ => None,
                };
                if let Some(c) = &coverage {
                    eye = c.eye;
                }
                let (row, stats) = if exact {
                    let stats = HemicubeStats {
                        exact_rows: 1,
                        ..HemicubeStats::default()
                    };
                    (
                        unoccluded_row(sources, eye, lattice.normal, e.surface),
                        stats,
                    )
                } else {
                    let hidden_back = closed.as_ref().map(|c| {
                        c.hidden_from(eye, hidden);
                        hidden.as_slice()
                    });
                    let before = cube.stats;
                    let samples = if emitters_exact {
                        match (settings.emitter_sampling, &coverage) {
                            (EmitterSampling::Rays | EmitterSampling::Pixels, _) => Samples::new(),
                            // A partly covered element's own visible
                            // points: the Gauss points would count the
                            // covered part twice, as its row is scaled
                            // by the visible share already.
                            (_, Some(c)) => c.samples.clone(),
                            (EmitterSampling::Element, None) => {
                                element_samples(&lattice.polygon(&e.cell), lift)
                            }
                            (EmitterSampling::Centre, None) => {
                                Samples::from_buf_and_len([(eye, 1.0); 4], 1)
                            }
                        }
                    } else {
                        Samples::new()
                    };
                    let rays =
                        occluders
                            .as_ref()
                            .filter(|_| emitters_exact)
                            .map(|o| EmitterVisibility {
                                occluders: o,
                                seed: h,
                                samples: &samples,
                            });
                    let mut row = cube.row_for(&RowRequest {
                        sources,
                        hidden_back,
                        eye,
                        normal: lattice.normal,
                        angle,
                        own_surface: e.surface,
                        method: settings.method,
                        emitter_rays: rays,
                        cull: occluders.as_ref().map(|o| Cull {
                            occluders: o,
                            lod: settings.level_of_detail.then_some(settings.table.n),
                        }),
                        // Surfaces within the element's own size: where
                        // they fill much of its view, what it receives
                        // changes across it (see `Row::near`).
                        reach: e.area.sqrt(),
                    });
                    if let Some(c) = &coverage {
                        row = row.covered(c.visible);
                    }
                    (row, cube.stats - before)
                };
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_multiple_of(64) || n == keys.len() {
                    progress(n);
                }
                (row.without_zeros(), stats)
            },
        )
        .collect();
    let mut stats = HemicubeStats::default();
    let rows = results
        .into_iter()
        .map(|(row, s)| {
            stats += s;
            row
        })
        .collect();
    (rows, stats)
}
