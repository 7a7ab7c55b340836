//! The bodies of a world, one slot each, in structure-of-arrays form: each
//! stage of a frame reads only the arrays it needs.

use std::sync::Arc;

use bvol_narrow::Contact;
use bvol_volumes::{Aabb, Obb, Pose, Sphere};
use glam::DVec3;

use crate::event::{ContactEvent, EventKind};
use crate::{BodyId, BodyKind, Shape};

/// How many bodies ahead the placing of world bounds asks for the slots it
/// will read and write, and `World::set_poses` for the pose slots it will
/// write: seven arrays in step are more streams than the processor's own
/// prefetcher follows (the figures are in docs/performance.md).
pub(crate) const BODIES_AHEAD: usize = 16;

/// The bodies, one slot each, in structure-of-arrays form: each stage of a
/// frame reads only the arrays it needs.
#[derive(Debug, Default)]
pub(crate) struct Bodies {
    pub(crate) shapes: Vec<Option<Arc<Shape>>>,
    pub(crate) generations: Vec<u32>,
    /// Poses as the narrow phase and the bounds read them: positions
    /// rounded to f32.
    pub(crate) poses: Vec<Pose>,
    /// Positions as given, in f64, kept once `far` (until then each is its
    /// pose's, and the poses alone are written: see [`Bodies::position`]).
    pub(crate) positions: Vec<DVec3>,
    /// Whether some position given was not an f32's: then bounds grow by
    /// their positions' rounding, and pairs are tested on positions
    /// relative to the first body's.
    pub(crate) far: bool,
    pub(crate) kinds: Vec<BodyKind>,
    pub(crate) user_data: Vec<u64>,
    pub(crate) layers: Vec<u32>,
    pub(crate) masks: Vec<u32>,
    /// World bounding spheres: 16 bytes a body, one load each for the
    /// sphere test.
    pub(crate) spheres: Vec<Sphere>,
    /// World oriented boxes.
    pub(crate) obbs: Vec<Obb>,
    /// Broadphase leaf boxes, from the world sphere and OBB.
    pub(crate) leaves: Vec<Aabb>,
    /// Free slots, the last freed taken first.
    pub(crate) free: Vec<u32>,
    /// Slots whose pose changed since the last update, each once.
    pub(crate) dirty: Vec<u32>,
    pub(crate) is_dirty: Vec<bool>,
    /// Whether a body was removed since the last update: `dirty` may then
    /// hold slots that are free.
    pub(crate) removed: bool,
    pub(crate) count: usize,
    /// Live bodies whose filter can turn a pair away (see `filters`).
    pub(crate) filtering: usize,
}

impl Bodies {
    /// One more slot, empty.
    pub(crate) fn grow(&mut self) {
        self.shapes.push(None);
        self.generations.push(0);
        self.poses.push(Pose::IDENTITY);
        self.positions.push(DVec3::ZERO);
        self.kinds.push(BodyKind::Dynamic);
        self.user_data.push(0);
        self.layers.push(0);
        self.masks.push(0);
        self.spheres.push(Sphere::default());
        self.obbs.push(Obb::default());
        self.leaves.push(Aabb::default());
        self.is_dirty.push(false);
    }

    /// Whether the body in `slot` can turn a pair away by its filter: it
    /// meets every body only when it is on some layer and collides with all.
    pub(crate) fn filters(&self, slot: u32) -> bool {
        let i = slot as usize;
        self.layers[i] == 0 || self.masks[i] != u32::MAX
    }

    /// The position of the body in `slot`, as given.
    pub(crate) fn position(&self, slot: usize) -> DVec3 {
        if self.far { self.positions[slot] } else { self.poses[slot].position.as_dvec3() }
    }

    /// Moves the body in `slot` to `pose`, its position as given being
    /// `position` (the pose's own, or one that rounds to it), and queues it
    /// to be placed, unless neither changed: a pose handed over unchanged
    /// moves nothing, so the body's bounds stay placed and its pairs with
    /// bodies also unmoved keep their answers untested.
    #[inline]
    pub(crate) fn move_to(&mut self, slot: usize, pose: Pose, position: DVec3) {
        if self.poses[slot] != pose || (self.far && self.positions[slot] != position) {
            self.poses[slot] = pose;
            if self.far {
                self.positions[slot] = position;
            }
            self.mark_dirty(slot as u32);
        }
    }

    /// Keeps the positions in f64 from now on, each its pose's so far.
    pub(crate) fn go_far(&mut self) {
        if !std::mem::replace(&mut self.far, true) {
            for (position, pose) in self.positions.iter_mut().zip(&self.poses) {
                *position = pose.position.as_dvec3();
            }
        }
    }

    /// Queues a slot for the next update's placing of world bounds.
    pub(crate) fn mark_dirty(&mut self, slot: u32) {
        if !std::mem::replace(&mut self.is_dirty[slot as usize], true) {
            self.dirty.push(slot);
        }
    }

    /// Whether the world spheres of two bodies overlap or touch. In f32,
    /// with the sum of radii padded by a few roundings so that no touching
    /// pair is lost.
    #[inline]
    pub(crate) fn spheres_overlap(&self, a: usize, b: usize) -> bool {
        let (a, b) = (&self.spheres[a], &self.spheres[b]);
        let d = a.center - b.center;
        let r = (a.radius + b.radius) * (1.0 + 4.0 * f32::EPSILON);
        d.length_squared() <= r * r
    }

    /// The end of the contact of the bodies in slots `a` and `b`.
    pub(crate) fn ended(&self, a: u32, b: u32) -> ContactEvent {
        self.event(EventKind::Ended, a, b, None)
    }

    /// The event of kind `kind` of the bodies in slots `a` and `b`, with
    /// their handles and user data now.
    pub(crate) fn event(
        &self,
        kind: EventKind,
        a: u32,
        b: u32,
        contact: Option<Contact>,
    ) -> ContactEvent {
        let (user_data_a, user_data_b) = (self.user_data[a as usize], self.user_data[b as usize]);
        ContactEvent { kind, a: self.id_of(a), b: self.id_of(b), user_data_a, user_data_b, contact }
    }

    /// The handle of the body in `slot` now.
    pub(crate) fn id_of(&self, slot: u32) -> BodyId {
        BodyId { index: slot, generation: self.generations[slot as usize] }
    }
}
