//! Region queries and ray casts.

use bvol_volumes::Ray;

use crate::node::Ref;
use crate::{Bound, Tree};

impl<B: Bound> Tree<B> {
    /// Calls `found(id)` for every leaf whose tight bound overlaps or touches
    /// `region`, in tree order.
    pub fn query(&self, region: &B, mut found: impl FnMut(u32)) {
        if self.root == Ref::NONE || !self.root_bound.overlaps(region) {
            return;
        }
        if self.root.is_leaf() {
            found(self.root.index());
            return;
        }
        let mut stack = vec![self.root.index()];
        while let Some(x) = stack.pop() {
            let n = &self.nodes[x as usize];
            for side in 0..2 {
                if n.bound(side).overlaps(region) {
                    let c = n.child[side];
                    if c.is_node() { stack.push(c.index()) } else { found(c.index()) }
                }
            }
        }
    }

    /// Calls `hit(id, t)` for every leaf whose tight bound the ray enters at
    /// `t <= max_t` (`t = 0` when it starts inside), in tree order.
    pub fn ray_cast_all(&self, ray: &Ray, max_t: f32, mut hit: impl FnMut(u32, f32)) {
        if self.root == Ref::NONE || self.root_bound.ray_entry(ray, max_t).is_none() {
            return;
        }
        if self.root.is_leaf() {
            if let Some(t) = self.root_bound.ray_entry(ray, max_t) {
                hit(self.root.index(), t);
            }
            return;
        }
        let mut stack = vec![self.root.index()];
        while let Some(x) = stack.pop() {
            let n = &self.nodes[x as usize];
            for side in 0..2 {
                if let Some(t) = n.bound(side).ray_entry(ray, max_t) {
                    let c = n.child[side];
                    if c.is_node() { stack.push(c.index()) } else { hit(c.index(), t) }
                }
            }
        }
    }

    /// The nearest hit along the ray within `max_t`: `(id, distance)`.
    ///
    /// Leaves are bounds, so `exact(id, t)` decides: it is called with a leaf
    /// whose bound the ray enters at `t` (a lower bound of any hit inside it)
    /// and returns the distance to the body itself, `None` for a miss. It must
    /// not return less than `t`. Pass `|_, t| Some(t)` to hit the bounds
    /// themselves. Subtrees are visited nearest first and skipped once they
    /// start beyond the best hit so far; ties go to the smaller id.
    pub fn ray_cast(
        &self,
        ray: &Ray,
        max_t: f32,
        mut exact: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        let mut limit = max_t;
        let mut consider = |id: u32, t: f32, limit: &mut f32| {
            let better = |d: f32| best.is_none_or(|(b, bd)| d < bd || (d == bd && id < b));
            if let Some(d) = exact(id, t).filter(|&d| d <= *limit && better(d)) {
                best = Some((id, d));
                *limit = d;
            }
        };
        match self.root {
            Ref::NONE => return None,
            r if r.is_leaf() => {
                if let Some(t) = self.root_bound.ray_entry(ray, limit) {
                    consider(r.index(), t, &mut limit);
                }
                return best;
            }
            _ => {}
        }
        let mut stack = vec![(self.root.index(), 0.0f32)];
        while let Some((x, entry)) = stack.pop() {
            if entry > limit {
                continue;
            }
            // Entries are computed in f64 and reported rounded down: a bound
            // reported at exactly `limit` may enter just past it, and must
            // not be culled, so that ties are decided by id. Never past
            // `max_t`, though: a bound entered just past it would be
            // reported at it, and hit where `ray_cast_all` finds nothing.
            let reach = if limit < max_t { limit.next_up() } else { max_t };
            let n = &self.nodes[x as usize];
            let t = [n.bound(0).ray_entry(ray, reach), n.bound(1).ray_entry(ray, reach)];
            // Push the farther child first, so the nearer is visited first.
            let order = if t[1].unwrap_or(f32::INFINITY) < t[0].unwrap_or(f32::INFINITY) {
                [0, 1]
            } else {
                [1, 0]
            };
            for side in order {
                let Some(t) = t[side] else { continue };
                let c = n.child[side];
                if c.is_node() {
                    stack.push((c.index(), t));
                } else {
                    consider(c.index(), t, &mut limit);
                }
            }
        }
        best
    }
}

impl<B: Bound> Tree<B> {
    /// Calls `visit(depth, bound)` for the root (depth 0) and every internal
    /// node below it, parents before children, with the bound the parent
    /// keeps for it (its fat bound); leaves are not visited. What a debug
    /// view draws to show the tree by depth.
    ///
    /// ```
    /// use bvol_tree::Tree;
    /// use bvol_volumes::Aabb;
    /// use glam::Vec3;
    ///
    /// let at = |x: f32| Aabb::new(Vec3::splat(x), Vec3::splat(x + 1.0));
    /// let tree = Tree::from_bounds(&[at(0.0), at(2.0), at(4.0), at(6.0)])?;
    /// let mut depths = Vec::new();
    /// tree.visit_nodes(|depth, _| depths.push(depth));
    /// assert_eq!(depths.len(), 3); // 4 leaves, 3 internal nodes
    /// assert_eq!(depths[0], 0);
    /// # Ok::<(), bvol_tree::TreeError>(())
    /// ```
    pub fn visit_nodes(&self, mut visit: impl FnMut(usize, &B)) {
        if !self.root.is_node() {
            return;
        }
        visit(0, &self.root_bound);
        let mut stack = vec![(self.root.index(), 0)];
        while let Some((x, depth)) = stack.pop() {
            let n = &self.nodes[x as usize];
            for side in 0..2 {
                if n.child[side].is_node() {
                    visit(depth + 1, &n.bound(side));
                    stack.push((n.child[side].index(), depth + 1));
                }
            }
        }
    }
}
