//! Bodies: their handles, kinds and descriptions, and the errors of the
//! calls that name them.

use std::fmt;
use std::sync::Arc;

use bvol_volumes::Pose;

use crate::Shape;
use crate::limits::{MAX_COORDINATE, ROTATION_LENGTH_SQUARED};

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

    /// The handle as one number, the generation in the high 32 bits and
    /// the slot in the low: for keeping handles where only integers fit
    /// (another language's objects, a file, a numpy array).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::{BodyDesc, BodyId, Shape, World, volumes::Pose};
    ///
    /// let mut world = World::new();
    /// let ball = Arc::new(Shape::ball(1.0)?);
    /// let id = world.add_body(BodyDesc::new(ball, Pose::IDENTITY))?;
    /// assert_eq!(BodyId::from_bits(id.to_bits()), id);
    /// world.remove_body(id)?;
    /// assert!(world.pose(BodyId::from_bits(id.to_bits())).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn to_bits(self) -> u64 {
        (u64::from(self.generation) << 32) | u64::from(self.index)
    }

    /// The handle [`to_bits`](Self::to_bits) gave. Any number makes a
    /// handle: one no world gave names no body, and a world's calls answer
    /// it with [`WorldError::UnknownBody`].
    pub fn from_bits(bits: u64) -> BodyId {
        BodyId { index: bits as u32, generation: (bits >> 32) as u32 }
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
    /// A [`WorldConfig`](crate::WorldConfig) asked for a thread pool of no
    /// threads or more than [`MAX_THREADS`](crate::WorldConfig::MAX_THREADS),
    /// or one the system could not start.
    BadThreads {
        /// The number of threads asked for.
        threads: usize,
    },
    /// A [`WorldConfig`](crate::WorldConfig) asked for a margin that is
    /// negative, not finite or beyond [`MAX_COORDINATE`].
    BadMargin {
        /// The margin asked for.
        margin: f32,
    },
    /// A [`WorldConfig`](crate::WorldConfig) asked for a reuse tolerance
    /// that is negative, not finite or above
    /// [`MAX_REUSE`](crate::narrow::MAX_REUSE).
    BadReuse {
        /// The tolerance asked for.
        reuse: f32,
    },
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
            WorldError::BadThreads { threads } => write!(
                f,
                "WorldConfig::threads: a pool of {threads} threads could not be started \
                 (from 1 to {} are allowed)",
                crate::WorldConfig::MAX_THREADS
            ),
            WorldError::BadMargin { margin } => write!(
                f,
                "WorldConfig::margin: {margin} is not a distance from 0 to {MAX_COORDINATE:e}"
            ),
            WorldError::BadReuse { reuse } => write!(
                f,
                "WorldConfig::reuse: {reuse} is not a tolerance from 0 to {:e}",
                crate::narrow::MAX_REUSE
            ),
        }
    }
}

impl std::error::Error for WorldError {}
