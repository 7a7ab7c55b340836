//! The 13 fixed slab directions shared by k-DOPs, EPOS and DiTO: the 3 axes,
//! the 4 cube-corner diagonals and the 6 cube-edge diagonals (Larsson 2008,
//! "Fast and tight fitting of bounding spheres", table 1). They are kept
//! unnormalised, with components in {-1, 0, 1}, so that projections of f32
//! points onto them are sums of coordinates, exact in f64.

/// All 13 directions: axes (0..3), corner diagonals (3..7), edge diagonals (7..13).
pub const DIRECTIONS: [[i8; 3]; 13] = [
    [1, 0, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 1, 1],
    [1, 1, -1],
    [1, -1, 1],
    [1, -1, -1],
    [1, 1, 0],
    [1, -1, 0],
    [1, 0, 1],
    [1, 0, -1],
    [0, 1, 1],
    [0, 1, -1],
];

/// The `n` directions used by a k-DOP or EPOS-k with k = 2n: 3 (axes), 7 (axes and
/// corners), 9 (axes and edges) or 13 (all). Any other `n` fails to compile where
/// used in a constant, and panics otherwise.
pub const fn directions<const N: usize>() -> [[i8; 3]; N] {
    let picks: &[usize] = match N {
        3 => &[0, 1, 2],
        7 => &[0, 1, 2, 3, 4, 5, 6],
        9 => &[0, 1, 2, 7, 8, 9, 10, 11, 12],
        13 => &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12],
        _ => panic!("k-DOPs have 3, 7, 9 or 13 slab directions (k = 6, 14, 18, 26)"),
    };
    let mut out = [[0i8; 3]; N];
    let mut i = 0;
    while i < N {
        out[i] = DIRECTIONS[picks[i]];
        i += 1;
    }
    out
}

/// The f64 vector of an integer direction.
#[inline]
pub(crate) fn as_dvec3(d: [i8; 3]) -> glam::DVec3 {
    glam::DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64)
}
