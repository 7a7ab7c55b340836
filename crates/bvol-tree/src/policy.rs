//! The update policy: one state machine deciding, frame by frame, how the
//! tree follows its leaves. [`Policy`] holds all of its state; its methods
//! are the transitions, and the tree carries out what they decide
//! ([`crate::paths`]).
//!
//! - **Path.** Few leaves moved ([`Config::refit_fraction`]): each moved
//!   leaf is updated on its own, then the bounded upkeep
//!   ([`Tree::optimize`](crate::Tree::optimize)) runs. Many: the whole tree
//!   is refit bottom-up in one pass. The fraction the last update moved
//!   predicts this frame's, so the refit path skips the scan for what moved.
//! - **Jumps.** A leaf whose new bound does not overlap its old one jumped
//!   (a teleport): refit in place, it would stretch its ancestors across
//!   the gap, so it keeps its old bound through the refit and is reinserted
//!   where it now is. When more than one leaf in [`MANY_JUMPS`] jumps in
//!   one frame (mass motion: bodies falling faster than their size), they
//!   are refit in place instead, and left to the rebuilds; the next frame
//!   expects the same and does not hold them.
//! - **Staged rebuild.** When the refit finds the SAH cost drifted
//!   ([`Config::drift`], from [`DRIFT_STAGED`] of it on), the tree is
//!   rebuilt a step a frame ([`crate::staged`]), and the topology is
//!   installed by the refit of the last of its [`STAGED_FRAMES`] frames: no
//!   frame pays for a whole rebuild. Its clusters are built by binned SAH
//!   ([`Clusters::BySah`]), as a load's are. The topology places the leaves
//!   where they were a few frames before: those that jumped meanwhile are
//!   noted as stale, left out of their cluster's bound, and reinserted once
//!   it is installed.
//! - **Trickle.** Where jumps come in a steady trickle, so many that a build
//!   taking a step a frame would find more than one leaf in [`MANY_JUMPS`]
//!   stale, the build starts at the full drift and takes [`TRICKLE_PACE`]
//!   steps a frame, its clusters split by code ([`Clusters::ByCode`]) in
//!   one step: built in two frames, it finds fewer leaves stale.
//! - **One go.** Only if one leaf in [`MANY_JUMPS`] is stale even so is the
//!   tree rebuilt in one go, in place of the install. A rebuild in one go
//!   splits its clusters by code, in half the time of SAH clusters: the
//!   leaves' motion spoils its tree within frames.
//! - **Outrun.** When mass motion stretches the tree so far that its cost
//!   is [`DRIFT_AT_ONCE`] drifts above the last build's, it is rebuilt in
//!   one go at once: bodies moving several times their size a frame would
//!   outrun any staged build. Nor does a staged build begin in mass motion
//!   when the cost, growing as it grew since the last refit, would get
//!   there before the build lands: its steps would be thrown away.
//! - **Mass motion during a build.** Its jumps are not noted: the topology
//!   is installed as it is, its cost is no baseline, and the next build
//!   starts at once; so does one more if leaves still jump during that one
//!   (the bodies were settling while it was built).
//!
//! Inserting or removing a leaf drops a staged build: its topology would no
//! longer hold exactly the tree's leaves.

use crate::Bound;
use crate::config::Config;
use crate::leaves::Leaves;
use crate::morton::Clusters;
use crate::node::Ref;
use crate::staged::{STAGED_FRAMES, Staged};
use crate::tuning::{DRIFT_AT_ONCE, DRIFT_STAGED, MANY_JUMPS, TRICKLE_PACE};

/// The update policy's state (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Policy<B: Bound> {
    /// SAH cost right after the last whole build: what the drift is
    /// measured from.
    built_cost: f64,
    /// SAH cost after the last refit (or whole build): how fast the cost
    /// drifts is told from it.
    last_cost: f64,
    /// Fraction of leaves the last update found moved.
    moved_fraction: f32,
    /// Whether the last refit found many leaves jumped.
    mass_motion: bool,
    /// The rebuild staged over frames, while one runs.
    staged: Option<Box<Rebuild<B>>>,
}

/// A rebuild staged over frames, and what happened while it ran.
#[derive(Clone, Debug)]
struct Rebuild<B: Bound> {
    /// The build.
    build: Staged<B>,
    /// Steps taken a frame.
    pace: usize,
    /// Ids that jumped clear of their bound since the build began, in
    /// frames without mass motion.
    stale: Vec<u32>,
    /// Whether a frame of mass motion passed since the build began.
    mass: bool,
    /// Whether it began at the install of one that saw mass motion.
    after_mass: bool,
}

/// What a frame's refit installs before it runs.
pub(crate) enum Install {
    /// The tree rebuilt in one go: too many leaves jumped while the staged
    /// build ran to reinsert them all.
    Rebuild,
    /// The staged build's topology: each internal node's children, in
    /// preorder from the root at node 0. `stale` jumped while it was built,
    /// and are placed where they were: `None` when a frame of mass motion
    /// passed meanwhile. `after_mass` when it began at the install of one
    /// that did.
    Topology { topology: Vec<[Ref; 2]>, stale: Option<Vec<u32>>, after_mass: bool },
}

/// What the tree does about its rebuild once a refit's leaves are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Next {
    /// Nothing.
    Wait,
    /// The staged build's steps for this frame ([`Policy::step`]).
    Step {
        /// A build started by this step began at the install of one that
        /// saw mass motion.
        after_mass: bool,
    },
    /// The tree's SAH cost as it is now is the new baseline
    /// ([`Policy::rebase`]).
    Rebase,
    /// The tree is rebuilt in one go now: mass motion outran the builds
    /// ([`DRIFT_AT_ONCE`]).
    Rebuild,
}

impl<B: Bound> Policy<B> {
    /// Whether this frame refits without first scanning for what moved:
    /// while a staged build runs (the refit advances it), or when the last
    /// update moved enough leaves.
    pub(crate) fn refit_unscanned(&self, config: &Config) -> bool {
        self.staged.is_some() || self.moved_fraction >= config.refit_fraction
    }

    /// Whether a frame in which `moved` of `len` leaves moved refits.
    pub(crate) fn refits(&self, config: &Config, moved: usize, len: usize) -> bool {
        moved as f32 >= config.refit_fraction * len as f32
    }

    /// Records that an update moved `moved` of `len` leaves.
    pub(crate) fn record(&mut self, moved: usize, len: usize) {
        self.moved_fraction = moved as f32 / len.max(1) as f32;
    }

    /// Whether a refit keeps the old bound of the leaves that jumped, to
    /// reinsert them after: not when the last frame had many jumps, which
    /// are then expected again and refit in place (reinserted instead,
    /// after the refit, if they turn out few).
    pub(crate) fn hold_jumps(&self) -> bool {
        !self.mass_motion
    }

    /// Records that a refit found `jumps` of `len` leaves jumped, and
    /// returns whether that is mass motion.
    pub(crate) fn mass_motion(&mut self, jumps: usize, len: usize) -> bool {
        self.mass_motion = jumps * MANY_JUMPS > len;
        self.mass_motion
    }

    /// Notes that leaf `id` jumped and was reinserted: a staged topology
    /// places it where it was.
    pub(crate) fn note_jump(&mut self, id: u32) {
        if let Some(staged) = &mut self.staged {
            staged.stale.push(id);
        }
    }

    /// Drops the staged build: a leaf was inserted or removed.
    pub(crate) fn drop_staged(&mut self) {
        self.staged = None;
    }

    /// Records a whole build of SAH cost `cost`: the baseline of the drift.
    pub(crate) fn rebuilt(&mut self, cost: f64) {
        self.staged = None;
        self.built_cost = cost;
        self.last_cost = cost;
    }

    /// Takes the staged build if it is finished: its topology to install,
    /// or a rebuild in one go when so many of the `len` leaves jumped while
    /// it ran that reinserting them would cost more than the staging saved.
    pub(crate) fn finish(&mut self, len: usize) -> Option<Install> {
        if !self.staged.as_ref()?.build.is_ready() {
            return None;
        }
        let staged = self.staged.take()?;
        let mut stale = staged.stale;
        stale.sort_unstable();
        stale.dedup();
        if !staged.mass && stale.len() * MANY_JUMPS > len {
            return Some(Install::Rebuild);
        }
        Some(Install::Topology {
            topology: staged.build.into_topology(),
            stale: (!staged.mass).then_some(stale),
            after_mass: staged.after_mass,
        })
    }

    /// The rebuild's move after a refit of `cost` over `len` leaves, of
    /// which `jumps` jumped (`mass`: many), that followed `installed`.
    ///
    /// After an install the refit's cost is the new baseline, unless the
    /// topology was out of date as it landed: when mass motion went on
    /// while it was built, the next build starts at once, and so does one
    /// more when the first build after mass motion still saw leaves jump
    /// (the bodies were settling, as a pile compacting, and its topology
    /// does not place those that moved less than their size); and when it
    /// placed stale leaves, the refit measured them stretched across their
    /// gaps, a baseline that would put the next rebuild off (among a
    /// trickle of teleports, for good): the cost after their reinsertion is
    /// taken instead. Otherwise a running build takes its steps, and one
    /// starts when the cost has drifted.
    pub(crate) fn after_refit(
        &mut self,
        config: &Config,
        installed: Option<&Install>,
        jumps: usize,
        mass: bool,
        cost: f64,
        len: usize,
    ) -> Next {
        // The cost `share` drifts above the last build's.
        let drift_at = |share: f64| self.built_cost * (1.0 + config.drift * share);
        let drifted = |share: f64| cost > drift_at(share);
        let growth = cost - std::mem::replace(&mut self.last_cost, cost);
        if mass && drifted(DRIFT_AT_ONCE) {
            return Next::Rebuild;
        }
        // Mass motion drifting so fast that a build begun now would be
        // dropped for a rebuild in one go before it lands: its steps would
        // be wasted.
        let outrun = mass && cost + growth * STAGED_FRAMES as f64 > drift_at(DRIFT_AT_ONCE);
        match installed {
            Some(Install::Rebuild) => Next::Wait,
            Some(Install::Topology { stale: None, .. }) => Next::Step { after_mass: true },
            Some(Install::Topology { stale: Some(stale), after_mass, .. }) => {
                if *after_mass && !stale.is_empty() {
                    Next::Step { after_mass: false }
                } else if stale.is_empty() {
                    self.built_cost = cost;
                    Next::Wait
                } else {
                    Next::Rebase
                }
            }
            None if self.staged.is_some() => Next::Step { after_mass: false },
            None if !mass && jumps * STAGED_FRAMES * MANY_JUMPS > len => {
                // A trickle: see the module docs. It starts at the full
                // drift, and lands soon after.
                if !drifted(1.0) {
                    return Next::Wait;
                }
                self.staged = Some(Box::new(Rebuild::new(TRICKLE_PACE, Clusters::ByCode, false)));
                Next::Step { after_mass: false }
            }
            None if drifted(DRIFT_STAGED) && !outrun => Next::Step { after_mass: false },
            None => Next::Wait,
        }
    }

    /// Takes the tree's SAH cost `cost` as the baseline of the drift.
    pub(crate) fn rebase(&mut self, cost: f64) {
        self.built_cost = cost;
    }

    /// The staged build's steps for this frame over `leaves`, noting the
    /// leaves that `jumped`, or that it was a frame of `mass` motion;
    /// starts a build first if none runs (`after_mass` when an install
    /// that saw mass motion starts it).
    pub(crate) fn step(
        &mut self,
        leaves: &Leaves<'_, B>,
        jumped: impl Iterator<Item = u32>,
        mass: bool,
        after_mass: bool,
    ) {
        let mut staged = self
            .staged
            .take()
            .unwrap_or_else(|| Box::new(Rebuild::new(1, Clusters::BySah, after_mass)));
        if mass {
            staged.mass = true;
        } else {
            jumped.for_each(|id| staged.stale.push(id));
        }
        for _ in 0..staged.pace {
            staged.build.advance(leaves, &staged.stale);
        }
        self.staged = Some(staged);
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.staged.as_ref().map_or(0, |s| s.build.memory_bytes() + s.stale.capacity() * 4)
    }
}

impl<B: Bound> Rebuild<B> {
    /// A build, not begun, taking `pace` steps a frame, its clusters built
    /// as `finish` says.
    fn new(pace: usize, finish: Clusters, after_mass: bool) -> Self {
        Rebuild { build: Staged::new(finish), pace, stale: Vec::new(), mass: false, after_mass }
    }
}

#[cfg(test)]
mod tests {
    use bvol_volumes::Aabb;

    use super::*;

    /// The first move other than waiting that the policy makes over frames
    /// whose refit finds the SAH cost `step` higher each frame than the
    /// last, from a whole build of cost 1, in mass motion or not.
    fn first_move(step: f64, mass: bool) -> Next {
        let config = Config::default();
        let mut policy = Policy::<Aabb>::default();
        policy.rebuilt(1.0);
        (1..1000)
            .map(|frame| {
                policy.after_refit(&config, None, 0, mass, 1.0 + step * frame as f64, 1000)
            })
            .find(|next| *next != Next::Wait)
            .unwrap()
    }

    #[test]
    fn mass_motion_begins_no_staged_build_a_rebuild_would_overtake() {
        // A staged build begins once the cost drifted DRIFT_STAGED drifts
        // and lands STAGED_FRAMES frames later; a rebuild in one go comes
        // past DRIFT_AT_ONCE drifts. Growing by `edge` a frame, the cost
        // gets from the one to the other in those frames.
        let drift = Config::default().drift;
        let edge = drift * (DRIFT_AT_ONCE - DRIFT_STAGED) / STAGED_FRAMES as f64;
        let (slow, fast) = (edge / 2.0, edge * 2.0);
        assert_eq!(first_move(slow, true), Next::Step { after_mass: false });
        assert_eq!(first_move(fast, true), Next::Rebuild);
        // Without mass motion no rebuild comes in one go: a build begins.
        assert_eq!(first_move(fast, false), Next::Step { after_mass: false });
    }
}
