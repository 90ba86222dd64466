//! Per-thread working buffers for parallel maps whose items differ in cost.
//!
//! Rows differ a hundredfold in cost: an element a contact crosses tests
//! dozens of points with rays first, one near an emitter casts rays to it.
//! Rayon hands each worker a few large runs of items and splits a run only
//! when another worker steals it, so the worker that drew the costly run
//! grinds through it alone while the others sleep (a fifth of the Cornell
//! job's form-factor stage on two cores). Splitting to single items keeps
//! every worker busy, but `map_init` would then build a hemi-cube (buffers
//! the size of the patch count) per item. Here each worker keeps one,
//! built on first use and reused for every item it takes.

use rayon::prelude::*;
use std::sync::Mutex;

/// One slot of working state per thread of the current rayon pool.
pub(crate) struct PerThread<S> {
    slots: Vec<Mutex<Option<S>>>,
}

impl<S: Send> PerThread<S> {
    /// Empty slots, one per thread of the pool this is called in.
    #[must_use]
    pub(crate) fn new() -> Self {
        PerThread {
            slots: (0..rayon::current_num_threads())
                .map(|_| Mutex::new(None))
                .collect(),
        }
    }

    /// `f` applied to this thread's state, built by `make` on first use. A
    /// thread that finds its slot taken (it is running this map again from
    /// inside `f`, as rayon may when `f` waits on nested work), or that does
    /// not belong to the pool, works on a state of its own.
    pub(crate) fn with<R>(&self, make: impl FnOnce() -> S, f: impl FnOnce(&mut S) -> R) -> R {
        let slot = rayon::current_thread_index().and_then(|i| self.slots.get(i));
        if let Some(Ok(mut guard)) = slot.map(Mutex::try_lock) {
            return f(guard.get_or_insert_with(make));
        }
        f(&mut make())
    }
}

/// `f(index, item, state)` for every item of `items`, in parallel and in
/// order, each item its own task, with `state` this thread's (see
/// [`PerThread`]). `f` must not depend on what earlier items left in the
/// state, so that the result is the same at any thread count.
pub(crate) fn map_items<T: Sync, S: Send, R: Send>(
    items: &[T],
    make: impl Fn() -> S + Sync,
    f: impl Fn(usize, &T, &mut S) -> R + Sync,
) -> Vec<R> {
    let states = PerThread::new();
    items
        .par_iter()
        .enumerate()
        .with_max_len(1)
        .map(|(i, item)| states.with(&make, |s| f(i, item, s)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn every_item_is_mapped_in_order_and_states_are_built_once_per_thread() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .expect("pool");
        let built = AtomicUsize::new(0);
        let items: Vec<u64> = (0..500).collect();
        let out = pool.install(|| {
            map_items(
                &items,
                || {
                    built.fetch_add(1, Ordering::Relaxed);
                    Vec::<u64>::new()
                },
                |i, &x, scratch| {
                    // The state is working room only: cleared before use.
                    scratch.clear();
                    scratch.extend(0..x % 7);
                    (i as u64) * 1000 + x + scratch.len() as u64
                },
            )
        });
        let expected: Vec<u64> = items.iter().map(|&x| x * 1000 + x + x % 7).collect();
        assert_eq!(out, expected);
        let built = built.load(Ordering::Relaxed);
        assert!((1..=3).contains(&built), "{built} states for 3 threads");
    }

    #[test]
    fn a_thread_outside_any_pool_builds_its_own_state() {
        let states: PerThread<u32> = PerThread { slots: Vec::new() };
        let v = states.with(|| 41, |s| *s + 1);
        assert_eq!(v, 42);
    }
}
