//! The paths of an update, carried out in order: per-leaf moves, or the
//! refit with what comes before it (installing a finished rebuild) and
//! after it (reinserting the leaves that jumped, the rebuild's next step).
//! Which path, and what happens to jumps and rebuilds, is the policy's to
//! decide ([`crate::policy`]); the work is done by the kernels
//! ([`crate::refit`], [`crate::moves`]).

use rayon::prelude::*;

use crate::error::TreeError;
use crate::morton::Clusters;
use crate::policy::{Install, Next};
use crate::tuning::JUMPS_A_TASK;
use crate::update::UpdateStats;
use crate::{Bound, Tree};

impl<B: Bound> Tree<B> {
    /// The first update of an empty tree: one batch build over `bounds`,
    /// which are known valid. The change log carries over: ids removed
    /// since the last pair-set update must still end their pairs.
    pub(crate) fn load(&mut self, bounds: &[B]) -> Result<UpdateStats, TreeError> {
        let changes = std::mem::take(&mut self.changes);
        *self = Self::build(self.config, bounds.iter().enumerate().map(|(i, b)| (i as u32, *b)))?;
        self.changes = changes;
        self.changes.grow(bounds.len());
        self.changes.mark_all();
        Ok(UpdateStats { inserted: bounds.len(), ..UpdateStats::default() })
    }

    /// Inserts the ids of `bounds` not yet in the tree; returns how many.
    pub(crate) fn insert_new(&mut self, bounds: &[B]) -> Result<usize, TreeError> {
        // Every id below the end of the tree's id range is in it when the
        // tree holds as many leaves as that range: then none is new, and
        // the pass looking for new ones is skipped.
        let mut inserted = 0;
        if self.len != self.leaf_parents.len() || bounds.len() > self.len {
            for id in 0..bounds.len() as u32 {
                if !self.contains(id) {
                    self.insert(id, bounds[id as usize])?;
                    inserted += 1;
                }
            }
        }
        Ok(inserted)
    }

    /// The leaves already in the tree brought to `bounds[id]`, by the path
    /// the policy picks: the refit straight away, or a scan for what moved
    /// and then the refit or per-leaf moves.
    pub(crate) fn follow(&mut self, bounds: &[B], stats: &mut UpdateStats) {
        if self.policy.refit_unscanned(&self.config) {
            return self.refit_slice(bounds, stats);
        }
        let moved = self.scan(bounds);
        if self.policy.refits(&self.config, moved.len(), self.len) {
            self.refit_slice(bounds, stats);
        } else {
            self.move_each(moved.iter().map(|&id| (id, bounds[id as usize])), stats);
        }
    }

    /// The refit path, the leaves' bounds read from `bounds[id]`.
    pub(crate) fn refit_slice(&mut self, bounds: &[B], stats: &mut UpdateStats) {
        let installed = self.install_finished();
        let mut moved = std::mem::take(&mut self.moved);
        let mut jumped = std::mem::take(&mut self.jumped);
        let cost = self.refit_pass(Some(bounds), &mut moved, &mut jumped);
        stats.moved = moved.len();
        // On tasks: in a mass motion nearly every leaf jumps, and the list's
        // pages are fresh.
        let mut jumps = Vec::new();
        let each = jumped.par_iter().with_min_len(JUMPS_A_TASK);
        each.map(|&id| (id, bounds[id as usize])).collect_into_vec(&mut jumps);
        self.after_refit(&jumps, moved.iter().copied(), cost, installed, stats);
        moved.clear();
        jumped.clear();
        (self.moved, self.jumped) = (moved, jumped);
    }

    /// The refit path, the leaves that moved listed with their bounds.
    pub(crate) fn refit_listed(&mut self, moved: &[(u32, B)], stats: &mut UpdateStats) {
        let installed = self.install_finished();
        stats.moved = moved.len();
        let jumped = self.place_listed(moved, self.policy.hold_jumps());
        let cost = self.refit_pass(None, &mut Vec::new(), &mut Vec::new());
        self.after_refit(&jumped, moved.iter().map(|m| m.0), cost, installed, stats);
    }

    /// Installs the policy's finished rebuild, if any, before a refit (which
    /// gives an installed topology's nodes their bounds).
    fn install_finished(&mut self) -> Option<Install> {
        let mut install = self.policy.finish(self.len)?;
        match &mut install {
            Install::Rebuild => self.rebuild_with(Clusters::ByCode),
            Install::Topology { topology, .. } => self.install_topology(&std::mem::take(topology)),
        }
        Some(install)
    }

    /// What follows a refit of SAH `cost`: the leaves that `jumped` clear
    /// of their old bound are reinserted where they now are, or refit in
    /// place when they are many; so are the stale leaves of an install; the
    /// `moved` ids are marked for the pair set; and the rebuild takes the
    /// policy's next move.
    fn after_refit(
        &mut self,
        jumped: &[(u32, B)],
        moved: impl ExactSizeIterator<Item = u32>,
        mut cost: f64,
        installed: Option<Install>,
        stats: &mut UpdateStats,
    ) {
        stats.refit = true;
        let held = self.policy.hold_jumps();
        let mass = self.policy.mass_motion(jumped.len(), self.len);
        let stale = match &installed {
            Some(Install::Topology { stale: Some(stale), .. }) => &stale[..],
            _ => &[],
        };
        if !mass {
            self.reinsert(jumped, stale, stats);
        } else {
            if held {
                // The refit kept the jumps' old bounds: they take their new
                // ones, and the cost is measured again.
                self.place_jumped(jumped);
                cost = self.refit_pass(None, &mut Vec::new(), &mut Vec::new());
            }
            self.reinsert(&[], stale, stats);
        }
        if moved.len() * 2 > self.len {
            self.changes.mark_all();
        } else {
            moved.for_each(|id| self.changes.mark(id));
        }
        if installed.is_some() {
            stats.rebuilt = self.len;
            stats.installed = matches!(installed, Some(Install::Topology { .. }));
        }
        let next = self.policy.after_refit(
            &self.config,
            installed.as_ref(),
            jumped.len(),
            mass,
            cost,
            self.len,
        );
        match next {
            Next::Wait => {}
            Next::Step { after_mass } => {
                if self.root.is_node() {
                    let mut policy = std::mem::take(&mut self.policy);
                    policy.step(&self.leaves(), jumped.iter().map(|j| j.0), mass, after_mass);
                    self.policy = policy;
                }
            }
            Next::Rebase => {
                let cost = self.sah_cost();
                self.policy.rebase(cost);
            }
            Next::Rebuild => {
                // Mass motion: the jumps took their new bounds above, and
                // the leaves that moved are marked; the new topology moves
                // none, as an installed rebuild's does not.
                self.rebuild_with(Clusters::ByCode);
                stats.rebuilt = self.len;
            }
        }
    }
}
