//! Typed errors for fitting and parsing.

use std::fmt;

use glam::Vec3;

/// Why a bound could not be fitted to a point set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitError {
    /// The point set is empty: there is nothing to bound.
    Empty,
    /// The point at `index` has a NaN or infinite coordinate.
    NonFinite {
        /// Position of the offending point in the input slice.
        index: usize,
    },
    /// The point at `index` has a coordinate beyond [`MAX_COORDINATE`].
    OutOfRange {
        /// Position of the offending point in the input slice.
        index: usize,
    },
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::Empty => write!(f, "no points to bound"),
            FitError::NonFinite { index } => {
                write!(f, "point {index} has a NaN or infinite coordinate")
            }
            FitError::OutOfRange { index } => {
                write!(f, "point {index} has a coordinate beyond ±{MAX_COORDINATE:e}")
            }
        }
    }
}

impl std::error::Error for FitError {}

/// Why [`ConvexHull::from_parts`](crate::ConvexHull::from_parts) refused its
/// parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HullError {
    /// Vertex `index` is not finite or beyond [`MAX_COORDINATE`].
    BadVertex {
        /// Its index.
        index: usize,
    },
    /// Fewer than four faces, or not one normal and offset a face.
    FaceCount {
        /// How many faces were given.
        faces: usize,
    },
    /// Face `face` has fewer than three vertices, an index out of range, a
    /// normal that is not unit or an offset that is not finite.
    BadFace {
        /// Its index.
        face: usize,
    },
    /// A vertex of face `face` is off its plane, or some vertex in front of
    /// it, by more than the tolerance.
    NotConvex {
        /// Its index.
        face: usize,
    },
    /// The tolerance is negative or not finite.
    BadTolerance,
}

impl fmt::Display for HullError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HullError::BadVertex { index } => write!(
                f,
                "hull vertex {index} is not finite or has a coordinate beyond ±{MAX_COORDINATE:e}"
            ),
            HullError::FaceCount { faces } => write!(
                f,
                "a solid hull needs at least four faces, each with a normal and an offset; got {faces} faces"
            ),
            HullError::BadFace { face } => write!(
                f,
                "hull face {face} has under three vertices, an index out of range, a normal that \
                 is not unit or an offset that is not finite"
            ),
            HullError::NotConvex { face } => write!(
                f,
                "hull face {face}: a vertex lies off its plane or in front of it by more than the tolerance"
            ),
            HullError::BadTolerance => write!(f, "the hull's tolerance is negative or not finite"),
        }
    }
}

impl std::error::Error for HullError {}

/// The largest magnitude bvol takes for a coordinate: of a point to fit, of
/// a body's position, of a shape's vertex in its own frame, of a primitive's
/// size. Within it every bound, and every square and area of one, is finite
/// in f32 (a radius fitted to points near 3e38 overflowed); beyond it a
/// body's bounds could overflow and the body would be lost to the trees.
pub const MAX_COORDINATE: f32 = 1e18;

/// Checks a point set before fitting: not empty, every coordinate finite
/// and within [`MAX_COORDINATE`]; the first point that is not is named.
pub(crate) fn check_points(points: &[Vec3]) -> Result<(), FitError> {
    if points.is_empty() {
        return Err(FitError::Empty);
    }
    let limit = Vec3::splat(MAX_COORDINATE);
    match points.iter().position(|p| !p.abs().cmple(limit).all()) {
        Some(index) if points[index].is_finite() => Err(FitError::OutOfRange { index }),
        Some(index) => Err(FitError::NonFinite { index }),
        None => Ok(()),
    }
}

/// A fitting-method name that is not one of the known ones.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownMethod {
    /// The name that was given.
    pub name: String,
    /// The names that are accepted.
    pub expected: &'static [&'static str],
}

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown method {:?}; expected one of: {}", self.name, self.expected.join(", "))
    }
}

impl std::error::Error for UnknownMethod {}
