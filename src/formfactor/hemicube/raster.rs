//! The item-buffer rasterizer: projects patch polygons onto the five faces with a
//! depth test, then sums the delta form factors of the pixels each patch won.

use super::faces::Face;
use super::table::DeltaTable;
use crate::formfactor::{
    point_to_polygon, EmitterVisibility, FormFactorMethod, PixelHint, Row, Sources,
};
use glam::{DVec2, DVec3};
use std::sync::Arc;

const NOTHING: u32 = u32::MAX;
/// The back of a single-sided surface: it hides what lies behind it but neither
/// emits nor reflects, so its pixels count for no patch.
const BACK_FACE: u32 = u32::MAX - 1;

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
    /// Back faces not drawn because front faces of their own closed object
    /// hide them (see `crate::formfactor::ClosedObjects`).
    pub back_faces_skipped: u64,
    /// Rows given by the exact unoccluded form factor with no hemi-cube at all
    /// (a convex enclosure; see `crate::formfactor::is_convex_enclosure`).
    pub exact_rows: u64,
}

impl HemicubeStats {
    /// Every counter, in declaration order, for element-wise arithmetic.
    fn counters(&mut self) -> [&mut u64; 8] {
        [
            &mut self.hemicubes,
            &mut self.polygons_rasterized,
            &mut self.pixels_tested,
            &mut self.empty_faces,
            &mut self.pixels_skipped,
            &mut self.polygons_culled,
            &mut self.back_faces_skipped,
            &mut self.exact_rows,
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

/// The pixel rectangle of one face that polygons were drawn into since it was
/// last cleared: rows `j0..j1`, columns `i0..i1` (empty when `j0 >= j1`).
/// Everything outside it still holds nothing, so clearing and reading out the
/// face can stop at its edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Drawn {
    j0: usize,
    j1: usize,
    i0: usize,
    i1: usize,
}

impl Drawn {
    const EMPTY: Drawn = Drawn {
        j0: usize::MAX,
        j1: 0,
        i0: usize::MAX,
        i1: 0,
    };

    fn is_empty(&self) -> bool {
        self.j0 >= self.j1 || self.i0 >= self.i1
    }

    fn include(&mut self, j0: usize, j1: usize, i0: usize, i1: usize) {
        self.j0 = self.j0.min(j0);
        self.j1 = self.j1.max(j1);
        self.i0 = self.i0.min(i0);
        self.i1 = self.i1.max(i1);
    }

    fn pixels(&self) -> usize {
        if self.is_empty() {
            0
        } else {
            (self.j1 - self.j0) * (self.i1 - self.i0)
        }
    }
}

/// What a hemi-cube saw of one source polygon (see [`Hemicube::coverage`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coverage {
    /// The polygon's index in its [`Sources`].
    pub id: u32,
    /// Delta form factors of the pixels it won the depth test for: its
    /// classic hemi-cube form factor.
    pub won: f64,
    /// Delta form factors of every pixel its front face covered, won or not.
    pub covered: f64,
    /// Number of pixels its front face covered.
    pub pixels: u32,
}

/// What a hemi-cube saw from one eye (see [`Hemicube::coverage`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ItemCoverage {
    /// Every source polygon whose front face covered a pixel, by increasing id.
    pub polygons: Vec<Coverage>,
    /// The form factor of the back faces won (0 to 1): near 1 when the eye is
    /// shut inside a closed object, such as a point of the floor under a box.
    pub back_faces: f64,
}

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
    /// Delta form factors of every pixel a front face covered, won or not.
    covered: Vec<f64>,
    /// Pixel counts of the same coverage.
    covered_pixels: Vec<u32>,
    covered_touched: Vec<u32>,
    /// Front faces that covered no pixel centre (hybrid method only): polygon
    /// index and its vertex mean in local and in world coordinates.
    subpixel: Vec<(u32, DVec3, DVec3)>,
    /// Per-row span limits of the polygon being scan converted.
    span_left: Vec<f64>,
    span_right: Vec<f64>,
    /// Per face, the rectangle drawn into since the last clear.
    drawn: [Drawn; 5],
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
            covered: vec![0.0; patches],
            covered_pixels: vec![0; patches],
            covered_touched: Vec::new(),
            subpixel: Vec::new(),
            span_left: vec![f64::INFINITY; n],
            span_right: vec![f64::NEG_INFINITY; n],
            drawn: [Drawn::EMPTY; 5],
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
        self.row_hiding(sources, None, eye, normal, angle, own_surface, method, None)
    }

    /// [`Hemicube::row`], not drawing the back faces of the surfaces `s`
    /// of the sources for which `hidden_back[s]` is true: back faces that
    /// front faces of their own object hide from `eye`, as
    /// `crate::formfactor::ClosedObjects::hidden_from` finds them. The row
    /// is then the same but where a back face would have won a silhouette
    /// pixel from the front face at equal depth.
    /// With `emitter_rays` (the occluders and a seed), the hybrid method finds
    /// the visibility of emitters that the item buffer saw only in part from
    /// the occluders themselves.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn row_hiding(
        &mut self,
        sources: &Sources,
        hidden_back: Option<&[bool]>,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
        method: FormFactorMethod,
        emitter_rays: Option<EmitterVisibility<'_>>,
    ) -> Row {
        let hybrid = method == FormFactorMethod::Hybrid;
        self.render::<true>(
            sources,
            hidden_back,
            eye,
            normal,
            angle,
            own_surface,
            hybrid,
        );
        let (mut row, front, back) = self.accumulate();
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
        row.with_hidden(back, open)
    }

    /// Renders the item buffer like [`Hemicube::row`] and reports, for every
    /// polygon of `sources` whose front face covers at least one pixel centre,
    /// what it won and what it covered, in increasing id order, and how much of
    /// the view back faces fill. The sources may be any polygons with any ids
    /// (patches, or leaf elements for a shooting patch's item buffer); what to
    /// make of the pixels is the caller's choice.
    pub fn coverage(
        &mut self,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
    ) -> ItemCoverage {
        self.render::<true>(sources, None, eye, normal, angle, own_surface, false);
        let back_faces = self.sum_won();
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
        self.render::<FILL>(sources, None, eye, normal, angle, own_surface, false);
        for id in self.covered_touched.drain(..) {
            self.covered[id as usize] = 0.0;
            self.covered_pixels[id as usize] = 0;
        }
    }

    /// Fills the item and depth buffers with the front faces of `sources` seen
    /// from `eye` (and the back faces that hide them, unless `hidden_back`
    /// says their own object hides them), and the coverage sums. (`FILL` is
    /// false only for [`Hemicube::render_stage`].)
    #[allow(clippy::too_many_arguments)]
    fn render<const FILL: bool>(
        &mut self,
        sources: &Sources,
        hidden_back: Option<&[bool]>,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
        list_subpixel: bool,
    ) {
        self.clear();
        let n = sources.patch_count();
        if self.accumulator.len() < n {
            self.accumulator.resize(n, 0.0);
            self.covered.resize(n, 0.0);
            self.covered_pixels.resize(n, 0);
        }
        let t0 = normal.any_orthonormal_vector();
        let b0 = normal.cross(t0);
        let (s, c) = angle.sin_cos();
        let t = t0 * c + b0 * s;
        let b = normal.cross(t);
        let to_local = |v: DVec3| {
            let d = v - eye;
            DVec3::new(d.dot(t), d.dot(b), d.dot(normal))
        };
        for (id, poly) in sources.polygons.iter().enumerate() {
            if poly.surface == own_surface || (poly.centre - eye).dot(normal) < -poly.radius {
                self.stats.polygons_culled += 1;
                continue;
            }
            let count = poly.count as usize;
            let mut local = [DVec3::ZERO; 4];
            let mut above = false;
            let mut scale: f64 = 0.0;
            for (l, v) in local.iter_mut().zip(&poly.vertices[..count]) {
                *l = to_local(*v);
                above |= l.z > 0.0;
                scale = scale.max(l.length());
            }
            if !above {
                self.stats.polygons_culled += 1;
                continue;
            }
            // Plane of the polygon in local coordinates: m . q = h. The receiver
            // sees the front when it lies on the normal's side (h < 0).
            let m = DVec3::new(
                poly.normal.dot(t),
                poly.normal.dot(b),
                poly.normal.dot(normal),
            );
            let h = m.dot(local[0]);
            if h.abs() <= 1e-12 * scale {
                self.stats.polygons_culled += 1;
                continue; // seen edge-on: covers no pixel
            }
            if h > 0.0 && hidden_back.is_some_and(|hidden| hidden[poly.surface as usize]) {
                self.stats.back_faces_skipped += 1;
                continue;
            }
            let item = if h < 0.0 { poly.patch } else { BACK_FACE };
            let near = 1e-7 * scale;
            for (fi, face) in Face::ALL.iter().enumerate() {
                self.rasterize::<FILL>(*face, fi, &local[..count], face.map(m), h, near, item);
            }
            if list_subpixel && item != BACK_FACE && self.covered[item as usize] == 0.0 {
                let mean = |v: &[DVec3]| v.iter().copied().sum::<DVec3>() / count as f64;
                self.subpixel.push((
                    id as u32,
                    mean(&local[..count]),
                    mean(&poly.vertices[..count]),
                ));
            }
        }
    }

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
    fn hybrid(
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
        if let Some(EmitterVisibility {
            occluders,
            seed,
            samples,
        }) = emitter_rays
        {
            let mut changed = false;
            for &j in &sources.emitters {
                let (won, covered) = (row.get(j), self.covered[j as usize]);
                let hint = if covered <= 0.0 {
                    PixelHint::Unseen
                } else if won >= covered * (1.0 - 1e-6) {
                    PixelHint::Whole
                } else if won > 0.0 {
                    PixelHint::Partial
                } else {
                    PixelHint::Hidden
                };
                // Polygon by polygon (a face cluster that emits has several).
                let mut f = 0.0;
                let mut seen = false;
                for q in sources.range(j) {
                    let poly = &sources.polygons[q];
                    if poly.surface == own_surface {
                        continue;
                    }
                    let exact = point_to_polygon(eye, normal, poly.corners());
                    if exact <= 0.0 {
                        continue;
                    }
                    seen = true;
                    let q = q as u32;
                    // The element's mean form factor where every sample can be
                    // clipped exactly; else the centre's, with ray-cast visibility.
                    let exact_mean = if samples.is_empty() {
                        None
                    } else {
                        occluders.mean_visible_form_factor(sources, samples, normal, own_surface, q)
                    };
                    f += exact_mean.unwrap_or_else(|| {
                        exact
                            * occluders.visible_fraction(
                                sources,
                                eye,
                                normal,
                                own_surface,
                                q,
                                seed,
                                hint,
                            )
                    });
                }
                if !seen {
                    continue;
                }
                match entries.binary_search_by_key(&j, |e| e.0) {
                    Ok(i) => entries[i] = (j, f, false),
                    Err(i) => entries.insert(i, (j, f, false)),
                }
                changed = true;
            }
            if changed {
                entries.retain(|e| e.1 > 0.0);
            }
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

    /// Whether the polygon `id`, whose centroid is `local` in the hemi-cube's
    /// frame and `world` in the scene, is visible from `eye` along the ray to
    /// its centroid: true if the pixel that ray falls in holds nothing, a patch of
    /// the same (planar) surface, or a patch whose plane the ray does not meet
    /// between the eye and the centroid. A back face, whose plane is not kept,
    /// and a face cluster, which has no one plane, are compared by the depth
    /// stored at the pixel centre.
    fn sample_visible(
        &self,
        sources: &Sources,
        id: u32,
        eye: DVec3,
        local: DVec3,
        world: DVec3,
    ) -> bool {
        let a = local.abs();
        let (fi, face) = if local.z >= a.x.max(a.y) {
            (0, Face::Top)
        } else if a.x >= a.y {
            if local.x > 0.0 {
                (1, Face::PosX)
            } else {
                (2, Face::NegX)
            }
        } else if local.y > 0.0 {
            (3, Face::PosY)
        } else {
            (4, Face::NegY)
        };
        let p = face.map(local);
        if p.z <= 0.0 || (!face.is_top() && p.y < 0.0) {
            return false; // behind the eye or below the horizon
        }
        let n = self.table.n;
        let half = n as f64 * 0.5;
        let (height, y_offset) = if face.is_top() {
            (n, 1.0)
        } else {
            (n / 2, 0.0)
        };
        let pixel = |s: f64, limit: usize| ((s * half).max(0.0) as usize).min(limit - 1);
        let px = pixel(p.y / p.z + y_offset, height) * n + pixel(p.x / p.z + 1.0, n);
        let winner = self.items[fi][px];
        if winner == NOTHING {
            return true;
        }
        let single = match winner {
            BACK_FACE => None,
            _ => match sources.patch(winner) {
                [w] => Some(w),
                _ => None,
            },
        };
        let Some(w) = single else {
            // A back face or a face cluster: by depth. The stored value
            // carries up to a span of single-precision steps.
            let stored = f64::from(self.depth[fi][px]);
            return 1.0 / p.z >= stored * (1.0 - 4.0 * n as f64 * f64::from(f32::EPSILON));
        };
        if w.surface == sources.polygons[id as usize].surface {
            return true;
        }
        let towards = w.normal.dot(world - eye);
        if towards == 0.0 {
            return true;
        }
        // The ray eye + s (world - eye) meets the winner's plane at s: it
        // hides the patch only between the eye and the centroid.
        let s = w.normal.dot(w.vertices[0] - eye) / towards;
        !(s > 0.0 && s < 1.0 - 1e-9)
    }

    /// Empties the item and depth buffers: only the drawn rectangles when
    /// skipping, since every other pixel still holds nothing.
    fn clear(&mut self) {
        let n = self.table.n;
        for f in 0..5 {
            let d = std::mem::replace(&mut self.drawn[f], Drawn::EMPTY);
            if !self.skip_empty {
                self.items[f].fill(NOTHING);
                self.depth[f].fill(0.0);
            } else if !d.is_empty() {
                for j in d.j0..d.j1 {
                    let span = j * n + d.i0..j * n + d.i1;
                    self.items[f][span.clone()].fill(NOTHING);
                    self.depth[f][span].fill(0.0);
                }
            }
        }
        self.subpixel.clear();
        self.stats.hemicubes += 1;
    }

    /// Clips the polygon to the face's view volume in front of the near plane,
    /// projects it, and scan converts it with a depth test on 1/depth (which is
    /// affine in face coordinates for a planar polygon, hence exact).
    #[allow(clippy::too_many_arguments)]
    fn rasterize<const FILL: bool>(
        &mut self,
        face: Face,
        fi: usize,
        local: &[DVec3],
        m: DVec3,
        h: f64,
        near: f64,
        item: u32,
    ) {
        // Cull against the frustum's planes (all vertices beyond one plane)
        // before building anything: most polygons miss most faces.
        let mut mapped = [DVec3::ZERO; 4];
        let mut outside = [true; 6];
        for (m, l) in mapped.iter_mut().zip(local) {
            let p = face.map(*l);
            *m = p;
            outside[0] &= p.z <= near;
            outside[1] &= p.x > p.z;
            outside[2] &= p.x < -p.z;
            outside[3] &= p.y > p.z;
            outside[4] &= if face.is_top() { p.y < -p.z } else { p.y < 0.0 };
            outside[5] &= p.z >= near;
        }
        if outside[..5].iter().any(|o| *o) {
            return;
        }
        // Fixed stack arrays: a quad clipped by one plane has at most 5 vertices.
        let mut clipped = [DVec3::ZERO; 8];
        let count = if outside[5] {
            clipped[..local.len()].copy_from_slice(&mapped[..local.len()]);
            local.len()
        } else {
            clip_near(&mapped[..local.len()], near, &mut clipped)
        };
        if count < 3 {
            return;
        }
        let pts = &clipped[..count];
        let n = self.table.n;
        let half = n as f64 * 0.5;
        let (width, height) = (n, if face.is_top() { n } else { n / 2 });
        let y_offset = if face.is_top() { 1.0 } else { 0.0 };
        let mut projected = [DVec2::ZERO; 8];
        for (s, p) in projected.iter_mut().zip(pts) {
            let inv = 1.0 / p.z;
            *s = DVec2::new((p.x * inv + 1.0) * half, (p.y * inv + y_offset) * half);
        }
        let screen = &projected[..count];
        // 1/depth at pixel (i, j): u = (i + 0.5)/half - 1, w = (j + 0.5)/half - y_offset.
        let (du, dw) = (m.x / h / half, m.y / h / half);
        let base = (m.x * (0.5 / half - 1.0) + m.y * (0.5 / half - y_offset) + m.z) / h;
        self.stats.polygons_rasterized += 1;
        let (ymin, ymax) = screen
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.y), hi.max(p.y))
            });
        let j0 = ceil_index(ymin - 0.5, height);
        let j1 = ceil_index(ymax - 0.5, height);
        if !FILL {
            // Keeps the projection above from being optimised away.
            std::hint::black_box((j0, j1));
            return;
        }
        if j0 >= j1 {
            return;
        }
        // Walk every edge once, recording per row the span's left and right ends
        // at the pixel-centre line (a convex polygon crosses each row twice).
        let (left, right) = (&mut self.span_left, &mut self.span_right);
        for k in 0..screen.len() {
            let a = screen[k];
            let b = screen[(k + 1) % screen.len()];
            let (lo, hi) = if a.y <= b.y { (a, b) } else { (b, a) };
            let (r0, r1) = (
                ceil_index(lo.y - 0.5, height),
                ceil_index(hi.y - 0.5, height),
            );
            if r0 >= r1 {
                continue;
            }
            let slope = (hi.x - lo.x) / (hi.y - lo.y);
            for j in r0..r1 {
                let x = lo.x + (j as f64 + 0.5 - lo.y) * slope;
                left[j] = left[j].min(x);
                right[j] = right[j].max(x);
            }
        }
        let items = &mut self.items[fi];
        let depth = &mut self.depth[fi];
        let prefix = if face.is_top() {
            &self.table.top_prefix
        } else {
            &self.table.side_prefix
        };
        let mut covered = 0.0;
        let mut tested = 0u64;
        let mut drawn = Drawn::EMPTY;
        for j in j0..j1 {
            let (xl, xr) = (
                std::mem::replace(&mut left[j], f64::INFINITY),
                std::mem::replace(&mut right[j], f64::NEG_INFINITY),
            );
            if xl >= xr {
                continue;
            }
            let i0 = ceil_index(xl - 0.5, width);
            let i1 = ceil_index(xr - 0.5, width);
            let off = j * width;
            // 1/depth steps linearly along the span; single precision is ample
            // for the depth test (the plane equation itself is in double).
            let mut z = (base + dw * j as f64 + du * i0 as f64) as f32;
            let dz = du as f32;
            for (d, it) in depth[off + i0..off + i1]
                .iter_mut()
                .zip(&mut items[off + i0..off + i1])
            {
                if z > *d {
                    *d = z;
                    *it = item;
                }
                z += dz;
            }
            if i1 > i0 {
                tested += (i1 - i0) as u64;
                covered += prefix[j * (width + 1) + i1] - prefix[j * (width + 1) + i0];
                drawn.include(j, j + 1, i0, i1);
            }
        }
        if !drawn.is_empty() {
            self.drawn[fi].include(drawn.j0, drawn.j1, drawn.i0, drawn.i1);
        }
        self.stats.pixels_tested += tested;
        if item < BACK_FACE && covered > 0.0 {
            let slot = &mut self.covered[item as usize];
            if *slot == 0.0 {
                self.covered_touched.push(item);
            }
            *slot += covered;
            self.covered_pixels[item as usize] += tested as u32;
        }
    }

    /// Sums delta form factors per patch and returns the sparse row, with
    /// the delta form factors of all the pixels front faces won and of those
    /// back faces won.
    fn accumulate(&mut self) -> (Row, f64, f64) {
        let back = self.sum_won();
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
        (Row::from_sorted(entries), front, back)
    }

    /// Adds the delta form factor of every won pixel to its polygon's slot of
    /// the accumulator, listing the slots touched. Returns the delta form
    /// factors of the pixels won by back faces.
    ///
    /// When skipping, only each face's drawn rectangle is read: the pixels
    /// outside it hold nothing, and the ones inside are visited in the same
    /// order as a whole-face pass, so every sum is the same bits.
    fn sum_won(&mut self) -> f64 {
        let table = Arc::clone(&self.table);
        let n = table.n;
        let mut back = 0.0;
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
                for (&id, &w) in self.items[f][span.clone()].iter().zip(&weights[span]) {
                    if id < BACK_FACE {
                        let slot = &mut self.accumulator[id as usize];
                        if *slot == 0.0 {
                            self.touched.push(id);
                        }
                        *slot += w;
                    } else if id == BACK_FACE {
                        back += w;
                    }
                }
            }
        }
        back
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

/// The smallest integer at or above `x`, clamped to `0..=limit` (pixel index
/// ranges; avoids a libm call per scanline on baseline x86-64).
#[inline]
fn ceil_index(x: f64, limit: usize) -> usize {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    if x >= limit as f64 {
        return limit;
    }
    // Signed conversions are single instructions on x86-64; unsigned ones are not.
    let t = x as i64;
    (if (t as f64) < x { t + 1 } else { t }) as usize
}

/// Sutherland-Hodgman against the plane depth = near, into `out`; returns the
/// vertex count.
fn clip_near(pts: &[DVec3], near: f64, out: &mut [DVec3; 8]) -> usize {
    let mut n = 0;
    for k in 0..pts.len() {
        let a = pts[k];
        let b = pts[(k + 1) % pts.len()];
        let (da, db) = (a.z - near, b.z - near);
        if da >= 0.0 {
            out[n] = a;
            n += 1;
        }
        if (da >= 0.0) != (db >= 0.0) {
            out[n] = a + (b - a) * (da / (da - db));
            n += 1;
        }
    }
    n
}
