//! Every overlapping pair of leaves: within one tree (each internal node's
//! two subtrees against each other), or between two trees (dynamic against
//! static: the static tree's leaves are never tested against each other).
//!
//! The search is a simultaneous descent over pairs of internal nodes, with a
//! mask of which children take part, so that a leaf met against a subtree
//! stays represented by its parent node and every step has the same shape:
//! load two nodes, four overlap tests, branch-free pushes. It runs breadth
//! first, a level of independent steps at a time, which the processor
//! overlaps; and over the nodes from last to first, so that a node's two
//! subtrees, searched just before it, are still in cache when the search
//! between them starts, instead of being fetched again from memory.
//!
//! The work is cut into a fixed list of independent tasks, fixed by the trees
//! alone, which rayon runs in parallel; their outputs are concatenated in task
//! order, so the result is the same `Vec`, in the same order, on any number
//! of threads. On one thread the same tasks run in the same order on one
//! walker, which writes straight into the caller's vector: no part a task
//! and no copies (with millions of pairs a frame, the copies would be a
//! noticeable share of the search).

use std::cell::RefCell;

use rayon::prelude::*;

use crate::cross::{Cross, cross, spread_first, spread_second};
use crate::node::{BOTH, Node, Ref, SELECT};
use crate::{Bound, BoundPair, Tree, one_thread};

/// Internal nodes per task of a one-tree search: small enough for work
/// stealing to balance 16+ threads, large enough that per-task overhead is
/// below 1% of the descent.
const CHUNK: usize = 256;
/// A two-tree search is expanded until it has this many pending visits.
const TASKS: usize = 512;
/// A breadth-first level with more visits than this is split in two tasks.
const SPLIT: usize = 4096;
/// How many visits ahead in a level the search asks for the two nodes of a
/// visit. Within the caches the search does not wait on memory and this
/// changes nothing; past them (a million boxes) a level's visits land
/// anywhere in the nodes, and each would wait for its two.
const LEVEL_AHEAD: usize = 32;

/// A pair of internal nodes to visit, `x` in the first tree and `y` in the
/// second, and which of their children take part: each a node index (below
/// 2^28, as ids are, and so node counts) with two selection bits above it,
/// bit 30 for side 0 and bit 31 for side 1: eight bytes where a separate mask
/// made twelve, and every visit writes four of them, kept or not. Not packed
/// into one `u64`: the shifts would cost more than the store they save.
#[derive(Clone, Copy, Debug, Default)]
struct Visit {
    x: u32,
    y: u32,
}

/// A search's pairs in runs, in their order: what a walker found, as the
/// walkers of the levels it split found them, not copied into one list.
type Parts = Vec<Vec<(u32, u32)>>;

impl Visit {
    /// The node index of a side.
    #[inline(always)]
    fn node(side: u32) -> u32 {
        side & ((1 << SELECT) - 1)
    }

    /// The selection bits of a side, bit `i` for child `i`.
    #[inline(always)]
    fn selected(side: u32) -> u32 {
        side >> SELECT
    }
}

/// A pair search over one tree (`a` and `b` the same nodes, each pair found
/// once, in either order) or two (`(id in a, id in b)`).
struct Search<'t, B: Bound> {
    a: &'t [Node<B>],
    b: &'t [Node<B>],
}

impl<B: Bound> Search<'_, B> {
    /// The two nodes of visit `v`, unchecked: a range check on each, at
    /// every visit and for the visit asked for ahead, made the search a
    /// tenth slower (the checks, and the registers they hold).
    #[inline(always)]
    fn nodes(&self, v: Visit) -> (&Node<B>, &Node<B>) {
        let (x, y) = (Visit::node(v.x) as usize, Visit::node(v.y) as usize);
        debug_assert!(x < self.a.len() && y < self.b.len(), "a visit names no node");
        // SAFETY: a visit's sides name nodes of its trees: each is a root,
        // or was read from a node's stored visit sides (its own index, or
        // an internal child's), and a tree's child references and visit
        // sides name its nodes (`Tree::validate` checks both).
        unsafe { (self.a.get_unchecked(x), self.b.get_unchecked(y)) }
    }
}

/// What one pair search ([`Tree::pairs_into`]) did: the work it took and
/// what it found, for telling where a search's time goes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SearchStats {
    /// Node pairs visited: an internal node against itself (its two
    /// children tested against each other), or two internal nodes (their
    /// selected children tested against each other, up to four tests). The
    /// same count on any number of threads.
    pub node_pairs: u64,
    /// Pairs of overlapping leaves found.
    pub pairs: u64,
}

impl<B: Bound> Tree<B> {
    /// Every pair of leaves whose tight bounds overlap or touch, each once as
    /// `(a, b)` with `a < b`. The order is fixed by the tree: the same on any
    /// number of threads (run inside a rayon pool to choose it).
    pub fn pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        self.pairs_into(&mut out);
        out
    }

    /// [`Tree::pairs`] into `out` (cleared first), reusing its allocation,
    /// and what the search took.
    ///
    /// ```
    /// use bvol_tree::Tree;
    /// use bvol_volumes::Aabb;
    /// use glam::Vec3;
    /// let at = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
    /// let tree = Tree::from_bounds(&[at(0.0), at(0.5), at(3.0), at(3.5)])?;
    /// let mut pairs = Vec::new();
    /// let stats = tree.pairs_into(&mut pairs);
    /// pairs.sort_unstable(); // they come in the tree's order
    /// assert_eq!(pairs, vec![(0, 1), (2, 3)]);
    /// assert_eq!(stats.pairs, 2);
    /// // The root's two subtrees, then each subtree's two leaves.
    /// assert_eq!(stats.node_pairs, 3);
    /// # Ok::<(), bvol_tree::TreeError>(())
    /// ```
    pub fn pairs_into(&self, out: &mut Vec<(u32, u32)>) -> SearchStats {
        let search = Search { a: &self.nodes, b: &self.nodes };
        // Last chunk first: in preorder a node's subtree follows it, so going
        // backwards a node's two subtrees were searched just before it, and
        // the search between them finds their nodes still in cache.
        let mut chunks: Vec<_> = (0..self.nodes.len()).step_by(CHUNK).rev().collect();
        let range = |start: usize| start..(start + CHUNK).min(self.nodes.len());
        let node_pairs;
        if one_thread() {
            let mut pairs = Buf { items: std::mem::take(out), len: 0 };
            node_pairs = with_walker(|walker| {
                std::mem::swap(&mut walker.out, &mut pairs);
                for &start in &chunks {
                    walker.siblings(&search, range(start));
                }
                std::mem::swap(&mut walker.out, &mut pairs);
                std::mem::take(&mut walker.visits)
            });
            // Its length stays the pairs': the next search overwrites them
            // in place (the walker's buffer holds its length as room already
            // written) rather than filling the buffer afresh.
            pairs.items.truncate(pairs.len);
            *out = pairs.items;
            for pair in out.iter_mut() {
                *pair = ordered(*pair);
            }
        } else {
            // The root's chunk runs first: its descents (the root's
            // subtrees against each other, and its nearest descendants')
            // are the longest of the search, and begun last they would be
            // left to one thread while the others wait. Its part goes back
            // to its place before the parts are joined.
            let top =
                self.root.is_node().then(|| chunks.len() - 1 - self.root.index() as usize / CHUNK);
            if let Some(top) = top {
                chunks[..=top].rotate_right(1);
            }
            // A task a chunk: by default rayon cuts the list into a few
            // runs, and a thread that has begun a run goes through it
            // alone, so that one thread was left with several long chunks
            // while the others had finished.
            let (mut parts, visits): (Vec<Parts>, Vec<u64>) = chunks
                .par_iter()
                .with_max_len(1)
                .map(|&start| {
                    with_walker(|walker| {
                        walker.siblings(&search, range(start));
                        walker.take()
                    })
                })
                .unzip();
            node_pairs = visits.iter().sum();
            if let Some(top) = top {
                parts[..=top].rotate_left(1);
            }
            concat(parts.into_iter().flatten().collect(), out, ordered);
        }
        SearchStats { node_pairs, pairs: out.len() as u64 }
    }

    /// Every pair `(id in self, id in other)` of leaves whose tight bounds
    /// overlap or touch, each once; leaves of the same tree are never tested
    /// against each other. Deterministic order, as [`Tree::pairs`].
    pub fn pairs_with(&self, other: &Tree<B>) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        if self.root == Ref::NONE
            || other.root == Ref::NONE
            || !self.root_bound.overlaps(&other.root_bound)
        {
            return out;
        }
        match (self.root.is_node(), other.root.is_node()) {
            (true, true) => {}
            // A one-leaf tree: a single query of its bound.
            (_, false) => {
                let b = other.root.index();
                self.query(&other.root_bound, |a| out.push((a, b)));
                return out;
            }
            (false, true) => {
                let a = self.root.index();
                other.query(&self.root_bound, |b| out.push((a, b)));
                return out;
            }
        }
        let search = Search { a: &self.nodes, b: &other.nodes };
        let first = Visit { x: self.root.index() | BOTH, y: other.root.index() | BOTH };
        let (visits, head) = with_walker(|walker| {
            let visits = walker.expand(&search, first, TASKS);
            (visits, walker.take().0)
        });
        let parts: Vec<Parts> = visits
            .par_chunks(TASKS / 64)
            .with_max_len(1)
            .map(|visits| {
                with_walker(|walker| {
                    walker.run(&search, visits);
                    walker.take().0
                })
            })
            .collect();
        let all = head.into_iter().chain(parts.into_iter().flatten()).collect();
        concat(all, &mut out, ids);
        out
    }
}

/// The search files a pair as it meets it, two leaves' references; one
/// pass over the pairs found orders them and takes their ids for less than
/// doing so for the four outcomes of every visit, kept or not (a tenth of
/// the search's instructions). Both references carry the leaf flag, so
/// they order as the ids do.
#[inline]
fn ordered(pair: (u32, u32)) -> (u32, u32) {
    ids((pair.0.min(pair.1), pair.0.max(pair.1)))
}

/// The ids of a pair of leaves' references.
#[inline]
fn ids(pair: (u32, u32)) -> (u32, u32) {
    (Ref(pair.0).index(), Ref(pair.1).index())
}

/// Writes the parts in order to `out`, each pair passed through `f`, and
/// cuts `out` there: a rayon task a part, each writing its own stretch of
/// `out`: with millions of pairs, one thread copying them after the search
/// would add a noticeable share of its time. What `out` held is overwritten
/// rather than cleared first, so that the last search's pairs save filling
/// that room with zeros.
fn concat(parts: Parts, out: &mut Vec<(u32, u32)>, f: impl Fn((u32, u32)) -> (u32, u32) + Sync) {
    out.resize(parts.iter().map(Vec::len).sum::<usize>(), (0, 0));
    let mut rest = &mut out[..];
    let mut stretches = Vec::with_capacity(parts.len());
    for part in &parts {
        let (stretch, tail) = std::mem::take(&mut rest).split_at_mut(part.len());
        stretches.push(stretch);
        rest = tail;
    }
    stretches.into_par_iter().zip(&parts).with_max_len(1).for_each(|(stretch, part)| {
        stretch.iter_mut().zip(part).for_each(|(to, &pair)| *to = f(pair));
    });
}

/// A stack (or output buffer) whose pushes are branch-free: the value is
/// written unconditionally and the length advanced by the condition, so the
/// unpredictable overlap results of a traversal cost no mispredictions.
struct Buf<T> {
    items: Vec<T>,
    len: usize,
}

impl<T: Copy + Default> Buf<T> {
    /// Makes room for `k` more pushes: twice that, so that a buffer grows
    /// by a level's worth at a time. Room is written (filled with defaults)
    /// when made, so not more than that: the output of a search on one
    /// thread is the caller's vector, cut to the last search's pairs, and
    /// doubling it would fill millions of entries every search. The vector's
    /// own capacity grows by doubling.
    #[inline]
    fn reserve(&mut self, k: usize) {
        if self.len + k > self.items.len() {
            let n = (self.len + 2 * k).max(64);
            self.items.resize(n, T::default());
        }
    }

    /// The four slots from the length on, where a visit files its
    /// outcomes. A range-checked slice here, at every visit, made the
    /// search a sixth slower: the checks, and the registers they hold.
    ///
    /// # Safety
    ///
    /// Room for four more must have been made ([`Buf::reserve`]) and not
    /// used since.
    #[inline(always)]
    unsafe fn window(&mut self) -> &mut [T; 4] {
        debug_assert!(self.len + 4 <= self.items.len(), "no room was made for a window");
        // SAFETY: the caller made room, `len + 4 <= items.len()`: the four
        // slots are in the vector, and `[T; 4]` has `T`'s alignment.
        unsafe { &mut *self.items.as_mut_ptr().add(self.len).cast::<[T; 4]>() }
    }

    /// Pushes `item` when `keep` holds; room must have been reserved.
    #[inline(always)]
    fn push_if(&mut self, item: T, keep: bool) {
        self.items[self.len] = item;
        self.len += usize::from(keep);
    }
}

impl<T> Default for Buf<T> {
    fn default() -> Self {
        Buf { items: Vec::new(), len: 0 }
    }
}

thread_local! {
    /// The walkers of each thread kept from search to search: their
    /// frontiers and output grow to a search's size once, instead of being
    /// allocated afresh, their room filled and their pages faulted in, at
    /// every search (with millions of pairs a frame, a noticeable share of
    /// the search). One a depth of nesting: a split's halves, run while
    /// their thread's walker is out, take the next, and keeping only one
    /// kept whichever came back first, a half's, so that the chunk's
    /// walker was made afresh at the next search.
    static SPARE: RefCell<Vec<Walker>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with one of this thread's spare walkers, or a fresh one when
/// they are all out, and keeps it as a spare. A walker comes back with
/// nothing pending.
fn with_walker<R>(f: impl FnOnce(&mut Walker) -> R) -> R {
    let mut walker = SPARE.with_borrow_mut(Vec::pop).unwrap_or_default();
    let result = f(&mut walker);
    SPARE.with_borrow_mut(|spare| spare.push(walker));
    result
}

/// The frontiers and output of one thread's descents.
#[derive(Default)]
struct Walker {
    /// The visits of the current level.
    now: Buf<Visit>,
    /// The visits of the next level.
    next: Buf<Visit>,
    out: Buf<(u32, u32)>,
    /// The pairs that follow `out`: the parts of the two halves of a split
    /// level, as the halves' walkers gave them. A descent ends at a split,
    /// so `out` takes nothing after them. Copied into `out` at every join
    /// instead, the pairs under a large leaf (most of a search's, in a world
    /// of mixed sizes) were copied once for each split above them, on one
    /// thread at a time.
    after: Parts,
    /// Node pairs visited since the last [`Walker::take`].
    visits: u64,
}

impl Walker {
    /// Every pair under the given visits, appended to the output.
    fn run<B: Bound>(&mut self, s: &Search<B>, visits: &[Visit]) {
        self.now.len = 0;
        self.now.reserve(visits.len());
        for &v in visits {
            self.now.push_if(v, true);
        }
        self.descend(s);
    }

    /// Runs the pending visits and every visit they lead to. The descent is
    /// breadth-first: the visits of one level do not depend on each other,
    /// so the processor overlaps their node loads and overlap tests, where a
    /// depth-first stack chains every step on the one before.
    ///
    /// A level wider than [`SPLIT`] is halved and the halves descended on
    /// two rayon tasks, their pairs appended left then right: the split
    /// depends on the level's width only, so the output does not depend on
    /// the thread count, and one wide search (a large leaf against all the
    /// small ones it covers) no longer holds up the whole pair search. On
    /// one thread this walker descends the halves in turn.
    fn descend<B: Bound>(&mut self, s: &Search<B>) {
        while self.now.len > 0 {
            if self.now.len > SPLIT {
                let (left, right) = self.now.items[..self.now.len].split_at(self.now.len / 2);
                if one_thread() {
                    let (left, right) = (left.to_vec(), right.to_vec());
                    self.run(s, &left);
                    self.run(s, &right);
                    return;
                }
                let half = |visits: &[Visit]| {
                    with_walker(|walker| {
                        walker.run(s, visits);
                        walker.take()
                    })
                };
                let (a, b) = rayon::join(|| half(left), || half(right));
                for (parts, visits) in [a, b] {
                    self.visits += visits;
                    self.after.extend(parts);
                }
                self.now.len = 0;
                return;
            }
            self.level(s);
            std::mem::swap(&mut self.now, &mut self.next);
        }
    }

    /// Visits the current level, filling the next.
    fn level<B: Bound>(&mut self, s: &Search<B>) {
        debug_assert!(self.after.is_empty(), "pairs filed after a split's parts");
        let n = self.now.len;
        self.visits += n as u64;
        self.next.len = 0;
        self.next.reserve(4 * n);
        self.out.reserve(4 * n);
        for k in 0..n {
            if let Some(&ahead) = self.now.items[..n].get(k + LEVEL_AHEAD) {
                let (a, b) = s.nodes(ahead);
                bvol_volumes::prefetch(a);
                bvol_volumes::prefetch(b);
            }
            let v = self.now.items[k];
            // SAFETY: room was made for four a visit of the level, and a
            // visit files at most four pairs and four visits.
            unsafe { self.step(s, v) };
        }
    }

    /// Runs levels from `first` until `n` visits are pending (or none is),
    /// and returns those; pairs found on the way are in the output.
    fn expand<B: Bound>(&mut self, s: &Search<B>, first: Visit, n: usize) -> Vec<Visit> {
        self.now.len = 0;
        self.now.reserve(1);
        self.now.push_if(first, true);
        while self.now.len > 0 && self.now.len < n {
            self.level(s);
            std::mem::swap(&mut self.now, &mut self.next);
        }
        let pending = self.now.items[..self.now.len].to_vec();
        self.now.len = 0;
        pending
    }

    /// One visit: the selected children of `x` against those of `y`, the
    /// four overlap tests at once ([`BoundPair::overlaps`]). The four
    /// outcomes go to fixed windows of the output and the next level.
    ///
    /// # Safety
    ///
    /// As [`Walker::file`].
    #[inline(always)]
    unsafe fn step<B: Bound>(&mut self, s: &Search<B>, v: Visit) {
        let (na, nb) = s.nodes(v);
        let selected = spread_first(Visit::selected(v.x)) & spread_second(Visit::selected(v.y));
        let hits = na.pair().overlaps(nb.pair()) & selected;
        // SAFETY: the caller's.
        unsafe { self.file((na, nb), hits) };
    }

    /// Files the outcomes `hits` (bit `2 i + j`) of children `i` of node
    /// `na` against children `j` of `nb`: two leaves are reported; a leaf
    /// against a subtree becomes a visit of the leaf's parent with only the
    /// leaf's side selected, two subtrees a visit of both: the visit sides
    /// the nodes store. Branch-free: every outcome is written, the lengths
    /// advanced by the verdicts.
    ///
    /// # Safety
    ///
    /// The next level and the output have room for four more each
    /// ([`Buf::window`]).
    #[inline(always)]
    unsafe fn file<B: Bound>(&mut self, (na, nb): (&Node<B>, &Node<B>), hits: u32) {
        let Cross { leaves, refs, visits: sides } = cross(na, nb);
        // SAFETY: the caller's.
        let (next, out) = unsafe { (self.next.window(), self.out.window()) };
        let (mut visits, mut pairs) = (0, 0);
        for k in 0..4 {
            out[pairs & 3] = (refs[k] as u32, (refs[k] >> 32) as u32);
            pairs += (hits & leaves) as usize >> k & 1;
            next[visits & 3] = Visit { x: sides[k] as u32, y: (sides[k] >> 32) as u32 };
            visits += (hits & !leaves) as usize >> k & 1;
        }
        self.next.len += visits;
        self.out.len += pairs;
    }

    /// Every pair within one tree whose lowest common ancestor is one of the
    /// internal nodes `nodes`: each node's two children against each other,
    /// then the levels below.
    fn siblings<B: Bound>(&mut self, s: &Search<B>, nodes: std::ops::Range<usize>) {
        debug_assert!(self.after.is_empty(), "pairs filed after a split's parts");
        self.next.len = 0;
        // A node files one pair or one visit at most.
        self.next.reserve(nodes.len());
        self.out.reserve(nodes.len());
        self.visits += nodes.len() as u64;
        for x in nodes.rev() {
            // The next chunk's nodes, met in the same order: read while this
            // chunk's descent works in the cache, they are there when its
            // turn comes (past the caches, each node would wait on memory).
            if let Some(next) = x.checked_sub(CHUNK) {
                bvol_volumes::prefetch(&s.a[next]);
            }
            let n = &s.a[x];
            // Free nodes have no second child.
            if n.child[1] != Ref::NONE {
                // Child 0 against child 1 only: the outcome at index 1.
                let hit = n.pair().overlaps(n.pair()) & 0b0010 != 0;
                let ([c0, c1], [v0, v1]) = (n.child, n.visit());
                let leaves = !c0.is_node() & !c1.is_node();
                self.out.push_if((c0.0, c1.0), hit & leaves);
                self.next.push_if(Visit { x: v0, y: v1 }, hit & !leaves);
            }
        }
        std::mem::swap(&mut self.now, &mut self.next);
        self.descend(s);
    }

    /// The pairs found, in parts, and the node pairs visited so far,
    /// leaving both empty.
    fn take(&mut self) -> (Parts, u64) {
        let mut parts = Vec::with_capacity(1 + self.after.len());
        parts.push(self.out.items[..self.out.len].to_vec());
        parts.append(&mut self.after);
        self.out.len = 0;
        (parts, std::mem::take(&mut self.visits))
    }
}
