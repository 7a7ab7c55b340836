//! The dynamic tree as a broadphase: each call is the tree's own.

use bvol_tree::{PairCache, Tree, TreeError};
use bvol_volumes::{Aabb, Ray};

use super::Broadphase;

impl Broadphase for Tree<Aabb> {
    type Error = TreeError;

    type Cache = PairCache;

    const ID_LIMIT: u32 = Tree::<Aabb>::ID_LIMIT;

    fn len(&self) -> usize {
        Tree::len(self)
    }

    fn contains(&self, id: u32) -> bool {
        Tree::contains(self, id)
    }

    fn insert_many(&mut self, leaves: &[(u32, Aabb)]) -> Result<(), TreeError> {
        Tree::insert_many(self, leaves)
    }

    fn remove(&mut self, id: u32) -> Result<(), TreeError> {
        Tree::remove(self, id).map(drop)
    }

    fn update_moved(&mut self, moved: &[(u32, Aabb)]) -> Result<(), TreeError> {
        Tree::update_moved(self, moved).map(drop)
    }

    fn update_from(&mut self, boxes: &[Aabb]) -> Result<(), TreeError> {
        Tree::update_from(self, boxes).map(drop)
    }

    fn pairs_into(&self, out: &mut Vec<(u32, u32)>) {
        Tree::pairs_into(self, out);
    }

    fn cached_pairs_into(&mut self, cache: &mut PairCache, out: &mut Vec<(u32, u32)>) {
        cache.update(self);
        out.clear();
        out.extend_from_slice(cache.pairs());
    }

    fn pairs_with(&self, other: &Self, out: &mut Vec<(u32, u32)>) {
        out.extend(Tree::pairs_with(self, other));
    }

    fn ray_cast(
        &self,
        ray: &Ray,
        max_t: f32,
        exact: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        Tree::ray_cast(self, ray, max_t, exact)
    }

    fn query(&self, region: &Aabb, found: impl FnMut(u32)) {
        Tree::query(self, region, found);
    }

    fn visit_nodes(&self, visit: impl FnMut(usize, &Aabb)) {
        Tree::visit_nodes(self, visit);
    }
}
