//! The frame update: all of a frame's bounds in, the tree brought up to date
//! by per-leaf moves or by one bottom-up refit, whichever the fraction of
//! leaves that moved makes cheaper.

use rayon::prelude::*;

use bvol_volumes::prefetch;

use crate::node::{NONE, Node, ROOT, Ref};
use crate::staged::{Installed, STAGED_FRAMES, Staged, TRICKLE_PACE};
use crate::tree::{check_bound, check_id};
use crate::{Bound, Tree, TreeError};

/// What one update ([`Tree::update`], [`Tree::update_from`] or
/// [`Tree::update_moved`]) did to the tree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UpdateStats {
    /// Leaves whose bound changed.
    pub moved: usize,
    /// Ids that were new, and inserted.
    pub inserted: usize,
    /// Whether the whole tree was refit (else moved leaves were updated one
    /// by one).
    pub refit: bool,
    /// Leaves reinserted because they landed clear of where they were.
    pub reinserted: usize,
    /// Atoms (leaves or kept subtrees) placed by the upkeep's rebuilds.
    pub rebuilt: usize,
    /// Whether a rebuild staged over the last frames was installed: then
    /// [`UpdateStats::rebuilt`] counts every leaf, and no frame paid for the whole
    /// rebuild (see [`Tree::update`]).
    pub installed: bool,
}

impl<B: Bound> Tree<B> {
    /// Brings the tree up to date with one frame: `bounds[id]` is the bound of
    /// leaf `id` (ids `0..bounds.len()`; ids not yet in the tree are inserted,
    /// ids beyond the slice are left alone). The tree finds what moved itself.
    ///
    /// When fewer than [`Config::refit_fraction`](crate::Config) of the
    /// leaves moved (predicted from the previous frame, confirmed by a scan),
    /// each moved leaf is updated as by [`Tree::set_bound`] and then
    /// [`Tree::optimize`] runs. Otherwise every internal node is refit
    /// bottom-up in one pass to the exact merge of its children, leaves that
    /// jumped clear of their old bound are reinserted, and when the tree's
    /// SAH cost has drifted (see [`Config::drift`](crate::Config)) it is
    /// rebuilt as by [`Tree::rebuild`], one phase a frame over the next six
    /// refits, and installed at the start of the seventh: no frame pays for
    /// a whole rebuild ([`UpdateStats::installed`] marks the frame that installs
    /// it). When more than one leaf in 16 jumps clear of its bound in one
    /// frame (bodies falling faster than their size), the jumps are refit
    /// where they land, like any move, and left to the staged rebuilds. A
    /// steady trickle of jumps (teleports) so frequent that a rebuild staged
    /// a phase a frame would find one leaf in 16 placed where it was has it
    /// staged three phases a frame, installed at the start of the third
    /// refit; only a trickle so heavy that even this one would (about one
    /// leaf in 50 a frame) rebuilds the tree in one go.
    ///
    /// Every bound is checked first: on error nothing has changed.
    pub fn update(&mut self, bounds: &[B]) -> Result<UpdateStats, TreeError> {
        if let Some(last) = bounds.len().checked_sub(1) {
            check_id(u32::try_from(last).unwrap_or(u32::MAX))?;
        }
        if let Some(id) = first_invalid(bounds) {
            check_bound(id as u32, &bounds[id])?;
        }
        let mut frame = UpdateStats::default();
        if self.is_empty() {
            // One batch build; the change log carries over (ids removed since
            // the last pair-set update must still end their pairs).
            let changes = std::mem::take(&mut self.changes);
            *self =
                Self::build(self.config, bounds.iter().enumerate().map(|(i, b)| (i as u32, *b)))?;
            self.changes = changes;
            self.changes.grow(bounds.len());
            self.changes.mark_all();
            frame.inserted = bounds.len();
            return Ok(frame);
        }
        self.follow(bounds, &mut frame);
        // Every id below the tree's id range's end is in it when the tree
        // holds as many leaves as that range: then none is new, and the pass
        // looking for new ones is skipped.
        if self.len != self.leaf_parents.len() || bounds.len() > self.len {
            for id in 0..bounds.len() as u32 {
                if !self.contains(id) {
                    self.insert(id, bounds[id as usize])?;
                    frame.inserted += 1;
                }
            }
        }
        self.upkeep.moved_fraction = frame.moved as f32 / self.len.max(1) as f32;
        Ok(frame)
    }

    /// Brings the leaves already in the tree up to date with one frame, as
    /// [`Tree::update`] does, reading `bounds[id]` for the ids in the tree
    /// alone and inserting none: for a caller whose slice also holds ids
    /// kept elsewhere (a world's resting bodies, in a second tree). Ids in
    /// the tree at or past the slice's end are left alone. Where most leaves
    /// moved, this refits from the slice in the tree's own order, in
    /// parallel subtrees, where [`Tree::update_moved`], handed a list,
    /// places each moved leaf in turn, wherever its parent lies, on the
    /// calling thread (100 000 boxes, every one moved, on two threads: 1.67
    /// against 1.90 ms; on one, 2.61 against 2.39).
    ///
    /// The bounds of the ids in the tree are checked first: on error nothing
    /// has changed. The other entries are not used: one that is not a valid
    /// bound is no error.
    ///
    /// ```
    /// use bvol_tree::Tree;
    /// use bvol_volumes::Aabb;
    /// use glam::Vec3;
    /// let cube = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
    /// let mut tree = Tree::new();
    /// tree.insert(0, cube(0.0))?;
    /// tree.insert(2, cube(5.0))?;
    /// // Slot 1 belongs to something else: its entry is not used.
    /// let slots = [cube(4.5), Aabb::new(Vec3::NAN, Vec3::NAN), cube(5.0)];
    /// tree.update_from(&slots)?;
    /// assert_eq!(tree.pairs(), vec![(0, 2)]);
    /// assert!(!tree.contains(1));
    /// # Ok::<(), bvol_tree::TreeError>(())
    /// ```
    pub fn update_from(&mut self, bounds: &[B]) -> Result<UpdateStats, TreeError> {
        // The branch-free fold over every bound first, as in `update`; only
        // when it finds one not valid are the tree's ids told apart.
        if let Some(first) = first_invalid(bounds) {
            let bad = |&id: &usize| self.contains(id as u32) && !bounds[id].is_valid();
            if let Some(id) = (first..bounds.len()).find(bad) {
                check_bound(id as u32, &bounds[id])?;
            }
        }
        let mut frame = UpdateStats::default();
        if !self.is_empty() {
            self.follow(bounds, &mut frame);
        }
        self.upkeep.moved_fraction = frame.moved as f32 / self.len.max(1) as f32;
        Ok(frame)
    }

    /// The leaves already in the tree brought to `bounds[id]`: by one refit
    /// (which also advances, or installs, a staged rebuild), or by per-leaf
    /// moves of those that moved when few did.
    fn follow(&mut self, bounds: &[B], frame: &mut UpdateStats) {
        let refit = self.staging() || self.upkeep.moved_fraction >= self.config.refit_fraction;
        if refit {
            self.refit_frame(bounds, frame);
        } else {
            let moved = self.scan(bounds);
            if moved.len() as f32 >= self.config.refit_fraction * self.len as f32 {
                self.refit_frame(bounds, frame);
            } else {
                self.move_each(bounds, &moved, frame);
            }
        }
    }

    /// Refits every internal node bottom-up to the exact merge of its
    /// children's bounds (tightening every fat margin), in one pass.
    pub fn refit(&mut self) {
        let mut scratch = Vec::new();
        self.refit_pass(None, &mut scratch, &mut Vec::new());
    }

    /// Brings the tree up to date with the leaves that moved: `moved[k]` is
    /// `(id, new bound)`, every id in the tree. For a caller that knows what
    /// moved (a world whose tree holds only some of its bodies): the same
    /// choice as [`Tree::update`] between per-leaf updates and one refit, by
    /// the fraction moved, without reading the bounds of leaves that did not.
    ///
    /// Every id and bound is checked first: on error nothing has changed.
    pub fn update_moved(&mut self, moved: &[(u32, B)]) -> Result<UpdateStats, TreeError> {
        // Folded without branches, as in `update`; the loop names the first
        // bad one.
        let good = |&(id, bound): &(u32, B)| bound.is_valid() & self.contains(id);
        if !moved.iter().fold(true, |ok, m| ok & good(m)) {
            for &(id, bound) in moved {
                check_bound(id, &bound)?;
                if !self.contains(id) {
                    return Err(TreeError::UnknownId { id });
                }
            }
        }
        let mut frame = UpdateStats { moved: moved.len(), ..UpdateStats::default() };
        if (moved.len() as f32) < self.config.refit_fraction * self.len as f32 {
            for &(id, bound) in moved {
                if self.move_leaf(id, bound) == crate::Move::Reinserted {
                    frame.reinserted += 1;
                }
                self.changes.mark(id);
            }
            frame.rebuilt = self.optimize();
        } else {
            let installed = self.install_staged();
            let hold = self.upkeep.hold_jumps();
            let mut jumped = Vec::new();
            for (k, &(id, bound)) in moved.iter().enumerate() {
                // The moved ids may come in any order, and their parents
                // lie anywhere: ask for a later one's parent early.
                if let Some(&(later, _)) = moved.get(k + PREFETCH_AHEAD) {
                    self.prefetch_leaf(later);
                }
                let p = self.leaf_parents[id as usize];
                if p == ROOT {
                    self.root_bound = bound;
                    continue;
                }
                let node = &mut self.nodes[p as usize];
                let old = &mut node.bounds[node.side_of(Ref::leaf(id))];
                if place_leaf(old, bound, hold) {
                    jumped.push((id, bound));
                }
            }
            let cost = self.refit_pass(None, &mut Vec::new(), &mut Vec::new());
            self.after_refit(&jumped, moved.iter().map(|m| m.0), cost, installed, &mut frame);
        }
        self.upkeep.moved_fraction = frame.moved as f32 / self.len.max(1) as f32;
        Ok(frame)
    }

    /// The refit path of a frame.
    fn refit_frame(&mut self, bounds: &[B], frame: &mut UpdateStats) {
        let installed = self.install_staged();
        let mut moved = std::mem::take(&mut self.upkeep.moved);
        let mut jumped = std::mem::take(&mut self.upkeep.jumped);
        let cost = self.refit_pass(Some(bounds), &mut moved, &mut jumped);
        frame.moved = moved.len();
        let jumps: Vec<(u32, B)> = jumped.iter().map(|&id| (id, bounds[id as usize])).collect();
        self.after_refit(&jumps, moved.iter().copied(), cost, installed, frame);
        moved.clear();
        jumped.clear();
        (self.upkeep.moved, self.upkeep.jumped) = (moved, jumped);
    }

    /// What follows a refit: leaves that `jumped` clear of their old bound
    /// go where they now are, the `moved` ids are marked for the pair set,
    /// and the staged rebuild takes its step, or starts if the `cost`
    /// drifted. The jumps kept their old bound in the refit unless the last
    /// frame had many ([`Upkeep::hold_jumps`](crate::upkeep::Upkeep)).
    /// `installed` says what happened to a finished staged rebuild before
    /// this refit.
    fn after_refit(
        &mut self,
        jumped: &[(u32, B)],
        moved: impl ExactSizeIterator<Item = u32>,
        mut cost: f64,
        installed: Option<Installed>,
        frame: &mut UpdateStats,
    ) {
        frame.refit = true;
        let held = self.upkeep.hold_jumps();
        let mass = jumped.len() * MANY_JUMPS > self.len;
        self.upkeep.mass_motion = mass;
        // An installed topology places the leaves that jumped while it was
        // built (`stale`) where they were.
        let stale = match &installed {
            Some(Installed::Staged { stale: Some(stale), .. }) => &stale[..],
            _ => &[],
        };
        if !mass {
            // A few leaves that jumped clear of their old bound: refit in
            // place they would stretch their ancestors across the gap, and
            // every later pair search would visit them. They are reinserted
            // where they now are (about 1 us each on 100 000 leaves).
            self.reinsert(jumped, stale, frame);
        } else {
            if held {
                // Many: bodies falling faster than their size, and their
                // neighbours with them. Reinserting them all, or rebuilding
                // the tree each such frame, cost more than the pair search
                // lost to a refit in place: the staged rebuilds keep up.
                for &(id, bound) in jumped {
                    let p = self.leaf_parents[id as usize];
                    let node = &mut self.nodes[p as usize];
                    node.bounds[node.side_of(Ref::leaf(id))] = bound;
                }
                cost = self.refit_pass(None, &mut Vec::new(), &mut Vec::new());
            }
            self.reinsert(&[], stale, frame);
        }
        if moved.len() * 2 > self.len {
            self.changes.mark_all();
        } else {
            moved.for_each(|id| self.changes.mark(id));
        }
        match installed {
            Some(Installed::Rebuilt) => frame.rebuilt = self.len,
            Some(Installed::Staged { stale, after_mass }) => {
                self.after_install(jumped, stale, after_mass, cost, frame)
            }
            None => self.upkeep_staged(jumped, mass, cost),
        }
    }

    /// Reinserts the leaves placed where they no longer are: this frame's
    /// `jumped`, with their new bounds (the refit kept their old), and the
    /// `stale` ids of an install, sorted, that are not among them. All are
    /// taken out before any goes back: inserted while others still stretch
    /// their ancestors, each would be placed by bounds that are not there
    /// (a trickle of teleports, reinserted one by one at an install, left
    /// the tree at twice a fresh build's SAH cost).
    fn reinsert(&mut self, jumped: &[(u32, B)], stale: &[u32], frame: &mut UpdateStats) {
        // This frame's jumps, sorted, to tell the stale leaves among them:
        // only an install has stale leaves.
        let mut now: Vec<u32> = Vec::new();
        if !stale.is_empty() {
            now.extend(jumped.iter().map(|j| j.0));
            now.sort_unstable();
        }
        let ids: Vec<u32> = jumped.iter().map(|j| j.0).chain(stale.iter().copied()).collect();
        let mut out = jumped.to_vec();
        for (k, &id) in ids.iter().enumerate() {
            if let Some(&later) = ids.get(k + REMOVE_AHEAD) {
                self.prefetch_leaf(later);
            }
            // A jump keeps its new bound; a stale leaf keeps the one it has.
            if k < jumped.len() {
                self.remove_leaf(id);
            } else if now.binary_search(&id).is_err() {
                out.push((id, self.remove_leaf(id)));
            }
        }
        for &(id, bound) in &out {
            self.insert_leaf(id, bound, &bound);
        }
        frame.reinserted += out.len();
    }

    /// After a staged rebuild's install and the refit (which reinserted the
    /// leaves that jumped while it was built): the refit's `cost` is the new
    /// baseline.
    /// When mass motion went on while it was built (`stale` is `None`), the
    /// topology is out of date as it lands: its cost is no baseline, and the
    /// next build starts at once. So does one more, when the first build
    /// after mass motion (`after_mass`) still saw leaves jump: the bodies
    /// were settling while it was built (a pile compacting), and its
    /// topology does not place those that moved less than their size.
    fn after_install(
        &mut self,
        jumped: &[(u32, B)],
        stale: Option<Vec<u32>>,
        after_mass: bool,
        cost: f64,
        frame: &mut UpdateStats,
    ) {
        frame.rebuilt = self.len;
        frame.installed = true;
        let Some(stale) = stale else {
            return self.advance_staged(jumped, self.upkeep.mass_motion, true);
        };
        if after_mass && !stale.is_empty() {
            self.advance_staged(jumped, self.upkeep.mass_motion, false);
        } else if stale.is_empty() {
            self.upkeep.built_cost = cost;
        } else {
            // The refit measured the stale leaves stretched across their
            // gaps: as a baseline, that cost would put the next rebuild off
            // (a trickle of teleports: for good).
            self.upkeep.built_cost = self.sah_cost();
        }
    }

    /// The staged rebuild's step after a refit of `cost`, or its start when
    /// the cost has drifted. `mass` says that this frame's jumps were many.
    fn upkeep_staged(&mut self, jumped: &[(u32, B)], mass: bool, cost: f64) {
        let drifted =
            |share: f64| cost > self.upkeep.built_cost * (1.0 + self.config.drift * share);
        if self.staging() {
            self.advance_staged(jumped, mass, false);
        } else if !mass && jumped.len() * STAGED_FRAMES * MANY_JUMPS > self.len {
            // Leaves jump so often, each on its own, that a build staged one
            // step a frame would find too many of them placed where they
            // were when it began: it takes three steps a frame (on 100 000
            // leaves with 1 000 teleports a frame, 3.4 and 4.3 ms added to
            // two frames, then 4.3 for the install and its 3 000
            // reinsertions, where the rebuild in one go added 12 to one
            // frame). It starts at the full drift: it lands soon after.
            if drifted(1.0) {
                self.staged = Some(Box::new(Staged::new(TRICKLE_PACE)));
                self.advance_staged(jumped, mass, false);
            }
        } else if drifted(DRIFT_STAGED) {
            // In one go, a rebuild adds about three refits to its frame
            // (9.5 ms on 100 000 leaves): it is spread over the next frames.
            self.advance_staged(jumped, mass, false);
        }
    }

    /// The ids `< bounds.len()` whose bound differs from the tree's, in node
    /// order.
    fn scan(&self, bounds: &[B]) -> Vec<u32> {
        let mut moved = Vec::new();
        if self.root.is_leaf() {
            let id = self.root.index();
            if bounds.get(id as usize).is_some_and(|b| *b != self.root_bound) {
                moved.push(id);
            }
            return moved;
        }
        for (node, &parent) in self.nodes.iter().zip(&self.parents) {
            if parent == NONE {
                continue;
            }
            for side in 0..2 {
                let c = node.child[side];
                if c.is_leaf()
                    && bounds.get(c.index() as usize).is_some_and(|b| *b != node.bounds[side])
                {
                    moved.push(c.index());
                }
            }
        }
        moved
    }

    /// The per-leaf path of a frame: each moved leaf updated on its own, then
    /// the bounded upkeep.
    fn move_each(&mut self, bounds: &[B], moved: &[u32], frame: &mut UpdateStats) {
        for &id in moved {
            if self.move_leaf(id, bounds[id as usize]) == crate::Move::Reinserted {
                frame.reinserted += 1;
            }
            self.changes.mark(id);
        }
        frame.moved = moved.len();
        frame.rebuilt = self.optimize();
    }

    /// Sets leaf bounds from `bounds` (when given), recording in `moved` the
    /// ids that changed and in `jumped` those whose new bound does not even
    /// overlap the old one (those keep their old bound, for the caller to
    /// reinsert), and refits every internal node to the exact merge of its
    /// children. Returns the SAH cost after the refit.
    ///
    /// Runs over the nodes in reverse preorder, children before parents: in
    /// place and in parallel subtrees when the nodes are laid out in preorder
    /// (after a whole build), else along a preorder walk.
    pub(crate) fn refit_pass(
        &mut self,
        bounds: Option<&[B]>,
        moved: &mut Vec<u32>,
        jumped: &mut Vec<u32>,
    ) -> f64 {
        if self.root.is_leaf() {
            let id = self.root.index();
            if let Some(&b) = bounds.and_then(|all| all.get(id as usize))
                && b != self.root_bound
            {
                moved.push(id);
                self.root_bound = b;
            }
            return 0.0;
        }
        if !self.root.is_node() {
            return 0.0;
        }
        if !self.upkeep.preorder && !self.upkeep.reshaped {
            // Not in preorder, but the shape has not changed since the last
            // refit: it is settling, and laying it out once pays for itself
            // in the refits (and pair searches) that follow.
            self.relayout();
        }
        self.upkeep.reshaped = false;
        let mut found = Refit { moved, jumped, hold: self.upkeep.hold_jumps(), inner: 0.0 };
        if self.upkeep.preorder {
            refit_subtree(&mut self.nodes, 0, bounds, &mut found);
        } else {
            self.refit_scattered(bounds, &mut found);
        }
        let inner = found.inner;
        self.root_bound = self.nodes[self.root.index() as usize].merged();
        self.enlarged.fill(false);
        let root_area = self.root_bound.cost();
        if root_area > 0.0 { 1.0 + inner / root_area } else { 0.0 }
    }

    /// Lays the nodes out in preorder from node 0 (children after parents,
    /// each subtree contiguous), dropping free nodes. In place: the nodes are
    /// permuted by following cycles, so no second node array is allocated.
    fn relayout(&mut self) {
        let n = self.nodes.len();
        // Preorder positions for the nodes in use, then the free ones.
        let mut position = vec![NONE; n];
        let mut next = 0;
        let mut stack = vec![self.root.index()];
        while let Some(x) = stack.pop() {
            position[x as usize] = next;
            next += 1;
            for c in self.nodes[x as usize].child.into_iter().rev() {
                if c.is_node() {
                    stack.push(c.index());
                }
            }
        }
        let used = next as usize;
        for p in position.iter_mut().filter(|p| **p == NONE) {
            *p = next;
            next += 1;
        }
        for (node, &p) in self.nodes.iter_mut().zip(&position) {
            if (p as usize) < used {
                for c in &mut node.child {
                    if c.is_node() {
                        *c = Ref::node(position[c.index() as usize]);
                    }
                }
            }
        }
        for i in 0..n {
            // Send the node at `i` where it belongs until the one that
            // belongs at `i` arrives.
            while position[i] as usize != i {
                let j = position[i] as usize;
                self.nodes.swap(i, j);
                self.enlarged.swap(i, j);
                position.swap(i, j);
            }
        }
        self.nodes.truncate(used);
        self.enlarged.truncate(used);
        self.parents.clear();
        self.parents.resize(used, NONE);
        self.free = Ref::NONE;
        self.free_count = 0;
        self.root = Ref::node(0);
        self.parents[0] = ROOT;
        for x in 0..used {
            for side in 0..2 {
                self.set_parent(self.nodes[x].child[side], x as u32);
            }
        }
        self.upkeep.preorder = true;
    }

    /// The refit of a tree whose nodes are not in preorder (after inserts,
    /// removes or partial rebuilds): in reverse of a preorder walk, one task.
    /// The layout is left as it is: while the shape keeps changing (leaves
    /// jumping every frame), moving every node back each frame would cost
    /// more than it saves.
    fn refit_scattered(&mut self, bounds: Option<&[B]>, found: &mut Refit) {
        let mut order = Vec::with_capacity(self.nodes.len() - self.free_count);
        let mut stack = vec![self.root.index()];
        while let Some(x) = stack.pop() {
            order.push(x);
            // Second child pushed first: the walk follows the memory order of
            // a mostly preorder layout.
            for c in self.nodes[x as usize].child.into_iter().rev() {
                if c.is_node() {
                    stack.push(c.index());
                }
            }
        }
        let mut inner = 0.0;
        for &x in order.iter().rev() {
            let child = |c: Ref| c.is_node().then(|| self.nodes[c.index() as usize].merged());
            let [c0, c1] = self.nodes[x as usize].child;
            let children = [child(c0), child(c1)];
            // In place: a copy on the stack, written back, made the
            // refit's speed depend on where the stack fell against the
            // arrays modulo 4 KiB (its stores then seem to alias the
            // next node's loads): +0.4 ms a frame on 100 000 leaves in
            // some builds and not in others.
            inner += refit_node(&mut self.nodes[x as usize], children, bounds, found);
        }
        found.inner += inner;
    }
}

/// The first index whose bound is not valid. In parallel, a chunk a task
/// (a task a bound cost 2.5 times a plain loop on one thread: 0.65 ms of a
/// 9 ms frame of 100 000 boxes), each chunk folded without branches; the
/// index is the first bad one, as a loop would find. Below four chunks on
/// the calling thread: waking a second one took longer than the check
/// (100 000 boxes on two threads: 0.20 ms in parallel, 0.12 on one).
fn first_invalid<B: Bound>(bounds: &[B]) -> Option<usize> {
    let bad = |c: &[B]| !c.iter().fold(true, |ok, b| ok & b.is_valid());
    let k = if bounds.len() < 4 * CHECK_CHUNK {
        bounds.chunks(CHECK_CHUNK).position(bad)
    } else {
        bounds.par_chunks(CHECK_CHUNK).position_first(bad)
    }?;
    let rest = &bounds[k * CHECK_CHUNK..];
    Some(k * CHECK_CHUNK + rest.iter().position(|b| !b.is_valid()).unwrap_or(0))
}

/// More than one leaf in this many jumping clear of its old bound is many.
/// In one frame (mass motion) they are refit in place rather than
/// reinserted: on the pile's 60 frames of falling boxes, refit in place and
/// left to staged rebuilds, the mean frame took 10% less than with the
/// tree rebuilt every such frame (and no frame paid for a rebuild). Over
/// a staged rebuild's frames, in a trickle (teleports), they would cost
/// more to reinsert at its install than a rebuild in one go (on 100 000
/// leaves, a rebuild costs about as much as 5 000 reinsertions): the
/// rebuild then takes fewer frames.
pub(crate) const MANY_JUMPS: usize = 16;
/// A staged rebuild starts when the SAH cost has drifted this fraction of
/// [`Config::drift`](crate::Config) above its cost after the last build:
/// the tree drifts on while the build runs, and its topology places the
/// leaves where they were when it began (on the uniform scene, 0.35 left
/// the mean pair search as it was with whole rebuilds at the full drift).
const DRIFT_STAGED: f64 = 0.35;
/// Bounds checked by one task of [`Tree::update`].
const CHECK_CHUNK: usize = 16384;
/// Subtrees with at least this many nodes are refit on two rayon tasks.
const PARALLEL_REFIT: usize = 8192;

/// What a refit found: leaves whose bound changed, those that jumped clear
/// of their old bound (which they keep when `hold`), and the summed area of
/// the internal nodes' bounds.
struct Refit<'a> {
    moved: &'a mut Vec<u32>,
    jumped: &'a mut Vec<u32>,
    hold: bool,
    inner: f64,
}

/// Refits the subtree laid out in preorder in `nodes` (its root first, named
/// `base`), children before parents. Large subtrees split into their two
/// child subtrees, refit on two rayon tasks; what they find is appended in a
/// fixed order (second child's first), so the result is the same whatever
/// the number of threads.
fn refit_subtree<B: Bound>(
    nodes: &mut [Node<B>],
    base: usize,
    bounds: Option<&[B]>,
    found: &mut Refit,
) {
    if nodes.len() < PARALLEL_REFIT {
        return refit_run(nodes, base, bounds, found);
    }
    let (head, rest) = nodes.split_at_mut(1);
    let node = &mut head[0];
    // In preorder the second child's subtree starts right after the first's.
    let second = match node.child[1] {
        c if c.is_node() => c.index() as usize - base - 1,
        _ => rest.len(),
    };
    let (first_nodes, second_nodes) = rest.split_at_mut(second);
    let part = |nodes: &mut [Node<B>], child: Ref| {
        let (mut moved, mut jumped) = (Vec::new(), Vec::new());
        let hold = found.hold;
        let mut part = Refit { moved: &mut moved, jumped: &mut jumped, hold, inner: 0.0 };
        if child.is_node() {
            refit_subtree(nodes, child.index() as usize, bounds, &mut part);
        }
        let inner = part.inner;
        (moved, jumped, inner)
    };
    let (a, b) =
        rayon::join(|| part(first_nodes, node.child[0]), || part(second_nodes, node.child[1]));
    for (moved, jumped, inner) in [b, a] {
        found.moved.extend_from_slice(&moved);
        found.jumped.extend_from_slice(&jumped);
        found.inner += inner;
    }
    // A child subtree's root is its run's first node.
    let children = [first_nodes.first().map(Node::merged), second_nodes.first().map(Node::merged)];
    found.inner += refit_node(node, children, bounds, found);
}

/// Refits a preorder run of nodes sequentially, last to first.
fn refit_run<B: Bound>(
    nodes: &mut [Node<B>],
    base: usize,
    bounds: Option<&[B]>,
    found: &mut Refit,
) {
    let mut inner = 0.0;
    for x in (0..nodes.len()).rev() {
        // The nodes are read and written backwards; asked for ahead, as
        // the user's bounds are, the stream does not wait on memory.
        if let Some(far) = x.checked_sub(NODES_AHEAD) {
            prefetch(&nodes[far]);
        }
        if let Some(all) = bounds
            && let Some(ahead) = x.checked_sub(PREFETCH_AHEAD)
        {
            for c in nodes[ahead].child {
                if let Some(b) = all.get(c.index() as usize).filter(|_| c.is_leaf()) {
                    prefetch(b);
                }
            }
        }
        let (head, tail) = nodes.split_at_mut(x + 1);
        let node = &mut head[x];
        let child = |side: usize| {
            let c = node.child[side];
            // Preorder: every child comes after its parent.
            c.is_node().then(|| tail[c.index() as usize - base - x - 1].merged())
        };
        let children = [child(0), child(1)];
        inner += refit_node(node, children, bounds, found);
    }
    found.inner += inner;
}

/// Gives a leaf stored with bound `old` its `new` one, unless it jumped
/// clear of the old while jumps are held ([`Upkeep::hold_jumps`](crate::upkeep::Upkeep)):
/// then it keeps the old for now, to be reinserted after the refit, which so
/// measures the cost without its stretch. Returns whether it jumped.
#[inline]
fn place_leaf<B: Bound>(old: &mut B, new: B, hold: bool) -> bool {
    let jumped = !new.overlaps(old);
    if !(jumped && hold) {
        *old = new;
    }
    jumped
}

/// How many nodes ahead of the one being refit [`refit_run`] asks for the
/// user's leaf bounds (and [`Tree::update_moved`] for a leaf's parent). Leaf
/// ids follow the user's order, not the tree's, so those reads are
/// scattered: past the caches (a million leaves), waiting for each in turn
/// took half the refit.
pub(crate) const PREFETCH_AHEAD: usize = 16;
/// How many leaves ahead [`Tree::reinsert`] asks for the parent node of the
/// leaf it will take out: jumps land anywhere in the tree (teleport frames'
/// update 4.89-5.07 -> 4.87-4.95 ms on 100 000 boxes; 8 ahead the same).
const REMOVE_AHEAD: usize = 4;
/// How many nodes ahead [`refit_run`] asks for the node it will refit: past
/// the caches (a million leaves, 56 MB of nodes) the plain refit frame went
/// from 34-35 to 29-30 ms (32 or 128 ahead did no better); within them it
/// changes nothing.
const NODES_AHEAD: usize = 64;

/// Sets one node's child bounds: internal children's from their refit
/// `children`, leaves' from `bounds` (recording moves and jumps). Returns
/// the internal children's summed area, for the caller to add up in a
/// register (added to `found` a node at a time, it chained every node's
/// refit on a store and a load).
#[inline]
fn refit_node<B: Bound>(
    node: &mut Node<B>,
    children: [Option<B>; 2],
    bounds: Option<&[B]>,
    found: &mut Refit,
) -> f64 {
    let mut inner = 0.0;
    for (side, child) in children.into_iter().enumerate() {
        let c = node.child[side];
        if let Some(b) = child {
            inner += b.cost();
            node.bounds[side] = b;
        } else if let Some(&b) = bounds.and_then(|all| all.get(c.index() as usize)) {
            let old = &mut node.bounds[side];
            if b != *old {
                found.moved.push(c.index());
                if place_leaf(old, b, found.hold) {
                    found.jumped.push(c.index());
                }
            }
        }
    }
    inner
}
