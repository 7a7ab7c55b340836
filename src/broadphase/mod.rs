//! The broadphase seam: what a [`World`](crate::World) needs of the structure
//! that finds which bodies' boxes overlap. The world keeps two of them, one
//! for moving bodies and one for resting ones (static and sleeping), and asks
//! for the pairs within the first and between the two; it never asks for
//! pairs within the resting set. Leaves are named by the bodies' slots.
//!
//! Two implementations: the dynamic tree ([`Tree<Aabb>`](bvol_tree::Tree),
//! the default) and [`BruteForce`], which tests every pair and is the tests'
//! reference. Another one (sweep-and-prune, a grid, one on a GPU) implements
//! [`Broadphase`] and goes in a world by its type, `World::<Mine>::default()`;
//! nothing else changes. Jolt's
//! `BroadPhase` / `BroadPhaseBruteForce` and Box2D v3's `broad_phase.c` are
//! the models.

mod brute_force;
mod tree;

use bvol_volumes::{Aabb, Ray};

pub use brute_force::BruteForce;

/// A set of leaves (an id and a box each) that answers which of them
/// overlap, which meet another set's, and which a ray or a region meets.
///
/// Overlap is closed: boxes that touch overlap. Every answer's order is fixed
/// by the set's contents and the calls that made it, never by the number of
/// threads, so that a world's events are deterministic.
///
/// ```
/// use bvol::{Broadphase, BruteForce};
/// use bvol::volumes::Aabb;
/// use bvol::tree::Tree;
/// use glam::Vec3;
///
/// let unit = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0));
/// let leaves = [(0, unit(0.0)), (1, unit(0.5)), (2, unit(3.0))];
/// let (mut tree, mut brute) = (Tree::<Aabb>::default(), BruteForce::default());
/// Broadphase::insert_many(&mut tree, &leaves)?;
/// brute.insert_many(&leaves)?;
/// let (mut a, mut b) = (Vec::new(), Vec::new());
/// Broadphase::pairs_into(&tree, &mut a);
/// brute.pairs_into(&mut b);
/// assert_eq!((a, b), (vec![(0, 1)], vec![(0, 1)]));
/// # Ok::<(), bvol::tree::TreeError>(())
/// ```
pub trait Broadphase: Default + std::fmt::Debug + Send + Sync {
    /// Why a call was refused: an unknown or repeated id, one at or above
    /// [`ID_LIMIT`](Self::ID_LIMIT), or a box that is not finite. A refused
    /// call changes nothing.
    type Error: std::error::Error + Send + Sync + 'static;

    /// What the set keeps from one call of
    /// [`cached_pairs_into`](Self::cached_pairs_into) to the next.
    type Cache: Default + std::fmt::Debug + Send + Sync;

    /// Ids must be below this.
    const ID_LIMIT: u32;

    /// Number of leaves.
    fn len(&self) -> usize;

    /// Whether there is no leaf.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether leaf `id` is in the set.
    fn contains(&self, id: u32) -> bool;

    /// Adds leaves, each id once and none already in the set.
    fn insert_many(&mut self, leaves: &[(u32, Aabb)]) -> Result<(), Self::Error>;

    /// Removes leaf `id`.
    fn remove(&mut self, id: u32) -> Result<(), Self::Error>;

    /// Gives leaves already in the set their new boxes.
    fn update_moved(&mut self, moved: &[(u32, Aabb)]) -> Result<(), Self::Error>;

    /// Gives every leaf its box `boxes[id]`: the update when most leaves
    /// moved, read from the world's array of every body's box. Entries for
    /// ids not in the set are not read; leaves at or past the slice's end
    /// keep their boxes, as [`Tree::update_from`](bvol_tree::Tree::update_from)
    /// has it.
    fn update_from(&mut self, boxes: &[Aabb]) -> Result<(), Self::Error>;

    /// Every pair of leaves whose boxes overlap, each once as `(a, b)` with
    /// `a < b`, into `out` (cleared first).
    fn pairs_into(&self, out: &mut Vec<(u32, u32)>);

    /// Every pair that [`pairs_into`](Self::pairs_into) lists, in an order
    /// of the set's own, with `cache` kept from the last call: the tree keeps
    /// its pairs in a [`PairCache`](bvol_tree::PairCache) and, when few
    /// leaves changed since, searches only around those. A cache serves one
    /// set alone.
    fn cached_pairs_into(&mut self, cache: &mut Self::Cache, out: &mut Vec<(u32, u32)>);

    /// Every pair `(id in self, id in other)` whose boxes overlap, appended
    /// to `out`. Leaves of one set are not tested against each other.
    fn pairs_with(&self, other: &Self, out: &mut Vec<(u32, u32)>);

    /// The nearest leaf a ray meets within `max_t`, as `(id, t)`. The boxes
    /// are bounds, so `exact(id, t)` decides: it is called with a leaf whose
    /// box the ray enters at `t`, returns where the ray meets what the leaf
    /// bounds (`None` for a miss) and never less than `t`. Ties go to the
    /// lower id.
    fn ray_cast(
        &self,
        ray: &Ray,
        max_t: f32,
        exact: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)>;

    /// Calls `found(id)` for every leaf whose box overlaps `region`.
    fn query(&self, region: &Aabb, found: impl FnMut(u32));

    /// Calls `visit(depth, bound)` for each node the set keeps above its
    /// leaves, parents first: what a debug view draws.
    fn visit_nodes(&self, visit: impl FnMut(usize, &Aabb));
}
