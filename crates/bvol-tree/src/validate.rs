//! The invariant check the tests run after every step.

use crate::error::Violation;
use crate::node::{NONE, ROOT, Ref, Slot};
use crate::{Bound, Tree};

impl<B: Bound> Tree<B> {
    /// Checks every invariant of the tree and returns the first violation:
    /// every stored bound valid; every internal node's bound (where it hangs)
    /// containing both its children's; parent links of nodes and leaves
    /// pointing where they hang; every node's stored visit sides those of
    /// its children; every node reached once from the root, none
    /// of them free; every recorded id reached, and nothing else; in-use plus
    /// free nodes adding up to the node array. O(n).
    pub fn validate(&self) -> Result<(), Violation> {
        let recorded = self.leaf_parents.iter().filter(|&&p| p != NONE).count();
        if self.root == Ref::NONE {
            return self.check_counts(0, recorded);
        }
        self.check_bound(Slot::Root, &self.root_bound)?;
        if self.root.is_leaf() {
            self.check_hangs(self.root, Slot::Root)?;
            return self.check_counts(1, recorded);
        }
        let free = self.free_list()?;
        let mut seen = vec![false; self.nodes.len()];
        for &x in &free {
            seen[x as usize] = true;
        }
        let (mut leaves, mut reached) = (0, 0);
        let mut stack = vec![(self.root, Slot::Root)];
        while let Some((r, slot)) = stack.pop() {
            self.check_hangs(r, slot)?;
            if r.is_leaf() {
                leaves += 1;
                continue;
            }
            let x = r.index();
            if seen[x as usize] {
                return Err(Violation::BadLink { node: x });
            }
            seen[x as usize] = true;
            reached += 1;
            let node = &self.nodes[x as usize];
            if !node.placed_at(x) {
                return Err(Violation::StaleVisits { node: x });
            }
            let own = self.get(slot);
            for side in 0..2 {
                let child = Slot::Child { node: x, side };
                self.check_bound(child, &node.bound(side))?;
                if !own.contains(&node.bound(side)) {
                    return Err(Violation::NotContained { slot, node: x, side });
                }
                stack.push((node.child[side], child));
            }
        }
        if leaves != self.len || leaves != recorded {
            return Err(Violation::LeafCount { reached: leaves, recorded });
        }
        if reached + free.len() != self.nodes.len() {
            return Err(Violation::NodeCount {
                reached,
                free: free.len(),
                total: self.nodes.len(),
            });
        }
        Ok(())
    }

    /// `Err` when the leaf or node `r` does not record `slot` as where it
    /// hangs, or is out of range.
    fn check_hangs(&self, r: Ref, slot: Slot) -> Result<(), Violation> {
        let parent = match slot {
            Slot::Root => ROOT,
            Slot::Child { node, .. } => node,
        };
        if r.is_leaf() {
            return match self.leaf_parents.get(r.index() as usize) {
                Some(&p) if p == parent => Ok(()),
                _ => Err(Violation::BadLeafParent { id: r.index(), slot }),
            };
        }
        match self.parents.get(r.index() as usize) {
            None => Err(Violation::BadLink { node: r.index() }),
            Some(&p) if p == parent => Ok(()),
            Some(&p) => Err(Violation::BadParent { node: r.index(), recorded: p }),
        }
    }

    /// `Err` when a stored bound is invalid.
    fn check_bound(&self, slot: Slot, bound: &B) -> Result<(), Violation> {
        bound.check().map_err(|reason| Violation::BadBound { slot, reason })
    }

    /// The free list, checked: in range, no repeats, marked free, as long as
    /// the free count says.
    fn free_list(&self) -> Result<Vec<u32>, Violation> {
        let mut free = Vec::new();
        let mut on_list = vec![false; self.nodes.len()];
        let mut r = self.free;
        while r != Ref::NONE {
            let x = r.index();
            let bad = x as usize >= self.nodes.len()
                || on_list[x as usize]
                || self.parents[x as usize] != NONE
                || free.len() >= self.free_count;
            if bad {
                return Err(Violation::BadLink { node: x });
            }
            on_list[x as usize] = true;
            free.push(x);
            r = self.nodes[x as usize].child[0];
        }
        if free.len() != self.free_count {
            return Err(Violation::NodeCount {
                reached: 0,
                free: free.len(),
                total: self.free_count,
            });
        }
        Ok(free)
    }

    /// The counts of a tree with no internal node in use.
    fn check_counts(&self, leaves: usize, recorded: usize) -> Result<(), Violation> {
        if leaves != self.len || leaves != recorded {
            return Err(Violation::LeafCount { reached: leaves, recorded });
        }
        let free = self.free_list()?;
        if free.len() != self.nodes.len() {
            return Err(Violation::NodeCount {
                reached: 0,
                free: free.len(),
                total: self.nodes.len(),
            });
        }
        Ok(())
    }
}
