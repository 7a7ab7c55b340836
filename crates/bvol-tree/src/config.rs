//! The tuning of a tree: its fat margins and its update policy's thresholds.

/// Tuning of a [`Tree`](crate::Tree). The defaults were chosen by
/// measurement on 100 000 moving boxes (`benches/frame.rs`; the runs are
/// recorded in `docs/performance.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Fat margin as a fraction of a leaf's size (largest half extent, or
    /// radius), added when a leaf is inserted or escapes its slack. Default
    /// 0.1, Box2D's 0.1 m margin for bodies of about a metre.
    pub fat_size: f32,
    /// Fat margin in multiples of the distance the leaf's centre just moved,
    /// so fast bodies get room for their next frames. Default 2.
    pub fat_motion: f32,
    /// Fraction of leaves moved at or above which
    /// [`Tree::update`](crate::Tree::update) refits the whole tree instead of
    /// updating leaves one by one. Default 0.001: with every bound handed
    /// over, finding what moved reads all of them anyway, so the refit (one
    /// more pass over the nodes) costs less than per-leaf moves from about
    /// one leaf in a thousand moved.
    pub refit_fraction: f32,
    /// SAH cost growth, relative to the cost after the last whole build,
    /// that [`Tree::update`](crate::Tree::update)'s refit path lets the tree
    /// reach before it rebuilds it. Default 0.3: boxes moving 0.1 of their
    /// size per frame reach it about every 20 frames, and rebuilding at a
    /// lower growth does not make the pair searches between rebuilds cheaper
    /// by what the rebuilds cost. The rebuild is staged over the next frames,
    /// so none pays for all of it, and starts at a fraction of this growth
    /// so that it is installed about when the tree would have reached it;
    /// where leaves teleport so often that a staged rebuild would find many
    /// placed where they were, it starts at this growth and takes several
    /// steps a frame.
    pub drift: f64,
    /// Most atoms (leaves and kept subtrees) one
    /// [`Tree::optimize`](crate::Tree::optimize) call places: the bound on
    /// the per-frame upkeep work. Default 4096, a few percent of a
    /// 100 000-leaf tree, so the upkeep stays small next to the frame's pair
    /// search.
    pub rebuild_budget: usize,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            fat_size: 0.1,
            fat_motion: 2.0,
            refit_fraction: 0.001,
            drift: 0.3,
            rebuild_budget: 4096,
        }
    }
}
