//! The parts of a shaped patch: a cut of its quadtree, the nodes below it,
//! and the radiosity of each part's exposed leaves.

use super::Part;
use crate::formfactor::{FormFactors, SourcePolygon};
use crate::math::Rgb;
use crate::mesh::{ElementKey, Mesh};
use crate::solve::Radiosity;

/// Most parts a patch's cut has: its leaves, or the deepest cut of its
/// quadtree with at most this many nodes (receivers near a part look
/// inside it).
pub(crate) const MAX_PARTS: usize = 64;

/// A shaped patch's parts (see [`Shaped::parts`]) and their mean.
///
/// [`Shaped::parts`]: super::Shaped::parts
pub(super) struct PartTree {
    pub(super) parts: Vec<Part>,
    pub(super) values: Vec<Rgb>,
    pub(super) top: usize,
    pub(super) keys: Vec<ElementKey>,
    pub(super) mean: Rgb,
}

impl PartTree {
    /// The parts under the nodes `cut` with anything exposed; `None` when
    /// fewer than two cut nodes have.
    pub(super) fn of(
        mesh: &Mesh,
        form_factors: &FormFactors,
        radiosity: &Radiosity,
        cut: &[ElementKey],
    ) -> Option<PartTree> {
        let part = |k: ElementKey| -> Option<(Part, Rgb, f64)> {
            let (area, power) = exposed_power(mesh, form_factors, radiosity, k);
            if area <= 0.0 {
                return None;
            }
            let e = &mesh.elements[k];
            let surface = &mesh.surfaces()[e.surface as usize];
            let polygon = surface.polygon(&e.cell);
            let source = SourcePolygon::new(&polygon, surface.normal, e.surface);
            let part = Part {
                area_centroid: source.area_and_centroid(),
                source,
                share: (area / e.area).min(1.0),
                children: 0..0,
            };
            Some((part, power * (1.0 / area), area))
        };
        let mut parts = Vec::new();
        let mut values = Vec::new();
        let mut keys = Vec::new();
        let mut below: Vec<(u32, ElementKey)> = Vec::new();
        let (mut area, mut power) = (0.0, Rgb::ZERO);
        for &k in cut {
            if let Some((p, value, a)) = part(k) {
                area += a;
                power += value * a;
                below.push((parts.len() as u32, k));
                parts.push(p);
                values.push(value);
                keys.push(k);
            }
        }
        let top = parts.len();
        if top < 2 {
            return None;
        }
        // Children after their parents, each node's contiguous.
        let mut next = 0;
        while next < below.len() {
            let (i, k) = below[next];
            next += 1;
            let start = parts.len() as u32;
            for &c in &mesh.elements[k].children {
                if let Some((p, value, _)) = part(c) {
                    below.push((parts.len() as u32, c));
                    parts.push(p);
                    values.push(value);
                    keys.push(c);
                }
            }
            parts[i as usize].children = start..parts.len() as u32;
        }
        Some(PartTree {
            parts,
            values,
            top,
            keys,
            mean: power * (1.0 / area),
        })
    }
}

/// The deepest cut of the quadtrees under `roots` with at most [`MAX_PARTS`]
/// nodes (the leaves when there are few enough), or `None` when even the
/// roots are too many.
pub(super) fn cut(mesh: &Mesh, roots: &[ElementKey]) -> Option<Vec<ElementKey>> {
    if roots.len() > MAX_PARTS {
        return None;
    }
    let mut parts = roots.to_vec();
    loop {
        let next: Vec<ElementKey> = parts
            .iter()
            .flat_map(|k| {
                let e = &mesh.elements[*k];
                if e.is_leaf() {
                    std::slice::from_ref(k).to_vec()
                } else {
                    e.children.to_vec()
                }
            })
            .collect();
        if next.len() == parts.len() || next.len() > MAX_PARTS {
            return Some(parts);
        }
        parts = next;
    }
}

/// The exposed area under node `k` and the power per unit of radiosity it
/// sends: sums of `A_e` and `A_e B_e` over its leaves with an exposed row.
/// Hidden leaves (under an object standing on the surface) send nothing,
/// and an interior node's stored mean would count them; a partly covered
/// leaf counts its visible part's area.
pub(super) fn exposed_power(
    mesh: &Mesh,
    form_factors: &FormFactors,
    radiosity: &Radiosity,
    k: ElementKey,
) -> (f64, Rgb) {
    let e = &mesh.elements[k];
    if e.is_leaf() {
        if !form_factors.is_exposed(k) {
            return (0.0, Rgb::ZERO);
        }
        // A leaf that objects standing on it cover in part has the mean
        // radiosity of its whole area, dark where covered; it sends that
        // power from its visible part alone.
        let visible = form_factors.view(k).map_or(1.0, |v| v.visible());
        return (e.area * visible, radiosity.element(k) * e.area);
    }
    e.children
        .iter()
        .map(|c| exposed_power(mesh, form_factors, radiosity, *c))
        .fold((0.0, Rgb::ZERO), |(a, p), (ca, cp)| (a + ca, p + cp))
}
