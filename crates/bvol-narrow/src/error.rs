//! Typed errors: bad shapes when they are built, bad poses and shapes when they are tested.

use std::fmt;

/// Why a [`Polyhedron`](crate::Polyhedron) could not be built, or a part
/// scaled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ShapeError {
    /// No points were given.
    Empty,
    /// The point at `index` has a NaN or infinite coordinate.
    NonFinite {
        /// Position of the offending point in the input slice.
        index: usize,
    },
    /// The point at `index` has a coordinate beyond
    /// [`MAX_COORDINATE`](bvol_volumes::MAX_COORDINATE).
    OutOfRange {
        /// Position of the offending point in the input slice.
        index: usize,
    },
    /// The points do not span a solid: one point, points on a line, a hull
    /// handed over flat, or flat points too far from the origin for their
    /// thickness ([`FLAT_THICKNESS`](crate::FLAT_THICKNESS)) to show at f32
    /// precision.
    Degenerate {
        /// Dimension of their hull: 0 (one point), 1 (a segment) or 2 (flat).
        dimension: u8,
    },
    /// A cuboid's half extents are not all finite and positive.
    BadHalfExtents,
    /// A round part (a ball, a capsule) scaled by unequal factors along its
    /// axes, which would make it another kind of solid.
    NonUniformScale,
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShapeError::Empty => write!(f, "no points to build a polyhedron from"),
            ShapeError::NonFinite { index } => {
                write!(f, "point {index} has a NaN or infinite coordinate")
            }
            ShapeError::OutOfRange { index } => write!(
                f,
                "point {index} has a coordinate beyond ±{:e}",
                bvol_volumes::MAX_COORDINATE
            ),
            ShapeError::Degenerate { dimension } => write!(
                f,
                "at f32 precision the points span {dimension} dimension(s) (points within 3 f32 epsilons of the shape's size of a line or plane count as on it), not a solid: a polyhedron needs 4 non-coplanar points (flat points are thickened, unless too far from the origin for the thickness to show)"
            ),
            ShapeError::BadHalfExtents => {
                write!(f, "cuboid half extents must be finite and greater than zero")
            }
            ShapeError::NonUniformScale => {
                write!(f, "a round part can only be scaled by one factor on every axis")
            }
        }
    }
}

impl std::error::Error for ShapeError {}

/// Which argument of a pair test an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Body {
    /// The first shape and pose.
    A,
    /// The second shape and pose.
    B,
}

impl Body {
    /// The other one.
    pub(crate) fn other(self) -> Body {
        match self {
            Body::A => Body::B,
            Body::B => Body::A,
        }
    }
}

impl fmt::Display for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Body::A => "A",
            Body::B => "B",
        })
    }
}

/// Why a pair test could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum NarrowError {
    /// The pose of `body` has a NaN or infinite component, or a zero rotation.
    NonFinitePose {
        /// The body whose pose is bad.
        body: Body,
    },
    /// The shape of `body` (a box, a sphere or a capsule) has a NaN or
    /// infinite field, or a negative half extent or radius.
    NonFiniteShape {
        /// The body whose shape is bad.
        body: Body,
    },
    /// The position of `body` has a coordinate beyond
    /// [`MAX_COORDINATE`](bvol_volumes::MAX_COORDINATE): distances from it
    /// could overflow f32.
    PoseOutOfRange {
        /// The body whose pose is bad.
        body: Body,
    },
    /// A margin ([`contact_within`](crate::contact_within)) that is negative
    /// or not finite.
    BadMargin,
    /// A reuse tolerance ([`WarmStart::reusing`](crate::WarmStart::reusing))
    /// that is negative, not finite or above
    /// [`MAX_REUSE`](crate::MAX_REUSE).
    BadTolerance,
}

impl NarrowError {
    /// The same error for the call with A and B swapped.
    pub(crate) fn swapped(self) -> NarrowError {
        match self {
            NarrowError::NonFinitePose { body } => {
                NarrowError::NonFinitePose { body: body.other() }
            }
            NarrowError::NonFiniteShape { body } => {
                NarrowError::NonFiniteShape { body: body.other() }
            }
            NarrowError::PoseOutOfRange { body } => {
                NarrowError::PoseOutOfRange { body: body.other() }
            }
            NarrowError::BadMargin => NarrowError::BadMargin,
            NarrowError::BadTolerance => NarrowError::BadTolerance,
        }
    }
}

impl fmt::Display for NarrowError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NarrowError::NonFinitePose { body } => {
                write!(f, "the pose of body {body} is not finite (or its rotation is zero)")
            }
            NarrowError::NonFiniteShape { body } => {
                write!(f, "the shape of body {body} has a non-finite field or a negative size")
            }
            NarrowError::PoseOutOfRange { body } => write!(
                f,
                "the position of body {body} has a coordinate beyond ±{:e}",
                bvol_volumes::MAX_COORDINATE
            ),
            NarrowError::BadMargin => {
                write!(f, "the margin must be finite and not negative")
            }
            NarrowError::BadTolerance => {
                write!(f, "the reuse tolerance must be finite, not negative and at most MAX_REUSE")
            }
        }
    }
}

impl std::error::Error for NarrowError {}
