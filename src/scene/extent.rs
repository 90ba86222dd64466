//! The scene's size for defaults that scale with it (patch size, smallest
//! element, coplanar gap): the geometry that matters, not whatever lies
//! farthest out. One stray triangle a kilometre away would otherwise make
//! every wall of a room one patch and every plane within a centimetre of
//! another one plane.

use super::Scene;
use glam::DVec3;

/// The bulk of a scene: on each axis, the surfaces whose centres lie within
/// this many times the spread of the middle half of the area (or the typical
/// surface's size, if larger) of that middle half.
const REACH: f64 = 2.0;

/// The bulk's box stands for the scene only when the whole box's diagonal
/// is more than this many times its own: otherwise the whole box is used, as
/// it always was.
const FAR: f64 = 10.0;

/// What lies outside the bulk of a scene's area.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outliers {
    /// The scene's size (see [`Scene::extent`]): the diagonal of the box of
    /// the bulk of its surfaces when outliers lie far away, else
    /// `diameter`.
    pub extent: f64,
    /// The diagonal of the box of every surface.
    pub diameter: f64,
    /// Indices of the objects with a surface outside the bulk's box by more
    /// than its diagonal, in order.
    pub objects: Vec<usize>,
}

impl Scene {
    /// The scene's size, from which default patch sizes and tolerances are
    /// derived: the bounding-box diagonal ([`Scene::diameter`]), unless a
    /// few surfaces lie so far out that the box is more than ten times the
    /// diagonal of the box of the rest (the surfaces whose centres lie within
    /// a few spreads of the middle half of the area on every axis); then the
    /// latter (see [`Scene::outliers`]).
    #[must_use]
    pub fn extent(&self) -> f64 {
        self.outliers().extent
    }

    /// The scene's size ([`Scene::extent`]) and the objects far outside the
    /// bulk of its area that it leaves out.
    #[must_use]
    pub fn outliers(&self) -> Outliers {
        let diameter = self.diameter();
        let whole = Outliers {
            extent: diameter,
            diameter,
            objects: Vec::new(),
        };
        let total: f64 = self.surfaces.iter().map(|s| s.area).sum();
        if !total.is_finite() || total <= 0.0 || self.surfaces.len() < 2 {
            return whole;
        }
        let centres: Vec<DVec3> = self
            .surfaces
            .iter()
            .map(|s| s.vertices.iter().copied().sum::<DVec3>() / s.vertices.len() as f64)
            .collect();
        // The typical surface's size: the area-weighted median diagonal.
        let mut sizes: Vec<(f64, f64)> = self
            .surfaces
            .iter()
            .map(|s| (bounds_of(&s.vertices).length(), s.area))
            .collect();
        sizes.sort_by(|a, b| a.0.total_cmp(&b.0));
        let typical = quantile(&sizes, 0.5 * total);
        let mut lo = DVec3::ZERO;
        let mut hi = DVec3::ZERO;
        for axis in 0..3 {
            let mut order: Vec<(f64, f64)> = centres
                .iter()
                .zip(&self.surfaces)
                .map(|(c, s)| (c[axis], s.area))
                .collect();
            order.sort_by(|a, b| a.0.total_cmp(&b.0));
            let q1 = quantile(&order, 0.25 * total);
            let q3 = quantile(&order, 0.75 * total);
            let reach = REACH * (q3 - q1).max(typical);
            lo[axis] = q1 - reach;
            hi[axis] = q3 + reach;
        }
        // The bulk: every surface whose centre is in that box, whole.
        let (mut blo, mut bhi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (c, s) in centres.iter().zip(&self.surfaces) {
            if c.cmpge(lo).all() && c.cmple(hi).all() {
                for v in &s.vertices {
                    blo = blo.min(*v);
                    bhi = bhi.max(*v);
                }
            }
        }
        if blo.x > bhi.x {
            return whole;
        }
        let extent = (bhi - blo).length();
        if !extent.is_finite() || extent <= 0.0 || diameter <= FAR * extent {
            return whole;
        }
        let (far_lo, far_hi) = (blo - DVec3::splat(extent), bhi + DVec3::splat(extent));
        let mut objects: Vec<usize> = self
            .surfaces
            .iter()
            .filter(|s| {
                s.vertices
                    .iter()
                    .any(|v| v.cmplt(far_lo).any() || v.cmpgt(far_hi).any())
            })
            .map(|s| s.object as usize)
            .collect();
        objects.sort_unstable();
        objects.dedup();
        Outliers {
            extent,
            diameter,
            objects,
        }
    }

    /// A warning naming the objects far outside the bulk of the scene, when
    /// the scene's size leaves them out (see [`Scene::outliers`]).
    #[must_use]
    pub(crate) fn outlier_warning(&self) -> Option<String> {
        let o = self.outliers();
        if o.objects.is_empty() {
            return None;
        }
        const SHOWN: usize = 5;
        let mut names: Vec<String> = o
            .objects
            .iter()
            .take(SHOWN)
            .map(|&i| {
                self.objects
                    .get(i)
                    .map_or_else(|| format!("#{i}"), |ob| format!("'{}'", ob.name))
            })
            .collect();
        if o.objects.len() > SHOWN {
            names.push(format!("and {} more", o.objects.len() - SHOWN));
        }
        let which = if o.objects.len() == 1 {
            "object"
        } else {
            "objects"
        };
        let verb = if o.objects.len() == 1 { "lies" } else { "lie" };
        Some(format!(
            "{which} {} {verb} far outside the rest of the scene (the whole scene spans {:.3e} m, the \
             rest {:.3e} m): default patch size, smallest element and coplanar gap follow \
             the rest; a distant sun or sky is fine, a stray object may be a modelling \
             mistake",
            names.join(", "),
            o.diameter,
            o.extent
        ))
    }
}

/// The diagonal of the bounding box of `v`.
fn bounds_of(v: &[DVec3]) -> DVec3 {
    let lo = v.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
    let hi = v.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
    hi - lo
}

/// The coordinate at which the running area of `sorted` (coordinate, area)
/// pairs first exceeds `area`.
fn quantile(sorted: &[(f64, f64)], area: f64) -> f64 {
    let mut run = 0.0;
    let mut last = 0.0;
    for &(x, a) in sorted {
        run += a;
        last = x;
        if run > area {
            return x;
        }
    }
    last
}
