//! How much a solve may hold, from memory rather than from fixed counts.
//!
//! What grows with a scene is the form-factor rows (8 bytes per entry, one row
//! per leaf element) and the patch system (16 bytes per entry, one row per
//! patch); the geometry is small beside them. Before the first form factor,
//! the workspace estimates the least the mesh it has built will hold, with
//! rows of [`LEAST_ROW_ENTRIES`] entries (or one per patch, if fewer), and
//! refuses the scene when even that does not fit
//! [`crate::Settings::max_memory`]: a scene is never refused that could have
//! been solved. The mesh is checked before it is split to the initial (or
//! uniform) depth, from the leaves that depth will make, so that a depth
//! the memory cannot hold is refused in milliseconds instead of after the
//! arena has grown past the limit. The hemi-cubes' buffers (one set per
//! worker thread, growing as the square of the resolution) count too.
//! Refinement then measures what the rows really take and adds elements
//! only while the measured bytes per element still fit.

use crate::error::{Error, LimitKind, Result};
use crate::mesh::{Element, Mesh, Patch};
use crate::pipeline::Settings;
use std::mem::size_of;

/// Entries an element's row holds in the estimate made before any row
/// exists: fewer than rows hold in practice (measured: 300 on average on the
/// atrium, 120 on many_boxes; most of the patches on a small room), so that
/// the estimate is a floor.
pub(crate) const LEAST_ROW_ENTRIES: usize = 64;

/// Bytes of one stored row entry: a 32-bit patch id and a single-precision
/// form factor.
const ROW_ENTRY_BYTES: usize = 8;

/// Bytes of one entry of the patch system's double-precision rows.
const SYSTEM_ENTRY_BYTES: usize = 16;

/// Bytes per leaf beside its row: the element's slot in the arena, its slot
/// in the row store and its radiosity (with room for its parent's).
pub(crate) fn leaf_bytes() -> usize {
    2 * (size_of::<Element>() + 8) + 2 * 32 + 3 * 8
}

/// The leaves `mesh` will have once every patch `splits` marks is split to
/// `depth`: computed, not made.
pub(crate) fn leaves_at_depth(mesh: &Mesh, depth: u8, splits: &[bool]) -> f64 {
    mesh.patches
        .iter()
        .zip(splits)
        .map(|(p, &split)| {
            let per_root = if split {
                4f64.powi(i32::from(depth))
            } else {
                1.0
            };
            p.roots.len() as f64 * per_root
        })
        .sum()
}

/// Bytes of the hemi-cubes at `resolution` for `patches` patches: per
/// worker thread, an item and a depth buffer over the top face and four
/// half faces (3 n^2 pixels of 4 + 4 bytes) and three per-patch sums; once,
/// the delta form-factor table and its prefix sums (about as large).
pub(crate) fn hemicube_bytes(resolution: usize, patches: usize, threads: usize) -> f64 {
    let pixels = 3.0 * (resolution as f64).powi(2);
    let per_cube = pixels * 8.0 + patches as f64 * 20.0;
    threads.max(1) as f64 * per_cube + pixels * 8.0
}

/// What a solve of `mesh` will need at least, once split to `depth`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Needs {
    patches: usize,
    leaves: f64,
    hemicubes: f64,
    /// Bytes in all.
    pub bytes: f64,
}

/// The least a solve of `mesh` will hold once every patch is split to
/// `depth`: its patches with their system rows, its leaves with rows of
/// [`LEAST_ROW_ENTRIES`] entries (or one per patch, if fewer), the parents
/// the splits leave in the arena (a third of the leaves), and the
/// hemi-cubes of `settings` on the current pool's threads.
pub(crate) fn needs_at_depth(
    mesh: &Mesh,
    depth: u8,
    splits: &[bool],
    settings: &Settings,
) -> Needs {
    let patches = mesh.patches().len();
    let leaves = leaves_at_depth(mesh, depth, splits);
    let entries = patches.min(LEAST_ROW_ENTRIES);
    let per_leaf = (leaf_bytes() + entries * ROW_ENTRY_BYTES) as f64;
    let parents = (leaves - patches as f64).max(0.0) / 3.0;
    let per_patch = (size_of::<Patch>() + entries * SYSTEM_ENTRY_BYTES) as f64;
    let hemicubes = hemicube_bytes(
        settings.hemicube_resolution,
        patches,
        rayon::current_num_threads(),
    );
    let bytes = patches as f64 * per_patch
        + leaves * per_leaf
        + parents * size_of::<Element>() as f64
        + hemicubes;
    Needs {
        patches,
        leaves,
        hemicubes,
        bytes,
    }
}

/// What a solve of `mesh` holds when its rows take `row_bytes`: the patches
/// with their system rows (as [`needs_at_depth`] counts them) and the leaves.
pub(crate) fn held(mesh: &Mesh, row_bytes: u64) -> u64 {
    let patches = mesh.patches().len();
    let entries = patches.min(LEAST_ROW_ENTRIES);
    let per_patch = size_of::<Patch>() + entries * SYSTEM_ENTRY_BYTES;
    (patches as u64) * per_patch as u64 + (mesh.leaf_count() * leaf_bytes()) as u64 + row_bytes
}

/// Refuses a solve whose [`Needs`] exceed `limit` bytes, before the mesh is
/// split: saying what it would need, of which the hemi-cubes how much, and
/// what can change that.
pub(crate) fn check_needs(needs: &Needs, depth: u8, limit: u64) -> Result<()> {
    if needs.bytes <= limit as f64 {
        return Ok(());
    }
    let hemicubes = if needs.hemicubes > 0.1 * needs.bytes {
        format!(
            ", of which {} for the hemi-cubes: a smaller `hemicube_resolution` or fewer worker \
             threads lowers that",
            gigabytes(needs.hemicubes as u64)
        )
    } else {
        String::new()
    };
    Err(Error::limit(
        LimitKind::Memory,
        format!(
            "the solve would need at least {} ({} patches split to depth {depth}: {:.0} \
         elements, with rows of at least {} entries{hemicubes}) and the memory limit is {}: \
         raise `max_memory` if the machine has it, or use a larger `patch_size` or a \
         smaller depth",
            gigabytes(needs.bytes.min(u64::MAX as f64) as u64),
            needs.patches,
            needs.leaves,
            needs.patches.min(LEAST_ROW_ENTRIES),
            gigabytes(limit),
        ),
    ))
}

/// How many more leaves fit in `limit` bytes, when `used` bytes are held now
/// and each leaf costs `per_leaf` bytes.
pub(crate) fn leaves_that_fit(limit: u64, used: u64, per_leaf: f64) -> usize {
    let room = limit.saturating_sub(used) as f64 / per_leaf.max(1.0);
    if room >= usize::MAX as f64 {
        usize::MAX
    } else {
        room as usize
    }
}

/// The most patches a mesh may be built with under `limit` bytes, each with
/// at least one leaf: a bound to check before allocating the lattice.
pub(crate) fn patches_that_fit(limit: u64) -> usize {
    let smallest = (size_of::<Patch>() + leaf_bytes()) as u64;
    usize::try_from(limit / smallest).unwrap_or(usize::MAX)
}

/// `bytes` for a person: "1.3 GB", "420 MB", "96 kB".
pub(crate) fn gigabytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.0} MB", b / 1e6)
    } else {
        format!("{:.0} kB", b / 1e3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::cornell_box;

    #[test]
    fn the_needs_at_a_depth_are_known_before_the_split_and_match_it() {
        let scene = cornell_box();
        let settings = Settings::default();
        let mut mesh = Mesh::new(&scene, 0.2, usize::MAX).unwrap();
        let all = vec![true; mesh.patches().len()];
        let predicted = leaves_at_depth(&mesh, 2, &all);
        let needs = needs_at_depth(&mesh, 2, &all, &settings);
        for _ in 0..2 {
            for k in mesh.leaves() {
                mesh.split(k);
            }
        }
        assert_eq!(predicted, mesh.leaf_count() as f64);
        // Sixteen leaves per patch, each with at least its row.
        assert!(needs.bytes > predicted * (LEAST_ROW_ENTRIES.min(mesh.patches().len()) * 8) as f64);
        let e = check_needs(&needs, 2, needs.bytes as u64 / 2)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("depth 2") && e.contains(&format!("{predicted:.0} elements")),
            "{e}"
        );
        assert!(check_needs(&needs, 2, needs.bytes as u64 + 1).is_ok());
    }

    #[test]
    fn hemicube_buffers_grow_as_the_square_of_the_resolution() {
        let small = hemicube_bytes(64, 0, 1);
        let large = hemicube_bytes(4096, 0, 1);
        assert_eq!(large / small, 4096.0 * 4096.0 / (64.0 * 64.0));
        // Per pixel: 8 bytes per thread and 8 for the table.
        assert_eq!(hemicube_bytes(100, 0, 3), 3.0 * 100.0 * 100.0 * 8.0 * 4.0);
    }

    #[test]
    fn room_for_leaves_is_what_is_left_over_their_cost() {
        assert_eq!(leaves_that_fit(1000, 400, 100.0), 6);
        assert_eq!(leaves_that_fit(1000, 1400, 100.0), 0);
        assert_eq!(leaves_that_fit(u64::MAX, 0, 1e-300), usize::MAX);
        assert_eq!(gigabytes(1_300_000_000), "1.3 GB");
        assert_eq!(gigabytes(420_000_000), "420 MB");
        assert_eq!(gigabytes(96_000), "96 kB");
    }
}
