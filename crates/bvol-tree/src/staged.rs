//! The refit path's rebuild, spread over frames so that no frame pays for a
//! whole one: the same build as [`Tree::rebuild`] (Morton-sorted clusters
//! joined by binned SAH, [`crate::morton`]), one phase a frame, each reading
//! the leaves' bounds as they are then. On 100 000 boxes a whole rebuild
//! added about 9.5 ms to its frame; the dearest phase adds 2 ms, and the
//! install 4 (the leaves' bounds moved into the new nodes). The result is a
//! topology alone (child references, 8 bytes a node), which a later refit
//! installs and gives every node its bounds.
//!
//! The leaves move while the build runs, so the topology places them where
//! they were a few frames before. A leaf that jumped clear of its bound
//! meanwhile (a teleport) would stretch its cluster's bound, and its new
//! ancestors, across the gap: it is left out of its cluster's bound, and
//! reinserted where it now is once the topology is installed. Where such
//! jumps come in a steady trickle, so many that a build taking a step a
//! frame would find more than one leaf in [`MANY_JUMPS`] stale, the build
//! takes [`TRICKLE_PACE`] steps a frame; only if one leaf in
//! [`MANY_JUMPS`] is stale even so is the tree rebuilt in one go. When
//! many leaves jump in one frame (mass motion: bodies falling faster than
//! their size, with their neighbours), the jumps are not noted: the topology
//! is installed as it is, and the next build starts at once. Inserting or
//! removing a leaf drops the build: its topology would no longer hold
//! exactly the tree's leaves.

use crate::build::{Atom, Expand, build, size_class};
use crate::morton::{Grid, LARGE_CLASSES, cut, lbvh, median_of, radix_sort};
use crate::node::{NONE, Node, NodeOut, Ref};
use crate::update::{MANY_JUMPS, PREFETCH_AHEAD};
use crate::{Bound, Tree};

/// The frames a staged rebuild takes, its install included.
pub(crate) const STAGED_FRAMES: usize = 7;
/// Steps a frame of a rebuild staged among a trickle of teleports: in three
/// frames, its install included, it finds a third as many of them placed
/// where they were as one step a frame would.
pub(crate) const TRICKLE_PACE: usize = 3;

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
    /// The clusters expanded into their subtrees.
    Expand,
    /// Done: the topology waits for the next refit.
    Ready,
}

/// A rebuild in progress (see the module docs).
#[derive(Clone, Debug)]
pub(crate) struct Staged<B: Bound> {
    step: Step,
    /// Steps taken a frame.
    pace: usize,
    /// How many leaves fall in each size class.
    counts: [usize; 256],
    /// Each id's size class (empty once the large leaves are set apart).
    classes: Vec<u8>,
    /// (code, id) of every leaf, then sorted.
    keyed: Vec<(u32, u32)>,
    /// The sorted leaves that are not large, and their codes.
    ids: Vec<u32>,
    codes: Vec<u32>,
    /// The large leaves' ids.
    large: Vec<u32>,
    /// Runs of `ids` that make a cluster.
    clusters: Vec<(usize, usize)>,
    /// The atoms of the top build: clusters and large leaves.
    atoms: Vec<Atom<B>>,
    /// Each internal node's children, in preorder from the root.
    topology: Vec<[Ref; 2]>,
    /// Ids that jumped clear of their bound since the build began, in
    /// frames without mass motion.
    stale: Vec<u32>,
    /// Whether a frame of mass motion passed since the build began.
    mass: bool,
    /// Whether it began at the install of one that saw mass motion.
    after_mass: bool,
}

impl<B: Bound> Staged<B> {
    /// A build, not begun, taking `pace` steps a frame.
    pub(crate) fn new(pace: usize) -> Self {
        Staged {
            step: Step::Codes,
            pace,
            counts: [0; 256],
            classes: Vec::new(),
            keyed: Vec::new(),
            ids: Vec::new(),
            codes: Vec::new(),
            large: Vec::new(),
            clusters: Vec::new(),
            atoms: Vec::new(),
            topology: Vec::new(),
            stale: Vec::new(),
            mass: false,
            after_mass: false,
        }
    }

    /// Notes that leaf `id` jumped clear of its bound: the topology may
    /// place it where it was.
    pub(crate) fn note_jump(&mut self, id: u32) {
        self.stale.push(id);
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.classes.capacity()
            + (self.keyed.capacity() * 2 + self.ids.capacity() + self.codes.capacity()) * 4
            + (self.large.capacity() + self.stale.capacity()) * 4
            + self.clusters.capacity() * size_of::<(usize, usize)>()
            + self.atoms.capacity() * size_of::<Atom<B>>()
            + self.topology.capacity() * size_of::<[Ref; 2]>()
    }

    /// Takes the next step over `tree`'s leaves as they are now.
    fn advance(&mut self, tree: &Tree<B>) {
        let bound = |id: u32| tree.bound(id).expect("a staged leaf is in the tree");
        match self.step {
            Step::Codes => {
                // In node order: the bounds are read in memory order, and
                // the classes (a byte an id) are written in the cache.
                let box_ = tree.root_bound.aabb();
                let grid = Grid::new(box_.min, box_.max);
                self.classes = vec![0; tree.leaf_parents.len()];
                self.keyed = Vec::with_capacity(tree.len);
                for (node, &parent) in tree.nodes.iter().zip(&tree.parents) {
                    for (c, b) in node.child.into_iter().zip(node.bounds) {
                        if parent != NONE && c.is_leaf() {
                            let class = size_class(&b);
                            self.classes[c.index() as usize] = class;
                            self.counts[class as usize] += 1;
                            self.keyed.push((grid.code(b.center()), c.index()));
                        }
                    }
                }
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
                    cut(&self.codes, 0, self.ids.len(), &mut self.clusters);
                }
                self.step = Step::Clusters;
            }
            Step::Clusters => {
                self.atoms = Vec::with_capacity(self.clusters.len() + self.large.len());
                self.atoms.extend(self.large.iter().map(|&id| Atom::new(Ref::leaf(id), bound(id))));
                // Sorted by code, the leaves lie anywhere in the nodes: each
                // read asks for a later one's parent link and node first (a
                // million leaves: this step's frame 53-56 -> 41-44 ms, where
                // one request a cluster had left most reads waiting).
                let ids = &self.ids;
                let bound_at = |k: usize| {
                    tree.prefetch_leaf_ahead(ids, k);
                    bound(ids[k])
                };
                // A leaf that jumped since the codes were taken sits in its
                // cluster where it was, and is reinserted at the install:
                // its bound now would stretch the cluster across the gap
                // and mislead the top build (a trickle of teleports left
                // the installed tree at twice a fresh build's SAH cost).
                let mut jumped = vec![false; tree.leaf_parents.len()];
                self.stale.iter().for_each(|&id| jumped[id as usize] = true);
                for &(start, end) in &self.clusters {
                    let run = &self.ids[start..end];
                    let kept = (start..end).filter(|&k| !jumped[ids[k] as usize]);
                    let merged = kept.map(bound_at).reduce(|a, b| a.merge(&b));
                    let merged = merged.unwrap_or_else(|| bound(run[0]));
                    self.atoms.push(match run {
                        &[one] => Atom::new(Ref::leaf(one), merged),
                        _ => Atom::weighted(Ref(start as u32), merged, run.len() as u32),
                    });
                }
                self.clusters = Vec::new();
                self.step = Step::Top;
            }
            Step::Top => {
                self.topology = vec![[Ref::NONE; 2]; tree.len - 1];
                build(&mut self.atoms, &mut self.topology, 0, &Deferred);
                self.atoms = Vec::new();
                self.step = Step::Expand;
            }
            Step::Expand => {
                let mut leaves = Vec::new();
                let mut x = 0;
                while x < self.topology.len() {
                    let [mark, start] = self.topology[x];
                    if mark.0 & (DEFERRED | Ref::LEAF) != DEFERRED {
                        x += 1;
                        continue;
                    }
                    let (start, weight) = (start.0 as usize, (mark.0 & !DEFERRED) as usize);
                    let range = start..start + weight;
                    // Split by code alone: the bounds are the refit's to set.
                    leaves.clear();
                    leaves.extend(
                        self.ids[range.clone()]
                            .iter()
                            .map(|&id| Atom::new(Ref::leaf(id), B::default())),
                    );
                    lbvh(
                        &leaves,
                        &self.codes[range],
                        &mut self.topology[x..x + weight - 1],
                        x as u32,
                    );
                    // The cluster's other nodes, just written, hold no marks.
                    x += weight - 1;
                }
                (self.ids, self.codes, self.large) = (Vec::new(), Vec::new(), Vec::new());
                self.step = Step::Ready;
            }
            Step::Ready => {}
        }
    }
}

/// What [`Tree::install_staged`] did.
pub(crate) enum Installed {
    /// Installed the staged topology; `stale` jumped while it was built,
    /// and are placed where they were: `None` when a frame of mass motion
    /// passed meanwhile (see the module docs). `after_mass` when it began at
    /// the install of one that did.
    Staged { stale: Option<Vec<u32>>, after_mass: bool },
    /// Rebuilt the tree in one go instead.
    Rebuilt,
}

/// The top build's clusters, left for [`Step::Expand`]: each marks its first
/// node (see [`DEFERRED`]).
struct Deferred;

impl<B: Bound> Expand<B> for Deferred {
    fn expand<N: NodeOut<B>>(&self, atom: &Atom<B>, out: &mut [N], base: u32) -> (Ref, B) {
        out[0].set([atom.bound; 2], [Ref(DEFERRED | atom.weight), atom.r]);
        (Ref::node(base), atom.bound)
    }
}

impl<B: Bound> Tree<B> {
    /// One step of the staged rebuild after a refit, noting the leaves that
    /// `jumped` this frame, or that it was a frame of `mass` motion; starts
    /// one first if none runs (`after_mass` when an install that saw mass
    /// motion starts it).
    pub(crate) fn advance_staged(&mut self, jumped: &[(u32, B)], mass: bool, after_mass: bool) {
        if !self.root.is_node() {
            return;
        }
        let mut staged =
            self.staged.take().unwrap_or_else(|| Box::new(Staged { after_mass, ..Staged::new(1) }));
        if mass {
            staged.mass = true;
        } else {
            jumped.iter().for_each(|&(id, _)| staged.note_jump(id));
        }
        for _ in 0..staged.pace {
            staged.advance(self);
        }
        self.staged = Some(staged);
    }

    /// Whether a staged rebuild runs.
    pub(crate) fn staging(&self) -> bool {
        self.staged.is_some()
    }

    /// Installs a finished staged rebuild in place of every node, each leaf
    /// keeping its bound (a refit must follow, for the internal nodes'). When
    /// so many leaves jumped while it ran that reinserting them would cost
    /// more than the staging saved, rebuilds the tree in one go instead.
    /// `None` when no staged rebuild is finished.
    pub(crate) fn install_staged(&mut self) -> Option<Installed> {
        if self.staged.as_ref()?.step != Step::Ready {
            return None;
        }
        let staged = self.staged.take()?;
        let mut stale = staged.stale;
        stale.sort_unstable();
        stale.dedup();
        if !staged.mass && stale.len() * MANY_JUMPS > self.len {
            self.rebuild();
            return Some(Installed::Rebuilt);
        }
        // The topology holds every leaf (any insert or removal dropped it):
        // as many internal nodes as the tree has in use, at most its array.
        debug_assert_eq!(staged.topology.len() + 1, self.len);
        // Each leaf's bound, gathered in node order (a sequential read) and
        // found again by the place noted in its parent link: the nodes are
        // then overwritten in place, in preorder, from the topology. (Read
        // by id from the old nodes, scattered, this took 4 ms on 100 000
        // leaves; the fresh node array it filled, 5.6 MB, faulted in.)
        let mut held = Vec::with_capacity(self.len);
        for (node, &parent) in self.nodes.iter().zip(&self.parents) {
            for (c, bound) in node.child.into_iter().zip(node.bounds) {
                if parent != NONE && c.is_leaf() {
                    self.leaf_parents[c.index() as usize] = held.len() as u32;
                    held.push(bound);
                }
            }
        }
        let topology = &staged.topology;
        self.preorder_arrays(topology.len());
        for (x, &child) in topology.iter().enumerate() {
            for c in topology.get(x + PREFETCH_AHEAD).into_iter().flatten() {
                if c.is_leaf() {
                    bvol_volumes::prefetch(&held[self.leaf_parents[c.index() as usize] as usize]);
                }
            }
            let leaf = |c: Ref| match c.is_leaf() {
                true => held[self.leaf_parents[c.index() as usize] as usize],
                false => B::default(),
            };
            self.nodes[x] = Node { bounds: [leaf(child[0]), leaf(child[1])], child };
            for c in child {
                self.set_parent(c, x as u32);
            }
        }
        let after_mass = staged.after_mass;
        Some(Installed::Staged { stale: (!staged.mass).then_some(stale), after_mass })
    }
}
