//! Sparse form-factor rows.

use std::sync::Arc;

/// The form factors from one receiver to the patches it sees: patch ids in
/// increasing order (32 bits) with single-precision values. Patches not seen
/// are not stored.
///
/// Besides the front faces, a receiver's hemisphere holds back faces of
/// single-sided surfaces, which block light and reflect none (it ends there,
/// absorbed), and, in an open scene, nothing at all (the light escapes). The
/// row keeps the form factor of each, so that the light a receiver sends there
/// can be accounted for: in a closed scene the three parts add up to 1.
///
/// Cloning a row shares its entries (facets of one group hold the one row
/// their lead rendered).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Row {
    entries: Arc<[(u32, f32)]>,
    back_faces: f32,
    open: f32,
    /// The share of the receiving element that other objects cover (shut
    /// in where something stands on it), 0 for most.
    covered: f32,
    /// The form factor of the surfaces the receiver sees close by (see
    /// [`Row::near`]).
    near: f32,
}

impl Row {
    /// A row from `(patch, form factor)` pairs sorted by patch id, with no
    /// back face or open sky in view.
    #[must_use]
    pub(crate) fn from_sorted(entries: Vec<(u32, f32)>) -> Self {
        debug_assert!(entries.windows(2).all(|w| w[0].0 < w[1].0));
        Row {
            entries: entries.into(),
            back_faces: 0.0,
            open: 0.0,
            covered: 0.0,
            near: 0.0,
        }
    }

    /// This row, taken at a visible point of an element of which only the
    /// share `visible` is not shut in, made the element's mean: every form
    /// factor times `visible`, the shut-in rest seeing back faces only (see
    /// `contacts.rs`).
    #[must_use]
    pub(crate) fn covered(self, visible: f64) -> Self {
        let scale = |x: f32| (f64::from(x) * visible) as f32;
        Row {
            entries: self.entries.iter().map(|&(j, f)| (j, scale(f))).collect(),
            back_faces: (f64::from(self.back_faces) * visible + (1.0 - visible)) as f32,
            open: scale(self.open),
            covered: (1.0 - visible) as f32,
            near: self.near,
        }
    }

    /// The share of the receiving element not covered by other objects:
    /// its form factors are its visible part's times this.
    #[must_use]
    pub fn visible(&self) -> f64 {
        1.0 - f64::from(self.covered)
    }

    /// The same row, seeing back faces over form factor `back_faces` and
    /// nothing over form factor `open`.
    #[must_use]
    pub(crate) fn with_hidden(mut self, back_faces: f64, open: f64) -> Self {
        self.back_faces = back_faces as f32;
        self.open = open as f32;
        self
    }

    /// The same row, seeing surfaces close by over form factor `near`.
    #[must_use]
    pub(crate) fn with_near(mut self, near: f64) -> Self {
        self.near = near as f32;
        self
    }

    /// The form factor of the surfaces, front or back, that the receiver
    /// saw closer than the reach its row was taken with (the element's
    /// size, the square root of its area), each pixel's distance taken
    /// along its hemi-cube face's axis: where it is large, what the element
    /// receives changes over the element's own extent.
    #[must_use]
    pub fn near(&self) -> f64 {
        f64::from(self.near)
    }

    /// The row without its stored zeros (the same row when it has none).
    #[must_use]
    pub(crate) fn without_zeros(self) -> Self {
        if self.entries.iter().all(|e| e.1 != 0.0) {
            return self;
        }
        let kept: Vec<(u32, f32)> = self
            .entries
            .iter()
            .copied()
            .filter(|e| e.1 != 0.0)
            .collect();
        Row {
            entries: kept.into(),
            ..self
        }
    }

    /// The form factor of the back faces the receiver sees: light it sends
    /// there is absorbed by them.
    #[must_use]
    pub(crate) fn back_faces(&self) -> f64 {
        f64::from(self.back_faces)
    }

    /// The form factor of the part of the receiver's view where nothing lies:
    /// light it sends there leaves the scene.
    #[must_use]
    pub fn open(&self) -> f64 {
        f64::from(self.open)
    }

    /// The stored `(patch, form factor)` pairs.
    #[must_use]
    pub fn entries(&self) -> &[(u32, f32)] {
        &self.entries
    }

    /// Number of stored entries.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when nothing is stored (not computed yet, or nothing visible).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The sum of the row (the fraction of the hemisphere that sees a front face).
    #[must_use]
    pub fn sum(&self) -> f64 {
        self.entries.iter().map(|e| f64::from(e.1)).sum()
    }

    /// The form factor to patch `j` (0 if not stored).
    #[must_use]
    pub fn get(&self, j: u32) -> f64 {
        self.entries
            .binary_search_by_key(&j, |e| e.0)
            .map_or(0.0, |i| f64::from(self.entries[i].1))
    }

    /// Bytes of heap memory held, or where clones share the entries this
    /// row's share of them, rounded down (so that the shares of all the
    /// holders add up to the bytes held, within a byte per holder).
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        std::mem::size_of_val(&*self.entries) / Arc::strong_count(&self.entries)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_their_entries_and_count_their_bytes_once() {
        let row = Row::from_sorted(vec![(1, 0.25), (4, 0.5), (9, 0.125)]);
        let alone = row.heap_bytes();
        assert_eq!(alone, 3 * std::mem::size_of::<(u32, f32)>());
        let copies: Vec<Row> = (0..3).map(|_| row.clone()).collect();
        assert!(copies
            .iter()
            .all(|c| std::ptr::eq(c.entries().as_ptr(), row.entries().as_ptr())));
        let shares: usize = copies.iter().map(Row::heap_bytes).sum::<usize>() + row.heap_bytes();
        assert_eq!(shares, alone);
        // A changed row holds entries of its own.
        let scaled = row.clone().covered(0.5);
        assert!(!std::ptr::eq(
            scaled.entries().as_ptr(),
            row.entries().as_ptr()
        ));
        assert_eq!(scaled.heap_bytes(), alone);
        drop(copies);
        assert_eq!(row.heap_bytes(), alone);
    }
}
