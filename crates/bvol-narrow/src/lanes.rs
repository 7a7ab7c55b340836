//! The first bounds of a query's faces or arcs, four at a time on f32 SIMD
//! lanes: which items of a run a few witness points leave, as a bit mask.
//!
//! A cold pair sunk deep into each other has weak bounds: most of its faces
//! and arcs get their cap bounds tested, one after another in f64. The bounds
//! only decide which items are searched, never an answer, so they may be
//! computed in f32 as long as no item that the exact bound leaves is ruled
//! out: each test is widened by [`LANE_SLACK`] of the magnitudes involved,
//! far above f32's rounding of them (a few 1e-7), and may leave an item the
//! f64 bound would have ruled out, whose search then finds nothing new.

use std::ops::Range;

use glam::{DVec3, Vec4};

use crate::cluster::Cap;

/// How far above the bar an item's f32 bound is taken to reach, relative to
/// the sum of the magnitudes that enter it (the witness's distance, the
/// depth, the radius, the bar): about 100 times f32's rounding of them.
const LANE_SLACK: f64 = 1e-5;

/// Four items' caps and depths (see [`Cap::max`]), one item a lane: the
/// same numbers as the f64 ones, rounded to f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CapLanes {
    axis: [Vec4; 3],
    cos: Vec4,
    sin: Vec4,
    inner: Vec4,
}

impl CapLanes {
    /// The items' caps and depths, four to a [`CapLanes`], the last padded
    /// with items no bound leaves.
    pub fn pack(items: &[(Cap, f64)]) -> Vec<CapLanes> {
        items
            .chunks(4)
            .map(|four| {
                let lane = |f: &dyn Fn(&(Cap, f64)) -> f64, pad: f32| {
                    Vec4::from_array(std::array::from_fn(|k| {
                        four.get(k).map_or(pad, |i| f(i) as f32)
                    }))
                };
                CapLanes {
                    axis: [
                        lane(&|(c, _)| c.axis.x, 0.0),
                        lane(&|(c, _)| c.axis.y, 0.0),
                        lane(&|(c, _)| c.axis.z, 0.0),
                    ],
                    cos: lane(&|(c, _)| c.cos, 1.0),
                    sin: lane(&|(c, _)| c.sin, 0.0),
                    inner: lane(&|(_, inner)| *inner, f32::INFINITY),
                }
            })
            .collect()
    }

    /// The lanes whose every witness's bound beats `bar`, as the low four bits.
    #[inline(always)]
    fn live<const N: usize>(&self, witnesses: &[LaneWitness; N], bar: Vec4) -> u32 {
        witnesses.iter().fold(0xf, |live, w| {
            let along = self.axis[0] * w.at[0] + self.axis[1] * w.at[1] + self.axis[2] * w.at[2];
            let shrunk = Vec4::select(along.cmpge(Vec4::ZERO), along, along * self.cos);
            let cap_max =
                Vec4::select(self.cos.cmple(Vec4::ZERO), w.length, shrunk + w.length * self.sin);
            live & (cap_max - self.inner - w.less).cmpgt(bar).bitmask()
        })
    }
}

/// A point that bounds every item of a query: an item's separation is at
/// most [`Cap::max`] of `at` (the point less the reference shape's inner
/// centre) less the item's depth, less `less` (a ball's radius, else 0).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Witness {
    /// The point, from the reference shape's inner centre.
    pub at: DVec3,
    /// Its length.
    pub length: f64,
    /// Taken off the bound.
    pub less: f64,
}

impl Witness {
    /// The bound it gives an item (or a cluster of items) of cap `cap` and
    /// depth `depth`: what [`lanes_left`] takes on lanes, in f64.
    #[inline]
    pub(crate) fn bound(&self, cap: &Cap, depth: f64) -> f64 {
        cap.max(self.at, self.length) - depth - self.less
    }
}

/// A [`Witness`] spread over the lanes.
#[derive(Clone, Copy, Debug)]
struct LaneWitness {
    at: [Vec4; 3],
    length: Vec4,
    less: Vec4,
}

/// The items of `run` (at most 64, indices into the items `lanes` packs)
/// whose bounds by all `witnesses` may beat `bar`, as a bit mask (bit `k`
/// for item `run.start + k`): every item whose f64 bounds beat it, and
/// perhaps a few more. `depth` is at least every item's depth.
pub(crate) fn lanes_left<const N: usize>(
    lanes: &[CapLanes],
    run: Range<u32>,
    witnesses: &[Witness; N],
    depth: f64,
    bar: f64,
) -> u64 {
    debug_assert!(run.len() <= 64);
    let magnitude = witnesses.iter().map(|w| w.length + w.less).sum::<f64>() + depth.abs();
    let slack = LANE_SLACK * (magnitude + if bar.is_finite() { bar.abs() } else { 0.0 });
    let bar = Vec4::splat((bar - slack) as f32);
    let spread = witnesses.map(|w| LaneWitness {
        at: [Vec4::splat(w.at.x as f32), Vec4::splat(w.at.y as f32), Vec4::splat(w.at.z as f32)],
        length: Vec4::splat(w.length as f32),
        less: Vec4::splat(w.less as f32),
    });
    // Blocks of four from the one holding the run's first item: up to 68
    // bits, shifted down to the run's first.
    let (first, last) = (run.start / 4, (run.end - 1) / 4);
    let live = (first..=last).fold(0u128, |live, b| {
        live | u128::from(lanes[b as usize].live(&spread, bar)) << (4 * (b - first))
    });
    let live = (live >> (run.start % 4)) as u64;
    live & (u64::MAX >> (64 - run.len()))
}

/// A range of items cut into runs of at most 64, for bit masks.
pub(crate) fn runs(items: Range<u32>) -> impl Iterator<Item = Range<u32>> {
    items.clone().step_by(64).map(move |start| start..(start + 64).min(items.end))
}

/// The items of a run (at most 64) that `keep` holds for, as a bit mask
/// (bit `k` for item `run.start + k`), found without a branch an item.
#[inline(always)]
pub(crate) fn live_mask(run: Range<u32>, keep: impl Fn(u32) -> bool) -> u64 {
    (0..).zip(run).fold(0, |live, (k, item)| live | u64::from(keep(item)) << k)
}

/// The items whose bits are set in `live`, in order, the first bit being
/// item `start`.
#[inline(always)]
pub(crate) fn set_bits(start: u32, mut live: u64) -> impl Iterator<Item = u32> {
    std::iter::from_fn(move || {
        let k = (live != 0).then(|| live.trailing_zeros())?;
        live &= live - 1;
        Some(start + k)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sat::tests::next;

    /// The f32 lanes leave every item the f64 bounds leave, whatever the
    /// caps, depths, witnesses and bar, at scales from 1e-3 to 1e3.
    #[test]
    fn lanes_leave_every_item_the_exact_bounds_leave() {
        let mut state = 7;
        let unit = |state: &mut u64| {
            DVec3::new(next(state) - 0.5, next(state) - 0.5, next(state) - 0.5).normalize()
        };
        let mut extra = 0;
        for round in 0..2000 {
            let scale = [1e-3, 1.0, 1e3][round % 3];
            let items: Vec<(Cap, f64)> = (0..23)
                .map(|k| {
                    let angle = if k % 5 == 0 { 0.0 } else { 2.0 * next(&mut state) };
                    (Cap::new(unit(&mut state), angle), scale * next(&mut state))
                })
                .collect();
            let lanes = CapLanes::pack(&items);
            let witness = |state: &mut u64, less: f64| {
                let at = unit(state) * scale * 2.0 * next(state);
                Witness { at, length: at.length(), less }
            };
            let radius = scale * next(&mut state);
            let witnesses = [witness(&mut state, 0.0), witness(&mut state, radius)];
            let start = (next(&mut state) * 10.0) as u32;
            let run = start..start + 1 + (next(&mut state) * 12.0) as u32;
            // Half the rounds put the bar a hair under one item's exact
            // bound, where f32 rounding alone would rule it out.
            let bound = |i: u32| {
                let (cap, inner) = items[i as usize];
                witnesses[0].bound(&cap, inner).min(witnesses[1].bound(&cap, inner))
            };
            let bar = if round % 2 == 0 {
                bound(run.start + (next(&mut state) * run.len() as f64) as u32) - 1e-12 * scale
            } else {
                scale * (next(&mut state) - 0.5)
            };
            let got = lanes_left(&lanes, run.clone(), &witnesses, scale, bar);
            for (k, i) in run.clone().enumerate() {
                let exact = bound(i) > bar;
                assert!(
                    !exact || got >> k & 1 == 1,
                    "item {i} of {run:?} ruled out in round {round}"
                );
                extra += usize::from(!exact && got >> k & 1 == 1);
            }
            assert_eq!(got >> run.len(), 0, "bits past the run");
        }
        assert!(extra < 20, "{extra} items left that the exact bounds rule out");
    }
}
