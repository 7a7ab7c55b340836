//! Whole-tree builds in near-linear time: leaves sorted along a Morton
//! (Z-order) curve by radix sort, cut at Morton bit boundaries into
//! clusters, and the clusters joined by binned SAH: HLBVH (Pantaleoni &
//! Luebke 2010; Garanzha, Pantaleoni & McAllister 2011). SAH decides the top
//! levels, where a poor split costs a pair search the most. Inside the
//! clusters ([`Clusters`]) either the sort decides too, splitting at Morton
//! bit boundaries, or binned SAH over the leaves' bounds does, in twice the
//! build's time, for a tree whose pair searches visit fewer node pairs.

use glam::Vec3;

use crate::Bound;
use crate::build::{Atom, Expand, NoClusters, build};
use crate::node::{NodeOut, Ref};

/// How a build finishes the clusters its Morton order is cut into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clusters {
    /// At most 16 leaves each, split at Morton bit boundaries (LBVH): the
    /// build in least time, for a rebuild in one go under mass motion,
    /// whose tree the next frames' motion spoils.
    ByCode,
    /// At most 256 leaves each, built by binned SAH over their bounds: about
    /// twice the build's time, and a tree whose pair search visits up to a
    /// sixth fewer node pairs (docs/performance.md); for loads, and the
    /// staged rebuilds of a tree that drifts.
    BySah,
}

impl Clusters {
    /// The most leaves a cluster holds.
    pub(crate) fn most(self) -> usize {
        match self {
            Clusters::ByCode => 16,
            Clusters::BySah => 256,
        }
    }
}

/// Leaves whose area is at least 2^(this + 1) times the median's are kept
/// out of the clusters.
pub(crate) const LARGE_CLASSES: u8 = 4;
/// Bits per axis of a Morton code (30 bits in all).
const BITS: u32 = 10;
/// The last cell of a Morton grid along an axis.
const LAST_CELL: f32 = ((1 << BITS) - 1) as f32;

/// Builds a tree over `leaves` (at least 2, weight 1 each) into `out`, which
/// must hold `leaves.len() - 1` nodes: preorder, `out[0]` the root, the
/// clusters finished as `finish` says. Returns the root's bound. `leaves`
/// is left reordered.
pub(crate) fn build_morton<B: Bound, N: NodeOut<B>>(
    leaves: &mut Vec<Atom<B>>,
    out: &mut [N],
    finish: Clusters,
) -> B {
    // Leaves far larger than the typical one stay out of the clusters: a
    // cluster holding one would be as large, and so would every node above
    // it, and a pair search would visit them all. The top-level SAH places
    // them on their own.
    let large_above = median_class(leaves).saturating_add(LARGE_CLASSES);
    let is_large = |a: &Atom<B>| a.class > large_above;
    // In place: most scenes have none, and copying every leaf into two new
    // vectors would cost as much as the radix sort.
    let mut atoms: Vec<_> = leaves.iter().filter(|a| is_large(a)).copied().collect();
    if !atoms.is_empty() {
        leaves.retain(|a| !is_large(a));
    }
    let codes = sort(leaves);
    let mut clusters = Vec::with_capacity(leaves.len() / (finish.most() / 2) + 1);
    if !leaves.is_empty() {
        cut(&codes, 0, leaves.len(), finish.most(), &mut clusters);
    }
    atoms.extend(clusters.iter().map(|&(start, end)| {
        if end - start == 1 {
            return leaves[start];
        }
        let bound =
            leaves[start + 1..end].iter().fold(leaves[start].bound, |b, a| b.merge(&a.bound));
        // A cluster is named by the position of its first leaf.
        Atom::weighted(Ref(start as u32), bound, (end - start) as u32)
    }));
    let sorted = Sorted { leaves, codes: &codes, finish };
    build(&mut atoms, out, 0, &sorted).1
}

/// The median size class of the leaves, from a histogram of the 256 classes.
fn median_class<B: Bound>(leaves: &[Atom<B>]) -> u8 {
    let mut counts = [0usize; 256];
    for a in leaves {
        counts[a.class as usize] += 1;
    }
    median_of(&counts)
}

/// The median class of a histogram of size classes.
pub(crate) fn median_of(counts: &[usize; 256]) -> u8 {
    let total: usize = counts.iter().sum();
    let mut seen = 0;
    for (class, &count) in counts.iter().enumerate() {
        seen += count;
        if 2 * seen >= total {
            return class as u8;
        }
    }
    u8::MAX
}

/// Leaves in Morton order with their codes: expands a cluster atom (named by
/// its first leaf's position) into a subtree, as `finish` says.
struct Sorted<'a, B: Bound> {
    leaves: &'a [Atom<B>],
    codes: &'a [u32],
    finish: Clusters,
}

impl<B: Bound> Expand<B> for Sorted<'_, B> {
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, out: &mut [N], base: u32) -> (Ref, B) {
        let range = atom.r.0 as usize..atom.r.0 as usize + atom.weight as usize;
        match self.finish {
            Clusters::ByCode => {
                (Ref::node(base), lbvh(&self.leaves[range.clone()], &self.codes[range], out, base))
            }
            // The build partitions its atoms in place: a copy of the
            // cluster's, which other tasks' clusters lie beside.
            Clusters::BySah => build(&mut self.leaves[range].to_vec(), out, base, &NoClusters),
        }
    }
}

/// Where to split the sorted range `start..end` (at least 2 long), relative
/// to `start`: at the first code with the highest differing bit set, or in the
/// middle when all codes are equal.
fn morton_split(codes: &[u32], start: usize, end: usize) -> usize {
    let (first, last) = (codes[start], codes[end - 1]);
    if first == last {
        return (end - start) / 2;
    }
    let bit = 31 - (first ^ last).leading_zeros();
    codes[start..end].partition_point(|c| c & (1 << bit) == 0)
}

/// Cuts the sorted range `start..end` at Morton bit boundaries until every
/// piece has at most `most` leaves, appending the pieces in order.
pub(crate) fn cut(
    codes: &[u32],
    start: usize,
    end: usize,
    most: usize,
    clusters: &mut Vec<(usize, usize)>,
) {
    if end - start <= most {
        clusters.push((start, end));
        return;
    }
    let mid = start + morton_split(codes, start, end);
    cut(codes, start, mid, most, clusters);
    cut(codes, mid, end, most, clusters);
}

/// Sorts `leaves` by the Morton code of their centres (in the [`Grid`] over
/// the leaves' box) with a stable LSD radix sort, and returns the sorted
/// codes.
fn sort<B: Bound>(leaves: &mut [Atom<B>]) -> Vec<u32> {
    // The box of the bounds, not of the centres: the grid a staged rebuild
    // takes from the root's bound, so that for boxes both builds make the
    // same tree. (On boxes resting on a floor, the centres' box, far
    // thinner than the bounds', would split them first across their
    // thickness, into a costlier tree.)
    let (lo, hi) = leaves.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), a| {
        let b = a.bound.aabb();
        (lo.min(b.min), hi.max(b.max))
    });
    let grid = Grid::new(lo, hi);
    let mut keyed: Vec<(u32, u32)> =
        leaves.iter().enumerate().map(|(i, a)| (grid.code(a.center), i as u32)).collect();
    radix_sort(&mut keyed);
    permute(leaves, &mut keyed);
    keyed.into_iter().map(|(c, _)| c).collect()
}

/// The Morton grid over a box (the leaves' bounds'): 2^10 cubic cells
/// along its longest axis.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Grid {
    lo: Vec3,
    scale: Vec3,
}

impl Grid {
    /// The grid over the box from `lo` to `hi`.
    pub(crate) fn new(lo: Vec3, hi: Vec3) -> Grid {
        let extent = hi - lo;
        // Cubic cells, sized by the longest axis: a thin axis gets as many
        // cells as its length fills, not all 1024. Scaled to 1024 cells of
        // its own, the height of bodies on a ground (a few body sizes
        // against hundreds along the ground) took a third of every code's
        // bits, and clusters came out a slice of height thin and tens of
        // bodies wide: their bounds overlapped each other's over the whole
        // layer, and a pair search visited five times the node pairs. A
        // world of one point gets scale 0 (every code 0).
        let scale = Vec3::splat(LAST_CELL / extent.max_element());
        let usable = extent.cmpgt(Vec3::ZERO) & scale.is_finite_mask();
        Grid { lo, scale: Vec3::select(usable, scale, Vec3::ZERO) }
    }

    /// The 30-bit Morton code of the cell holding `p` (clamped into the grid).
    #[inline]
    pub(crate) fn code(&self, p: Vec3) -> u32 {
        let q = ((p - self.lo) * self.scale).clamp(Vec3::ZERO, Vec3::splat(LAST_CELL)).as_uvec3();
        spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2
    }
}

/// Reorders `items` in place so that position `p` holds the item that was
/// at `from[p].1`, following the permutation's cycles (each item moves once,
/// with no second array of items, whose pages would be faulted in at every
/// build). Leaves every `from[p].1` spent.
fn permute<T: Copy>(items: &mut [T], from: &mut [(u32, u32)]) {
    const DONE: u32 = u32::MAX;
    for start in 0..items.len() {
        if from[start].1 == DONE {
            continue;
        }
        let first = items[start];
        let mut p = start;
        loop {
            let src = std::mem::replace(&mut from[p].1, DONE) as usize;
            if src == start {
                items[p] = first;
                break;
            }
            items[p] = items[src];
            p = src;
        }
    }
}

/// Spreads the low 10 bits of `v` to every third bit (bit i to bit 3i).
fn spread(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | x << 16) & 0x0300_00FF;
    x = (x | x << 8) & 0x0300_F00F;
    x = (x | x << 4) & 0x030C_30C3;
    (x | x << 2) & 0x0924_9249
}

/// Stable LSD radix sort of (key, value) by the 30-bit key: three passes of
/// 10 bits, O(n).
pub(crate) fn radix_sort(items: &mut Vec<(u32, u32)>) {
    let mut scratch = vec![(0, 0); items.len()];
    for pass in 0..3 {
        let shift = pass * BITS;
        let digit = |k: u32| ((k >> shift) & ((1 << BITS) - 1)) as usize;
        let mut offsets = vec![0usize; 1 << BITS];
        for &(k, _) in items.iter() {
            offsets[digit(k)] += 1;
        }
        let mut sum = 0;
        for o in offsets.iter_mut() {
            (*o, sum) = (sum, sum + *o);
        }
        for &item in items.iter() {
            let d = digit(item.0);
            scratch[offsets[d]] = item;
            offsets[d] += 1;
        }
        std::mem::swap(items, &mut scratch);
    }
}

/// Top-down LBVH over a sorted range of at least 2 leaves: split where the
/// highest differing bit of the range's codes flips (Lauterbach et al. 2009).
/// Within a cluster this costs nothing but the split search, and makes
/// subtrees as good for pair searches as binned SAH would, in less time.
pub(crate) fn lbvh<B: Bound, N: NodeOut<B>>(
    leaves: &[Atom<B>],
    codes: &[u32],
    out: &mut [N],
    base: u32,
) -> B {
    let mid = morton_split(codes, 0, codes.len());
    let (head, rest) = out.split_at_mut(1);
    let (left_out, right_out) = rest.split_at_mut(mid - 1);
    let sub = |range: std::ops::Range<usize>, out: &mut [N], base: u32| match range.len() {
        1 => (leaves[range.start].r, leaves[range.start].bound),
        _ => (Ref::node(base), lbvh(&leaves[range.clone()], &codes[range], out, base)),
    };
    let (lr, lb) = sub(0..mid, left_out, base + 1);
    let (rr, rb) = sub(mid..codes.len(), right_out, base + mid as u32);
    head[0].set([lb, rb], [lr, rr], base);
    lb.merge(&rb)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    proptest! {
        /// The in-place permutation gives what a gather into a new array gives.
        #[test]
        fn permute_matches_a_gather(keys in prop::collection::vec(any::<u32>(), 0..300)) {
            let mut order: Vec<(u32, u32)> = (0..keys.len() as u32).map(|i| (keys[i as usize], i)).collect();
            order.sort_by_key(|&(k, i)| (k, i)); // some permutation of the positions
            let items: Vec<u64> = (0..keys.len() as u64).map(|i| i * 7 + 3).collect();
            let gathered: Vec<u64> = order.iter().map(|&(_, i)| items[i as usize]).collect();
            let mut permuted = items.clone();
            permute(&mut permuted, &mut order);
            prop_assert_eq!(permuted, gathered);
        }
    }
}
