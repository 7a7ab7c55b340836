//! The counts and times of a world update's stages.

use std::time::Duration;

/// Pairs let through by each stage of a frame, and the time each took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Bodies whose world bounds were placed anew (those that moved or were
    /// added).
    pub moved: usize,
    /// Pairs whose leaf boxes overlap in the broadphase (layer filtering
    /// included).
    pub candidates: usize,
    /// Of those, pairs whose world spheres overlap.
    pub after_spheres: usize,
    /// Of those, pairs whose world OBBs overlap.
    pub after_obbs: usize,
    /// Of those, pairs whose shapes touch.
    pub touching: usize,
    /// Of those, pairs whose shapes are apart within the world's
    /// [`margin`](crate::WorldConfig::margin): 0 without one.
    pub near: usize,
    /// Time to place the world bounds of the bodies that moved.
    pub bounds_time: Duration,
    /// Time of the broadphase: its upkeep and the pair search.
    pub broadphase_time: Duration,
    /// Time of the sphere test.
    pub spheres_time: Duration,
    /// Time of the OBB test.
    pub obbs_time: Duration,
    /// Time of the narrow phase and the contact events (the pairs' sort by
    /// slot that matches them with last frame's included).
    pub narrow_time: Duration,
}

impl FrameStats {
    /// The whole frame's time.
    pub fn total_time(&self) -> Duration {
        self.bounds_time
            + self.broadphase_time
            + self.spheres_time
            + self.obbs_time
            + self.narrow_time
    }
}
