//! Bodies: their handles, kinds and descriptions, and the errors of the
//! calls that name them.

use std::fmt;
use std::ops::RangeInclusive;
use std::sync::Arc;

use bvol_volumes::Pose;
use glam::Vec3;

use crate::Shape;

/// The largest magnitude a world takes for a coordinate: of a body's
/// position, of a shape's vertex in its own frame, of a primitive's size.
/// Within it every world bound, and every square and area of one, is finite
/// in f32; beyond it a body's bounds could overflow and the body would be
/// lost to the trees.
pub const MAX_COORDINATE: f32 = 1e18;

/// The squared lengths a body's rotation quaternion may have (it need not be
/// a unit one). Within them the world bounds' f32 rotation, normalised in
/// f32, is the exact rotation to a few ulps; a longer quaternion's squared
/// length overflows, and a shorter one's loses its digits, and the bounds
/// would no longer hold the shape the narrow phase tests.
pub const ROTATION_LENGTH_SQUARED: RangeInclusive<f32> = 1e-18..=1e18;

/// Whether every coordinate of `v` is at most [`MAX_COORDINATE`] in
/// magnitude (a NaN one is not): the one test of that limit, for poses,
/// shapes' points and primitives' sizes.
pub(crate) fn within_limit(v: Vec3) -> bool {
    v.abs().cmple(Vec3::splat(MAX_COORDINATE)).all()
}

/// Whether a world can place a body at `pose`: its position finite and within
/// [`MAX_COORDINATE`], its rotation's squared length within
/// [`ROTATION_LENGTH_SQUARED`] (which no NaN or infinite one is).
pub(crate) fn placeable(pose: &Pose) -> bool {
    within_limit(pose.position) && ROTATION_LENGTH_SQUARED.contains(&pose.rotation.length_squared())
}

/// A body in a [`World`](crate::World): its slot and the slot's generation,
/// so that a handle to a removed body is never taken for the body that
/// reuses its slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId {
    pub(crate) index: u32,
    pub(crate) generation: u32,
}

impl BodyId {
    /// The body's slot: dense from 0, reused after removals. Handy to index
    /// the user's own per-body arrays.
    pub fn index(self) -> u32 {
        self.index
    }
}

impl fmt::Display for BodyId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "body {} (generation {})", self.index, self.generation)
    }
}

/// How a body takes part in collision detection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BodyKind {
    /// Moves: tested against every other body.
    #[default]
    Dynamic,
    /// Never moves (floors, walls): tested against dynamic bodies only.
    Static,
    /// At rest for now: kept with the static bodies, so tested against
    /// dynamic bodies only, until set dynamic again.
    Sleeping,
}

/// What a new body is: its shape (shared), pose, kind, the user's data, and
/// its collision filter.
///
/// Two bodies are tested only when each one's `layers` meets the other's
/// `mask` (Box2D's category and mask bits).
#[derive(Clone, Debug)]
pub struct BodyDesc {
    /// The geometry, in the body's frame.
    pub shape: Arc<Shape>,
    /// Where the body is.
    pub pose: Pose,
    /// How it takes part.
    pub kind: BodyKind,
    /// Anything the user wants back with the body's events and ray hits.
    pub user_data: u64,
    /// The layers the body is on. Default: layer 0 (bit 1).
    pub layers: u32,
    /// The layers it collides with. Default: all.
    pub mask: u32,
}

impl BodyDesc {
    /// A dynamic body of `shape` at `pose`, on layer 0, colliding with all.
    pub fn new(shape: Arc<Shape>, pose: Pose) -> Self {
        BodyDesc { shape, pose, kind: BodyKind::Dynamic, user_data: 0, layers: 1, mask: u32::MAX }
    }

    /// The same, of another kind.
    pub fn with_kind(self, kind: BodyKind) -> Self {
        BodyDesc { kind, ..self }
    }

    /// The same, carrying `user_data`.
    pub fn with_user_data(self, user_data: u64) -> Self {
        BodyDesc { user_data, ..self }
    }

    /// The same, on `layers`, colliding with `mask`.
    pub fn with_filter(self, layers: u32, mask: u32) -> Self {
        BodyDesc { layers, mask, ..self }
    }
}

/// A call on a [`World`](crate::World) that could not be done; the world is
/// left as it was.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum WorldError {
    /// The body was removed, or never was in this world.
    UnknownBody(BodyId),
    /// A pose a world cannot place a body at: a position that is not finite
    /// or beyond [`MAX_COORDINATE`], or a rotation whose squared length is
    /// not within [`ROTATION_LENGTH_SQUARED`] (a NaN, infinite or zero one
    /// among them).
    BadPose {
        /// The body it was for (its slot when it was being added).
        body: BodyId,
        /// The pose.
        pose: Pose,
    },
    /// `set_poses` was given different numbers of bodies and poses.
    LengthMismatch {
        /// Number of bodies.
        bodies: usize,
        /// Number of poses.
        poses: usize,
    },
    /// The world holds as many bodies as a tree can name.
    Full,
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorldError::UnknownBody(id) => write!(f, "{id}: no such body in this world"),
            WorldError::BadPose { body, pose } => {
                write!(
                    f,
                    "{body}: pose {pose:?} has a position that is not finite or beyond \
                     ±{MAX_COORDINATE:e}, or a rotation of squared length outside \
                     {ROTATION_LENGTH_SQUARED:?}"
                )
            }
            WorldError::LengthMismatch { bodies, poses } => {
                write!(f, "set_poses: {bodies} bodies but {poses} poses")
            }
            WorldError::Full => write!(f, "the world is full: too many bodies"),
        }
    }
}

impl std::error::Error for WorldError {}
