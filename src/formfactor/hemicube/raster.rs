//! Scan conversion: projects source polygons onto the five faces with a depth
//! test on 1/depth.

use super::cull::{Between, Cull, Frame};
use super::faces::Face;
use super::parts::PartSources;
use super::{Drawn, Hemicube, BACK_FACE, NOTHING};
use crate::formfactor::{SourcePolygon, Sources};
use glam::{DVec2, DVec3};
use smallvec::SmallVec;

/// How [`Hemicube::draw_polygon`] draws.
#[derive(Clone, Copy)]
pub(super) struct Draw<'a> {
    pub(super) frame: &'a Frame,
    pub(super) own_surface: u32,
    pub(super) hidden_back: Option<&'a [bool]>,
    pub(super) list_subpixel: bool,
    /// Count the pixels the front face covers and leave the item and depth
    /// buffers as they are (see `occlusion.rs`).
    pub(super) cover_only: bool,
}

/// Where [`Hemicube::rasterize`] draws a polygon: on which face, as which
/// item, and whether only to count its coverage.
#[derive(Clone, Copy)]
struct Target {
    face: Face,
    fi: usize,
    item: u32,
    cover_only: bool,
}

/// Relative margin on a polygon's largest 1/depth (see `Hemicube::nearest`),
/// far above the rounding of the depth steps along a span (at most a
/// face's width of single-precision additions, about 1e-5).
const NEAREST_MARGIN: f64 = 1e-3;

impl Hemicube {
    /// Fills the item and depth buffers with the front faces of `sources` seen
    /// from `eye` (and the back faces that hide them, unless `hidden_back`
    /// says their own object hides them), and the coverage sums. (`FILL` is
    /// false only for [`Hemicube::render_stage`].)
    #[allow(clippy::too_many_arguments)]
    pub(super) fn render<const FILL: bool>(
        &mut self,
        sources: &Sources,
        hidden_back: Option<&[bool]>,
        eye: DVec3,
        normal: DVec3,
        angle: f64,
        own_surface: u32,
        list_subpixel: bool,
        cull: Option<&Cull<'_>>,
        parts: &[PartSources<'_>],
    ) {
        self.clear();
        let n = sources.patch_count() + parts.iter().map(|w| w.parts.len()).sum::<usize>();
        if self.accumulator.len() < n {
            self.accumulator.resize(n, 0.0);
            self.covered.resize(n, 0.0);
            self.covered_pixels.resize(n, 0);
        }
        let frame = Frame::new(eye, normal, angle);
        // Only what may stand between the eye and the patches drawn part by
        // part matters then; where nothing can be left out for one of them,
        // everything does.
        let within: SmallVec<[Between; 2]> = parts
            .iter()
            .map(|w| Between::of(eye, w.parts.iter().copied()))
            .collect::<Option<_>>()
            .unwrap_or_default();
        let draw = Draw {
            frame: &frame,
            own_surface,
            hidden_back,
            list_subpixel,
            cover_only: false,
        };
        if let Some(cull) = cull.filter(|c| c.occlusion) {
            let culled = self.draw_nearest_first::<FILL>(cull, sources, &draw, &within, parts);
            self.stats.polygons_culled += culled;
            self.cover_hidden(cull, sources, &draw, &within, parts);
            self.draw_parts::<FILL>(&draw, sources, parts);
            return;
        }
        let mut ids = std::mem::take(&mut self.candidates);
        ids.clear();
        match cull {
            Some(cull) => {
                let culled =
                    cull.visible(&frame, &mut ids, &mut self.splats, &mut self.found, &within);
                self.stats.polygons_culled += culled;
            }
            None => ids.extend(0..sources.polygons.len() as u32),
        }
        for &id in &ids {
            let poly = &sources.polygons[id as usize];
            if !drawn_elsewhere(poly, &within, parts) {
                self.draw_polygon::<FILL>(poly, id, poly.patch, &draw);
            }
        }
        self.candidates = ids;
        self.draw_parts::<FILL>(&draw, sources, parts);
        let splats = std::mem::take(&mut self.splats);
        if let Some(cull) = cull {
            for &node in &splats {
                self.splat(cull, node, &frame, own_surface, list_subpixel);
            }
        }
        self.splats = splats;
    }

    /// Draws the patches of `parts` part by part, each part its own item
    /// after the patches' (see `parts.rs`).
    fn draw_parts<const FILL: bool>(
        &mut self,
        draw: &Draw<'_>,
        sources: &Sources,
        parts: &[PartSources<'_>],
    ) {
        let draw = Draw {
            list_subpixel: false,
            ..*draw
        };
        let mut item = sources.patch_count() as u32;
        for w in parts {
            for &poly in &w.parts {
                self.draw_polygon::<FILL>(poly, u32::MAX, item, &draw);
                item += 1;
            }
        }
    }

    /// Draws `poly` (source polygon `id`) seen from `draw.frame` as `item`
    /// where its front shows (see [`Hemicube::render`]).
    pub(super) fn draw_polygon<const FILL: bool>(
        &mut self,
        poly: &SourcePolygon,
        id: u32,
        item: u32,
        draw: &Draw<'_>,
    ) {
        let &Draw {
            frame,
            own_surface,
            hidden_back,
            list_subpixel,
            cover_only,
        } = draw;
        if poly.surface == own_surface || (poly.centre - frame.eye).dot(frame.normal) < -poly.radius
        {
            self.stats.polygons_culled += 1;
            return;
        }
        let count = poly.count as usize;
        let mut local = [DVec3::ZERO; 4];
        let mut above = false;
        let mut scale_squared: f64 = 0.0;
        for (l, v) in local.iter_mut().zip(&poly.vertices[..count]) {
            *l = frame.local(*v);
            above |= l.z > 0.0;
            scale_squared = scale_squared.max(l.length_squared());
        }
        // One square root: it is monotonic and correctly rounded, so this is
        // the largest of the vertices' distances to the bit.
        let scale = scale_squared.sqrt();
        if !above {
            self.stats.polygons_culled += 1;
            return;
        }
        // Plane of the polygon in local coordinates: m . q = h. The receiver
        // sees the front when it lies on the normal's side (h < 0).
        let m = frame.direction(poly.normal);
        let h = m.dot(local[0]);
        if h.abs() <= 1e-12 * scale {
            self.stats.polygons_culled += 1;
            return; // seen edge-on: covers no pixel
        }
        if h > 0.0 && hidden_back.is_some_and(|hidden| hidden[poly.surface as usize]) {
            self.stats.back_faces_skipped += 1;
            return;
        }
        let item = if h < 0.0 { item } else { BACK_FACE };
        if cover_only && item == BACK_FACE {
            return; // back faces cover nothing that counts
        }
        let near = 1e-7 * scale;
        match sole_face(&local[..count]) {
            Some(fi) => {
                let face = Face::ALL[fi];
                let target = Target {
                    face,
                    fi,
                    item,
                    cover_only,
                };
                self.rasterize::<FILL>(target, &local[..count], face.map(m), h, near);
            }
            None => {
                for (fi, face) in Face::ALL.iter().enumerate() {
                    let target = Target {
                        face: *face,
                        fi,
                        item,
                        cover_only,
                    };
                    self.rasterize::<FILL>(target, &local[..count], face.map(m), h, near);
                }
            }
        }
        if list_subpixel && item != BACK_FACE && self.covered[item as usize] == 0.0 {
            let mean = |v: &[DVec3]| v.iter().copied().sum::<DVec3>() / count as f64;
            self.subpixel
                .push((id, mean(&local[..count]), mean(&poly.vertices[..count])));
        }
    }

    /// Empties the item and depth buffers: only the drawn rectangles when
    /// skipping, since every other pixel still holds nothing.
    pub(super) fn clear(&mut self) {
        let n = self.table.n;
        for f in 0..5 {
            let d = std::mem::replace(&mut self.drawn[f], Drawn::EMPTY);
            self.nearest[f] = 0.0;
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
        self.minor.clear();
        self.stats.hemicubes += 1;
    }

    /// Clips the polygon to the face's view volume in front of the near plane,
    /// projects it, and scan converts it with a depth test on 1/depth (which is
    /// affine in face coordinates for a planar polygon, hence exact).
    fn rasterize<const FILL: bool>(
        &mut self,
        target: Target,
        local: &[DVec3],
        m: DVec3,
        h: f64,
        near: f64,
    ) {
        let Target {
            face,
            fi,
            item,
            cover_only,
        } = target;
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
        if !cover_only {
            self.stats.polygons_rasterized += 1;
        }
        // The first pixel row at or below each vertex's pixel-centre line,
        // once per vertex: every edge's row range, and the polygon's, are
        // made of these (ceil_index is monotonic, so the polygon's is the
        // least and greatest of them).
        let mut row_of = [0usize; 8];
        for (r, p) in row_of.iter_mut().zip(screen) {
            *r = ceil_index(p.y - 0.5, height);
        }
        let rows = &row_of[..count];
        let j0 = rows.iter().copied().min().unwrap_or(0);
        let j1 = rows.iter().copied().max().unwrap_or(0);
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
            let next = (k + 1) % screen.len();
            let (a, b) = (screen[k], screen[next]);
            let ((lo, hi), (r0, r1)) = if a.y <= b.y {
                ((a, b), (rows[k], rows[next]))
            } else {
                ((b, a), (rows[next], rows[k]))
            };
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
        let mut most = 0.0f64;
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
            let first = base + dw * j as f64 + du * i0 as f64;
            if !cover_only {
                let mut z = first as f32;
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
            }
            if i1 > i0 {
                // 1/depth is affine along the span: its largest value is at
                // one end.
                most = most.max(first).max(first + du * (i1 - 1 - i0) as f64);
                tested += (i1 - i0) as u64;
                covered += prefix[j * (width + 1) + i1] - prefix[j * (width + 1) + i0];
                drawn.include(j, j + 1, i0, i1);
            }
        }
        if !drawn.is_empty() && !cover_only {
            self.drawn[fi].include(drawn.j0, drawn.j1, drawn.i0, drawn.i1);
            // The pixels' single-precision steps can overshoot the largest
            // span end by rounding only; the margin covers it many times over.
            self.nearest[fi] = self.nearest[fi].max((most * (1.0 + NEAREST_MARGIN)) as f32);
        }
        if !cover_only {
            self.stats.pixels_tested += tested;
        }
        if item < BACK_FACE && covered > 0.0 {
            let slot = &mut self.covered[item as usize];
            if *slot == 0.0 {
                self.covered_touched.push(item);
            }
            *slot += covered;
            self.covered_pixels[item as usize] += tested as u32;
        }
    }
}

/// Whether `poly` is drawn part by part (with `parts`) or can hide none of
/// the patches drawn that way (outside every one of `within`), so that the
/// pass over the patches leaves it out.
pub(super) fn drawn_elsewhere(
    poly: &SourcePolygon,
    within: &[Between],
    parts: &[PartSources<'_>],
) -> bool {
    parts.iter().any(|w| w.patch == poly.patch)
        || (!within.is_empty() && !within.iter().any(|b| b.meets(poly.centre, poly.radius)))
}

/// The face whose view cone holds every vertex of `local` strictly inside
/// it, if there is one: a convex polygon then lies in that cone, and each
/// other face's frustum test in `rasterize` rejects it on one plane (every
/// vertex beyond it by a strict inequality on the same values), so drawing
/// that face alone gives the same pixels. Most polygons a hemi-cube draws
/// are small and fall in one face.
fn sole_face(local: &[DVec3]) -> Option<usize> {
    let region = |l: DVec3| {
        let (ax, ay) = (l.x.abs(), l.y.abs());
        if l.z > ax && l.z > ay {
            Some(0)
        } else if l.x > ay && l.x > l.z {
            Some(1)
        } else if -l.x > ay && -l.x > l.z {
            Some(2)
        } else if l.y > ax && l.y > l.z {
            Some(3)
        } else if -l.y > ax && -l.y > l.z {
            Some(4)
        } else {
            None
        }
    };
    let first = region(local[0])?;
    local[1..]
        .iter()
        .all(|l| region(*l) == Some(first))
        .then_some(first)
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
    (t + i64::from((t as f64) < x)) as usize
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

#[cfg(test)]
mod tests {
    use super::super::DeltaTable;
    use super::*;
    use crate::formfactor::visibility::unit;
    use std::sync::Arc;

    #[test]
    fn a_polygon_in_one_face_cone_is_rejected_by_every_other_face() {
        // What `draw_polygon` relies on to draw such a polygon on its sole
        // face: each other face's own test draws none of it.
        let mut cube = Hemicube::new(Arc::new(DeltaTable::new(16)), 1);
        let mut state = 7u64;
        let mut next = || 2.0 * unit(&mut state) - 1.0;
        let (mut sole, mut spanning) = (0, 0);
        for _ in 0..5000 {
            let c = DVec3::new(next(), next(), next());
            let tri: Vec<DVec3> = (0..3)
                .map(|_| c + DVec3::new(next(), next(), next()) * 0.3)
                .collect();
            let Some(f) = sole_face(&tri) else {
                spanning += 1;
                continue;
            };
            sole += 1;
            // The face the polygon's centre direction falls in is its own.
            let centre = tri.iter().copied().sum::<DVec3>() / 3.0;
            if let Some((fi, _, _)) = cube.pixel_of(centre) {
                assert_eq!(fi, f, "{tri:?}");
            }
            for (fi, face) in Face::ALL.iter().enumerate() {
                if fi == f {
                    continue;
                }
                let before = cube.stats.polygons_rasterized;
                let target = Target {
                    face: *face,
                    fi,
                    item: 0,
                    cover_only: false,
                };
                cube.rasterize::<true>(target, &tri, face.map(DVec3::Z), -1.0, 1e-9);
                assert_eq!(
                    cube.stats.polygons_rasterized, before,
                    "face {fi} drew a polygon of face {f}: {tri:?}"
                );
                assert!(cube.drawn[fi].is_empty());
            }
        }
        assert!(sole > 1000 && spanning > 100, "{sole} {spanning}");
    }
}
