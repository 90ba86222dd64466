//! Emitter entries of a hybrid row: the visible form factor of every emitter
//! polygon the receiver sees, found exactly (by clipping the shaft, else by
//! shadow rays) rather than read from the pixels, so that penumbrae do not
//! inherit the item buffer's staircase.
//!
//! The exact path costs a shaft walk and a clipping per emitter polygon, and
//! up to a thousand rays when the shaft is crowded. A receiver that sees many
//! emitter polygons (an emissive fan, a mesh of small LEDs, a tessellated
//! lamp) would pay that hundreds of times per row; but an emitter seen as
//! less than a pixel casts a penumbra no wider than what a pixel of the
//! hemi-cube resolves anyway. Past [`MANY_EMITTERS`] seen polygons, those
//! smaller than a pixel take Lambert's formula at the receiving point times
//! one shadow ray to their centre, and the cost of a row stays in proportion
//! to what its pixels can tell apart. Rows that see fewer emitter polygons
//! (every built-in scene) are computed as before, bit for bit.

use super::Hemicube;
use crate::formfactor::{point_to_polygon, EmitterVisibility, PixelHint, Row, Sources};
use crate::math::polygon_area;
use glam::DVec3;

/// A row that sees more emitter polygons than this treats those seen as
/// less than a pixel with one shadow ray each.
pub(crate) const MANY_EMITTERS: usize = 64;

/// One emitter polygon a receiver sees: its patch, its index among the
/// source polygons and its unoccluded form factor.
#[derive(Clone, Copy)]
struct Seen {
    patch: u32,
    polygon: u32,
    unoccluded: f64,
}

impl Hemicube {
    /// Replaces (or adds) the entry of every emitter patch the receiver at
    /// `eye` (unit `normal`, on `own_surface`) sees in `entries` (sorted by
    /// patch; `(patch, form factor, partly hidden)`) by its visible form
    /// factor, summed over the patch's polygons. `row` holds the pixels each
    /// patch won.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn emitter_entries(
        &mut self,
        row: &Row,
        entries: &mut Vec<(u32, f64, bool)>,
        sources: &Sources,
        eye: DVec3,
        normal: DVec3,
        own_surface: u32,
        visibility: &EmitterVisibility<'_>,
    ) {
        let mut seen: Vec<Seen> = Vec::new();
        for &j in &sources.emitters {
            // Polygon by polygon (a face cluster that emits has several).
            for q in sources.range(j) {
                let poly = &sources.polygons[q];
                if poly.surface == own_surface {
                    continue;
                }
                let unoccluded = point_to_polygon(eye, normal, poly.corners());
                if unoccluded > 0.0 {
                    seen.push(Seen {
                        patch: j,
                        polygon: q as u32,
                        unoccluded,
                    });
                }
            }
        }
        if seen.is_empty() {
            return;
        }
        let many = seen.len() > MANY_EMITTERS;
        // The solid angle of the pixel at the top face's centre, the largest.
        let pixel = (2.0 / self.table.n as f64).powi(2);
        let mut changed = false;
        let mut i = 0;
        while i < seen.len() {
            let j = seen[i].patch;
            let hint = self.hint(row, j);
            let mut f = 0.0;
            while i < seen.len() && seen[i].patch == j {
                let s = seen[i];
                f += if many && solid_angle(sources, s.polygon, eye) < pixel {
                    self.stats.emitters_one_ray += 1;
                    let occluders = visibility.occluders;
                    if occluders.emitter_centre_visible(sources, eye, own_surface, s.polygon) {
                        s.unoccluded
                    } else {
                        0.0
                    }
                } else {
                    self.stats.emitters_exact += 1;
                    exact(sources, visibility, eye, normal, own_surface, s, hint)
                };
                i += 1;
            }
            match entries.binary_search_by_key(&j, |e| e.0) {
                Ok(k) => entries[k] = (j, f, false),
                Err(k) => entries.insert(k, (j, f, false)),
            }
            changed = true;
        }
        if changed {
            entries.retain(|e| e.1 > 0.0);
        }
    }

    /// What the item buffer saw of emitter patch `j`: how far the rays must
    /// go before their answer is trusted.
    fn hint(&self, row: &Row, j: u32) -> PixelHint {
        let (won, covered) = (row.get(j), self.covered[j as usize]);
        if covered <= 0.0 {
            PixelHint::Unseen
        } else if won >= covered * (1.0 - 1e-6) {
            PixelHint::Whole
        } else if won > 0.0 {
            PixelHint::Partial
        } else {
            PixelHint::Hidden
        }
    }
}

/// The visible form factor of the seen polygon `s`: the element's mean where
/// every sample point can be clipped exactly (the centre's unoccluded form
/// factor instead where the sampling asks for it and nothing hides any of
/// the emitter from any point), else the centre's with ray-cast visibility.
fn exact(
    sources: &Sources,
    visibility: &EmitterVisibility<'_>,
    eye: DVec3,
    normal: DVec3,
    own_surface: u32,
    s: Seen,
    hint: PixelHint,
) -> f64 {
    let EmitterVisibility {
        occluders,
        seed,
        samples,
        centre_where_clear,
    } = *visibility;
    let exact_mean = if samples.is_empty() {
        None
    } else {
        let clear = centre_where_clear.then_some(s.unoccluded);
        occluders.mean_visible_form_factor(sources, samples, normal, own_surface, s.polygon, clear)
    };
    exact_mean.unwrap_or_else(|| {
        s.unoccluded
            * occluders.visible_fraction(sources, eye, normal, own_surface, s.polygon, seed, hint)
    })
}

/// The solid angle polygon `q` subtends at `eye`, to first order (its area
/// foreshortened over the squared distance to its centre): good enough to
/// tell what is smaller than a pixel.
fn solid_angle(sources: &Sources, q: u32, eye: DVec3) -> f64 {
    let poly = &sources.polygons[q as usize];
    let d = poly.centre - eye;
    let r2 = d.length_squared();
    if r2 <= 0.0 {
        return f64::INFINITY;
    }
    polygon_area(poly.corners()) * poly.normal.dot(d).abs() / (r2 * r2.sqrt())
}

/// The visible form factor from `eye` (unit `normal`, on `own_surface`) to
/// every emitter patch it sees, by patch, found as
/// [`Hemicube::emitter_entries`] finds it but without an item buffer of its
/// own: where clipping cannot decide, the rays trust what `hint` says of
/// each patch (what another receiver's pixels saw of it). `None` when the
/// receiver sees more than [`MANY_EMITTERS`] emitter polygons (such rows
/// lean on their pixels).
pub(crate) fn emitter_form_factors(
    sources: &Sources,
    eye: DVec3,
    normal: DVec3,
    own_surface: u32,
    visibility: &EmitterVisibility<'_>,
    hint: &dyn Fn(u32) -> PixelHint,
) -> Option<Vec<(u32, f64)>> {
    let mut seen = 0;
    let mut out: Vec<(u32, f64)> = Vec::new();
    for &j in &sources.emitters {
        let mut f = 0.0;
        // Once per patch, and only for a patch the receiver sees.
        let mut patch_hint = None;
        for q in sources.range(j) {
            let poly = &sources.polygons[q];
            if poly.surface == own_surface {
                continue;
            }
            let unoccluded = point_to_polygon(eye, normal, poly.corners());
            if unoccluded <= 0.0 {
                continue;
            }
            seen += 1;
            if seen > MANY_EMITTERS {
                return None;
            }
            let s = Seen {
                patch: j,
                polygon: q as u32,
                unoccluded,
            };
            let h = *patch_hint.get_or_insert_with(|| hint(j));
            f += exact(sources, visibility, eye, normal, own_surface, s, h);
        }
        if f > 0.0 {
            out.push((j, f));
        }
    }
    Some(out)
}
