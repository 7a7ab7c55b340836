//! The change log: which ids were inserted, moved or removed since the last
//! time a [`PairCache`](crate::PairCache) or [`PairSet`](crate::PairSet)
//! caught up, so it retests only those.

/// Above this fraction of changed leaves, a pair list is recomputed by one
/// tree self-search instead of querying each changed leaf: the queries'
/// cost grows with the leaves changed, and reaches the full search's a
/// little above this fraction (chosen by measurement on `benches/frame.rs`).
const FULL_FRACTION: f32 = 0.15;

/// Ids changed since the log was last cleared: a list for iterating and a
/// bit per id for membership, or "all of them" after a whole-tree update.
#[derive(Clone, Debug, Default)]
pub(crate) struct Changes {
    all: bool,
    ids: Vec<u32>,
    bits: Vec<u64>,
}

impl Changes {
    /// Makes room for ids below `n`.
    pub(crate) fn grow(&mut self, n: usize) {
        let words = n.div_ceil(64);
        if self.bits.len() < words {
            self.bits.resize(words, 0);
        }
    }

    /// Records that `id` changed (once).
    #[inline]
    pub(crate) fn mark(&mut self, id: u32) {
        if self.all {
            return;
        }
        let (word, bit) = (id as usize / 64, 1u64 << (id % 64));
        if self.bits[word] & bit == 0 {
            self.bits[word] |= bit;
            self.ids.push(id);
        }
    }

    /// Records that every id may have changed.
    pub(crate) fn mark_all(&mut self) {
        self.clear();
        self.all = true;
    }

    /// Whether `id` changed.
    #[inline]
    pub(crate) fn is_marked(&self, id: u32) -> bool {
        self.all || self.bits.get(id as usize / 64).is_some_and(|w| w & (1 << (id % 64)) != 0)
    }

    /// Whether few enough of `len` leaves changed that querying each costs
    /// less than searching all pairs again.
    pub(crate) fn few(&self, len: usize) -> bool {
        !self.all && self.ids.len() as f32 <= FULL_FRACTION * len as f32
    }

    /// The ids marked one by one (empty when all are marked).
    pub(crate) fn ids(&self) -> &[u32] {
        &self.ids
    }

    /// Forgets every change.
    pub(crate) fn clear(&mut self) {
        for &id in &self.ids {
            self.bits[id as usize / 64] &= !(1 << (id % 64));
        }
        self.ids.clear();
        self.all = false;
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.ids.capacity() * 4 + self.bits.capacity() * 8
    }
}
