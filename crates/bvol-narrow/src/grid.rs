//! The 26 directions of the grid `{-1, 0, 1}^3`: the slots of the tables of
//! hill-climbing seeds, and the groups that faces and arcs are clustered by.

use glam::DVec3;

/// Slot in a [`SEEDS`]-entry table of the direction nearest `dir` among the 26
/// of the grid `{-1, 0, 1}^3` (component by component: beyond `tan 22.5` of
/// the largest, its sign; else 0).
pub(crate) fn seed_slot(dir: DVec3) -> usize {
    let cut = dir.abs().max_element() * 0.414_213_562_373_095;
    let level = |x: f64| {
        if x > cut {
            2
        } else if x < -cut {
            0
        } else {
            1
        }
    };
    level(dir.x) + 3 * level(dir.y) + 9 * level(dir.z)
}

/// Entries in a seed table: the 27 cells of `{-1, 0, 1}^3`, the centre unused.
pub(crate) const SEEDS: usize = 27;

/// The grid direction of seed slot `slot`.
pub(crate) fn seed_direction(slot: usize) -> DVec3 {
    DVec3::new((slot % 3) as f64 - 1.0, ((slot / 3) % 3) as f64 - 1.0, (slot / 9) as f64 - 1.0)
}
