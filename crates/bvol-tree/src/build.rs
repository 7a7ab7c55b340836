//! Top-down tree construction with the binned surface area heuristic
//! (Wald 2007, "On fast construction of SAH-based bounding volume
//! hierarchies"), over "atoms": leaves, whole subtrees kept as they are when
//! only part of a tree is rebuilt, or clusters of leaves that a callback
//! builds (the top levels of [`crate::morton`]'s builds).

use bvol_volumes::Aabb;
use glam::Vec3;

use crate::Bound;
use crate::node::{NodeOut, Ref};

/// Bins per split. Wald reports 16 to 32 bins within a few percent of a full
/// sweep; 16 keeps the bins in L1.
const BINS: usize = 16;
/// Below this depth splits are by SAH; deeper, by the median, so a skewed
/// input cannot make the recursion (or the tree) deeper than this plus
/// log2(n).
const SAH_DEPTH: u32 = 48;
/// Ranges up to this long are split by an exact SAH sweep over the sorted
/// centres: the few atoms are cheaper to sort than to bin, and most nodes of
/// a tree are this small.
const SWEEP: usize = 16;
/// Ranges at least this long are built on two rayon tasks.
const PARALLEL_MIN: usize = 4096;

/// What a build places: a leaf or a subtree kept whole (weight 1), or a
/// cluster of `weight` leaves that the build's callback expands in place.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Atom<B: Bound> {
    /// The leaf or subtree; for a cluster, whatever names it to the callback.
    pub(crate) r: Ref,
    /// Its bound.
    pub(crate) bound: B,
    /// The centre of its bound, cached: binning reads it at every level.
    pub(crate) center: Vec3,
    /// The leaves it stands for: 1, or a cluster's size.
    pub(crate) weight: u32,
    /// Its size class: the binary exponent of its surface area.
    pub(crate) class: u8,
}

impl<B: Bound> Atom<B> {
    /// The atom for a leaf or kept subtree `r` with bound `bound`.
    pub(crate) fn new(r: Ref, bound: B) -> Self {
        Self::weighted(r, bound, 1)
    }

    /// An atom standing for `weight` leaves.
    pub(crate) fn weighted(r: Ref, bound: B, weight: u32) -> Self {
        Atom { r, bound, center: bound.center(), weight, class: size_class(&bound) }
    }
}

/// The binary exponent of a bound's surface area, from the bits of the f32
/// area (0 for zero, 255 for infinite): a size class in one shift.
pub(crate) fn size_class<B: Bound>(bound: &B) -> u8 {
    ((bound.cost() as f32).to_bits() >> 23) as u8
}

/// Builds a cluster atom into its nodes: given the atom, its `weight - 1`
/// nodes and the name of the first, returns the subtree's root and bound.
pub(crate) trait Expand<B: Bound>: Sync {
    /// Builds `atom`'s subtree into `out`, node `out[i]` named `base + i`.
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, out: &mut [N], base: u32) -> (Ref, B);
}

/// For builds with no clusters.
pub(crate) struct NoClusters;

impl<B: Bound> Expand<B> for NoClusters {
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, _: &mut [N], _: u32) -> (Ref, B) {
        (atom.r, atom.bound)
    }
}

/// Builds a tree over `atoms` (total weight at least 2) into `out`, which
/// must hold exactly `weight - 1` nodes: preorder, `out[0]` the root, node
/// `out[i]` named `base + i` in child references. Returns the root's bound.
/// `out` takes whole nodes, or child references alone ([`NodeOut`]).
///
/// Every subtree takes a contiguous run of `out` whose length is fixed by the
/// weight of its atoms, so the two halves of a split can be built in parallel
/// and the result is the same whatever the number of threads.
pub(crate) fn build<B: Bound, N: NodeOut<B>>(
    atoms: &mut [Atom<B>],
    out: &mut [N],
    base: u32,
    clusters: &impl Expand<B>,
) -> (Ref, B) {
    match atoms {
        [one] if one.weight > 1 => clusters.expand(one, out, base),
        [one] => (one.r, one.bound),
        _ => (Ref::node(base), build_at(atoms, out, base, 0, clusters)),
    }
}

fn build_at<B: Bound, N: NodeOut<B>>(
    atoms: &mut [Atom<B>],
    out: &mut [N],
    base: u32,
    depth: u32,
    clusters: &impl Expand<B>,
) -> B {
    let parallel = out.len() >= PARALLEL_MIN;
    let mid = split(atoms, depth);
    let (left, right) = atoms.split_at_mut(mid);
    let left_weight: u32 = left.iter().map(|a| a.weight).sum();
    let (head, rest) = out.split_at_mut(1);
    let (left_out, right_out) = rest.split_at_mut(left_weight as usize - 1);
    let sub = |atoms: &mut [Atom<B>], out: &mut [N], base: u32| match atoms {
        [one] if one.weight > 1 => clusters.expand(one, out, base),
        [one] => (one.r, one.bound),
        _ => (Ref::node(base), build_at(atoms, out, base, depth + 1, clusters)),
    };
    let right_base = base + left_weight;
    let ((lr, lb), (rr, rb)) = if parallel {
        rayon::join(|| sub(left, left_out, base + 1), || sub(right, right_out, right_base))
    } else {
        (sub(left, left_out, base + 1), sub(right, right_out, right_base))
    };
    head[0].set([lb, rb], [lr, rr], base);
    lb.merge(&rb)
}

/// Reorders `atoms` into two non-empty halves and returns the length of the
/// first: the binned-SAH split along the widest axis of the centres, or the
/// median when the centres coincide or the recursion is deep.
fn split<B: Bound>(atoms: &mut [Atom<B>], depth: u32) -> usize {
    let n = atoms.len();
    if n == 2 {
        return 1;
    }
    let (lo, hi) = atoms.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), a| {
        (lo.min(a.center), hi.max(a.center))
    });
    let axis = (hi - lo).max_position();
    if n <= SWEEP {
        return sweep(atoms, axis);
    }
    if depth >= SAH_DEPTH {
        return median(atoms, axis);
    }
    match place_split(atoms, axis, lo[axis], hi[axis] - lo[axis]) {
        Some((bins, last)) => partition(atoms, |a| bins.of(a) <= last),
        None => median(atoms, axis),
    }
}

/// Bins of atom centres along one axis.
#[derive(Clone, Copy)]
struct Bins {
    axis: usize,
    min: f32,
    scale: f32,
    count: usize,
}

impl Bins {
    /// The bin of an atom's centre.
    #[inline]
    fn of<B: Bound>(&self, a: &Atom<B>) -> usize {
        (((a.center[self.axis] - self.min) * self.scale) as usize).min(self.count - 1)
    }
}

/// The cheapest binned split by centre along `axis` (centres spanning
/// `min .. min + extent`), if any: the bins, and the last bin of the left
/// half.
fn place_split<B: Bound>(
    atoms: &[Atom<B>],
    axis: usize,
    min: f32,
    extent: f32,
) -> Option<(Bins, usize)> {
    // Fewer bins for short ranges: the sweeps cost O(bins) per node, which
    // dominates the bottom levels of the tree when it is a fixed 16.
    let count = atoms.len().clamp(2, BINS);
    let scale = count as f32 / extent;
    if !(extent > 0.0 && scale.is_finite()) {
        return None;
    }
    let bins = Bins { axis, min, scale, count };
    let last = best_bin(atoms, count, |a| bins.of(a))?;
    Some((bins, last))
}

/// The last bin of the left half in the cheapest binned split, `None` when no
/// split has atoms on both sides. Cost = area * leaves on each side, in f64.
fn best_bin<B: Bound>(
    atoms: &[Atom<B>],
    bins: usize,
    bin: impl Fn(&Atom<B>) -> usize,
) -> Option<usize> {
    let empty = Aabb::new(Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut boxes = [empty; BINS];
    let mut counts = [0usize; BINS];
    for a in atoms {
        let k = bin(a);
        boxes[k] = boxes[k].merge(&a.bound.aabb());
        counts[k] += a.weight as usize;
    }
    // Right-to-left sweep: cost of the right half starting at each bin.
    let mut right_cost = [0.0f64; BINS];
    let (mut acc, mut count) = (empty, 0);
    for k in (1..bins).rev() {
        (acc, count) = (acc.merge(&boxes[k]), count + counts[k]);
        right_cost[k] = if count > 0 { acc.cost() * count as f64 } else { f64::INFINITY };
    }
    let (mut acc, mut count) = (empty, 0);
    let mut best: Option<(usize, f64)> = None;
    for k in 0..bins - 1 {
        (acc, count) = (acc.merge(&boxes[k]), count + counts[k]);
        if count == 0 || right_cost[k + 1].is_infinite() {
            continue;
        }
        let cost = acc.cost() * count as f64 + right_cost[k + 1];
        if best.is_none_or(|(_, c)| cost < c) {
            best = Some((k, cost));
        }
    }
    best.map(|(k, _)| k)
}

/// The exact SAH split of a few atoms (2 < n <= [`SWEEP`]): sorted by centre
/// along `axis`, then every split position costed with prefix and suffix
/// bounds. Returns the length of the first half.
fn sweep<B: Bound>(atoms: &mut [Atom<B>], axis: usize) -> usize {
    let n = atoms.len();
    // Insertion sort: stable and quick for so few.
    for i in 1..n {
        let mut j = i;
        while j > 0 && atoms[j - 1].center[axis] > atoms[j].center[axis] {
            atoms.swap(j - 1, j);
            j -= 1;
        }
    }
    let mut right = [0.0f64; SWEEP];
    let (mut acc, mut count) = (atoms[n - 1].bound.aabb(), atoms[n - 1].weight as f64);
    for k in (1..n).rev() {
        if k < n - 1 {
            acc = acc.merge(&atoms[k].bound.aabb());
            count += atoms[k].weight as f64;
        }
        right[k] = acc.cost() * count;
    }
    let (mut acc, mut count) = (atoms[0].bound.aabb(), 0.0);
    let mut best = (1, f64::INFINITY);
    for k in 1..n {
        if k > 1 {
            acc = acc.merge(&atoms[k - 1].bound.aabb());
        }
        count += atoms[k - 1].weight as f64;
        let cost = acc.cost() * count + right[k];
        if cost < best.1 {
            best = (k, cost);
        }
    }
    best.0
}

/// Moves the atoms for which `left` holds to the front (stable in neither
/// half, but deterministic); returns how many there are.
fn partition<B: Bound>(atoms: &mut [Atom<B>], left: impl Fn(&Atom<B>) -> bool) -> usize {
    let mut i = 0;
    for j in 0..atoms.len() {
        if left(&atoms[j]) {
            atoms.swap(i, j);
            i += 1;
        }
    }
    i
}

/// Splits at the median centre along `axis` (an O(n) selection).
fn median<B: Bound>(atoms: &mut [Atom<B>], axis: usize) -> usize {
    let mid = atoms.len() / 2;
    atoms.select_nth_unstable_by(mid, |a, b| a.center[axis].total_cmp(&b.center[axis]));
    mid
}
