//! Rows after source patches split: most need only their entries for the
//! split patches redone.
//!
//! A row holds, per patch, the visible form factor from the element to it.
//! When patch `P` becomes four patches, every other entry of every row stays
//! what a new hemi-cube would give, to rounding: the same surfaces, the same
//! occluders.
//! Where a row saw `P` whole (its entry is Lambert's exact form factor to `P`,
//! nothing in front), each child is seen whole too, and its entry is Lambert's
//! exact form factor to the child, which is what the hybrid method stores for
//! a patch seen whole. Only rows that saw a split patch in part, or saw a split
//! emitter (whose entries come from exact shaft visibility), and elements
//! without a row yet, need their hemi-cube rendered again.

use crate::formfactor::{point_to_polygon, receiving_point, FormFactors, Row, RowState, Sources};
use crate::mesh::{ElementKey, Mesh};
use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

/// One source patch split into four.
#[derive(Clone, Debug)]
pub(crate) struct SplitPatch {
    /// Its id before the split (kept by its first child).
    pub(crate) old: u32,
    /// Its polygon before the split.
    pub(crate) polygon: SmallVec<[DVec3; 4]>,
    /// The ids of its four children.
    pub(crate) children: [u32; 4],
}

/// An entry within this relative distance of Lambert's exact form factor saw
/// its patch whole (entries are stored in single precision).
const WHOLE: f64 = 1e-6;

/// Brings every leaf's row up to `splits` where the entries of the split
/// patches can be derived (see the module docs), in place, and returns the
/// leaves whose rows must be computed anew. `sources` are the patches after
/// the split.
pub(crate) fn update_rows_for_splits(
    mesh: &Mesh,
    form_factors: &mut FormFactors,
    sources: &Sources,
    splits: &[SplitPatch],
) -> Vec<ElementKey> {
    let mut split_of = vec![None; mesh.patches.len()];
    for (i, s) in splits.iter().enumerate() {
        split_of[s.old as usize] = Some(i);
    }
    let emitter: Vec<bool> = {
        let mut e = vec![false; mesh.patches.len()];
        for &j in &sources.emitters {
            e[j as usize] = true;
        }
        e
    };
    let leaves = mesh.leaves();
    let store = &*form_factors;
    let updates: Vec<Update> = leaves
        .par_iter()
        .map(|&k| derived_row(mesh, store, sources, splits, &split_of, &emitter, k))
        .collect();
    let mut anew = Vec::new();
    for (k, update) in leaves.into_iter().zip(updates) {
        match update {
            Update::Unchanged => {}
            Update::Derived(row) => form_factors.set_row(k, row),
            Update::Anew => anew.push(k),
        }
    }
    anew
}

/// What a split does to one leaf's row.
enum Update {
    /// It saw no split patch, or it has no row to change: it needs none
    /// (reflects nothing) or it sees nothing (shut in).
    Unchanged,
    /// Its entries for the split patches, derived.
    Derived(Row),
    /// It must be rendered anew.
    Anew,
}

/// What the splits do to the row of leaf `k`.
fn derived_row(
    mesh: &Mesh,
    form_factors: &FormFactors,
    sources: &Sources,
    splits: &[SplitPatch],
    split_of: &[Option<usize>],
    emitter: &[bool],
    k: ElementKey,
) -> Update {
    let row = match form_factors.state(k) {
        RowState::Computed(row) => row,
        RowState::Skipped | RowState::ShutIn(_) => return Update::Unchanged,
        RowState::Pending => return Update::Anew,
    };
    if !row
        .entries()
        .iter()
        .any(|&(j, _)| split_of[j as usize].is_some())
    {
        return Update::Unchanged;
    }
    let e = &mesh.elements[k];
    let normal = mesh.surfaces[e.surface as usize].normal;
    let eye = receiving_point(e.centroid, normal, e.area);
    let mut entries: Vec<(u32, f32)> = Vec::with_capacity(row.len() + 3 * splits.len());
    for &(j, f) in row.entries() {
        let Some(i) = split_of[j as usize] else {
            entries.push((j, f));
            continue;
        };
        let split = &splits[i];
        if split.children.iter().any(|&c| emitter[c as usize]) {
            return Update::Anew;
        }
        let whole = point_to_polygon(eye, normal, &split.polygon);
        if whole <= 0.0 || (f64::from(f) / whole - 1.0).abs() > WHOLE {
            return Update::Anew;
        }
        for &c in &split.children {
            let poly = &sources.patch(c)[0];
            let exact = point_to_polygon(eye, normal, &poly.vertices[..poly.count as usize]);
            if exact > 0.0 {
                entries.push((c, exact as f32));
            }
        }
    }
    entries.sort_unstable_by_key(|x| x.0);
    // Splitting a patch changes neither the back faces nor the sky in view.
    Update::Derived(
        Row::from_sorted(entries)
            .with_hidden(row.back_faces(), row.open())
            .without_zeros(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::hemicube::DeltaTable;
    use crate::formfactor::{compute_rows, EmitterSampling, FormFactorMethod, RowSettings};
    use crate::scenes::cornell_box;
    use std::sync::Arc;

    fn rows_for_all(mesh: &Mesh, store: &mut FormFactors, sources: &Sources) {
        let settings = RowSettings {
            table: Arc::new(DeltaTable::new(64)),
            seed: 7,
            method: FormFactorMethod::Hybrid,
            emitter_sampling: EmitterSampling::Centre,
            level_of_detail: false,
        };
        let leaves = mesh.leaves();
        let (rows, _) = compute_rows(mesh, sources, &leaves, &settings, &|_| {});
        for (k, row) in leaves.into_iter().zip(rows) {
            store.set_row(k, row);
        }
    }

    #[test]
    fn derived_rows_are_the_rows_a_new_hemicube_gives() {
        // Split a spread of patches of the Cornell box (not the light); every
        // row derived must equal the row rendered anew after the split, to
        // rounding, and most rows must be derived.
        let mut mesh = Mesh::new(&cornell_box(), 0.14, 100_000).unwrap();
        for k in mesh.leaves() {
            mesh.split(k);
        }
        let sources = Sources::from_mesh(&mesh);
        let mut store = FormFactors::new();
        rows_for_all(&mesh, &mut store, &sources);
        let light = sources.emitters[0];
        let picks: Vec<u32> = (0..mesh.patches.len() as u32)
            .step_by(40)
            .filter(|&p| p != light)
            .collect();
        let mut splits = Vec::new();
        for p in picks {
            let polygon = mesh.patches[p as usize].polygon.clone();
            store.forget(mesh.patches[p as usize].roots[0]);
            let children = mesh.split_patch(p);
            splits.push(SplitPatch {
                old: p,
                polygon,
                children,
            });
        }
        let sources = Sources::from_mesh(&mesh);
        let anew = update_rows_for_splits(&mesh, &mut store, &sources, &splits);
        let leaves = mesh.leaves();
        let derived: Vec<(ElementKey, Row)> = leaves
            .iter()
            .filter(|k| !anew.contains(k))
            .map(|&k| (k, store.row(k).cloned().unwrap_or_default()))
            .collect();
        rows_for_all(&mesh, &mut store, &sources);
        let mut with_children = 0;
        let mut worst: f64 = 0.0;
        let mut missing: f64 = 0.0;
        for (k, row) in &derived {
            let fresh = store.row(*k).cloned().unwrap_or_default();
            // An entry only one side has is a sliver at grazing incidence
            // that the new hemi-cube's pixels missed (derived entries are
            // Lambert's formula, which does not).
            for &(j, _) in row.entries().iter().chain(fresh.entries()) {
                let (a, b) = (row.get(j), fresh.get(j));
                let d = (a - b).abs();
                if a == 0.0 || b == 0.0 {
                    missing = missing.max(d);
                } else {
                    worst = worst.max(d / b);
                }
            }
            with_children += usize::from(
                row.entries()
                    .iter()
                    .any(|&(j, _)| j as usize >= mesh.patches.len() - 3 * splits.len()),
            );
        }
        // Rendering four polygons where there was one moves the depth-test
        // ties and the shaft clipping along their edges by rounding only.
        assert!(worst < 1e-5, "worst relative difference {worst}");
        // Measured 6.6e-6; a pixel of the 64 hemi-cube's top face is worth
        // 3.5e-5 (corner) to 3.1e-4 (centre).
        assert!(missing < 2e-5, "worst entry on one side only {missing}");
        assert!(
            derived.len() > leaves.len() / 2 && with_children > 100 && !anew.is_empty(),
            "{} derived, {with_children} of them with new patches, {} anew of {}",
            derived.len(),
            anew.len(),
            leaves.len()
        );
    }

    #[test]
    fn rows_that_saw_a_split_emitter_are_rendered_anew() {
        let mut mesh = Mesh::new(&cornell_box(), 0.14, 100_000).unwrap();
        for k in mesh.leaves() {
            mesh.split(k);
        }
        let sources = Sources::from_mesh(&mesh);
        let mut store = FormFactors::new();
        rows_for_all(&mesh, &mut store, &sources);
        let light = sources.emitters[0];
        let saw_light: Vec<ElementKey> = mesh
            .leaves()
            .into_iter()
            .filter(|k| store.row(*k).is_some_and(|r| r.get(light) > 0.0))
            .collect();
        assert!(saw_light.len() > 100);
        let polygon = mesh.patches[light as usize].polygon.clone();
        store.forget(mesh.patches[light as usize].roots[0]);
        let children = mesh.split_patch(light);
        let splits = [SplitPatch {
            old: light,
            polygon,
            children,
        }];
        let sources = Sources::from_mesh(&mesh);
        let anew = update_rows_for_splits(&mesh, &mut store, &sources, &splits);
        for k in &saw_light {
            assert!(anew.contains(k));
        }
    }
}
