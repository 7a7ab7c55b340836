//! The whole-tree refit: every internal node set bottom-up to the exact
//! merge of its children's bounds, in one pass over the nodes (the refit
//! path of an update, and [`Tree::refit`]), taking the leaves' new bounds
//! on the way when given them. In parallel subtrees when the nodes are laid
//! out in preorder, the same result on any number of threads.

use bvol_volumes::prefetch;

use crate::leaves::ask_leaf_bounds;
use crate::node::{NONE, Node, ROOT, Ref};
use crate::tuning::{NODES_AHEAD, PARALLEL_REFIT, PREFETCH_AHEAD, SETTLED, WALK_LATE};
use crate::{Bound, BoundPair, Tree, one_thread};

impl<B: Bound> Tree<B> {
    /// Sets leaf bounds from `bounds` (when given), recording in `moved` the
    /// ids that changed and in `jumped` those whose new bound does not even
    /// overlap the old one (those keep their old bound, for the caller to
    /// reinsert), and refits every internal node to the exact merge of its
    /// children. Returns the SAH cost after the refit.
    ///
    /// Runs over the nodes children before parents: in parallel subtrees
    /// when the nodes are laid out in preorder (after a whole build or a
    /// layout), in parallel blocks of the node array when few nodes have a
    /// child in another block ([`Tree::refit_blocks`]), else along a
    /// preorder walk.
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
        self.held = if self.reshaped { 0 } else { self.held.saturating_add(1) };
        self.reshaped = false;
        // Late nodes piled up a few a frame (a trickle of reinsertions)
        // would be walked every frame from now on: a layout clears them
        // for the frames that follow. Many at once (a burst, which a
        // settling tree may never see again) are walked this frame; if
        // they are still there at the next, it lays the tree out.
        let nodes = self.nodes.len();
        let crowded = |late: usize| late * WALK_LATE > nodes;
        let piled_up = crowded(self.late) && !crowded(self.late_gain);
        if !self.preorder && (piled_up || self.held >= SETTLED) {
            self.relayout();
        }
        let mut found = Refit { moved, jumped, hold: self.policy.hold_jumps(), inner: 0.0 };
        if self.preorder {
            refit_subtree(&mut self.nodes, 0, bounds, &mut found);
            (self.late, self.late_gain) = (0, 0);
        } else {
            let late = match crowded(self.late) {
                true => self.refit_walked(bounds, &mut found),
                false => self.refit_blocks(bounds, &mut found),
            };
            self.late_gain = late.saturating_sub(self.late);
            self.late = late;
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
            self.nodes[x].place(x as u32);
            for side in 0..2 {
                self.set_parent(self.nodes[x].child[side], x as u32);
            }
        }
        self.preorder = true;
    }

    /// The refit of a tree whose nodes are not in preorder (after inserts,
    /// removes or partial rebuilds), most of them still after their
    /// parents: over the node array from last to first, as a tree in
    /// preorder is, in parallel blocks of it. After a build every child
    /// comes after its parent in the array, and a removal keeps that; a node
    /// placed since (an insertion takes any free slot) may come after a
    /// child of its. Such a child, refit later in the pass, hands its new
    /// bound up to the ancestors refit before it in its block
    /// ([`climb`]). A node with an internal child in another block (refit
    /// on another task) keeps that child's old bound in the pass: it is
    /// late, and refit again with its ancestors once the two blocks are
    /// joined ([`settle`]). Returns how many nodes were late.
    fn refit_blocks(&mut self, bounds: Option<&[B]>, found: &mut Refit) -> usize {
        let mut late = Vec::new();
        let settled = refit_block(&mut self.nodes, 0, &self.parents, bounds, found, &mut late);
        // Every child lies in the whole array: the last join settled all.
        debug_assert!(late.is_empty());
        settled
    }

    /// The refit of a tree whose nodes are far from preorder (many leaves
    /// reinserted since its last layout, as a trickle of teleports leaves
    /// it): in reverse of a preorder walk, one task, where
    /// [`Tree::refit_blocks`] would refit many nodes again. Returns how many
    /// nodes come after one of their children in the array: how far the
    /// layout strayed from preorder, counted as late.
    fn refit_walked(&mut self, bounds: Option<&[B]>, found: &mut Refit) -> usize {
        let nodes = &mut self.nodes;
        let mut order = vec![0; nodes.len() - self.free_count];
        // Every node in the order once: a walk whose pushes are written
        // unconditionally and counted by whether they are nodes, which no
        // branch predictor could learn.
        let mut stack = vec![0; order.len() + 2];
        stack[0] = self.root.index();
        let (mut top, mut len) = (1, 0);
        while top > 0 {
            top -= 1;
            let x = stack[top];
            order[len] = x;
            len += 1;
            // Second child pushed first: the walk follows the memory order of
            // a mostly preorder layout.
            for c in nodes[x as usize].child.into_iter().rev() {
                stack[top] = c.index();
                top += usize::from(c.is_node());
            }
        }
        let (mut inner, mut late) = (0.0, 0);
        for k in (0..len).rev() {
            // As in `refit_run`, asked for ahead: the nodes are where the
            // order puts them, mostly in a row.
            if let Some(&far) = k.checked_sub(NODES_AHEAD).map(|far| &order[far]) {
                prefetch(&nodes[far as usize]);
            }
            if let Some(all) = bounds
                && let Some(&ahead) = k.checked_sub(PREFETCH_AHEAD).map(|ahead| &order[ahead])
            {
                ask_leaf_bounds(&nodes[ahead as usize], all);
            }
            let x = order[k];
            let child = |c: Ref| c.is_node().then(|| *nodes[c.index() as usize].pair());
            let [c0, c1] = nodes[x as usize].child;
            let before = |c: Ref| c.is_node() & (c.index() < x);
            late += usize::from(before(c0) | before(c1));
            let pairs = [child(c0), child(c1)];
            let children = [pairs[0].as_ref(), pairs[1].as_ref()];
            // In place: a copy on the stack, written back, would make
            // the refit's speed depend on where the stack falls against
            // the arrays modulo 4 KiB (its stores can alias the next
            // node's loads), and so differ from build to build.
            inner += refit_node(&mut nodes[x as usize], children, bounds, found);
        }
        found.inner += inner;
        late
    }

    /// Gives the leaves `listed` their new bounds for a refit to follow
    /// ([`BoundPair::refit`]): those that jumped clear of their old bound
    /// keep it when `hold` (see [`crate::policy`]), to be reinserted after
    /// the refit, which so measures the cost without their stretch. Returns
    /// the ones that jumped.
    pub(crate) fn place_listed(&mut self, listed: &[(u32, B)], hold: bool) -> Vec<(u32, B)> {
        let mut jumped = Vec::new();
        for (k, &(id, bound)) in listed.iter().enumerate() {
            // The ids may come in any order, and their parents lie
            // anywhere: ask for a later one's parent early.
            if let Some(&(later, _)) = listed.get(k + PREFETCH_AHEAD) {
                self.leaves().prefetch(later);
            }
            let p = self.leaf_parents[id as usize];
            if p == ROOT {
                self.root_bound = bound;
                continue;
            }
            let node = &mut self.nodes[p as usize];
            let mut leaves = [None; 2];
            leaves[node.side_of(Ref::leaf(id))] = Some(&bound);
            if node.pair_mut().refit([None; 2], leaves, hold).jumped != 0 {
                jumped.push((id, bound));
            }
        }
        jumped
    }
}

/// What a refit found: leaves whose bound changed, those that jumped clear
/// of their old bound (which they keep when `hold`), and the summed area of
/// the internal nodes' bounds.
struct Refit<'a> {
    moved: &'a mut Vec<u32>,
    jumped: &'a mut Vec<u32>,
    hold: bool,
    inner: f64,
}

impl Refit<'_> {
    /// Runs `first` and `second` on two rayon tasks, each finding into a
    /// refit of its own, and appends what they found here in a fixed order
    /// (second's first, as a pass from last to first meets them), so the
    /// result is the same whatever the number of threads. Returns what each
    /// returned.
    fn join<R: Send>(
        &mut self,
        first: impl FnOnce(&mut Refit) -> R + Send,
        second: impl FnOnce(&mut Refit) -> R + Send,
    ) -> (R, R) {
        if one_thread() {
            // On one thread each appends to these lists, in the order the
            // join gives them (second's first), instead of filling lists of
            // its own that are copied in at every level of the split; its
            // area is summed on its own and added as the join adds it, so
            // the cost is the same to the bit.
            let (b_inner, b) = self.along(second);
            let (a_inner, a) = self.along(first);
            self.inner += b_inner;
            self.inner += a_inner;
            return (a, b);
        }
        let hold = self.hold;
        let (a, b) = rayon::join(|| Refit::apart(hold, first), || Refit::apart(hold, second));
        for (moved, jumped, inner, _) in [&b, &a] {
            self.moved.extend_from_slice(moved);
            self.jumped.extend_from_slice(jumped);
            self.inner += inner;
        }
        (a.3, b.3)
    }

    /// Runs `run` on a refit that appends to these lists but sums its own
    /// area: that area, and what it returned.
    fn along<R>(&mut self, run: impl FnOnce(&mut Refit) -> R) -> (f64, R) {
        let (moved, jumped) = (&mut *self.moved, &mut *self.jumped);
        let mut part = Refit { moved, jumped, hold: self.hold, inner: 0.0 };
        let result = run(&mut part);
        (part.inner, result)
    }

    /// Runs `run` on a refit of its own: what it found, and what it returned.
    fn apart<R>(hold: bool, run: impl FnOnce(&mut Refit) -> R) -> (Vec<u32>, Vec<u32>, f64, R) {
        let (mut moved, mut jumped) = (Vec::new(), Vec::new());
        let mut part = Refit { moved: &mut moved, jumped: &mut jumped, hold, inner: 0.0 };
        let result = run(&mut part);
        let inner = part.inner;
        (moved, jumped, inner, result)
    }
}

/// Refits the subtree laid out in preorder in `nodes` (its root first, named
/// `base`), children before parents. Large subtrees split into their two
/// child subtrees, refit on two rayon tasks ([`Refit::join`]).
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
    let part = |nodes: &mut [Node<B>], child: Ref, part: &mut Refit| {
        if child.is_node() {
            refit_subtree(nodes, child.index() as usize, bounds, part);
        }
    };
    let [c0, c1] = node.child;
    found.join(|p| part(first_nodes, c0, p), |p| part(second_nodes, c1, p));
    // A child subtree's root is its run's first node.
    let children = [first_nodes.first().map(Node::pair), second_nodes.first().map(Node::pair)];
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
        ask_ahead(nodes, x, bounds);
        let (head, tail) = nodes.split_at_mut(x + 1);
        let node = &mut head[x];
        let child = |side: usize| {
            let c = node.child[side];
            // Preorder: every child comes after its parent.
            c.is_node().then(|| tail[c.index() as usize - base - x - 1].pair())
        };
        let children = [child(0), child(1)];
        inner += refit_node(node, children, bounds, found);
    }
    found.inner += inner;
}

/// Refits the nodes `block` (from `lo` in the node array; `parents` for
/// all of it), last to first, listing in `late` the nodes that kept an
/// internal child's old bound because the child lies in another block.
/// Long blocks split in two halves, refit on two rayon tasks
/// ([`Refit::join`]); then the halves' late nodes whose children all lie
/// in the block are settled ([`settle`]), second half's first, and the
/// others listed. Returns how many late nodes were settled.
fn refit_block<B: Bound>(
    block: &mut [Node<B>],
    lo: usize,
    parents: &[u32],
    bounds: Option<&[B]>,
    found: &mut Refit,
    late: &mut Vec<u32>,
) -> usize {
    if block.len() >= 2 * PARALLEL_REFIT {
        let mid = block.len() / 2;
        let (first, second) = block.split_at_mut(mid);
        let part = |block: &mut [Node<B>], lo: usize, part: &mut Refit| {
            let mut late = Vec::new();
            let settled = refit_block(block, lo, parents, bounds, part, &mut late);
            (late, settled)
        };
        let (a, b) = found.join(|p| part(first, lo, p), |p| part(second, lo + mid, p));
        let mut settled = a.1 + b.1;
        for x in b.0.into_iter().chain(a.0) {
            let k = x as usize - lo;
            if in_block(&block[k], lo, block.len()) {
                found.inner += settle(block, lo, k, parents);
                settled += 1;
            } else {
                late.push(x);
            }
        }
        return settled;
    }
    let (mut inner, len) = (0.0, block.len());
    for k in (0..len).rev() {
        ask_ahead(block, k, bounds);
        let x = lo + k;
        if parents[x] == NONE {
            continue; // free
        }
        let (head, tail) = block.split_at_mut(k + 1);
        let node = &mut head[k];
        // A child in another block is refit on another task.
        if !in_block(node, lo, len) {
            late.push(x as u32);
        }
        // An internal child refit before it in this block lies after it.
        // One not refit yet is given as neither: its side keeps its bound
        // until the child is refit and climbs back here.
        let refit = |c: Ref| tail.get((c.index() as usize).wrapping_sub(x + 1));
        let child = |c: Ref| if c.is_node() { refit(c).map(Node::pair) } else { None };
        let children = [child(node.child[0]), child(node.child[1])];
        inner += refit_node(node, children, bounds, found);
        // Mostly a node's parent comes before it, and there is no climb.
        if parents[x] as usize > x {
            inner += climb(block, lo, k, k + 1, parents);
        }
    }
    found.inner += inner;
    0
}

/// Whether every internal child of `node` lies in the block of `len` nodes
/// from `lo`.
fn in_block<B: Bound>(node: &Node<B>, lo: usize, len: usize) -> bool {
    let here = |c: Ref| !c.is_node() || (lo..lo + len).contains(&(c.index() as usize));
    here(node.child[0]) && here(node.child[1])
}

/// Refits node `lo + k` of `block`, late, from its internal children, all
/// refit by now in the block, and hands its bound up to its ancestors in
/// the block, all refit by now too. Returns the change in the internal
/// children's summed area.
fn settle<B: Bound>(block: &mut [Node<B>], lo: usize, k: usize, parents: &[u32]) -> f64 {
    let mut inner = 0.0;
    for side in 0..2 {
        let c = block[k].child[side];
        if c.is_node() {
            let merged = block[c.index() as usize - lo].merged();
            inner += set_side(&mut block[k], side, merged);
        }
    }
    inner + climb(block, lo, k, 0, parents)
}

/// Sets `node`'s child bound on `side` to `bound`. Returns the change in
/// its area.
fn set_side<B: Bound>(node: &mut Node<B>, side: usize, bound: B) -> f64 {
    let change = bound.cost() - node.bound(side).cost();
    node.set_bound(side, bound);
    change
}

/// Hands the bound of node `lo + k`, just refit, to its ancestors at
/// `first` or after in `block`, up to the first that is not. In the pass,
/// `first` is `k + 1`: the ancestors the pass refit before it (those after
/// it in the array, as a node an insertion placed after its new sibling);
/// the first it did not reach is refit later in the pass, from its children
/// as they stand then. Only the child's side of each is set: a leaf side's
/// move was recorded when the node was refit. The climb stops at the first
/// ancestor that already holds the bound handed up: every node refit so far
/// holds the merge of its children as they stand (but on the side of a
/// child not refit yet, or late, which climbs back when it is), so nothing
/// above that one changes either. Returns the change in the internal
/// children's summed area.
fn climb<B: Bound>(
    block: &mut [Node<B>],
    lo: usize,
    k: usize,
    first: usize,
    parents: &[u32],
) -> f64 {
    let mut inner = 0.0;
    let mut y = k;
    // `ROOT` and `NONE` fall past the block.
    while let Some(p) = (parents[lo + y] as usize).checked_sub(lo)
        && p >= first
        && p < block.len()
    {
        let merged = block[y].merged();
        let side = block[p].side_of(Ref::node((lo + y) as u32));
        if block[p].bound(side) == merged {
            break;
        }
        inner += set_side(&mut block[p], side, merged);
        y = p;
    }
    inner
}

/// Before refitting `nodes[k]` in a pass from last to first, asks for a
/// node further on and the leaf bounds of a nearer one: the nodes are read
/// and written backwards, and asked for ahead, as the user's bounds are, the
/// stream does not wait on memory.
#[inline]
fn ask_ahead<B: Bound>(nodes: &[Node<B>], k: usize, bounds: Option<&[B]>) {
    if let Some(far) = k.checked_sub(NODES_AHEAD) {
        prefetch(&nodes[far]);
    }
    if let Some(all) = bounds
        && let Some(ahead) = k.checked_sub(PREFETCH_AHEAD)
    {
        ask_leaf_bounds(&nodes[ahead], all);
    }
}

/// Refits one node's child bounds ([`BoundPair::refit`]): internal
/// children's from their refit pairs `children`, leaves' from `bounds`,
/// recording moves and jumps. Returns the internal children's summed area,
/// for the caller to add up in a register (added to `found` a node at a
/// time, it chained every node's refit on a store and a load).
#[inline(always)]
fn refit_node<B: Bound>(
    node: &mut Node<B>,
    children: [Option<&B::Pair>; 2],
    bounds: Option<&[B]>,
    found: &mut Refit,
) -> f64 {
    let child = node.child;
    let leaf = |c: Ref| bounds.filter(|_| c.is_leaf()).and_then(|all| all.get(c.index() as usize));
    let refit = node.pair_mut().refit(children, [leaf(child[0]), leaf(child[1])], found.hold);
    if refit.moved != 0 {
        for side in (0..2).filter(|s| refit.moved >> s & 1 == 1) {
            let id = child[side].index();
            found.moved.push(id);
            if refit.jumped >> side & 1 == 1 {
                found.jumped.push(id);
            }
        }
    }
    refit.cost
}

#[cfg(test)]
mod tests {
    use bvol_volumes::Aabb;
    use glam::Vec3;

    use super::*;
    use crate::Config;

    fn cube(x: f32, y: f32) -> Aabb {
        Aabb::new(Vec3::new(x, y, 0.0), Vec3::new(x + 1.0, y + 1.0, 1.0))
    }

    /// Whether some node in use comes after one of its internal children.
    fn out_of_order(tree: &Tree<Aabb>) -> bool {
        (0..tree.nodes.len()).any(|x| {
            tree.parents[x] != NONE
                && tree.nodes[x].child.iter().any(|c| c.is_node() && (c.index() as usize) < x)
        })
    }

    #[test]
    fn a_tree_out_of_preorder_is_refit_exactly() {
        // Enough nodes for the refit to split them into blocks.
        let n = 4 * PARALLEL_REFIT;
        let mut boxes: Vec<Aabb> =
            (0..n).map(|i| cube((i % 200) as f32 * 1.5, (i / 200) as f32 * 1.5)).collect();
        let mut tree = Tree::from_bounds(&boxes).unwrap();
        // Leaves set clear of where they were are reinserted into free
        // slots, before or after their new neighbours.
        for (k, id) in [7, 300, 5120, 9999, 41, 26500, 128, 18000].into_iter().enumerate() {
            boxes[id] = cube(-3.0 * k as f32, -4.0);
            tree.set_bound(id as u32, boxes[id]).unwrap();
        }
        assert!(out_of_order(&tree));
        // Every leaf moves a little: one refit of the whole tree.
        for b in &mut boxes {
            *b = Aabb::new(b.min + 0.1, b.max + 0.1);
        }
        assert!(tree.update(&boxes).unwrap().refit);
        assert!(out_of_order(&tree));
        assert_exact(&tree, &boxes);
        // One leaf in seven moves, each a little, some growing and some
        // shrinking: most climbs reach an ancestor whose bound stays.
        for (i, b) in boxes.iter_mut().enumerate().filter(|(i, _)| i % 7 == 3) {
            let d = if i % 2 == 0 { 0.2 } else { -0.2 };
            *b = Aabb::new(b.min - d, b.max + d);
        }
        assert!(tree.update(&boxes).unwrap().refit);
        assert!(out_of_order(&tree));
        assert_exact(&tree, &boxes);
    }

    /// A refit pass on one thread, whose halves append to the caller's lists
    /// in turn, finds what the pass on two finds, where the halves' lists
    /// are joined: the same moved and jumped ids in the same order, the
    /// same cost to the bit, in preorder (split into subtrees) and out of
    /// it (split into blocks), jumps held or not.
    #[test]
    fn a_refit_pass_finds_the_same_on_one_thread_and_two() {
        let n = 4 * PARALLEL_REFIT;
        let boxes: Vec<Aabb> =
            (0..n).map(|i| cube((i % 200) as f32 * 1.5, (i / 200) as f32 * 1.5)).collect();
        let mut moved_boxes = boxes.clone();
        for (i, b) in moved_boxes.iter_mut().enumerate() {
            // Most drift a little (their ancestors' areas change by varied
            // amounts); one in 97 jumps clear of where it was.
            *b = match i % 97 {
                0 => cube(-2.0 * (i % 50) as f32, -5.0),
                k => Aabb::new(b.min + 0.003 * k as f32, b.max + 0.01),
            };
        }
        let preorder = Tree::from_bounds(&boxes).unwrap();
        let mut reshaped = preorder.clone();
        for id in [7, 300, 5120, 9999, 41, 26500, 128, 18000] {
            reshaped.set_bound(id, cube(-3.0 * id as f32, -4.0)).unwrap();
        }
        assert!(out_of_order(&reshaped));
        for (tree, hold) in [(&preorder, false), (&preorder, true), (&reshaped, true)] {
            let pass = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| {
                    let mut tree = tree.clone();
                    let (mut moved, mut jumped) = (Vec::new(), Vec::new());
                    let mut found =
                        Refit { moved: &mut moved, jumped: &mut jumped, hold, inner: 0.0 };
                    match tree.preorder {
                        true => refit_subtree(&mut tree.nodes, 0, Some(&moved_boxes), &mut found),
                        false => {
                            tree.refit_blocks(Some(&moved_boxes), &mut found);
                        }
                    }
                    (found.inner.to_bits(), moved, jumped)
                })
            };
            let one = pass(1);
            assert!(one.1.len() > n / 2 && !one.2.is_empty());
            assert_eq!(pass(2), one, "hold {hold}, preorder {}", tree.preorder);
        }
    }

    /// Every node's bounds are the exact merge of its children's, and the
    /// leaves' are `boxes`.
    fn assert_exact(tree: &Tree<Aabb>, boxes: &[Aabb]) {
        for (x, node) in tree.nodes.iter().enumerate().filter(|&(x, _)| tree.parents[x] != NONE) {
            for (side, c) in node.child.into_iter().enumerate() {
                let want = match c.is_node() {
                    true => tree.nodes[c.index() as usize].merged(),
                    false => boxes[c.index() as usize],
                };
                assert_eq!(node.bound(side), want, "node {x}, side {side}");
            }
        }
    }

    #[test]
    fn a_trickle_of_reinsertions_is_refit_exactly_in_blocks_and_laid_out() {
        let n = 4 * PARALLEL_REFIT;
        let mut boxes: Vec<Aabb> =
            (0..n).map(|i| cube((i % 200) as f32 * 1.5, (i / 200) as f32 * 1.5)).collect();
        // No rebuilds: the reinsertions alone reshape the tree.
        let config = Config { drift: f64::INFINITY, ..Config::default() };
        let mut tree = Tree::build(config, (0..).zip(boxes.iter().copied())).unwrap();
        let (mut blocks, mut layouts, mut gained, mut seed) = (0, 0, 0, 1u64);
        for frame in 0..80 {
            // Every box drifts; one in a hundred lands anywhere in the grid.
            for b in &mut boxes {
                *b = Aabb::new(b.min + 0.01, b.max + 0.01);
            }
            for _ in 0..n / 100 {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let id = (seed >> 33) as usize % n;
                let (x, y) = ((seed >> 20) % 300, (seed >> 10) % 250);
                boxes[id] = cube(x as f32, y as f32);
            }
            let was_late = !tree.preorder && tree.late > 0;
            assert!(tree.update(&boxes).unwrap().refit);
            // Laid out, the tree was refit in preorder: none late.
            blocks += usize::from(was_late && tree.late > 0);
            gained += if was_late && tree.late > 0 { tree.late_gain } else { 0 };
            layouts += usize::from(was_late && tree.late == 0);
            assert_exact(&tree, &boxes);
            tree.validate().unwrap_or_else(|v| panic!("frame {frame}: {v}"));
            assert!(tree.late * WALK_LATE <= 2 * n, "frame {frame}: {} nodes late", tree.late);
        }
        assert!(blocks >= 10 && layouts >= 2, "{blocks} refits in blocks, {layouts} layouts");
        // Most reinsertions take a free node after their new parent, in the
        // block of their new sibling: about one in ten had a child in
        // another block. Taking the free list's first, seven in ten did.
        let reinserted = blocks * (n / 100);
        assert!(gained * 4 < reinserted, "{gained} late after {reinserted} reinsertions");
    }
}
