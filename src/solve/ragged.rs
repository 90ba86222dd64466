//! Rows of different lengths held in one block.
//!
//! The shaped gather keeps, per leaf, a few entries to the patches it is
//! near, and per entry a list of part weights: hundreds of thousands of
//! short lists. Each in its own heap block, they cost an allocation apiece
//! (and its bookkeeping in memory), and freeing them was a visible part of
//! the gather. Here every row lives in one vector, found by its start.

use rayon::prelude::*;

/// Rows of `T`: row `i` is `items[starts[i]..starts[i + 1]]`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ragged<T> {
    items: Vec<T>,
    starts: Vec<usize>,
}

impl<T> Default for Ragged<T> {
    fn default() -> Self {
        Ragged {
            items: Vec::new(),
            starts: vec![0],
        }
    }
}

impl<T> Ragged<T> {
    /// Appends a row.
    #[cfg(test)]
    pub(crate) fn push_row(&mut self, row: impl IntoIterator<Item = T>) {
        self.items.extend(row);
        self.starts.push(self.items.len());
    }

    /// Appends a row of what `fill` pushes onto the items.
    pub(crate) fn push_row_with(&mut self, fill: impl FnOnce(&mut Vec<T>)) {
        fill(&mut self.items);
        self.starts.push(self.items.len());
    }

    /// Appends the rows of `other` after this one's.
    pub(crate) fn append(&mut self, other: Ragged<T>) {
        let offset = self.items.len();
        self.items.extend(other.items);
        self.starts
            .extend(other.starts[1..].iter().map(|s| s + offset));
    }

    /// Row `i`.
    pub(crate) fn row(&self, i: usize) -> &[T] {
        &self.items[self.starts[i]..self.starts[i + 1]]
    }

    /// Row `i`, to change its items.
    pub(crate) fn row_mut(&mut self, i: usize) -> &mut [T] {
        &mut self.items[self.starts[i]..self.starts[i + 1]]
    }

    /// The rows in order.
    pub(crate) fn rows(&self) -> impl Iterator<Item = &[T]> + '_ {
        self.starts.windows(2).map(|w| &self.items[w[0]..w[1]])
    }

    /// The same rows with every item mapped by `f`.
    pub(crate) fn map<U>(self, f: impl FnMut(T) -> U) -> Ragged<U> {
        Ragged {
            items: self.items.into_iter().map(f).collect(),
            starts: self.starts,
        }
    }
}

impl<T: Send> Ragged<T> {
    /// `count` rows, row `n` made by `fill(n, out)` pushing its items onto
    /// `out`. Rows are made in parallel, in blocks of `block` rows each
    /// gathered in a vector of its own, and the blocks joined in order: the
    /// same rows at any thread count.
    pub(crate) fn from_par_rows(
        count: usize,
        block: usize,
        fill: impl Fn(usize, &mut Vec<T>) + Sync,
    ) -> Self {
        let block = block.max(1);
        let blocks: Vec<Ragged<T>> = (0..count.div_ceil(block))
            .into_par_iter()
            .map(|b| {
                let mut part = Ragged::default();
                for n in b * block..((b + 1) * block).min(count) {
                    fill(n, &mut part.items);
                    part.starts.push(part.items.len());
                }
                part
            })
            .collect();
        let mut all = Ragged {
            items: Vec::with_capacity(blocks.iter().map(|b| b.items.len()).sum()),
            starts: Vec::with_capacity(count + 1),
        };
        all.starts.push(0);
        for part in blocks {
            all.append(part);
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_made_in_parallel_blocks_are_the_rows_made_one_by_one() {
        let fill =
            |n: usize, out: &mut Vec<u64>| out.extend((0..n % 5).map(|k| (n * 10 + k) as u64));
        let mut one_by_one = Ragged::default();
        for n in 0..103 {
            let mut row = Vec::new();
            fill(n, &mut row);
            one_by_one.push_row(row);
        }
        for block in [1, 4, 16, 1000] {
            let blocks = Ragged::from_par_rows(103, block, fill);
            assert_eq!(blocks, one_by_one, "block {block}");
        }
        assert_eq!(one_by_one.row(7), &[70, 71]);
        assert!(one_by_one.row(5).is_empty());
        assert_eq!(one_by_one.rows().count(), 103);
        let doubled = one_by_one.clone().map(|x| 2 * x);
        assert_eq!(doubled.row(8), &[160, 162, 164]);
    }
}
