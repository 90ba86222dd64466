//! Rasterizing a whole mesh onto a grid of samples, in parallel bands of rows.
//!
//! 1. Every vertex is moved to view space and, when it needs no clipping,
//!    snapped to fixed-point sample coordinates once (shared by its triangles).
//! 2. Each triangle's row span is found and the triangle is listed in every
//!    band of rows it touches, in submission order.
//! 3. Bands are rasterized in parallel; inside a band triangles are drawn in
//!    submission order with a strict depth test, so the result is the same
//!    bits at any thread count.

use super::clip::{ClipVolume, MAX_CLIPPED_VERTICES};
use super::raster::{for_each_covered, sample_range, to_fixed, FixedPoint};
use super::shading::TriangleShading;
use super::view::View;
use super::ShadedMesh;
use crate::math::Rgb;
use glam::DVec3;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::Arc;

/// Rows per parallel work item.
const BAND_ROWS: u32 = 16;

/// The near plane sits at this fraction of the farthest vertex depth: close
/// enough to the eye to cut nothing visible, far enough to keep `1 / z` finite.
const NEAR_FRACTION: f64 = 1e-9;

/// Back faces are pushed this fraction farther in the depth test, so that where a
/// front face and a back face coincide (a double-sided surface stored as two
/// patches back to back) the front face wins whatever the submission order.
const BACK_FACE_DEPTH_BIAS: f64 = 1e-8;

/// Colour and `1 / z` per sample; `1 / z = 0` where nothing was drawn.
pub(crate) struct SampleGrid {
    pub colour: Vec<Rgb>,
    pub inverse_depth: Vec<f64>,
}

/// A triangle's footprint on the sample grid: the (clipped) polygon in fixed
/// point and the range of `1 / z` over it.
struct Footprint {
    points: [FixedPoint; MAX_CLIPPED_VERTICES],
    len: usize,
    inverse_depth_range: (f64, f64),
}

/// Everything the bands share.
struct Prepared<'a> {
    mesh: &'a ShadedMesh,
    view: &'a View,
    clip: ClipVolume,
    view_positions: Vec<DVec3>,
    /// Snapped sample coordinates of vertices inside the clip volume.
    snapped: Vec<Option<FixedPoint>>,
}

/// Renders a validated `mesh` onto the grid of `view`.
pub(crate) fn render_samples(mesh: &ShadedMesh, view: &View) -> SampleGrid {
    let count = view.width as usize * view.height as usize;
    // Filled in parallel: at the default 2 x 2 supersampling the grid is
    // tens of megabytes, and zeroing it (and faulting its pages in) on one
    // thread left the other idle. The depths are written too, not taken
    // zeroed from the allocator: a fresh zeroed page is first read by the
    // depth test, which maps the shared zero page, and the write after it
    // then costs a copy-on-write fault that stops every thread to flush
    // its address translations (5% of the default job's time, seen in
    // `perf`).
    let mut colour = Vec::with_capacity(count);
    colour.par_extend(rayon::iter::repeat_n(Rgb::ZERO, count));
    let mut inverse_depth = Vec::with_capacity(count);
    inverse_depth.par_extend(rayon::iter::repeat_n(0.0, count));
    let mut grid = SampleGrid {
        colour,
        inverse_depth,
    };
    let view_positions: Vec<DVec3> = mesh
        .positions
        .par_iter()
        .map(|&p| view.to_view(p))
        .collect();
    // max is exact and order-independent, so this reduction is deterministic.
    let farthest = view_positions
        .par_iter()
        .map(|p| p.z)
        .reduce(|| f64::NEG_INFINITY, f64::max);
    if mesh.triangles.is_empty() || farthest <= 0.0 {
        return grid;
    }
    let clip = ClipVolume::new(view, farthest * NEAR_FRACTION);
    let snapped = view_positions
        .par_iter()
        .map(|&v| clip.contains(v).then(|| to_fixed(view.to_pixel(v))))
        .collect();
    let prepared = Prepared {
        mesh,
        view,
        clip,
        view_positions,
        snapped,
    };
    let bins = prepared.bin_by_band();
    let band_len = (BAND_ROWS * view.width) as usize;
    grid.colour
        .par_chunks_mut(band_len)
        .zip(grid.inverse_depth.par_chunks_mut(band_len))
        .enumerate()
        // A band per task: the bands through the middle of the picture hold
        // most of the triangles, and runs of bands would leave a worker idle.
        .with_max_len(1)
        .for_each(|(band, (colour, depth))| {
            let first = band as u32 * BAND_ROWS;
            let rows = first..(first + BAND_ROWS).min(view.height);
            for &t in &bins.triangles[bins.starts[band]..bins.starts[band + 1]] {
                prepared.draw(t as usize, rows.clone(), colour, depth);
            }
        });
    grid
}

/// Triangle indices per band, flattened: band `b` owns
/// `triangles[starts[b]..starts[b + 1]]`.
struct Bins {
    starts: Vec<usize>,
    triangles: Vec<u32>,
}

impl Prepared<'_> {
    fn vertices(&self, t: usize) -> [usize; 3] {
        self.mesh.triangles[t].map(|i| i as usize)
    }

    /// The triangle's footprint, or `None` when it lies outside the clip volume.
    fn footprint(&self, t: usize) -> Option<Footprint> {
        let idx = self.vertices(t);
        let mut fp = Footprint {
            points: [[0; 2]; MAX_CLIPPED_VERTICES],
            len: 0,
            inverse_depth_range: (f64::INFINITY, 0.0),
        };
        let add = |fp: &mut Footprint, point: FixedPoint, z: f64| {
            fp.points[fp.len] = point;
            fp.len += 1;
            let (lo, hi) = fp.inverse_depth_range;
            fp.inverse_depth_range = (lo.min(1.0 / z), hi.max(1.0 / z));
        };
        if let [Some(a), Some(b), Some(c)] = idx.map(|i| self.snapped[i]) {
            for (point, i) in [a, b, c].into_iter().zip(idx) {
                add(&mut fp, point, self.view_positions[i].z);
            }
        } else {
            let poly = self.clip.clip_triangle(idx.map(|i| self.view_positions[i]));
            for &v in poly.vertices() {
                add(&mut fp, to_fixed(self.view.to_pixel(v)), v.z);
            }
        }
        (fp.len >= 3).then_some(fp)
    }

    /// The sample rows the triangle may cover, if any sample at all.
    fn row_span(&self, t: usize) -> Option<(u32, u32)> {
        let fp = self.footprint(t)?;
        let pts = &fp.points[..fp.len];
        let lo = |k: usize| pts.iter().map(|p| p[k]).min().unwrap_or(0);
        let hi = |k: usize| pts.iter().map(|p| p[k]).max().unwrap_or(0);
        sample_range(lo(0), hi(0), self.view.width)?;
        sample_range(lo(1), hi(1), self.view.height)
    }

    /// Lists each triangle in every band its row span touches (a counting sort,
    /// so each band's list keeps submission order).
    fn bin_by_band(&self) -> Bins {
        let spans: Vec<Option<(u32, u32)>> = (0..self.mesh.triangles.len())
            .into_par_iter()
            .map(|t| self.row_span(t))
            .collect();
        let bands = self.view.height.div_ceil(BAND_ROWS) as usize;
        let mut starts = vec![0usize; bands + 1];
        for &(y0, y1) in spans.iter().flatten() {
            for b in (y0 / BAND_ROWS)..=(y1 / BAND_ROWS) {
                starts[b as usize + 1] += 1;
            }
        }
        for b in 0..bands {
            starts[b + 1] += starts[b];
        }
        let mut next = starts.clone();
        let mut triangles = vec![0u32; starts[bands]];
        for (t, span) in spans.iter().enumerate() {
            if let Some((y0, y1)) = *span {
                for b in (y0 / BAND_ROWS)..=(y1 / BAND_ROWS) {
                    triangles[next[b as usize]] = t as u32;
                    next[b as usize] += 1;
                }
            }
        }
        Bins { starts, triangles }
    }

    /// Draws triangle `t` into the band holding sample rows `rows`.
    fn draw(&self, t: usize, rows: Range<u32>, colour: &mut [Rgb], depth: &mut [f64]) {
        let Some(fp) = self.footprint(t) else {
            return;
        };
        let width = self.view.width;
        // Set up on the first covered sample: most small triangles cover none.
        let mut shading: Option<Option<TriangleShading>> = None;
        let mut visit = |x: u32, y: u32| {
            let shading = shading.get_or_insert_with(|| {
                let idx = self.vertices(t);
                let texel = self.mesh.texels.as_ref().and_then(|x| {
                    let material = x.materials[t].as_ref()?;
                    Some((idx.map(|i| x.uv[i]), Arc::clone(material)))
                });
                TriangleShading::new(
                    self.view,
                    idx.map(|i| self.view_positions[i]),
                    idx.map(|i| self.mesh.values[i]),
                    fp.inverse_depth_range,
                    texel,
                )
            });
            let Some(s) = shading else {
                return;
            };
            if !s.front && self.mesh.cull_back_faces {
                return;
            }
            let (sx, sy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let inverse_depth = s.inverse_depth_at(sx, sy);
            let tested = if s.front {
                inverse_depth
            } else {
                inverse_depth * (1.0 - BACK_FACE_DEPTH_BIAS)
            };
            let i = ((y - rows.start) * width + x) as usize;
            if tested > depth[i] {
                depth[i] = tested;
                colour[i] = if s.front {
                    s.value_at(sx, sy, inverse_depth)
                } else {
                    Rgb::ZERO
                };
            }
        };
        for k in 1..fp.len - 1 {
            let tri = [fp.points[0], fp.points[k], fp.points[k + 1]];
            for_each_covered(tri, width, rows.clone(), &mut visit);
        }
    }
}
