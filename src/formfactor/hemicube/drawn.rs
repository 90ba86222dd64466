//! The rectangle of each face drawn into since the last clear.

/// The pixel rectangle of one face that polygons were drawn into since it was
/// last cleared: rows `j0..j1`, columns `i0..i1` (empty when `j0 >= j1`).
/// Everything outside it still holds nothing, so clearing and reading out the
/// face can stop at its edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Drawn {
    pub(super) j0: usize,
    pub(super) j1: usize,
    pub(super) i0: usize,
    pub(super) i1: usize,
}

impl Drawn {
    pub(super) const EMPTY: Drawn = Drawn {
        j0: usize::MAX,
        j1: 0,
        i0: usize::MAX,
        i1: 0,
    };

    pub(super) fn is_empty(&self) -> bool {
        self.j0 >= self.j1 || self.i0 >= self.i1
    }

    pub(super) fn include(&mut self, j0: usize, j1: usize, i0: usize, i1: usize) {
        self.j0 = self.j0.min(j0);
        self.j1 = self.j1.max(j1);
        self.i0 = self.i0.min(i0);
        self.i1 = self.i1.max(i1);
    }

    pub(super) fn pixels(&self) -> usize {
        if self.is_empty() {
            0
        } else {
            (self.j1 - self.j0) * (self.i1 - self.i0)
        }
    }
}
