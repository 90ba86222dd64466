//! The form factors of a solve: one row per leaf element, with the state of
//! each, owned by the form-factor stage. The mesh holds geometry only.

use super::Row;
use crate::mesh::ElementKey;
use slotmap::SecondaryMap;
use smallvec::SmallVec;

/// What a computed row says of the receiver's whole view: how much of it
/// front faces fill (the row's sum), how much back faces (whose light is
/// absorbed there) and how much nothing at all (open sky, where light
/// leaves). In a closed scene the three add up to 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RowView {
    /// The row's sum: the form factor of the front faces in view.
    pub sum: f64,
    /// The form factor of the back faces in view.
    pub back_faces: f64,
    /// The form factor of the part of the view where nothing lies.
    pub open: f64,
    /// The share of the receiver that other objects cover (see
    /// [`Row::visible`]); single precision, as the row holds it, so that
    /// the view takes no more room with `near` beside it.
    pub covered: f32,
    /// The form factor of the surfaces seen close by (see [`Row::near`]).
    pub near: f32,
}

impl RowView {
    /// The view of `row`.
    #[must_use]
    pub fn of(row: &Row) -> Self {
        RowView {
            sum: row.sum(),
            back_faces: row.back_faces(),
            open: row.open(),
            covered: (1.0 - row.visible()) as f32,
            near: row.near() as f32,
        }
    }

    /// The share of the receiver not covered by other objects (see
    /// [`Row::visible`]).
    #[must_use]
    pub fn visible(&self) -> f64 {
        1.0 - f64::from(self.covered)
    }
}

/// Where a leaf's row stands.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum RowState {
    /// Not computed yet (a new leaf, or one whose row a split made stale).
    #[default]
    Pending,
    /// Not computed because it is not needed: the leaf's surface reflects
    /// nothing, so its radiosity is its emission whatever it receives.
    Skipped,
    /// Computed, and the leaf sees no front face (it lies under a box
    /// standing on it): by reciprocity nothing sees it, so it takes no part
    /// in the exchange. Its view says where its own light (if it emits)
    /// goes.
    ShutIn(RowView),
    /// Computed, with what the leaf sees.
    Computed(Row),
}

impl RowState {
    /// True when the leaf sees some front face: its row was computed and is
    /// not empty.
    #[must_use]
    pub(crate) fn is_exposed(&self) -> bool {
        matches!(self, RowState::Computed(_))
    }

    /// True when the row was computed (exposed or shut in).
    #[must_use]
    pub(crate) fn is_computed(&self) -> bool {
        matches!(self, RowState::Computed(_) | RowState::ShutIn(_))
    }

    /// What the row says of the receiver's view, once computed.
    #[must_use]
    pub fn view(&self) -> Option<RowView> {
        match self {
            RowState::Computed(row) => Some(RowView::of(row)),
            RowState::ShutIn(view) => Some(*view),
            RowState::Pending | RowState::Skipped => None,
        }
    }
}

/// The rows of every leaf that has one, keyed by element.
#[derive(Clone, Debug, Default)]
pub struct FormFactors {
    states: SecondaryMap<ElementKey, RowState>,
    /// Per facet that holds a copy of its group's row, what its own view of
    /// the emitters adds to the copy (see [`FormFactors::emitter_shift`]).
    emitter_shifts: SecondaryMap<ElementKey, EmitterShift>,
}

/// How a facet's own view of the emitters changes the row it borrows from
/// its group lead (see [`FormFactors::emitter_shift`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct EmitterShift {
    /// The factor on every borrowed entry.
    pub scale: f32,
    /// Per emitter patch, what is added to the scaled entry (or stands
    /// alone where the lead saw none of it).
    pub entries: SmallVec<[(u32, f32); 2]>,
}

impl EmitterShift {
    /// No change.
    pub(crate) fn none() -> Self {
        EmitterShift {
            scale: 1.0,
            entries: SmallVec::new(),
        }
    }

    fn is_none(&self) -> bool {
        self.scale == 1.0 && self.entries.is_empty()
    }
}

/// The state of a leaf with no entry.
static PENDING: RowState = RowState::Pending;

impl FormFactors {
    /// An empty store: every leaf pending.
    #[must_use]
    pub fn new() -> Self {
        FormFactors::default()
    }

    /// The state of leaf `k`'s row.
    #[must_use]
    pub fn state(&self, k: ElementKey) -> &RowState {
        self.states.get(k).unwrap_or(&PENDING)
    }

    /// Leaf `k`'s row, if computed and held here.
    #[must_use]
    pub fn row(&self, k: ElementKey) -> Option<&Row> {
        match self.states.get(k) {
            Some(RowState::Computed(row)) => Some(row),
            _ => None,
        }
    }

    /// The stored `(patch, form factor)` pairs of leaf `k` (none unless
    /// computed and exposed).
    #[must_use]
    pub fn entries(&self, k: ElementKey) -> &[(u32, f32)] {
        self.row(k).map_or(&[], Row::entries)
    }

    /// True when leaf `k` sees some front face (see [`RowState::is_exposed`]).
    #[must_use]
    pub(crate) fn is_exposed(&self, k: ElementKey) -> bool {
        self.state(k).is_exposed()
    }

    /// What leaf `k`'s row says of its view, once computed.
    #[must_use]
    pub fn view(&self, k: ElementKey) -> Option<RowView> {
        self.state(k).view()
    }

    /// Stores a computed row: [`RowState::ShutIn`] when it is empty.
    pub fn set_row(&mut self, k: ElementKey, row: Row) {
        self.emitter_shifts.remove(k);
        let state = if row.is_empty() {
            RowState::ShutIn(RowView::of(&row))
        } else {
            RowState::Computed(row)
        };
        self.states.insert(k, state);
    }

    /// Gives leaf `k` a copy of leaf `from`'s row and state (a facet that
    /// shares its group's row; see `crate::pipeline`'s row groups).
    pub(crate) fn share(&mut self, k: ElementKey, from: ElementKey) {
        self.emitter_shifts.remove(k);
        let state = self.state(from).clone();
        self.states.insert(k, state);
    }

    /// Gives leaf `k`, which holds a copy of another leaf's row (see
    /// [`FormFactors::share`]), the difference its own view of the emitters
    /// makes (none when `shift` is empty).
    pub(crate) fn set_emitter_shift(&mut self, k: ElementKey, shift: EmitterShift) {
        if shift.is_none() {
            self.emitter_shifts.remove(k);
        } else {
            self.emitter_shifts.insert(k, shift);
        }
    }

    /// How leaf `k`'s own view of the emitters changes the row it holds:
    /// `None` (no change) unless the row is a copy of its group lead's (see
    /// `crate::pipeline`'s row groups). Its form factor to patch `j` is then
    /// the row's times `scale`, plus the shift's entry for `j`.
    ///
    /// Direct light changes with a facet's tilt and place far more than
    /// what the rest of its view gathers, so a facet that borrows its lead's
    /// row takes its own visible form factors to the emitters. What it sees
    /// more of the emitters it sees less of the rest, as the lead did the
    /// other way: the borrowed entries are scaled so that the row's sum
    /// stays the lead's. (With the emitters' entries replaced and the rest
    /// left as borrowed, a lead that saw more sky than its facets also lent
    /// them less of the floor: the 10 000-triangle atrium's columns read
    /// 0.7% darker than with the whole row borrowed.)
    #[must_use]
    pub(crate) fn emitter_shift(&self, k: ElementKey) -> Option<&EmitterShift> {
        match self.states.get(k) {
            Some(RowState::Computed(_)) => self.emitter_shifts.get(k),
            _ => None,
        }
    }

    /// Leaf `k`'s form factors as the gather uses them, `(patch, F_kj)` in
    /// patch order: its stored entries, with its own view of the emitters
    /// applied where it borrows its group lead's row (see
    /// [`FormFactors::emitter_shift`]). A solver that reads the rows some
    /// other way than the gather (shots by the transposed rows) takes them
    /// from here, so that it solves the same system.
    #[must_use]
    pub(crate) fn gathered_entries(&self, k: ElementKey) -> Vec<(u32, f64)> {
        let entries = self.entries(k);
        let Some(shift) = self.emitter_shift(k) else {
            return entries.iter().map(|&(j, f)| (j, f64::from(f))).collect();
        };
        let scale = f64::from(shift.scale);
        let mut out: Vec<(u32, f64)> = entries
            .iter()
            .map(|&(j, f)| (j, f64::from(f) * scale))
            .collect();
        for &(j, d) in &shift.entries {
            match out.binary_search_by_key(&j, |e| e.0) {
                Ok(i) => out[i].1 += f64::from(d),
                Err(i) => out.insert(i, (j, f64::from(d))),
            }
        }
        out
    }

    /// Marks leaf `k` as needing no row.
    pub fn skip(&mut self, k: ElementKey) {
        self.emitter_shifts.remove(k);
        self.states.insert(k, RowState::Skipped);
    }

    /// Forgets leaf `k`'s row (it was split: its children get their own).
    pub fn forget(&mut self, k: ElementKey) {
        self.emitter_shifts.remove(k);
        self.states.remove(k);
    }

    /// Every stored row with its leaf.
    pub fn rows(&self) -> impl Iterator<Item = (ElementKey, &Row)> {
        self.states.iter().filter_map(|(k, s)| match s {
            RowState::Computed(row) => Some((k, row)),
            _ => None,
        })
    }

    /// Heap bytes of the stored rows' entries.
    #[must_use]
    pub fn row_bytes(&self) -> usize {
        self.rows().map(|(_, r)| r.heap_bytes()).sum()
    }

    /// Stored entries over all rows.
    #[must_use]
    pub fn row_entries(&self) -> usize {
        self.rows().map(|(_, r)| r.len()).sum()
    }

    /// Heap bytes of the store's own table (one slot per element key ever
    /// seen), without the rows' entries.
    #[must_use]
    pub(crate) fn table_bytes(&self) -> usize {
        self.states.capacity() * std::mem::size_of::<(u32, RowState)>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use slotmap::SlotMap;

    /// A shift lives as long as the borrowed row it goes with: a row of the
    /// leaf's own, a skip or a split leaves none.
    #[test]
    fn a_shift_goes_with_the_borrowed_row_only() {
        let mut keys: SlotMap<ElementKey, ()> = SlotMap::with_key();
        let (lead, facet) = (keys.insert(()), keys.insert(()));
        let mut store = FormFactors::new();
        store.set_row(lead, Row::from_sorted(vec![(0, 0.2), (3, 0.5)]));
        let shift = || EmitterShift {
            scale: 0.9,
            entries: SmallVec::from_slice(&[(3, 0.1)]),
        };
        store.share(facet, lead);
        store.set_emitter_shift(facet, shift());
        assert_eq!(store.emitter_shift(facet), Some(&shift()));
        assert_eq!(store.emitter_shift(lead), None);
        // Its own row.
        store.set_row(facet, Row::from_sorted(vec![(3, 0.6)]));
        assert_eq!(store.emitter_shift(facet), None);
        // Shared again, then skipped: the entries are gone, so is the shift.
        store.share(facet, lead);
        store.set_emitter_shift(facet, shift());
        store.skip(facet);
        assert_eq!(store.emitter_shift(facet), None);
        // No change is not kept.
        store.share(facet, lead);
        store.set_emitter_shift(facet, EmitterShift::none());
        assert!(store.emitter_shifts.get(facet).is_none());
        store.set_emitter_shift(facet, shift());
        store.forget(facet);
        assert!(store.emitter_shifts.get(facet).is_none());
    }
}
