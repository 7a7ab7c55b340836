//! Input checks, run before anything changes: ids in range and known,
//! bounds valid. Each names the first bad input, as a loop over the input
//! in order would.

use rayon::prelude::*;

use crate::Bound;
use crate::error::TreeError;
use crate::node::ID_LIMIT;
use crate::tuning::CHECK_CHUNK;

/// `Ok` when `id` can index the per-id arrays.
pub(crate) fn check_id(id: u32) -> Result<(), TreeError> {
    if id < ID_LIMIT { Ok(()) } else { Err(TreeError::IdOutOfRange { id }) }
}

/// `Ok` when `bound` can go in a tree; else the error naming `id`.
pub(crate) fn check_bound<B: Bound>(id: u32, bound: &B) -> Result<(), TreeError> {
    bound.check().map_err(|reason| TreeError::InvalidBound { id, reason })
}

/// `Ok` when `bounds[id]` can be leaf `id` for every index of the slice.
pub(crate) fn check_slice<B: Bound>(bounds: &[B]) -> Result<(), TreeError> {
    if let Some(last) = bounds.len().checked_sub(1) {
        check_id(u32::try_from(last).unwrap_or(u32::MAX))?;
    }
    match first_invalid(bounds) {
        Some(id) => check_bound(id as u32, &bounds[id]),
        None => Ok(()),
    }
}

/// `Ok` when `bounds[id]` is valid for every id that `holds`; the other
/// entries are not looked at. The branch-free fold over every bound runs
/// first; only when it finds one not valid are the held ids told apart.
pub(crate) fn check_held<B: Bound>(
    bounds: &[B],
    holds: impl Fn(u32) -> bool,
) -> Result<(), TreeError> {
    if let Some(first) = first_invalid(bounds)
        && let Some(id) =
            (first..bounds.len()).find(|&id| holds(id as u32) && !bounds[id].is_valid())
    {
        return check_bound(id as u32, &bounds[id]);
    }
    Ok(())
}

/// `Ok` when every `(id, bound)` of `listed` has a valid bound and an id
/// that `holds`. Folded without branches; the loop names the first bad one.
pub(crate) fn check_listed<B: Bound>(
    listed: &[(u32, B)],
    holds: impl Fn(u32) -> bool,
) -> Result<(), TreeError> {
    let good = |&(id, bound): &(u32, B)| bound.is_valid() & holds(id);
    if !listed.iter().fold(true, |ok, l| ok & good(l)) {
        for &(id, bound) in listed {
            check_bound(id, &bound)?;
            if !holds(id) {
                return Err(TreeError::UnknownId { id });
            }
        }
    }
    Ok(())
}

/// The first index whose bound is not valid. In parallel, a chunk a task,
/// each chunk folded without branches; the index is the first bad one, as a
/// loop would find. Below four chunks on the calling thread: waking a
/// second one would take longer than the check.
fn first_invalid<B: Bound>(bounds: &[B]) -> Option<usize> {
    let bad = |c: &[B]| !c.iter().fold(true, |ok, b| ok & b.is_valid());
    let k = if bounds.len() < 4 * CHECK_CHUNK {
        bounds.chunks(CHECK_CHUNK).position(bad)
    } else {
        bounds.par_chunks(CHECK_CHUNK).position_first(bad)
    }?;
    let rest = &bounds[k * CHECK_CHUNK..];
    Some(k * CHECK_CHUNK + rest.iter().position(|b| !b.is_valid()).unwrap_or(0))
}
