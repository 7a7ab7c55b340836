//! The pair cache: a tree's overlapping pairs kept from frame to frame,
//! in no particular order and without events, so that a frame in which few
//! leaves moved searches only around those.

use rayon::prelude::*;

use crate::{Bound, SearchStats, Tree};

/// Changed ids per task of a cache or pair set update's queries.
const CHUNK: usize = 256;

/// The overlapping pairs of one [`Tree`], kept up to date frame to frame:
/// the cheapest way to have every pair each frame when most leaves stay
/// put (a layer of bodies at rest, a settled pile).
///
/// [`PairCache::update`] reads the tree's change log (ids inserted, moved or
/// removed since the last update). When few leaves changed, the pairs
/// between unchanged leaves are kept without a test, and each changed leaf
/// queries the tree for its own; when many did, one search finds every
/// pair, as [`Tree::pairs_into`]. Unlike [`PairSet`](crate::PairSet) the
/// list is not sorted and no began or ended pairs are worked out, which on
/// a frame that searches everything costs as much again as the search.
///
/// Pairs `(a, b)` have `a < b`. Their order is fixed by the tree and the
/// frames before: the same on any number of threads. The cache must be the
/// only reader of its tree's change log (one `PairCache` or `PairSet` a
/// tree), or it misses the changes another update cleared.
///
/// ```
/// use bvol_tree::{PairCache, Tree};
/// use bvol_volumes::Aabb;
/// use glam::Vec3;
///
/// let at = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
/// // Leaves 0 and 1 overlap; 2 to 9 stand apart along x.
/// let xs = [0.0, 0.5, 3.0, 6.0, 9.0, 12.0, 15.0, 18.0, 21.0, 24.0];
/// let mut tree = Tree::from_bounds(&xs.map(at))?;
/// let mut cache = PairCache::new();
/// cache.update(&mut tree);
/// assert_eq!(cache.pairs(), &[(0, 1)]);
/// tree.set_bound(3, at(3.5))?; // one leaf in ten moved: only it is searched for
/// let update = cache.update(&mut tree);
/// assert_eq!((update.kept, update.queried, update.search), (1, 1, None));
/// let mut pairs = cache.pairs().to_vec();
/// pairs.sort_unstable();
/// assert_eq!(pairs, [(0, 1), (2, 3)]);
/// # Ok::<(), bvol_tree::TreeError>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct PairCache {
    pairs: Vec<(u32, u32)>,
    /// The changed leaves' pairs of an update, reused.
    fresh: Vec<(u32, u32)>,
}

/// What one [`PairCache::update`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheUpdate {
    /// The search of every pair, when many leaves had changed.
    pub search: Option<SearchStats>,
    /// Pairs kept from the last update, both leaves unchanged.
    pub kept: usize,
    /// Changed leaves that queried the tree for their pairs.
    pub queried: usize,
}

impl PairCache {
    /// An empty cache: its first update searches every pair.
    pub fn new() -> Self {
        Self::default()
    }

    /// The pairs after the last update.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.pairs
    }

    /// Brings the pairs up to date with `tree` and clears the tree's change
    /// log.
    pub fn update<B: Bound>(&mut self, tree: &mut Tree<B>) -> CacheUpdate {
        let changes = &tree.changes;
        let update = if changes.few(tree.len()) {
            // Independent: the queries read the tree, the drop the old pairs.
            rayon::join(
                || tree.changed_pairs(&mut self.fresh),
                || changes.swap_out_touched(&mut self.pairs),
            );
            let kept = self.pairs.len();
            self.pairs.extend_from_slice(&self.fresh);
            CacheUpdate { search: None, kept, queried: changes.ids().len() }
        } else {
            let search = tree.pairs_into(&mut self.pairs);
            CacheUpdate { search: Some(search), kept: 0, queried: 0 }
        };
        tree.changes.clear();
        update
    }
}

impl<B: Bound> Tree<B> {
    /// Fills `out` with the pairs that touch a changed leaf, in the change
    /// log's order: each changed leaf queries the tree, and a pair of two
    /// changed leaves is kept from the query of the smaller id only.
    pub(crate) fn changed_pairs(&self, out: &mut Vec<(u32, u32)>) {
        let changes = &self.changes;
        let parts: Vec<Vec<(u32, u32)>> = changes
            .ids()
            .par_chunks(CHUNK)
            .map(|ids| {
                let mut found = Vec::new();
                for &id in ids {
                    let Some(bound) = self.bound(id) else { continue };
                    self.query(&bound, |other| {
                        if other != id && (!changes.is_marked(other) || id < other) {
                            found.push((id.min(other), id.max(other)));
                        }
                    });
                }
                found
            })
            .collect();
        out.clear();
        for part in parts {
            out.extend_from_slice(&part);
        }
    }
}
