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
//! to what its pixels can tell apart. In such rows, too, a polygon of a patch
//! the pixels saw whole (or saw hidden wherever it would lie) takes that
//! answer without rays: only patches the pixels saw in part, where a shadow
//! edge crosses, are clipped exactly. (A tessellated lamp whose emissive
//! texture lights 2 500 facets spent two thirds of its time clipping
//! polygons the pixels had seen whole.) Rows that see fewer emitter
//! polygons (every built-in scene) are computed as before, bit for bit.

use super::Hemicube;
use crate::formfactor::{point_to_polygon, EmitterVisibility, PixelHint, PointsMean, Row, Sources};
use crate::math::polygon_area;
use glam::DVec3;
use smallvec::SmallVec;
use std::cell::Cell;

/// A row that sees more emitter polygons than this treats those seen as
/// less than a pixel with one shadow ray each.
pub(crate) const MANY_EMITTERS: usize = 64;

/// In a row that sees many emitter polygons, a polygon of a patch the pixels
/// saw whole, or saw none of, is taken as the pixels saw it only while it
/// is seen as less than this many pixels. A larger one may still show a
/// sliver past what hides it, or hide a sliver behind what the pixels
/// missed, and a row taken at the element's points needs what each point
/// sees of it: clipping finds both. (Taking every such polygon from the
/// pixels put elements of a furnace room 1.5% off.)
const TRUSTED_PIXELS: f64 = 16.0;

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
        let seen = seen_from(sources, eye, normal, own_surface);
        if seen.is_empty() {
            return;
        }
        let many = seen.len() > MANY_EMITTERS;
        // The solid angle of the pixel at the top face's centre, the largest.
        let pixel = (2.0 / self.table.n as f64).powi(2);
        let receiver = Receiver {
            sources,
            visibility,
            eye,
            normal,
            own_surface,
        };
        let mut looks: Vec<(Seen, PixelHint, Look)> = Vec::with_capacity(seen.len());
        let mut hint = (u32::MAX, PixelHint::Unseen);
        for &s in &seen {
            if hint.0 != s.patch {
                hint = (s.patch, self.hint(row, s.patch));
            }
            let angle = if many {
                solid_angle(sources, s.polygon, eye)
            } else {
                f64::INFINITY
            };
            let trusted = angle < TRUSTED_PIXELS * pixel
                && matches!(hint.1, PixelHint::Whole | PixelHint::Hidden);
            let look = if many && trusted {
                // A small polygon of a patch the pixels saw whole, or saw
                // none of: no shadow edge crosses it that the item buffer
                // could resolve, so its answer is taken.
                self.stats.emitters_by_pixels += 1;
                let whole = matches!(hint.1, PixelHint::Whole);
                Look::Pixels(if whole { s.unoccluded } else { 0.0 })
            } else if many && angle < pixel {
                self.stats.emitters_one_ray += 1;
                let occluders = visibility.occluders;
                let open = occluders.emitter_centre_visible(sources, eye, own_surface, s.polygon);
                Look::OneRay(if open { s.unoccluded } else { 0.0 })
            } else {
                self.stats.emitters_exact += 1;
                receiver.first_look(s, hint.1)
            };
            looks.push((s, hint.1, look));
        }
        let found = receiver.settle_row(&mut looks);
        for (j, f) in found {
            match entries.binary_search_by_key(&j, |e| e.0) {
                Ok(k) => entries[k] = (j, f, false),
                Err(k) => entries.insert(k, (j, f, false)),
            }
        }
        entries.retain(|e| e.1 > 0.0);
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

/// What a first look finds of one emitter polygon a receiving element sees.
#[derive(Clone, Copy, Debug)]
enum Look {
    /// Found at the element's centre by shadow rays (the sampling asks for
    /// no points, or clipping could not decide at them).
    Centre(f64),
    /// One shadow ray from the centre (from each point, in a row taken at
    /// the points) to a polygon smaller than a pixel in a row that sees
    /// many.
    OneRay(f64),
    /// Clipped at the element's points: their mean, and whether anything
    /// hides part of the polygon from any of them.
    Points { mean: f64, shadowed: bool },
    /// Shadowed sampling found too many surfaces casting shadows for the
    /// points: the centre decides.
    Crowded,
    /// Taken from the pixels at the centre, in a row that sees many emitter
    /// polygons, for a small polygon of a patch the pixels saw whole or saw
    /// none of. A row taken at the points looks at it exactly after all:
    /// what the points see of it may differ from what the centre's pixels
    /// did (a polygon hidden from the centre by a shadow's edge can show to
    /// some points).
    Pixels(f64),
}

/// A receiving element as its emitter entries see it: its centre `eye`,
/// unit `normal` and surface, and how its lights' visibility is found.
#[derive(Clone, Copy)]
struct Receiver<'a> {
    sources: &'a Sources,
    visibility: &'a EmitterVisibility<'a>,
    eye: DVec3,
    normal: DVec3,
    own_surface: u32,
}

impl Receiver<'_> {
    /// The first look at the seen polygon `s`: clipped at the element's sample
    /// points where they can be, else by rays at the centre.
    fn first_look(&self, s: Seen, hint: PixelHint) -> Look {
        let v = self.visibility;
        if v.samples.is_empty() {
            return Look::Centre(self.rays_at_centre(s, hint));
        }
        // Shadowed sampling keeps the points to shafts with few casters.
        let few_casters = v.shadowed_sampling;
        match v.occluders.mean_visible_form_factor(
            self.sources,
            v.samples,
            self.normal,
            self.own_surface,
            s.polygon,
            few_casters,
        ) {
            PointsMean::Visible { mean, shadowed } => Look::Points { mean, shadowed },
            PointsMean::Crowded => Look::Crowded,
            PointsMean::Undecided => Look::Centre(self.rays_at_centre(s, hint)),
        }
    }

    /// Adds to `looks` (sorted by patch, then polygon) the emitter polygons
    /// that some of the element's points see but its centre does not (a floor
    /// element reaching under a floating box, whose side's plane passes between
    /// its points), with the points' mean, and keeps them sorted by patch. A row
    /// taken at the points must hold them: without them its emitters add up to
    /// less than the points see (in a furnace, 0.4% of an element's light).
    fn looks_past_the_centre(&self, looks: &mut Vec<(Seen, PixelHint, Look)>) {
        let Receiver {
            sources,
            visibility,
            eye: _,
            normal,
            own_surface,
        } = *self;
        let samples = visibility.samples;
        let before = looks.len();
        for &j in &sources.emitters {
            for q in sources.range(j) {
                let poly = &sources.polygons[q];
                if poly.surface == own_surface
                    || looks[..before]
                        .binary_search_by_key(&(j, q as u32), |l| (l.0.patch, l.0.polygon))
                        .is_ok()
                {
                    continue;
                }
                let seen_by_a_point = samples.iter().any(|&(p, _)| {
                    poly.normal.dot(p - poly.centre) > 0.0
                        && point_to_polygon(p, normal, poly.corners()) > 0.0
                });
                if !seen_by_a_point {
                    continue;
                }
                let found = visibility.occluders.mean_visible_form_factor(
                    sources,
                    samples,
                    normal,
                    own_surface,
                    q as u32,
                    false,
                );
                // Where clipping cannot decide, the polygon is left out, as the
                // centre leaves it.
                if let Some(mean) = found.found() {
                    let s = Seen {
                        patch: j,
                        polygon: q as u32,
                        unoccluded: 0.0,
                    };
                    let look = Look::Points {
                        mean,
                        shadowed: true,
                    };
                    looks.push((s, PixelHint::Unseen, look));
                }
            }
        }
        if looks.len() > before {
            looks.sort_by_key(|l| (l.0.patch, l.0.polygon));
        }
    }

    /// The visible form factor of the seen polygon `s` from what `look` found:
    /// the points' mean where the sampling takes the points (with shadowed
    /// sampling, where something hides part of it from some point); else the
    /// centre's, its unoccluded form factor where nothing hid any of it from any
    /// point, clipped (or by rays) at the centre where too many surfaces did.
    fn settle(&self, look: Look, at_points: bool, s: Seen, hint: PixelHint) -> f64 {
        let Receiver {
            sources,
            visibility,
            eye,
            normal,
            own_surface,
        } = *self;
        let occluders = visibility.occluders;
        let at_centre = || {
            occluders
                .mean_visible_form_factor(
                    sources,
                    &[(eye, 1.0)],
                    normal,
                    own_surface,
                    s.polygon,
                    false,
                )
                .found()
                .unwrap_or_else(|| self.rays_at_centre(s, hint))
        };
        // The centre's visible share of the polygon carried over to the points'
        // mean unoccluded form factor: what the points see of it, as far as
        // its visibility is known at the centre alone.
        let at_the_points = |f: f64| {
            if f <= 0.0 {
                return 0.0;
            }
            let poly = &sources.polygons[s.polygon as usize];
            let front = |p: DVec3| poly.normal.dot(p - poly.centre) > 0.0;
            self.mean_over_points(s, front) * (f / s.unoccluded).min(1.0)
        };
        match look {
            // In a shadowed sampling row at the centre no look is shadowed
            // at the points (see `row_at_points`).
            Look::Points { mean, shadowed }
                if at_points || shadowed || !visibility.shadowed_sampling =>
            {
                mean
            }
            Look::Points { .. } => s.unoccluded,
            Look::OneRay(_) if at_points => {
                // One ray from each point, as from the centre.
                let open =
                    |p: DVec3| occluders.emitter_centre_visible(sources, p, own_surface, s.polygon);
                self.mean_over_points(s, open)
            }
            Look::Pixels(_) if at_points => {
                // Rays first, the exact look only where they leave doubt (it
                // cost 2.7 times the CPU of the lamp of the real scenes at
                // every such polygon). A patch the centre's pixels saw whole
                // whose polygon's centre every point sees takes the points'
                // rays; one they saw none of, hidden from every point at its
                // centre and near each corner, stays hidden. Elsewhere a
                // shadow's edge may cross the polygon as the points see it
                // (one ray to the centre alone left an element of a furnace
                // beside a box 0.27% off), and the exact look decides.
                let shut = Cell::new(0u32);
                let sees = |p: DVec3| {
                    let seen = occluders.emitter_centre_visible(sources, p, own_surface, s.polygon);
                    shut.set(shut.get() + u32::from(!seen));
                    seen
                };
                match hint {
                    PixelHint::Whole => {
                        let mean = self.mean_over_points(s, sees);
                        if shut.get() == 0 {
                            return mean;
                        }
                    }
                    PixelHint::Hidden if self.hidden_from_points(s) => return 0.0,
                    _ => {}
                }
                self.settle(self.first_look(s, hint), true, s, hint)
            }
            Look::Centre(f) if at_points => at_the_points(f),
            Look::Centre(f) | Look::OneRay(f) | Look::Pixels(f) => f,
            Look::Crowded if at_points => at_the_points(at_centre()),
            Look::Crowded => at_centre(),
        }
    }

    /// Shadow rays from the centre to the seen polygon `s`, weighted as its
    /// unoccluded form factor (`hint`: what the pixels saw of its patch).
    fn rays_at_centre(&self, s: Seen, hint: PixelHint) -> f64 {
        let v = self.visibility;
        let fraction = v.occluders.visible_fraction(
            self.sources,
            self.eye,
            self.normal,
            self.own_surface,
            s.polygon,
            v.seed,
            hint,
        );
        s.unoccluded * fraction
    }

    /// Whether no point of the element sees the seen polygon `s` at its
    /// centre or near any of its corners (or sees only its back).
    fn hidden_from_points(&self, s: Seen) -> bool {
        let poly = &self.sources.polygons[s.polygon as usize];
        let corners = poly.corners();
        let centre = corners.iter().copied().sum::<DVec3>() / corners.len() as f64;
        let occluders = self.visibility.occluders;
        let skip = [self.own_surface, poly.surface];
        let targets =
            std::iter::once(centre).chain(corners.iter().map(|&c| c + (centre - c) * 0.05));
        let targets: SmallVec<[DVec3; 5]> = targets.collect();
        self.visibility.samples.iter().all(|&(p, _)| {
            targets.iter().all(|&t| {
                poly.normal.dot(p - t) <= 0.0 || !occluders.clear(self.sources, p, t, skip)
            })
        })
    }

    /// The mean over the element's points from which `sees` holds of their
    /// unoccluded form factor to the seen polygon `s` (zero from the rest).
    fn mean_over_points(&self, s: Seen, sees: impl Fn(DVec3) -> bool) -> f64 {
        let corners = self.sources.polygons[s.polygon as usize].corners();
        self.visibility
            .samples
            .iter()
            .filter(|&&(p, _)| sees(p))
            .map(|&(p, w)| w * point_to_polygon(p, self.normal, corners))
            .sum()
    }

    /// The visible form factor of every emitter patch in `looks` (one row's,
    /// sorted by patch), by patch in the same order, zero where it is hidden:
    /// each polygon's look settled the way the row takes its emitters (see
    /// [`row_at_points`]), with the polygons only the points see added where
    /// the row takes them at the points.
    fn settle_row(&self, looks: &mut Vec<(Seen, PixelHint, Look)>) -> Vec<(u32, f64)> {
        let at_points = row_at_points(looks, self.visibility);
        if at_points {
            self.looks_past_the_centre(looks);
        }
        let mut out: Vec<(u32, f64)> = Vec::new();
        for &(s, hint, look) in looks.iter() {
            let f = self.settle(look, at_points, s, hint);
            match out.last_mut() {
                Some(last) if last.0 == s.patch => last.1 += f,
                _ => out.push((s.patch, f)),
            }
        }
        out
    }
}

/// Whether a row takes its emitters at the element's points, all of them:
/// with element sampling, always (the centre's one point with centre
/// sampling); with shadowed sampling, where something hides part of one of
/// them from some point. A row takes all its emitters at one set of points
/// or all at the centre: mixed, they would not add up to what the receiver
/// sees (an element in a furnace beside a wall, whose form factor curves
/// fast across it, came out 0.3% off). In a row at the points, a polygon
/// given one ray from the centre is given one from each point; one whose
/// visibility is found at the centre alone (by rays where clipping cannot
/// decide, or clipped there because too many surfaces cast shadows) takes
/// the points' mean unoccluded form factor times the centre's visible share
/// (see [`settle`]).
fn row_at_points(looks: &[(Seen, PixelHint, Look)], visibility: &EmitterVisibility<'_>) -> bool {
    if visibility.shadowed_sampling {
        looks
            .iter()
            .any(|l| matches!(l.2, Look::Points { shadowed: true, .. }))
    } else {
        visibility.samples.len() > 1
    }
}

/// Every emitter polygon (not on `own_surface`) with a positive unoccluded
/// form factor from `eye` (unit `normal`), polygon by polygon (a face
/// cluster that emits has several), by patch.
fn seen_from(sources: &Sources, eye: DVec3, normal: DVec3, own_surface: u32) -> Vec<Seen> {
    let mut seen: Vec<Seen> = Vec::new();
    for &j in &sources.emitters {
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
    seen
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
    let receiver = Receiver {
        sources,
        visibility,
        eye,
        normal,
        own_surface,
    };
    let seen = seen_from(sources, eye, normal, own_surface);
    if seen.len() > MANY_EMITTERS {
        return None;
    }
    let mut looks: Vec<(Seen, PixelHint, Look)> = Vec::with_capacity(seen.len());
    // One hint per patch, and only for a patch the receiver sees.
    let mut patch_hint = (u32::MAX, PixelHint::Unseen);
    for s in seen {
        if patch_hint.0 != s.patch {
            patch_hint = (s.patch, hint(s.patch));
        }
        looks.push((s, patch_hint.1, receiver.first_look(s, patch_hint.1)));
    }
    let mut out = receiver.settle_row(&mut looks);
    out.retain(|e| e.1 > 0.0);
    Some(out)
}
