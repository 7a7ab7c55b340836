//! A whole rebuild taken a step at a time, so that no frame pays for all
//! of it: the build of [`Tree::rebuild`](crate::Tree::rebuild) (Morton-sorted
//! clusters joined by binned SAH, [`crate::morton`]), one phase a step, each
//! reading the leaves' bounds as they are then. Its clusters are built as
//! [`Clusters`] says: by binned SAH, over [`EXPAND_STEPS`] steps (most of
//! the build's work), or split by code in one; either way on rayon tasks, a
//! cluster a task, as is the step that bounds the clusters. The result is
//! a topology alone (child references, 8 bytes a node), which the
//! refit that installs it gives every node its bounds. When the steps are
//! taken, and what becomes of leaves that move meanwhile, is the update
//! policy's ([`crate::policy`]).

use rayon::prelude::*;

use crate::Bound;
use crate::build::{Atom, Expand, build, size_class};
use crate::leaves::Leaves;
use crate::morton::{Clusters, Grid, LARGE_CLASSES, cut, median_of, radix_sort};
use crate::node::{NodeOut, Ref};

/// The steps the clusters' SAH builds are shared out over: in one step they
/// would cost a frame about as much as the pair search.
const EXPAND_STEPS: usize = 3;
/// The frames a rebuild with SAH clusters taking a step a frame takes (a
/// drift rebuild), its install included: one for each of the five steps
/// before the expand ([`Step::Codes`] to [`Step::Top`]), one an expand step,
/// and the refit that installs it.
pub(crate) const STAGED_FRAMES: usize = 5 + EXPAND_STEPS + 1;

/// A cluster not yet expanded, as the top build leaves it in the topology:
/// its first node holds this bit and the cluster's size, then the position
/// of its first leaf in the sorted order. No child reference has bit 30 set
/// alone: node indices and ids stay below 2^28, and leaves set bit 31.
const DEFERRED: u32 = 1 << 30;

/// What the next step does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// Morton codes and size classes of the leaves.
    Codes,
    /// Radix sort of the codes.
    Sort,
    /// Large leaves set apart; the sorted leaves cut into clusters.
    Cut,
    /// Each cluster's bound.
    Clusters,
    /// Binned SAH over the clusters and large leaves: the top of the tree.
    Top,
    /// The clusters expanded into their subtrees: a share of the topology
    /// a step, in as many steps as the clusters' finish takes.
    Expand,
    /// Done: the topology waits for the next refit.
    Ready,
}

/// A rebuild in progress (see the module docs).
#[derive(Clone, Debug)]
pub(crate) struct Staged<B: Bound> {
    /// How the clusters are built.
    finish: Clusters,
    /// What the next step does.
    step: Step,
    /// How many leaves fall in each size class.
    counts: [usize; 256],
    /// Each id's size class (empty once the large leaves are set apart).
    classes: Vec<u8>,
    /// (code, id) of every leaf, then sorted.
    keyed: Vec<(u32, u32)>,
    /// The sorted leaves that are not large.
    ids: Vec<u32>,
    /// Their codes.
    codes: Vec<u32>,
    /// The large leaves' ids.
    large: Vec<u32>,
    /// Runs of `ids` that make a cluster.
    clusters: Vec<(usize, usize)>,
    /// The atoms of the top build: clusters and large leaves.
    atoms: Vec<Atom<B>>,
    /// Each internal node's children, in preorder from the root.
    topology: Vec<[Ref; 2]>,
    /// The expand steps taken.
    expanded: usize,
    /// The topology node the next expand step starts at.
    expand_at: usize,
}

impl<B: Bound> Staged<B> {
    /// A build not begun, its clusters to be built as `finish` says.
    pub(crate) fn new(finish: Clusters) -> Self {
        Staged {
            finish,
            step: Step::Codes,
            counts: [0; 256],
            classes: Vec::new(),
            keyed: Vec::new(),
            ids: Vec::new(),
            codes: Vec::new(),
            large: Vec::new(),
            clusters: Vec::new(),
            atoms: Vec::new(),
            topology: Vec::new(),
            expanded: 0,
            expand_at: 0,
        }
    }

    /// Whether every step is taken: the topology waits for its install.
    pub(crate) fn is_ready(&self) -> bool {
        self.step == Step::Ready
    }

    /// The finished topology: each internal node's children, in preorder
    /// from the root at node 0.
    pub(crate) fn into_topology(self) -> Vec<[Ref; 2]> {
        self.topology
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.classes.capacity()
            + (self.keyed.capacity() * 2 + self.ids.capacity() + self.codes.capacity()) * 4
            + self.large.capacity() * 4
            + self.clusters.capacity() * size_of::<(usize, usize)>()
            + self.atoms.capacity() * size_of::<Atom<B>>()
            + self.topology.capacity() * size_of::<[Ref; 2]>()
    }

    /// Takes the next step over the `leaves` as they are now; `stale` are
    /// the ids that jumped clear of their bound since the build began.
    pub(crate) fn advance(&mut self, leaves: &Leaves<'_, B>, stale: &[u32]) {
        match self.step {
            Step::Codes => {
                self.take_codes(leaves);
                self.step = Step::Sort;
            }
            Step::Sort => {
                radix_sort(&mut self.keyed);
                self.step = Step::Cut;
            }
            Step::Cut => {
                // As in a whole build: leaves far larger than the typical one
                // stay out of the clusters.
                let large_above = median_of(&self.counts).saturating_add(LARGE_CLASSES);
                let n = self.keyed.len();
                (self.ids, self.codes) = (Vec::with_capacity(n), Vec::with_capacity(n));
                for &(code, id) in &self.keyed {
                    if self.classes[id as usize] > large_above {
                        self.large.push(id);
                    } else {
                        self.ids.push(id);
                        self.codes.push(code);
                    }
                }
                (self.keyed, self.classes) = (Vec::new(), Vec::new());
                if !self.ids.is_empty() {
                    cut(&self.codes, 0, self.ids.len(), self.finish.most(), &mut self.clusters);
                }
                self.step = Step::Clusters;
            }
            Step::Clusters => {
                self.bound_clusters(leaves, stale);
                self.clusters = Vec::new();
                self.step = Step::Top;
            }
            Step::Top => {
                self.topology = vec![[Ref::NONE; 2]; leaves.len - 1];
                build(&mut self.atoms, &mut self.topology, 0, &Deferred);
                self.atoms = Vec::new();
                self.step = Step::Expand;
            }
            Step::Expand => {
                let steps = match self.finish {
                    Clusters::ByCode => 1,
                    Clusters::BySah => EXPAND_STEPS,
                };
                // The clusters that begin in this step's share of the
                // topology; the last step's share ends with it.
                let end = self.topology.len() * (self.expanded + 1) / steps;
                self.expand_at = self.expand_clusters(leaves, end);
                self.expanded += 1;
                if self.expanded == steps {
                    (self.ids, self.codes, self.large) = (Vec::new(), Vec::new(), Vec::new());
                    self.step = Step::Ready;
                }
            }
            Step::Ready => {}
        }
    }

    /// The Morton code and size class of every leaf, and the classes'
    /// histogram. In node order: the bounds are read in memory order, and
    /// the classes (a byte an id) are written in the cache.
    fn take_codes(&mut self, leaves: &Leaves<'_, B>) {
        let box_ = leaves.root_bound.aabb();
        let grid = Grid::new(box_.min, box_.max);
        self.classes = vec![0; leaves.leaf_parents.len()];
        self.keyed = Vec::with_capacity(leaves.len);
        for (id, b) in leaves.in_node_order() {
            let class = size_class(&b);
            self.classes[id as usize] = class;
            self.counts[class as usize] += 1;
            self.keyed.push((grid.code(b.center()), id));
        }
    }

    /// The atoms of the top build: the large leaves, and each cluster with
    /// the merged bound of its leaves that did not jump (`stale`), on rayon
    /// tasks, in order.
    fn bound_clusters(&mut self, leaves: &Leaves<'_, B>, stale: &[u32]) {
        let bound = |id| bound_of(leaves, id);
        self.atoms = Vec::with_capacity(self.clusters.len() + self.large.len());
        self.atoms.extend(self.large.iter().map(|&id| Atom::new(Ref::leaf(id), bound(id))));
        // Sorted by code, the leaves lie anywhere in the nodes: each read
        // asks for a later one's parent link and node first (past the
        // caches, one request a cluster left most reads waiting).
        let ids = &self.ids;
        let bound_at = |k: usize| {
            leaves.prefetch_ahead(ids, k);
            bound(ids[k])
        };
        // A leaf that jumped since the codes were taken sits in its cluster
        // where it was, and is reinserted at the install: its bound now
        // would stretch the cluster across the gap and mislead the top build
        // (a trickle of teleports would leave the installed tree far
        // costlier than a fresh build).
        let mut jumped = vec![false; leaves.leaf_parents.len()];
        stale.iter().for_each(|&id| jumped[id as usize] = true);
        let clusters = self.clusters.par_iter().map(|&(start, end)| {
            let run = &ids[start..end];
            let kept = (start..end).filter(|&k| !jumped[ids[k] as usize]);
            let merged = kept.map(bound_at).reduce(|a, b| a.merge(&b));
            let merged = merged.unwrap_or_else(|| bound(run[0]));
            match run {
                &[one] => Atom::new(Ref::leaf(one), merged),
                _ => Atom::weighted(Ref(start as u32), merged, run.len() as u32),
            }
        });
        self.atoms.par_extend(clusters);
    }

    /// Expands the deferred clusters that begin in the topology from
    /// `expand_at` up to `end`; returns where the next share begins. Each
    /// cluster's nodes are a run of the topology of their own, so the
    /// clusters are built on rayon tasks, the same on any number of threads:
    /// on one, a step of SAH clusters was most of a frame.
    fn expand_clusters(&mut self, leaves: &Leaves<'_, B>, end: usize) -> usize {
        // Marks first, each cluster's run split off the topology in turn
        // (`rest` begins at node `at(rest)`).
        let mut runs = Vec::new();
        let len = self.topology.len();
        let mut rest = &mut self.topology[self.expand_at..];
        let at = |rest: &[[Ref; 2]]| len - rest.len();
        while at(rest) < end {
            let [mark, start] = rest[0];
            if mark.0 & (DEFERRED | Ref::LEAF) != DEFERRED {
                rest = &mut rest[1..];
                continue;
            }
            let (x, start, weight) = (at(rest), start.0 as usize, (mark.0 & !DEFERRED) as usize);
            // The cluster's other nodes hold no marks.
            let (out, tail) = rest.split_at_mut(weight - 1);
            runs.push((out, x as u32, start..start + weight));
            rest = tail;
        }
        let next = at(rest);
        let (finish, ids, codes) = (self.finish, &self.ids, &self.codes);
        runs.into_par_iter().for_each_init(Vec::new, |atoms, (out, base, range)| {
            let ids = &ids[range.clone()];
            atoms.clear();
            atoms.extend(ids.iter().enumerate().map(|(k, &id)| match finish {
                // Split by code alone: the bounds are the refit's to set.
                Clusters::ByCode => Atom::new(Ref::leaf(id), B::default()),
                Clusters::BySah => {
                    leaves.prefetch_ahead(ids, k);
                    Atom::new(Ref::leaf(id), bound_of(leaves, id))
                }
            }));
            finish.build(atoms, &codes[range], out, base);
        });
        next
    }
}

/// Leaf `id`'s bound: every leaf a staged build names is in the tree.
fn bound_of<B: Bound>(leaves: &Leaves<'_, B>, id: u32) -> B {
    leaves.bound(id).expect("a staged leaf is in the tree")
}

/// The top build's clusters, left for [`Step::Expand`]: each marks its first
/// node (see [`DEFERRED`]).
struct Deferred;

impl<B: Bound> Expand<B> for Deferred {
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, out: &mut [N], base: u32) -> (Ref, B) {
        out[0].set([atom.bound; 2], [Ref(DEFERRED | atom.weight), atom.r], base);
        (Ref::node(base), atom.bound)
    }
}
