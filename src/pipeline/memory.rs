//! How much a solve may hold, from memory rather than from fixed counts.
//!
//! What grows with a scene is the form-factor rows (8 bytes per entry, one row
//! per leaf element) and the patch system (16 bytes per entry, one row per
//! patch); the geometry is small beside them. Before the first form factor,
//! the workspace estimates the least the mesh it has built will hold, with
//! rows of [`LEAST_ROW_ENTRIES`] entries (or one per patch, if fewer), and
//! refuses the scene when even that does not fit
//! [`crate::Settings::max_memory`]: a scene is never refused that could have
//! been solved. Refinement then measures what the rows really take and adds
//! elements only while the measured bytes per element still fit.

use crate::error::{Error, Result};
use crate::mesh::{Element, Mesh, Patch};
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

/// The least a solve of `mesh` (its patches and current leaves) will hold,
/// estimated before any row is computed.
pub(crate) fn estimate(mesh: &Mesh) -> u64 {
    let entries = mesh.patches().len().min(LEAST_ROW_ENTRIES);
    let rows = mesh.leaf_count() as u64 * (entries * ROW_ENTRY_BYTES) as u64;
    held(mesh, rows)
}

/// What a solve of `mesh` holds when its rows take `row_bytes`: the patches
/// with their system rows (as [`estimate`] counts them) and the leaves.
pub(crate) fn held(mesh: &Mesh, row_bytes: u64) -> u64 {
    let patches = mesh.patches().len();
    let entries = patches.min(LEAST_ROW_ENTRIES);
    let per_patch = size_of::<Patch>() + entries * SYSTEM_ENTRY_BYTES;
    (patches as u64) * per_patch as u64 + (mesh.leaf_count() * leaf_bytes()) as u64 + row_bytes
}

/// Refuses `mesh` when its [`estimate`] exceeds `limit` bytes, saying what it
/// would need and what can change that.
pub(crate) fn check_fits(mesh: &Mesh, limit: u64) -> Result<()> {
    let needed = estimate(mesh);
    if needed <= limit {
        return Ok(());
    }
    Err(Error::Limit(format!(
        "the solve would need at least {} ({} patches, {} elements, rows of at least {} \
         entries) and the memory limit is {}: raise --max-memory if the machine has \
         it, or use a larger --patch-size or a smaller --initial-depth",
        gigabytes(needed),
        mesh.patches().len(),
        mesh.leaf_count(),
        mesh.patches().len().min(LEAST_ROW_ENTRIES),
        gigabytes(limit),
    )))
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
    fn the_estimate_follows_patches_and_leaves() {
        let scene = cornell_box();
        let coarse = Mesh::new(&scene, 0.2, usize::MAX).unwrap();
        let mut fine = Mesh::new(&scene, 0.2, usize::MAX).unwrap();
        for k in fine.leaves() {
            fine.split(k);
        }
        let (a, b) = (estimate(&coarse), estimate(&fine));
        // Four leaves per patch instead of one: the leaves' part grows four
        // times, the patches' part stays.
        let p = coarse.patches().len() as u64;
        let entries = coarse.patches().len().min(LEAST_ROW_ENTRIES);
        let per_leaf = (leaf_bytes() + entries * ROW_ENTRY_BYTES) as u64;
        assert_eq!(b - a, 3 * p * per_leaf);
        assert!(check_fits(&fine, b).is_ok());
        let e = check_fits(&fine, b - 1).unwrap_err().to_string();
        assert!(e.contains("--max-memory") && e.contains("patches"), "{e}");
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
