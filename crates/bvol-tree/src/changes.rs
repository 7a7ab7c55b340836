//! The change log: which ids were inserted, moved or removed since the last
//! time a [`PairCache`](crate::PairCache) or [`PairSet`](crate::PairSet)
//! caught up, so it retests only those.

use bvol_volumes::prefetch;

use crate::tuning::PAIRS_AHEAD;

/// Pairs in a 64-byte cache line.
const LINE: usize = 8;

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
        self.bit(id) != 0
    }

    /// 1 when `id` changed, else 0: without a branch, for folding.
    #[inline]
    fn bit(&self, id: u32) -> u64 {
        let word = self.bits.get(id as usize / 64).map_or(0, |w| w >> (id % 64));
        (word & 1) | u64::from(self.all)
    }

    /// 1 when either id of `pair` changed, else 0, as [`Changes::bit`].
    #[inline]
    fn touches(&self, (a, b): (u32, u32)) -> u64 {
        self.bit(a) | self.bit(b)
    }

    /// Drops from `pairs` those that touch a changed id, keeping the others
    /// in order, and hands each dropped pair to `dropped`.
    ///
    /// The pairs are read a cache line (eight pairs) at a time: a line with
    /// no changed id, most of them, moves as a block without a branch a
    /// pair, and past the caches the line [`PAIRS_AHEAD`] pairs on is asked
    /// for, which the processor's own read-ahead does not do for this loop.
    pub(crate) fn drop_touched(
        &self,
        pairs: &mut Vec<(u32, u32)>,
        mut dropped: impl FnMut((u32, u32)),
    ) {
        if self.none() {
            return; // every pair stays (a pile at rest)
        }
        let mut kept = 0;
        for start in (0..pairs.len()).step_by(LINE) {
            let end = (start + LINE).min(pairs.len());
            if let Some(ahead) = pairs.get(start + PAIRS_AHEAD) {
                prefetch(ahead);
            }
            let touched = pairs[start..end].iter().fold(0, |t, &pair| t | self.touches(pair));
            if touched == 0 {
                if kept < start {
                    pairs.copy_within(start..end, kept);
                }
                kept += end - start;
                continue;
            }
            for i in start..end {
                let pair = pairs[i];
                let touched = self.touches(pair);
                pairs[kept] = pair;
                kept += (touched ^ 1) as usize;
                if touched != 0 {
                    dropped(pair);
                }
            }
        }
        pairs.truncate(kept);
    }

    /// Drops from `pairs` those that touch a changed id, each gap filled
    /// with the last pair kept: the order changes (the same for the same
    /// pairs and changes), but only the gaps are written, a few percent of
    /// the pairs when few leaves changed, where [`Changes::drop_touched`]
    /// moves every pair after the first gap. Read a line at a time, as
    /// there.
    pub(crate) fn swap_out_touched(&self, pairs: &mut Vec<(u32, u32)>) {
        if self.none() {
            return;
        }
        let (mut i, mut end) = (0, pairs.len());
        while i < end {
            let line = (i + LINE).min(end);
            if let Some(ahead) = pairs.get(i + PAIRS_AHEAD) {
                prefetch(ahead);
            }
            if pairs[i..line].iter().fold(0, |t, &pair| t | self.touches(pair)) == 0 {
                i = line;
                continue;
            }
            while i < line && i < end {
                if self.touches(pairs[i]) != 0 {
                    // The last pair past `i` not touched takes its place;
                    // when there is none, `end` comes down to `i`.
                    while end > i + 1 && self.touches(pairs[end - 1]) != 0 {
                        end -= 1;
                    }
                    end -= 1;
                    pairs[i] = pairs[end];
                }
                i += 1;
            }
        }
        pairs.truncate(end);
    }

    /// Whether nothing changed.
    fn none(&self) -> bool {
        !self.all && self.ids.is_empty()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs of ids below 100, some runs of lines untouched and some not.
    fn pairs(len: usize) -> Vec<(u32, u32)> {
        (0..len).map(|i| ((i * 7 % 100) as u32, ((i * 13 + 1) % 100) as u32)).collect()
    }

    #[test]
    fn drop_touched_keeps_the_untouched_pairs_in_order() {
        let marked = [3, 17, 64, 99];
        let mut changes = Changes::default();
        changes.grow(100);
        for id in marked {
            changes.mark(id);
        }
        for len in [0, 1, 7, 8, 9, 31, 300] {
            let all = pairs(len);
            let (keep, drop): (Vec<_>, Vec<_>) =
                all.iter().partition(|(a, b)| !marked.contains(a) && !marked.contains(b));
            let (mut kept, mut dropped) = (all.clone(), Vec::new());
            changes.drop_touched(&mut kept, |pair| dropped.push(pair));
            assert_eq!((kept, dropped), (keep, drop), "{len} pairs");
        }
        // Nothing marked: every pair stays.
        let (mut kept, mut dropped) = (pairs(300), Vec::new());
        let mut unchanged = Changes::default();
        unchanged.grow(100);
        unchanged.drop_touched(&mut kept, |pair| dropped.push(pair));
        assert_eq!((kept, dropped), (pairs(300), Vec::new()));
    }

    /// Swapped out, the pairs kept are the untouched ones, in some order:
    /// runs of lines untouched and not, gaps near the end and at it.
    #[test]
    fn swap_out_touched_keeps_the_untouched_pairs() {
        for marked in [&[3, 17, 64, 99][..], &[0], &[1, 8, 15, 22, 29]] {
            let mut changes = Changes::default();
            changes.grow(100);
            for &id in marked {
                changes.mark(id);
            }
            for len in [0, 1, 7, 8, 9, 31, 300] {
                let untouched = |&(a, b): &(u32, u32)| !marked.contains(&a) && !marked.contains(&b);
                let mut kept: Vec<_> = pairs(len).into_iter().filter(untouched).collect();
                let mut swapped = pairs(len);
                changes.swap_out_touched(&mut swapped);
                swapped.sort_unstable();
                kept.sort_unstable();
                assert_eq!(swapped, kept, "{len} pairs, {marked:?} marked");
            }
        }
        // Nothing marked: every pair stays, in order; all marked: none.
        let mut unchanged = Changes::default();
        unchanged.grow(100);
        let mut kept = pairs(300);
        unchanged.swap_out_touched(&mut kept);
        assert_eq!(kept, pairs(300));
        unchanged.mark_all();
        unchanged.swap_out_touched(&mut kept);
        assert!(kept.is_empty());
    }

    #[test]
    fn drop_touched_drops_everything_when_all_changed() {
        let mut changes = Changes::default();
        changes.grow(100);
        changes.mark_all();
        let (mut kept, mut dropped) = (pairs(30), Vec::new());
        changes.drop_touched(&mut kept, |pair| dropped.push(pair));
        assert_eq!((kept, dropped), (Vec::new(), pairs(30)));
    }
}
