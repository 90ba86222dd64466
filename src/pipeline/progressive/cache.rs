//! The form factors of each patch's last shot, kept for its next shots.
//!
//! A patch shoots many times while the solve converges (each time its unshot
//! radiosity has grown again), and each shot renders its cells' hemi-cubes
//! anew for the same form factors. The first shot's factors are kept instead,
//! per receiving leaf, and later shots only scale them: rendering dominates a
//! shot's cost. The factors are the transpose of the gathering rows (a leaf
//! seeing a patch is a nonzero both ways), so the cache holds about as many
//! entries as the Gauss-Seidel path's rows; a byte budget bounds it, and a
//! patch that does not fit renders every shot as before.
//!
//! A refinement pass replaces some leaves by their children: entries of leaves
//! that are no longer leaves are dropped, and each new leaf brings its entry
//! from the gathering row it computed to adopt what has been shot (`F_ej` from
//! leaf `e` to patch `j` is the factor a shot of `j` needs). So no cached patch
//! renders again when the mesh changes.

use super::Receivers;
use crate::formfactor::FormFactors;
use crate::mesh::{ElementKey, Mesh};

/// Bytes one cached entry takes.
pub(super) const ENTRY_BYTES: usize = std::mem::size_of::<(ElementKey, f64)>();

#[derive(Clone, Debug)]
struct Cached {
    /// Shooter cell depth the factors were rendered at.
    depth: u8,
    /// `(leaf, F_ei)`, leaf to patch, without the patch's open scale.
    factors: Vec<(ElementKey, f64)>,
}

/// Per patch, the form factors from every receiving leaf to it.
#[derive(Clone, Debug, Default)]
pub(crate) struct ShotCache {
    patches: Vec<Option<Cached>>,
    entries: usize,
    budget_entries: usize,
}

impl ShotCache {
    /// An empty cache for `patches` patches holding at most `budget_bytes`.
    #[must_use]
    pub(crate) fn new(patches: usize, budget_bytes: usize) -> Self {
        ShotCache {
            patches: vec![None; patches],
            entries: 0,
            budget_entries: budget_bytes / ENTRY_BYTES,
        }
    }

    /// The factors of `patch`, if kept from a shot at a cell depth of at least
    /// `depth`.
    #[must_use]
    pub(crate) fn get(&self, patch: u32, depth: u8) -> Option<&[(ElementKey, f64)]> {
        match &self.patches[patch as usize] {
            Some(c) if c.depth >= depth => Some(&c.factors),
            _ => None,
        }
    }

    /// Keeps `factors` of `patch` (rendered at cell depth `depth`), replacing
    /// what it held for the patch, if they fit the budget; hands them back
    /// when they do not.
    pub(crate) fn store(
        &mut self,
        patch: u32,
        depth: u8,
        factors: Vec<(ElementKey, f64)>,
    ) -> Result<(), Vec<(ElementKey, f64)>> {
        let slot = &mut self.patches[patch as usize];
        let old = slot.as_ref().map_or(0, |c| c.factors.len());
        if self.budget_entries == 0 || self.entries - old + factors.len() > self.budget_entries {
            return Err(factors);
        }
        self.entries = self.entries - old + factors.len();
        *slot = Some(Cached { depth, factors });
        Ok(())
    }

    /// Replaces every patch's factors by the transpose of the gathering rows
    /// in `form_factors` of `keys` (every leaf of the mesh), if they fit the
    /// budget; returns whether they did. From then on every patch is served
    /// at any depth, and a shot of patch `j` delivers to each leaf `e` by its
    /// row entry `F_ej`, the factor the Gauss-Seidel path gathers with.
    pub(crate) fn gather(
        &mut self,
        patches: usize,
        form_factors: &FormFactors,
        keys: &[ElementKey],
    ) -> bool {
        let entries: usize = keys.iter().map(|k| form_factors.entries(*k).len()).sum();
        if entries > self.budget_entries {
            return false;
        }
        let mut factors: Vec<Vec<(ElementKey, f64)>> = vec![Vec::new(); patches];
        let mut entries = 0;
        for &k in keys {
            for (j, f) in form_factors.gathered_entries(k) {
                factors[j as usize].push((k, f));
                entries += 1;
            }
        }
        self.patches = factors
            .into_iter()
            .map(|factors| {
                Some(Cached {
                    depth: u8::MAX,
                    factors,
                })
            })
            .collect();
        self.entries = entries;
        true
    }

    /// Brings the cache up to a refinement pass: entries of elements that are
    /// no longer leaves go, and so do those of the leaves in `fresh`; each
    /// leaf of `fresh` (with its gathering row in `form_factors`) then joins
    /// every cached patch its row sees. `fresh` holds the new leaves and the
    /// leaves whose rows were taken again (members of a facet group that no
    /// longer shares its lead's row): their old entries must not stay beside
    /// the new, or a shot would reach them twice.
    pub(crate) fn refine(&mut self, mesh: &Mesh, form_factors: &FormFactors, fresh: &[ElementKey]) {
        let retaken: std::collections::HashSet<ElementKey> = fresh.iter().copied().collect();
        let mut entries = 0;
        for c in self.patches.iter_mut().flatten() {
            c.factors.retain(|(k, _)| {
                !retaken.contains(k) && mesh.elements.get(*k).is_some_and(|e| e.is_leaf())
            });
            entries += c.factors.len();
        }
        for &k in fresh {
            for (j, f) in form_factors.gathered_entries(k) {
                if let Some(c) = &mut self.patches[j as usize] {
                    c.factors.push((k, f));
                    entries += 1;
                }
            }
        }
        self.entries = entries;
        // A pass adds entries without asking the budget (dropping patches
        // here would cost renders for no memory gained back this pass); the
        // next stores see the total.
    }

    /// The gathering rows of every leaf of `receivers` (in their order), as
    /// far as the cache holds them: the transpose of the factors of every
    /// patch kept from gathered rows. Empty rows where it holds none.
    #[must_use]
    pub(crate) fn rows(&self, receivers: &Receivers) -> Vec<Vec<(u32, f32)>> {
        let mut rows = vec![Vec::new(); receivers.len()];
        for (j, cached) in self.patches.iter().enumerate() {
            let Some(c) = cached.as_ref().filter(|c| c.depth == u8::MAX) else {
                continue;
            };
            for &(k, f) in &c.factors {
                if let Some(&i) = receivers.index.get(k) {
                    rows[i as usize].push((j as u32, f as f32));
                }
            }
        }
        rows
    }

    /// Entries held, over all patches.
    #[must_use]
    #[cfg(test)]
    pub(crate) fn entries(&self) -> usize {
        self.entries
    }

    /// Bytes the entries take.
    #[must_use]
    pub(crate) fn bytes(&self) -> usize {
        self.entries * ENTRY_BYTES
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::Row;
    use crate::scenes::cornell_box;

    fn mesh() -> Mesh {
        Mesh::new(&cornell_box(), 0.3, 100_000).unwrap()
    }

    #[test]
    fn a_patch_is_served_only_at_its_depth_or_coarser() {
        let m = mesh();
        let leaf = m.leaves()[0];
        let mut cache = ShotCache::new(m.patches.len(), 1 << 20);
        assert!(cache.get(3, 0).is_none());
        assert!(cache.store(3, 1, vec![(leaf, 0.25)]).is_ok());
        assert_eq!(cache.get(3, 0), Some(&[(leaf, 0.25)][..]));
        assert_eq!(cache.get(3, 1), Some(&[(leaf, 0.25)][..]));
        assert!(cache.get(3, 2).is_none(), "a finer shot must render");
        assert!(cache.get(2, 0).is_none());
        // Replacing a patch's factors counts its entries once.
        assert!(cache.store(3, 2, vec![(leaf, 0.5), (leaf, 0.125)]).is_ok());
        assert_eq!(cache.entries(), 2);
        assert_eq!(cache.bytes(), 2 * ENTRY_BYTES);
    }

    #[test]
    fn the_budget_refuses_what_does_not_fit() {
        let m = mesh();
        let leaf = m.leaves()[0];
        let mut cache = ShotCache::new(m.patches.len(), 3 * ENTRY_BYTES);
        assert!(cache.store(0, 0, vec![(leaf, 0.1), (leaf, 0.2)]).is_ok());
        assert!(cache.store(1, 0, vec![(leaf, 0.1), (leaf, 0.2)]).is_err());
        assert!(cache.get(1, 0).is_none());
        assert!(cache.store(1, 0, vec![(leaf, 0.3)]).is_ok());
        assert_eq!(cache.entries(), 3);
        // Nothing fits in no budget.
        let mut none = ShotCache::new(m.patches.len(), 0);
        assert!(none.store(0, 0, vec![(leaf, 0.1)]).is_err());
    }

    #[test]
    fn refinement_drops_split_leaves_and_adds_new_ones_from_their_rows() {
        let mut m = mesh();
        let leaves = m.leaves();
        let (a, b) = (leaves[0], leaves[1]);
        let mut cache = ShotCache::new(m.patches.len(), 1 << 20);
        assert!(cache.store(5, 0, vec![(a, 0.1), (b, 0.2)]).is_ok());
        assert!(cache.store(6, 0, vec![(b, 0.3)]).is_ok());
        let fresh = m.split(a);
        // Each child sees patches 5 and 7; patch 7 has nothing kept.
        let mut rows = FormFactors::new();
        for (c, &k) in fresh.iter().enumerate() {
            rows.set_row(
                k,
                Row::from_sorted(vec![(5, 0.01 * (c + 1) as f32), (7, 0.5)]),
            );
        }
        cache.refine(&m, &rows, &fresh);
        let five = cache.get(5, 0).unwrap();
        assert_eq!(five.len(), 5);
        assert_eq!(
            five[0],
            (b, 0.2),
            "the split leaf is gone, its neighbour stays"
        );
        for (c, &(k, f)) in five[1..].iter().enumerate() {
            assert_eq!(k, fresh[c]);
            assert_eq!(f, f64::from(0.01 * (c + 1) as f32));
        }
        assert_eq!(cache.get(6, 0), Some(&[(b, 0.3)][..]));
        assert!(
            cache.get(7, 0).is_none(),
            "refinement does not create patches' entries"
        );
        assert_eq!(cache.entries(), 6);
    }

    #[test]
    fn a_leaf_whose_row_is_taken_again_is_reached_once_by_its_new_factor() {
        // Leaf `b` held a copy of its group lead's row; the group stopped
        // sharing, and `b` rendered a row of its own: the cache keeps only
        // the new factor, so a shot of patch 5 reaches `b` once.
        let m = mesh();
        let leaves = m.leaves();
        let (a, b) = (leaves[0], leaves[1]);
        let mut cache = ShotCache::new(m.patches.len(), 1 << 20);
        assert!(cache.store(5, 0, vec![(a, 0.1), (b, 0.2)]).is_ok());
        let mut rows = FormFactors::new();
        rows.set_row(b, Row::from_sorted(vec![(5, 0.25)]));
        cache.refine(&m, &rows, &[b]);
        let five = cache.get(5, 0).unwrap();
        let reaching_b: Vec<f64> = five.iter().filter(|e| e.0 == b).map(|e| e.1).collect();
        assert_eq!(reaching_b, vec![0.25]);
        assert!(five.contains(&(a, 0.1)));
        assert_eq!(cache.entries(), 2);
    }
}
