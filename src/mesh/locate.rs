//! Point location and edge neighbours within a surface lattice, and the 2:1
//! balance that keeps neighbouring leaves within one level of each other.

use super::cell::{Probe, MAX_DEPTH};
use super::{ElementKey, Mesh};

impl Mesh {
    /// The deepest element at depth at most `max_depth` whose cell contains the
    /// probe on `surface`, or `None` when the probe lies outside the surface.
    #[must_use]
    pub fn locate(&self, surface: u32, probe: Probe, max_depth: u8) -> Option<ElementKey> {
        let lattice = &self.surfaces[surface as usize];
        let local = lattice.patch_at(probe)?;
        let mut key = self.top_roots[(lattice.first_root + local) as usize];
        loop {
            let e = &self.elements[key];
            if e.is_leaf() || e.depth >= max_depth {
                return Some(key);
            }
            key = *e
                .children
                .iter()
                .find(|c| self.elements[**c].cell.contains(probe))?;
        }
    }

    /// For each edge of `key`: the element across it at the same depth, or the
    /// leaf that covers that place if the other side is coarser. `None` on the
    /// surface's boundary.
    #[must_use]
    pub fn edge_neighbours(&self, key: ElementKey) -> smallvec::SmallVec<[Option<ElementKey>; 4]> {
        let e = &self.elements[key];
        e.cell
            .edge_probes()
            .iter()
            .map(|(probe, _, _)| self.locate(e.surface, *probe, e.depth))
            .collect()
    }

    /// Splits leaves until every leaf's edge neighbours are at most one level
    /// coarser. `seeds` are the leaves to start checking from (the new ones).
    /// Returns the leaves split to restore balance.
    pub fn balance(&mut self, seeds: Vec<ElementKey>) -> Vec<ElementKey> {
        let mut split = Vec::new();
        let mut work = seeds;
        while let Some(key) = work.pop() {
            let Some(e) = self.elements.get(key) else {
                continue;
            };
            if !e.is_leaf() || e.depth < 2 {
                continue;
            }
            let depth = e.depth;
            for n in self.edge_neighbours(key).into_iter().flatten() {
                let ne = &self.elements[n];
                if ne.is_leaf() && ne.depth + 1 < depth && ne.depth < MAX_DEPTH {
                    let kids = self.split(n);
                    split.push(n);
                    work.extend_from_slice(&kids);
                    // Re-check this leaf: its neighbour may still be too coarse.
                    work.push(key);
                }
            }
        }
        split
    }
}
