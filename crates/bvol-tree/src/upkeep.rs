//! Bounded per-frame quality upkeep: partial rebuilds of the region of the
//! tree that leaf escapes enlarged (Box2D v3's `b2DynamicTree_Rebuild` with
//! `fullBuild = false`), a budget of atoms at a time.

use crate::build::{Atom, NoClusters, build};
use crate::node::{NONE, Node, Ref, Slot};
use crate::{Bound, Tree};

impl<B: Bound> Tree<B> {
    /// Bounded quality upkeep; call once per frame after [`Tree::set_bound`]
    /// calls ([`Tree::update`] calls it itself). Returns the number of atoms
    /// placed.
    ///
    /// Leaves that escaped their slack enlarged their ancestors and flagged
    /// them, up to the root. The flagged region is rebuilt with binned SAH
    /// over its atoms: the leaves and the unflagged subtrees hanging off it,
    /// which are kept whole. At most [`Config::rebuild_budget`](crate::Config)
    /// atoms are placed per call: when the region is larger, its largest
    /// subregions that fit are rebuilt, and the part above them waits for a
    /// later call, when it has fewer atoms.
    pub fn optimize(&mut self) -> usize {
        let budget = self.config.rebuild_budget.max(2);
        let region = self.enlarged_region();
        let mut placed = 0;
        let mut i = 0;
        while i < region.len() {
            let (x, size) = region[i];
            // A region of `size` internal nodes has `size + 1` atoms.
            if placed + (size as usize) < budget {
                placed += self.rebuild_region(x);
                i += size as usize;
            } else {
                i += 1;
            }
        }
        placed
    }

    /// The flagged nodes reachable from the root through flagged nodes, in
    /// preorder, each with the number of flagged nodes in its subregion (its
    /// own included): a subregion is a contiguous run of the list.
    fn enlarged_region(&self) -> Vec<(u32, u32)> {
        let mut region = Vec::new();
        if !self.root.is_node() || !self.enlarged[self.root.index() as usize] {
            return region;
        }
        let mut stack = vec![self.root.index()];
        while let Some(x) = stack.pop() {
            region.push((x, 1));
            for side in (0..2).rev() {
                let c = self.nodes[x as usize].child[side];
                if c.is_node() && self.enlarged[c.index() as usize] {
                    stack.push(c.index());
                }
            }
        }
        // In reverse preorder a subregion's size is known before its parent's:
        // add each size to the parent's entry, found by position.
        let mut position = vec![NONE; self.nodes.len()];
        for (i, &(x, _)) in region.iter().enumerate() {
            position[x as usize] = i as u32;
        }
        for i in (1..region.len()).rev() {
            let parent = self.parents[region[i].0 as usize];
            let p = position[parent as usize] as usize;
            region[p].1 += region[i].1;
        }
        region
    }

    /// Rebuilds the flagged subregion under flagged node `r` with binned SAH
    /// over its atoms, reusing its nodes. Returns the number of atoms.
    fn rebuild_region(&mut self, r: u32) -> usize {
        let mut atoms = Vec::new();
        let mut freed = Vec::new();
        let mut stack = vec![r];
        while let Some(x) = stack.pop() {
            freed.push(x);
            let n = self.nodes[x as usize];
            for side in 0..2 {
                let c = n.child[side];
                if c.is_node() && self.enlarged[c.index() as usize] {
                    stack.push(c.index());
                } else {
                    atoms.push(Atom::new(c, n.bound(side)));
                }
            }
        }
        let slot = self.slot_of_node(r);
        // Built under names past every node, so that built nodes and kept
        // subtrees can be told apart, then moved into the freed nodes.
        let base = self.nodes.len() as u32;
        let mut local = vec![Node::empty(); atoms.len() - 1];
        let (top, bound) = build(&mut atoms, &mut local, base, &NoClusters);
        // Reused in increasing order: subtrees built together stay close.
        freed.sort_unstable();
        let place = |c: Ref| match c.index().checked_sub(base) {
            Some(i) if c.is_node() => Ref::node(freed[i as usize]),
            _ => c,
        };
        for (i, n) in local.iter().enumerate() {
            let x = freed[i];
            self.nodes[x as usize] =
                Node::new(n.bounds(), [place(n.child[0]), place(n.child[1])], x);
            self.enlarged[x as usize] = false;
            for side in 0..2 {
                self.set_parent(self.nodes[x as usize].child[side], x);
            }
        }
        self.link(slot, place(top), bound);
        if let Slot::Child { node, .. } = slot {
            // The new bound is the exact merge of the same atoms, so it fits
            // where the old one did for boxes; a sphere merge may not.
            self.enlarge_from(node, bound, false);
        }
        self.mark_reshaped();
        atoms.len()
    }
}
