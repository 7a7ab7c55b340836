//! What a world's update reports of each pair of bodies that touch or did.

use bvol_narrow::Contact;

use crate::BodyId;

/// What happened to a pair in contact: touching, or, in a world with a
/// [`margin`](crate::WorldConfig::margin), apart by at most the margin.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// It is in contact now and was not last frame.
    Began,
    /// It was in contact last frame and still is.
    Persisting,
    /// It was in contact last frame and is not now (or a body was removed).
    Ended,
}

/// A contact event: the two bodies (`a` before `b` by slot) with their user
/// data, and, unless it ended, how they touch, the normal pointing from `a`
/// to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent {
    /// What happened.
    pub kind: EventKind,
    /// The body with the lower slot.
    pub a: BodyId,
    /// The other body.
    pub b: BodyId,
    /// `a`'s user data (see [`BodyDesc::with_user_data`](crate::BodyDesc::with_user_data)).
    pub user_data_a: u64,
    /// `b`'s user data: for a body removed since, the value it had.
    pub user_data_b: u64,
    /// The contact: `None` for an ended pair.
    pub contact: Option<Contact>,
}

impl ContactEvent {
    /// The slots of its bodies: the key a frame's events are sorted by.
    pub(crate) fn slots(&self) -> (u32, u32) {
        (self.a.index, self.b.index)
    }
}

/// The contact of bodies `a` and `b` (`a` in the lower slot) among `events`,
/// sorted by slots and starting at the first whose slots are not below
/// theirs: that of these very bodies, as a removed body's slot may be held
/// by another since.
pub(crate) fn contact_of(events: &[ContactEvent], a: BodyId, b: BodyId) -> Option<Contact> {
    let key = (a.index, b.index);
    let theirs = events.iter().take_while(|e| e.slots() == key);
    theirs.filter(|e| e.a == a && e.b == b).find_map(|e| e.contact)
}
