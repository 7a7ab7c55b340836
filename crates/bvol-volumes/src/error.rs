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
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::Empty => write!(f, "no points to bound"),
            FitError::NonFinite { index } => {
                write!(f, "point {index} has a NaN or infinite coordinate")
            }
        }
    }
}

impl std::error::Error for FitError {}

/// Checks a point set before fitting: not empty, every coordinate finite.
pub(crate) fn check_points(points: &[Vec3]) -> Result<(), FitError> {
    if points.is_empty() {
        return Err(FitError::Empty);
    }
    match points.iter().position(|p| !p.is_finite()) {
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
