//! Whole-tree builds in near-linear time: leaves sorted along a Morton
//! (Z-order) curve by radix sort, cut at Morton bit boundaries into
//! clusters, and the clusters joined by binned SAH: HLBVH (Pantaleoni &
//! Luebke 2010; Garanzha, Pantaleoni & McAllister 2011). SAH decides the top
//! levels, where a poor split costs a pair search the most. Inside the
//! clusters ([`Clusters`]) either the sort decides too, splitting at Morton
//! bit boundaries, or binned SAH over the leaves' bounds does, in twice the
//! build's time, for a tree whose pair searches visit fewer node pairs.

use glam::Vec3;
use rayon::prelude::*;

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
/// Clusters a rayon task bounds in a whole build: enough that the task's
/// overhead is lost in the gathers.
const CLUSTERS_A_TASK: usize = 256;
/// Leaves a rayon task reads in a whole build's passes over them (the size
/// classes, the box, the codes).
const LEAVES_A_TASK: usize = 4096;
/// Bits per axis of a Morton code (30 bits in all).
const BITS: u32 = 10;
/// The last cell of a Morton grid along an axis.
const LAST_CELL: f32 = ((1 << BITS) - 1) as f32;

/// Builds a tree over `leaves` (at least 2, weight 1 each) into `out`, which
/// must hold `leaves.len() - 1` nodes: preorder, `out[0]` the root, the
/// clusters finished as `finish` says. Returns the root's bound. The large
/// leaves (see below) are taken out of `leaves`.
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
    let (codes, order) = sort(leaves);
    let mut clusters = Vec::with_capacity(leaves.len() / (finish.most() / 2) + 1);
    if !leaves.is_empty() {
        cut(&codes, 0, leaves.len(), finish.most(), &mut clusters);
    }
    let leaf = |k: usize| &leaves[order[k] as usize];
    let bounded = clusters.par_iter().with_min_len(CLUSTERS_A_TASK).map(|&(start, end)| {
        if end - start == 1 {
            return *leaf(start);
        }
        let bound = (start + 1..end).fold(leaf(start).bound, |b, k| b.merge(&leaf(k).bound));
        // A cluster is named by the position of its first leaf.
        Atom::weighted(Ref(start as u32), bound, (end - start) as u32)
    });
    atoms.par_extend(bounded);
    let sorted = Sorted { leaves, order: &order, codes: &codes, finish };
    build(&mut atoms, out, 0, &sorted).1
}

/// The median size class of the leaves, from a histogram of the 256 classes.
fn median_class<B: Bound>(leaves: &[Atom<B>]) -> u8 {
    let count = |run: &[Atom<B>]| {
        let mut counts = [0; 256];
        run.iter().for_each(|a| counts[a.class as usize] += 1);
        counts
    };
    let add = |mut a: [usize; 256], b: [usize; 256]| {
        a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
        a
    };
    median_of(&leaves.par_chunks(LEAVES_A_TASK).map(count).reduce(|| [0; 256], add))
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

/// Leaves in Morton order (`leaves[order[k]]`, of code `codes[k]`): expands
/// a cluster atom (named by its first leaf's position) into a subtree, as
/// `finish` says.
struct Sorted<'a, B: Bound> {
    leaves: &'a [Atom<B>],
    order: &'a [u32],
    codes: &'a [u32],
    finish: Clusters,
}

impl<B: Bound> Expand<B> for Sorted<'_, B> {
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, out: &mut [N], base: u32) -> (Ref, B) {
        let range = atom.r.0 as usize..atom.r.0 as usize + atom.weight as usize;
        // Gathered: the build partitions its atoms in place, and other
        // tasks' clusters' leaves lie among these.
        let mut atoms: Vec<_> =
            self.order[range.clone()].iter().map(|&i| self.leaves[i as usize]).collect();
        (Ref::node(base), self.finish.build(&mut atoms, &self.codes[range], out, base))
    }
}

impl Clusters {
    /// Builds a cluster of `atoms` (at least 2 leaves, in Morton order, of
    /// codes `codes`) into `out` as this finish says: its nodes, `out[i]`
    /// named `base + i`, the cluster's root first. Returns its bound.
    pub(crate) fn build<B: Bound, N: NodeOut<B>>(
        self,
        atoms: &mut [Atom<B>],
        codes: &[u32],
        out: &mut [N],
        base: u32,
    ) -> B {
        match self {
            Clusters::ByCode => lbvh(atoms, codes, out, base),
            Clusters::BySah => build(atoms, out, base, &NoClusters).1,
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

/// The order of `leaves` by the Morton code of their centres (in the
/// [`Grid`] over the leaves' box), by a stable LSD radix sort: the codes
/// sorted, and the position in `leaves` of each. The leaves stay where
/// they are: the clusters gather theirs, on their tasks, where moving them
/// into order here would chase the permutation's cycles on one thread.
fn sort<B: Bound>(leaves: &[Atom<B>]) -> (Vec<u32>, Vec<u32>) {
    // The box of the bounds, not of the centres: the grid a staged rebuild
    // takes from the root's bound, so that for boxes both builds make the
    // same tree. (On boxes resting on a floor, the centres' box, far
    // thinner than the bounds', would split them first across their
    // thickness, into a costlier tree.) A minimum and a maximum come out
    // the same in any grouping: so does the box on any number of threads.
    let each = || leaves.par_iter().with_min_len(LEAVES_A_TASK);
    let empty = || (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (lo, hi) = each()
        .map(|a| a.bound.aabb())
        .fold(empty, |(lo, hi), b| (lo.min(b.min), hi.max(b.max)))
        .reduce(empty, |(lo, hi), (l, h)| (lo.min(l), hi.max(h)));
    let grid = Grid::new(lo, hi);
    let mut keyed = Vec::new();
    each().enumerate().map(|(i, a)| (grid.code(a.center), i as u32)).collect_into_vec(&mut keyed);
    radix_sort(&mut keyed);
    keyed.into_iter().unzip()
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
        /// The radix sort orders by the 30-bit key as a stable sort does:
        /// equal keys keep their values' order.
        #[test]
        fn radix_sort_matches_a_stable_sort(keys in prop::collection::vec(0u32..1 << 30, 0..300)) {
            // Few distinct low bits too, so that equal keys are common.
            let mut items: Vec<(u32, u32)> =
                (0..).zip(&keys).map(|(i, &k)| (k & !0xff0, i)).collect();
            let mut expected = items.clone();
            expected.sort_by_key(|&(k, _)| k);
            radix_sort(&mut items);
            prop_assert_eq!(items, expected);
        }
    }
}
