//! The mean visible form factor from the points of a receiving element to
//! an emitter, exact by clipping the shadows in each point's shaft (see
//! `shaft.rs`).

use super::Occluders;
use crate::formfactor::bvh_walk::walk;
use crate::formfactor::shaft::{
    pieces_form_factor, sliver_area, subtract, Piece, Shaft, MAX_OCCLUDERS,
};
use crate::formfactor::{point_to_polygon, Sources};
use glam::DVec3;
use smallvec::SmallVec;

/// Past this many surfaces casting a shadow on the first point of a
/// receiving element, [`Occluders::mean_visible_form_factor`] asked to keep
/// to few casters (shadowed sampling) stops and leaves the light to the
/// element's centre (see [`PointsMean::Crowded`]). Each point clips every
/// shadow of its own, so a shaft crowded by a tessellated mesh's facets costs
/// four times the centre's clipping for an edge no sharper than the facets'
/// staircase; the sharp edges that a centre misses (a box's side across a
/// dim element) come from a few large planar surfaces, however many patches
/// they are split into.
pub(crate) const FEW_CASTERS: usize = 4;

/// What [`Occluders::mean_visible_form_factor`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PointsMean {
    /// The points' mean visible form factor, and whether anything hides
    /// part of the light from any point (or a point sees none of its front).
    Visible {
        /// The mean.
        mean: f64,
        /// Whether the light's visibility changes across the points.
        shadowed: bool,
    },
    /// Asked to keep to few casters, more than [`FEW_CASTERS`] surfaces
    /// shadow the first point: the centre must decide.
    Crowded,
    /// Clipping cannot decide (too many shadows or pieces, or geometry too
    /// thin to project): the rays must.
    Undecided,
}

impl PointsMean {
    /// The mean found, if one was.
    pub(crate) fn found(self) -> Option<f64> {
        match self {
            PointsMean::Visible { mean, .. } => Some(mean),
            PointsMean::Crowded | PointsMean::Undecided => None,
        }
    }
}

impl Occluders {
    /// The mean over `samples` (points of the receiving element, with weights
    /// summing to 1) of the visible form factor to patch `target`, each computed
    /// exactly by clipping; [`PointsMean::Undecided`] if any point needs the
    /// rays instead.
    ///
    /// The BVH is walked once for all the points: a node is entered when any
    /// point's shaft may hold something in it; the first point clips what
    /// its shaft holds there and then, and each other point later clips the
    /// polygons its own shaft may hold. Each point gets the same shadows
    /// in the same order as a walk of its own would give it (a polygon in a
    /// node its shaft misses clips to nothing), so the result is the same as
    /// point by point, for one walk instead of one per point.
    ///
    /// With `few_casters`, more than [`FEW_CASTERS`] surfaces shadowing
    /// the first point end the walk with [`PointsMean::Crowded`].
    #[must_use]
    pub(crate) fn mean_visible_form_factor(
        &self,
        sources: &Sources,
        samples: &[(DVec3, f64)],
        normal: DVec3,
        own_surface: u32,
        target: u32,
        few_casters: bool,
    ) -> PointsMean {
        let poly = &sources.polygons[target as usize];
        let light = &poly.vertices[..poly.count as usize];
        let mut points: SmallVec<[PointShaft<'_>; 4]> = SmallVec::new();
        for &(eye, weight) in samples {
            let full = point_to_polygon(eye, normal, light);
            // An emitter shines from its front only.
            if full <= 0.0 || poly.normal.dot(eye - light[0]) <= 0.0 {
                continue;
            }
            let Some(shaft) = Shaft::new(eye, normal, light, poly.normal) else {
                return PointsMean::Undecided;
            };
            points.push(PointShaft {
                weight,
                full,
                shaft,
            });
        }
        if points.is_empty() {
            // The centre may see the light's front; no point does.
            return PointsMean::Visible {
                mean: 0.0,
                shadowed: true,
            };
        }
        // Shadowed sampling counts the surfaces casting the first point's
        // shadows: a box face split into patches casts one straight edge.
        let crowd_limit = few_casters.then_some(FEW_CASTERS);
        let mut casters: SmallVec<[u32; 8]> = SmallVec::new();
        let mut crowded = false;
        // A point that does not see the light's front at all is as good as
        // a shadow: the light's visibility changes across the element.
        let mut shadowed = points.len() < samples.len();
        // The first point clips what it holds as the walk meets it, so that
        // a shaft holding too many shadows ends the walk early, as it does
        // for the centre alone; the polygons the other points may hold are
        // kept for them. Both in the BVH's order, which is fixed by its
        // build, so that each point's pieces (and the sum over them) come
        // out the same on every run.
        let (first, others) = points.split_first().expect("points is not empty");
        let mut first_shadows: SmallVec<[Piece; 4]> = SmallVec::new();
        let mut held: SmallVec<[u32; 32]> = SmallVec::new();
        let mut overflow = false;
        // Only the nodes some shaft's planes do not cut away: a shaft's
        // bounding box holds many polygons its thin pyramid misses.
        walk(
            &self.bvh,
            self.centre,
            |lo, hi| points.iter().any(|p| !p.shaft.misses_box(lo, hi)),
            |id| {
                let p = &sources.polygons[id];
                if p.surface == own_surface || p.surface == poly.surface {
                    return true;
                }
                if !first.shaft.misses(p.centre, p.radius) {
                    if let Some(shadow) = first.shaft.shadow_of(p.corners()) {
                        first_shadows.push(shadow);
                        if first_shadows.len() > MAX_OCCLUDERS {
                            overflow = true;
                            return false;
                        }
                        if let Some(limit) = crowd_limit {
                            if !casters.contains(&p.surface) {
                                casters.push(p.surface);
                                if casters.len() > limit {
                                    crowded = true;
                                    return false;
                                }
                            }
                        }
                    }
                }
                if others.iter().any(|s| !s.shaft.misses(p.centre, p.radius)) {
                    held.push(id as u32);
                }
                true
            },
        );
        if crowded {
            return PointsMean::Crowded;
        }
        if overflow {
            return PointsMean::Undecided;
        }
        let sum = (|| {
            let mut sum =
                first.weight * first.visible_past(&first_shadows, light, normal, poly.normal)?;
            shadowed |= !first_shadows.is_empty();
            for point in others {
                let shadows = point.shadows(sources, &held)?;
                sum += point.weight * point.visible_past(&shadows, light, normal, poly.normal)?;
                shadowed |= !shadows.is_empty();
            }
            Some(sum)
        })();
        match sum {
            None => PointsMean::Undecided,
            Some(mean) => PointsMean::Visible { mean, shadowed },
        }
    }
}

/// One point of a receiving element with its weight and its shaft to a
/// light (see [`Occluders::mean_visible_form_factor`]).
struct PointShaft<'a> {
    weight: f64,
    /// The unoccluded form factor from the point to the light.
    full: f64,
    shaft: Shaft<'a>,
}

impl PointShaft<'_> {
    /// The shadows on the light of the polygons `held` (in the BVH's order)
    /// that the shaft holds; `None` when there are more than
    /// [`MAX_OCCLUDERS`] (the rays decide then).
    fn shadows(&self, sources: &Sources, held: &[u32]) -> Option<SmallVec<[Piece; 4]>> {
        let mut shadows = SmallVec::new();
        for &id in held {
            let p = &sources.polygons[id as usize];
            if self.shaft.misses(p.centre, p.radius) {
                continue;
            }
            if let Some(shadow) = self.shaft.shadow_of(p.corners()) {
                shadows.push(shadow);
                if shadows.len() > MAX_OCCLUDERS {
                    return None;
                }
            }
        }
        Some(shadows)
    }

    /// The form factor from the point to the part of `light` that
    /// `shadows` leave, by cutting them out of it; `None` when the geometry
    /// is degenerate for projection (the rays decide then).
    fn visible_past(
        &self,
        shadows: &[Piece],
        light: &[DVec3],
        normal: DVec3,
        light_normal: DVec3,
    ) -> Option<f64> {
        if shadows.is_empty() {
            return Some(self.full);
        }
        let mut pieces = vec![Piece::from_slice(light)];
        let min_area = sliver_area(light);
        for shadow in shadows {
            if !subtract(&mut pieces, shadow, light_normal, min_area) {
                return None;
            }
            if pieces.is_empty() {
                return Some(0.0);
            }
        }
        // What is left of the light can be no more than all of it.
        Some(pieces_form_factor(self.shaft.eye(), normal, &pieces).clamp(0.0, self.full))
    }
}
