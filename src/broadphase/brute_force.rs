//! The reference broadphase: a list of leaves, every pair tested. Quadratic,
//! so for small worlds and for tests, where it is the oracle the tree's
//! answers are checked against through a whole [`World`](crate::World).

use bvol_tree::{Bound, Tree, TreeError};
use bvol_volumes::{Aabb, Ray};

use super::Broadphase;

/// Every leaf in a list, every pair of them tested: the answer a broadphase
/// must give, found with no structure that could be wrong. Refuses what the
/// tree refuses, with the tree's errors.
///
/// ```
/// use std::sync::Arc;
/// use bvol::volumes::Pose;
/// use bvol::{BodyDesc, BruteForce, Shape, World};
/// use glam::{Quat, Vec3};
///
/// let mut world = World::<BruteForce>::default();
/// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
/// world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
/// world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 0.9, Quat::IDENTITY)))?;
/// world.update();
/// assert_eq!(world.events().len(), 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct BruteForce {
    /// The leaves' ids, in the order they came.
    ids: Vec<u32>,
    /// Their boxes, in step with `ids`.
    boxes: Vec<Aabb>,
    /// Each id's place in `ids`, by id (`None` when not in the set).
    place: Vec<Option<u32>>,
}

impl BruteForce {
    /// Leaf `id`'s place in the lists.
    fn place_of(&self, id: u32) -> Option<usize> {
        self.place.get(id as usize).copied().flatten().map(|k| k as usize)
    }

    /// `Ok` when every id of `moved` is in the set and every box valid; else
    /// the first bad one, as the tree names it.
    fn check_moved(&self, moved: &[(u32, Aabb)]) -> Result<(), TreeError> {
        for &(id, aabb) in moved {
            aabb.check().map_err(|reason| TreeError::InvalidBound { id, reason })?;
            if !self.contains(id) {
                return Err(TreeError::UnknownId { id });
            }
        }
        Ok(())
    }
}

impl Broadphase for BruteForce {
    type Error = TreeError;

    /// Nothing kept: every call tests every pair.
    type Cache = ();

    const ID_LIMIT: u32 = Tree::<Aabb>::ID_LIMIT;

    fn len(&self) -> usize {
        self.ids.len()
    }

    fn contains(&self, id: u32) -> bool {
        self.place_of(id).is_some()
    }

    fn insert_many(&mut self, leaves: &[(u32, Aabb)]) -> Result<(), TreeError> {
        // The tree's checks, in its order: each leaf's id, box and presence,
        // then the first id given a second time.
        for &(id, aabb) in leaves {
            if id >= Self::ID_LIMIT {
                return Err(TreeError::IdOutOfRange { id });
            }
            aabb.check().map_err(|reason| TreeError::InvalidBound { id, reason })?;
            if self.contains(id) {
                return Err(TreeError::DuplicateId { id });
            }
        }
        let mut seen = std::collections::HashSet::new();
        if let Some(&(id, _)) = leaves.iter().find(|&&(id, _)| !seen.insert(id)) {
            return Err(TreeError::DuplicateId { id });
        }
        for &(id, aabb) in leaves {
            if self.place.len() <= id as usize {
                self.place.resize(id as usize + 1, None);
            }
            self.place[id as usize] = Some(self.ids.len() as u32);
            self.ids.push(id);
            self.boxes.push(aabb);
        }
        Ok(())
    }

    fn remove(&mut self, id: u32) -> Result<(), TreeError> {
        let k = self.place_of(id).ok_or(TreeError::UnknownId { id })?;
        self.ids.swap_remove(k);
        self.boxes.swap_remove(k);
        self.place[id as usize] = None;
        if let Some(&moved) = self.ids.get(k) {
            self.place[moved as usize] = Some(k as u32);
        }
        Ok(())
    }

    fn update_moved(&mut self, moved: &[(u32, Aabb)]) -> Result<(), TreeError> {
        self.check_moved(moved)?;
        for &(id, aabb) in moved {
            let k = self.place_of(id).expect("checked");
            self.boxes[k] = aabb;
        }
        Ok(())
    }

    fn update_from(&mut self, boxes: &[Aabb]) -> Result<(), TreeError> {
        // By id, so that the first bad box named is the tree's: the lowest.
        let mut held: Vec<u32> =
            self.ids.iter().copied().filter(|&id| (id as usize) < boxes.len()).collect();
        held.sort_unstable();
        let moved: Vec<(u32, Aabb)> = held.into_iter().map(|id| (id, boxes[id as usize])).collect();
        self.update_moved(&moved)
    }

    fn pairs_into(&self, out: &mut Vec<(u32, u32)>) {
        out.clear();
        for (i, a) in self.boxes.iter().enumerate() {
            for (j, b) in self.boxes.iter().enumerate().skip(i + 1) {
                if a.overlaps(b) {
                    let (x, y) = (self.ids[i], self.ids[j]);
                    out.push((x.min(y), x.max(y)));
                }
            }
        }
    }

    fn cached_pairs_into(&mut self, _: &mut (), out: &mut Vec<(u32, u32)>) {
        self.pairs_into(out);
    }

    fn pairs_with(&self, other: &Self, out: &mut Vec<(u32, u32)>) {
        for (&x, a) in self.ids.iter().zip(&self.boxes) {
            for (&y, b) in other.ids.iter().zip(&other.boxes) {
                if a.overlaps(b) {
                    out.push((x, y));
                }
            }
        }
    }

    fn ray_cast(
        &self,
        ray: &Ray,
        max_t: f32,
        mut exact: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        for (&id, aabb) in self.ids.iter().zip(&self.boxes) {
            let Some(t) = aabb.ray_entry(ray, max_t) else { continue };
            let Some(d) = exact(id, t).filter(|&d| d <= max_t) else { continue };
            if best.is_none_or(|(b, bd)| d < bd || (d == bd && id < b)) {
                best = Some((id, d));
            }
        }
        best
    }

    fn query(&self, region: &Aabb, mut found: impl FnMut(u32)) {
        for (&id, aabb) in self.ids.iter().zip(&self.boxes) {
            if aabb.overlaps(region) {
                found(id);
            }
        }
    }

    /// One node: the box around every leaf, when there are two or more (a
    /// tree of one leaf has no node above it either).
    fn visit_nodes(&self, mut visit: impl FnMut(usize, &Aabb)) {
        if let [first, rest @ ..] = self.boxes.as_slice()
            && !rest.is_empty()
        {
            visit(0, &rest.iter().fold(*first, |all, b| all.merge(b)));
        }
    }
}
