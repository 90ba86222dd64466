//! A set of polygon ids read out in increasing order.

/// Ids marked one by one and read out in increasing order, a bit per id.
/// A hemi-cube draws the polygons its BVH walk finds in id order, so that
/// ties in the depth test go the same way whatever the walk; marking them
/// here puts them in that order without sorting them.
#[derive(Clone, Debug, Default)]
pub(super) struct IdSet {
    words: Vec<u64>,
    /// The words `lo..hi` may hold marks; every other word is 0.
    lo: usize,
    hi: usize,
}

impl IdSet {
    /// Marks `id`.
    #[inline]
    pub(super) fn insert(&mut self, id: u32) {
        let w = (id / 64) as usize;
        if w >= self.words.len() {
            self.words.resize(w + 1, 0);
        }
        if self.lo >= self.hi {
            (self.lo, self.hi) = (w, w + 1);
        } else {
            self.lo = self.lo.min(w);
            self.hi = self.hi.max(w + 1);
        }
        self.words[w] |= 1 << (id % 64);
    }

    /// Appends the marked ids to `out` in increasing order, each once, and
    /// empties the set.
    pub(super) fn drain_into(&mut self, out: &mut Vec<u32>) {
        for (w, word) in self.words[self.lo..self.hi].iter_mut().enumerate() {
            let base = ((self.lo + w) * 64) as u32;
            let mut bits = std::mem::take(word);
            while bits != 0 {
                out.push(base + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
        (self.lo, self.hi) = (0, 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_come_out_sorted_once_each_and_the_set_empties() {
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as u32
        };
        let mut set = IdSet::default();
        for round in 0..20 {
            let count = 1 + round * 37;
            let span = 1 + (next() % 5000);
            let ids: Vec<u32> = (0..count).map(|_| 100 + next() % span).collect();
            for &id in &ids {
                set.insert(id);
            }
            let mut expected = ids.clone();
            expected.sort_unstable();
            expected.dedup();
            let mut out = vec![u32::MAX];
            set.drain_into(&mut out);
            assert_eq!(out[0], u32::MAX, "appends");
            assert_eq!(&out[1..], &expected[..], "round {round}");
        }
        let mut out = Vec::new();
        set.drain_into(&mut out);
        assert!(out.is_empty());
        // Marks far apart, the later first.
        set.insert(70_000);
        set.insert(0);
        set.drain_into(&mut out);
        assert_eq!(out, vec![0, 70_000]);
    }
}
