//! The buffers of a frame's lists, kept from frame to frame.

use bvol_volumes::Aabb;

use crate::event::ContactEvent;
use crate::narrow_phase::PairStates;

/// Buffers that one frame fills and the next refills: their contents are
/// never read across frames (but for `events`, last frame's events). A frame of many bodies fills tens of MB of
/// them, and fresh pages would cost a page fault each, every frame.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    /// The moved bodies' leaves: moved and new, of each broadphase.
    pub(crate) leaves: [Vec<(u32, Aabb)>; 4],
    /// The broadphases' overlapping pairs that the filters allow, in their
    /// order.
    pub(crate) found: Vec<(u32, u32)>,
    /// Those whose spheres overlap.
    pub(crate) near: Vec<(u32, u32)>,
    /// Those whose OBBs overlap too.
    pub(crate) nearer: Vec<(u32, u32)>,
    /// The counting sort's slot starts.
    pub(crate) starts: Vec<u32>,
    /// Those sorted.
    pub(crate) sorted: Vec<(u32, u32)>,
    /// The pair states' other buffer: the narrow phase moves last frame's
    /// states into it, and keeps last frame's, emptied, for the next.
    pub(crate) states: PairStates,
    /// The narrow phase's events of each run of pairs, on several threads.
    pub(crate) runs: Vec<Vec<ContactEvent>>,
    /// The events' other buffer: a frame writes its events here while it
    /// reads last frame's (the contacts of the pairs it keeps untested),
    /// then swaps the two.
    pub(crate) events: Vec<ContactEvent>,
    /// The bodies placed this update, a bit a slot.
    pub(crate) placed: Vec<u64>,
}
