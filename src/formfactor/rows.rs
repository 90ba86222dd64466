//! Element-to-patch rows for many receivers at once, in parallel.

use super::contacts::Contacts;
use super::contacts::Coverage;
use super::hemicube::emitter_form_factors;
use super::hemicube::{Cull, DeltaTable, Hemicube, HemicubeStats, PartSources, RowRequest};
use super::scratch::map_items;
use super::EmitterShift;
use super::{
    back_to_back_twins, element_samples, eye_lift, point_to_polygon, unoccluded_row, ClosedObjects,
    EmitterSampling, EmitterVisibility, FormFactors, Occluders, PixelHint, Row, Samples, Sources,
};
use crate::mesh::{Cell, ElementKey, Mesh};
use glam::DVec3;
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
    let scene = RowScene::new(mesh, sources, settings, skips);
    let results: Vec<(Row, HemicubeStats)> = map_items(
        keys,
        || scene.cube(),
        |_, &key, (cube, hidden)| {
            let (row, stats) = scene.row(cube, hidden, key);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if n.is_multiple_of(64) || n == keys.len() {
                progress(n);
            }
            (row.without_zeros(), stats)
        },
    );
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

/// For each (facet, its group lead) of `pairs`, whose lead's row
/// `form_factors` holds, what the facet's own view of the emitters adds to
/// that row (see [`FormFactors::emitter_shift`]). In parallel, in the order
/// of `pairs`; the same at any thread count. `progress` is called with the
/// pairs done so far.
pub(crate) fn emitter_shifts(
    mesh: &Mesh,
    sources: &Sources,
    pairs: &[(ElementKey, ElementKey)],
    form_factors: &FormFactors,
    settings: &RowSettings,
    skips: &RowSkips,
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<EmitterShift> {
    if pairs.is_empty() || sources.emitters.is_empty() {
        return vec![EmitterShift::none(); pairs.len()];
    }
    let scene = RowScene::new(mesh, sources, settings, skips);
    let done = AtomicUsize::new(0);
    progress(0);
    pairs
        .par_iter()
        .map(|&(k, lead)| {
            let shift = scene.emitter_shift(k, lead, form_factors.entries(lead));
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if n.is_multiple_of(64) || n == pairs.len() {
                progress(n);
            }
            shift
        })
        .collect()
}

/// What the rows of a mesh's leaves are drawn with, built once for many.
pub(crate) struct RowScene<'a> {
    mesh: &'a Mesh,
    sources: &'a Sources,
    settings: &'a RowSettings,
    skips: RowSkips,
    /// Hybrid rows are the exact unoccluded form factors (see
    /// [`RowSkips::unoccluded`]).
    exact: bool,
    /// The visibility of emitters is found by rays where the item buffer is
    /// unsure.
    emitters_exact: bool,
    /// The BVH over the polygons: what each hemi-cube draws is found
    /// through it, and so is the visibility of emitters.
    occluders: Option<Occluders>,
    /// Where other objects touch a surface, the elements they cover in part.
    contacts: Option<Contacts>,
    closed: Option<ClosedObjects>,
    /// Per surface, whether a back-to-back twin hides its back (see
    /// [`back_to_back_twins`]); `None` when no surface has one.
    twins: Option<Vec<bool>>,
}

/// Where a leaf looks from.
struct Viewpoint {
    eye: DVec3,
    angle: f64,
    /// The leaf's seed (see [`element_seed`]).
    seed: u64,
    lift: DVec3,
    /// The part of it that objects touching its surface leave visible.
    coverage: Option<Coverage>,
}

impl<'a> RowScene<'a> {
    /// The scene of `mesh`'s leaves seen through `sources`.
    pub(crate) fn new(
        mesh: &'a Mesh,
        sources: &'a Sources,
        settings: &'a RowSettings,
        skips: &RowSkips,
    ) -> Self {
        let exact = skips.unoccluded && settings.method == super::FormFactorMethod::Hybrid;
        let occluders = (!exact).then(|| Occluders::new(sources));
        let emitters_exact = !exact
            && settings.emitter_sampling != EmitterSampling::Pixels
            && settings.method == super::FormFactorMethod::Hybrid
            && !sources.emitters.is_empty();
        let contacts = occluders
            .as_ref()
            .map(|o| Contacts::new(mesh, sources, o))
            .filter(|c| !c.is_empty());
        let closed = (skips.hidden_back_faces && !exact)
            .then(|| ClosedObjects::new(mesh))
            .filter(|c| !c.is_empty());
        let twins = (!exact)
            .then(|| back_to_back_twins(mesh))
            .filter(|t| t.iter().any(|&t| t));
        RowScene {
            mesh,
            sources,
            settings,
            skips: *skips,
            exact,
            emitters_exact,
            occluders,
            contacts,
            closed,
            twins,
        }
    }

    /// A worker's hemi-cube and its buffer of hidden back faces.
    fn cube(&self) -> (Hemicube, Vec<bool>) {
        let mut cube = Hemicube::new(Arc::clone(&self.settings.table), self.mesh.patches.len());
        cube.set_skip_empty_faces(self.skips.empty_faces);
        (cube, Vec::new())
    }

    /// Where leaf `key` looks from: its centroid, lifted off its surface,
    /// or the centre of its visible part where other objects cover it.
    fn viewpoint(&self, key: ElementKey) -> Viewpoint {
        let e = &self.mesh.elements[key];
        let lattice = &self.mesh.surfaces[e.surface as usize];
        let seed = element_seed(self.settings.seed, e.surface, &e.cell);
        let angle = (seed >> 11) as f64 * (1.0 / (1u64 << 53) as f64) * std::f64::consts::TAU;
        let lift = eye_lift(lattice.normal, e.area);
        let coverage = match (&self.contacts, &self.occluders) {
            (Some(c), Some(o)) => {
                let polygon = lattice.polygon(&e.cell);
                c.touching(e.surface, &polygon, lattice.normal)
                    .and_then(|size| {
                        o.coverage(
                            self.sources,
                            &polygon,
                            lattice.normal,
                            e.surface,
                            lift,
                            seed,
                            size,
                        )
                    })
            }
            _ => None,
        };
        let eye = coverage.as_ref().map_or(e.centroid + lift, |c| c.eye);
        Viewpoint {
            eye,
            angle,
            seed,
            lift,
            coverage,
        }
    }

    /// The request for leaf `key`'s row from `view`, without emitter rays.
    fn request<'r>(
        &'r self,
        key: ElementKey,
        view: &Viewpoint,
        hidden: &'r mut Vec<bool>,
    ) -> RowRequest<'r> {
        let e = &self.mesh.elements[key];
        let lattice = &self.mesh.surfaces[e.surface as usize];
        let hidden_back = match (&self.closed, &self.twins) {
            (Some(c), twins) => {
                c.hidden_from(view.eye, hidden);
                if let Some(twins) = twins {
                    for (h, &t) in hidden.iter_mut().zip(twins) {
                        *h |= t;
                    }
                }
                Some(hidden.as_slice())
            }
            (None, Some(twins)) => Some(twins.as_slice()),
            (None, None) => None,
        };
        RowRequest {
            sources: self.sources,
            hidden_back,
            eye: view.eye,
            normal: lattice.normal,
            angle: view.angle,
            own_surface: e.surface,
            method: self.settings.method,
            emitter_rays: None,
            cull: self.occluders.as_ref().map(|o| Cull {
                occluders: o,
                lod: self
                    .settings
                    .level_of_detail
                    .then_some(self.settings.table.n),
                occlusion: self.settings.level_of_detail,
            }),
            // Surfaces within the element's own size: where they fill much
            // of its view, what it receives changes across it (see
            // `Row::near`).
            reach: e.area.sqrt(),
        }
    }

    /// Leaf `key`'s row, drawn with `cube`, and the work it took.
    fn row(
        &self,
        cube: &mut Hemicube,
        hidden: &mut Vec<bool>,
        key: ElementKey,
    ) -> (Row, HemicubeStats) {
        let e = &self.mesh.elements[key];
        let lattice = &self.mesh.surfaces[e.surface as usize];
        let view = self.viewpoint(key);
        if self.exact {
            let stats = HemicubeStats {
                exact_rows: 1,
                ..HemicubeStats::default()
            };
            let row = unoccluded_row(self.sources, view.eye, lattice.normal, e.surface);
            return (row, stats);
        }
        let before = cube.stats;
        // The Gauss points of an element lit without shadow give way to its
        // centre (see `EmitterSampling::Shadowed`); a partly covered
        // element's visible points are its mean in every mode.
        let shadowed_sampling =
            view.coverage.is_none() && self.settings.emitter_sampling == EmitterSampling::Shadowed;
        let samples = self.emitter_samples(key, &view);
        let mut request = self.request(key, &view, hidden);
        request.emitter_rays = self
            .occluders
            .as_ref()
            .filter(|_| self.emitters_exact)
            .map(|o| EmitterVisibility {
                occluders: o,
                seed: view.seed,
                samples: &samples,
                shadowed_sampling,
            });
        let mut row = cube.row_for(&request);
        if let Some(c) = &view.coverage {
            row = row.covered(c.visible);
        }
        (row, cube.stats - before)
    }

    /// The points of leaf `key` seen from `view` at which its emitters'
    /// visible form factors are found, by the emitter sampling (none where
    /// the pixels or rays decide).
    fn emitter_samples(&self, key: ElementKey, view: &Viewpoint) -> Samples {
        if !self.emitters_exact {
            return Samples::new();
        }
        let e = &self.mesh.elements[key];
        let lattice = &self.mesh.surfaces[e.surface as usize];
        match (self.settings.emitter_sampling, &view.coverage) {
            (EmitterSampling::Rays | EmitterSampling::Pixels, _) => Samples::new(),
            // A partly covered element's own visible points: the Gauss
            // points would count the covered part twice, as its row is
            // scaled by the visible share already.
            (_, Some(c)) => c.samples.clone(),
            (EmitterSampling::Element | EmitterSampling::Shadowed, None) => {
                element_samples(&lattice.polygon(&e.cell), view.lift)
            }
            (EmitterSampling::Centre, None) => Samples::from_buf_and_len([(view.eye, 1.0); 4], 1),
        }
    }

    /// What leaf `key`'s own view of the emitters adds to `borrowed`, the
    /// entries of its group lead's row that it holds (see
    /// [`FormFactors::emitter_shift`]): per emitter patch, its own visible
    /// form factor less the borrowed one. Empty where emitters are not
    /// found exactly (the pixels decide: the borrowed pixels stand), where
    /// other objects cover part of the leaf, or where it sees too many
    /// emitter polygons to find them without pixels.
    fn emitter_shift(
        &self,
        key: ElementKey,
        lead: ElementKey,
        borrowed: &[(u32, f32)],
    ) -> EmitterShift {
        let Some(occluders) = self.occluders.as_ref().filter(|_| self.emitters_exact) else {
            return EmitterShift::none();
        };
        let view = self.viewpoint(key);
        if view.coverage.is_some() {
            return EmitterShift::none();
        }
        let e = &self.mesh.elements[key];
        let normal = self.mesh.surfaces[e.surface as usize].normal;
        let samples = self.emitter_samples(key, &view);
        let visibility = EmitterVisibility {
            occluders,
            seed: view.seed,
            samples: &samples,
            shadowed_sampling: self.settings.emitter_sampling == EmitterSampling::Shadowed,
        };
        // Where the rays must decide, they trust what the lead's pixels saw
        // of each emitter (its row holds the visible form factor, to be
        // compared with the unoccluded one at its eye), as its row's did.
        let (lead_eye, lead_surface) = (self.viewpoint(lead).eye, self.mesh.elements[lead].surface);
        let lead_normal = self.mesh.surfaces[lead_surface as usize].normal;
        let hint = |j: u32| {
            let unoccluded: f64 = self
                .sources
                .range(j)
                .map(|q| &self.sources.polygons[q])
                .filter(|poly| poly.surface != lead_surface)
                .map(|poly| point_to_polygon(lead_eye, lead_normal, poly.corners()))
                .sum();
            let seen = borrowed
                .binary_search_by_key(&j, |x| x.0)
                .map_or(0.0, |i| f64::from(borrowed[i].1));
            if unoccluded <= 0.0 {
                PixelHint::Unseen
            } else if seen >= unoccluded * (1.0 - 1e-3) {
                PixelHint::Whole
            } else if seen <= 0.0 {
                PixelHint::Hidden
            } else {
                PixelHint::Partial
            }
        };
        let Some(own) = emitter_form_factors(
            self.sources,
            view.eye,
            normal,
            e.surface,
            &visibility,
            &hint,
        ) else {
            return EmitterShift::none();
        };
        // The row's sum stays the lead's: what the facet sees more of the
        // emitters it sees less of the rest.
        let is_emitter = |j: &u32| self.sources.emitters.binary_search(j).is_ok();
        let total: f64 = borrowed.iter().map(|&(_, f)| f64::from(f)).sum();
        let lent: f64 = borrowed
            .iter()
            .filter(|(j, _)| is_emitter(j))
            .map(|&(_, f)| f64::from(f))
            .sum();
        let mine: f64 = own.iter().map(|&(_, f)| f).sum();
        let scale = if total - lent > 0.0 {
            ((total - mine) / (total - lent)).max(0.0)
        } else {
            1.0
        };
        // Both lists are in patch order: walk them together.
        let lent = borrowed.iter().filter(|(j, _)| is_emitter(j));
        let mut shift = EmitterShift {
            scale: scale as f32,
            entries: smallvec::SmallVec::new(),
        };
        let scale = f64::from(shift.scale);
        let (mut a, mut b) = (own.iter().peekable(), lent.peekable());
        loop {
            let (j, d) = match (a.peek(), b.peek()) {
                (None, None) => break,
                (Some(&&(j, f)), None) => {
                    a.next();
                    (j, f)
                }
                (None, Some(&&(j, g))) => {
                    b.next();
                    (j, -scale * f64::from(g))
                }
                (Some(&&(j, f)), Some(&&(k, g))) => {
                    if j < k {
                        a.next();
                        (j, f)
                    } else if k < j {
                        b.next();
                        (k, -scale * f64::from(g))
                    } else {
                        a.next();
                        b.next();
                        (j, f - scale * f64::from(g))
                    }
                }
            };
            let d = d as f32;
            if d != 0.0 {
                shift.entries.push((j, d));
            }
        }
        shift
    }

    /// Per leaf of `keys` (the `n`th), `f(n, view)`, where `view` draws the
    /// leaf's hemi-cube from the point its row was drawn from with the
    /// patches it is given part by part (see [`Hemicube::part_view`]). In
    /// parallel, in the order of `keys`; the same at any thread count.
    /// `progress` is called with the leaves done so far and their number.
    pub(crate) fn with_part_views<T: Send>(
        &self,
        keys: &[ElementKey],
        progress: &(dyn Fn(usize, usize) + Sync),
        f: impl Fn(usize, &mut dyn FnMut(&[PartSources<'_>]) -> Vec<(f64, f64)>) -> T + Sync,
    ) -> Vec<T> {
        let done = AtomicUsize::new(0);
        progress(0, keys.len());
        map_items(
            keys,
            || self.cube(),
            |n, &key, (cube, hidden)| {
                let view = self.viewpoint(key);
                let out = f(n, &mut |wanted| {
                    let request = self.request(key, &view, hidden);
                    cube.part_view(&request, wanted)
                });
                let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
                if finished.is_multiple_of(64) || finished == keys.len() {
                    progress(finished, keys.len());
                }
                out
            },
        )
    }
}
