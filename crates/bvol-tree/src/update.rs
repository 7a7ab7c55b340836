//! The frame update, the tree's public face for a moving scene: a frame's
//! bounds handed over whole ([`Tree::update`], [`Tree::update_from`]) or as
//! the list of those that moved ([`Tree::update_moved`]), and the plain
//! refit ([`Tree::refit`]). Each checks its input and follows the policy's
//! path ([`crate::paths`]).

use crate::awake::awake;
use crate::check::{check_held, check_listed, check_slice};
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
    /// Brings the tree up to date with one frame: `bounds[id]` is the bound
    /// of leaf `id` (ids `0..bounds.len()`; ids not yet in the tree are
    /// inserted, ids beyond the slice are left alone). The tree finds what
    /// moved itself.
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
    /// a whole rebuild ([`UpdateStats::installed`] marks the frame that
    /// installs it). When more than one leaf in 16 jumps clear of its bound
    /// in one frame (bodies falling faster than their size), the jumps are
    /// refit where they land, like any move, and left to the staged
    /// rebuilds; bodies so fast that the SAH cost outruns those (four times
    /// the drift above the last build's) have the tree rebuilt in one go,
    /// and no staged rebuild begins that such a rebuild would overtake. A
    /// steady trickle of jumps (teleports) so frequent that a rebuild
    /// staged a phase a frame would find one leaf in 16 placed where it was
    /// has it staged three phases a frame, installed at the start of the
    /// third refit; only a trickle so heavy that even this one would (about
    /// one leaf in 50 a frame) rebuilds the tree in one go.
    ///
    /// Every bound is checked first: on error nothing has changed.
    pub fn update(&mut self, bounds: &[B]) -> Result<UpdateStats, TreeError> {
        awake(|| {
            check_slice(bounds)?;
            if self.is_empty() {
                return self.load(bounds);
            }
            let mut stats = UpdateStats::default();
            self.follow(bounds, &mut stats);
            stats.inserted = self.insert_new(bounds)?;
            self.policy.record(stats.moved, self.len);
            Ok(stats)
        })
    }

    /// Brings the leaves already in the tree up to date with one frame, as
    /// [`Tree::update`] does, reading `bounds[id]` for the ids in the tree
    /// alone and inserting none: for a caller whose slice also holds ids
    /// kept elsewhere (a world's resting bodies, in a second tree). Ids in
    /// the tree at or past the slice's end are left alone. Where most leaves
    /// moved, this refits from the slice in the tree's own order, in
    /// parallel subtrees, where [`Tree::update_moved`], handed a list,
    /// places each moved leaf in turn, wherever its parent lies, on the
    /// calling thread.
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
        awake(|| {
            check_held(bounds, |id| self.contains(id))?;
            let mut stats = UpdateStats::default();
            if !self.is_empty() {
                self.follow(bounds, &mut stats);
            }
            self.policy.record(stats.moved, self.len);
            Ok(stats)
        })
    }

    /// Brings the tree up to date with the leaves that moved: `moved[k]` is
    /// `(id, new bound)`, every id in the tree. For a caller that knows what
    /// moved (a world whose tree holds only some of its bodies): the same
    /// choice as [`Tree::update`] between per-leaf updates and one refit, by
    /// the fraction moved, without reading the bounds of leaves that did not.
    ///
    /// Every id and bound is checked first: on error nothing has changed.
    pub fn update_moved(&mut self, moved: &[(u32, B)]) -> Result<UpdateStats, TreeError> {
        check_listed(moved, |id| self.contains(id))?;
        let mut stats = UpdateStats::default();
        if self.policy.refits(&self.config, moved.len(), self.len) {
            // Keepers for the refit's passes; per-leaf moves run on this thread.
            awake(|| self.refit_listed(moved, &mut stats));
        } else {
            self.move_each(moved.iter().copied(), &mut stats);
        }
        self.policy.record(stats.moved, self.len);
        Ok(stats)
    }

    /// Refits every internal node bottom-up to the exact merge of its
    /// children's bounds (tightening every fat margin), in one pass.
    pub fn refit(&mut self) {
        self.refit_pass(None, &mut Vec::new(), &mut Vec::new());
    }
}
