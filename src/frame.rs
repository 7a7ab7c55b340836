//! One frame of the world, as ../shared/DESIGN.md "One frame" has it: world
//! bounds of the bodies that moved, tree upkeep, candidate pairs, the sphere
//! test, the OBB test, the hull separating-axis test, and the contact events.
//! Each stage counts what it lets through and times itself.

use std::time::{Duration, Instant};

use bvol_narrow::{Collision, Contact, WarmStart, hull_hull, sphere_hull, sphere_sphere};
use bvol_volumes::{Aabb, BodyBounds, Pose, WorldBounds, prefetch};
use rayon::prelude::*;

use crate::shape::Part;
use crate::world::{Bodies, PairState, PairStates, Scratch};
use crate::{BodyId, BodyKind, World};

/// What happened to a touching pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// It touches now and did not last frame.
    Began,
    /// It touched last frame and still does.
    Persisting,
    /// It touched last frame and does not now (or a body was removed).
    Ended,
}

/// A contact event: the two bodies (`a` before `b` by slot) and, unless it
/// ended, how they touch, the normal pointing from `a` to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent {
    /// What happened.
    pub kind: EventKind,
    /// The body with the lower slot.
    pub a: BodyId,
    /// The other body.
    pub b: BodyId,
    /// The contact: `None` for an ended pair.
    pub contact: Option<Contact>,
}

impl ContactEvent {
    /// The end of a pair's contact.
    pub(crate) fn ended(a: BodyId, b: BodyId) -> Self {
        ContactEvent { kind: EventKind::Ended, a, b, contact: None }
    }
}

/// Pairs let through by each stage of a frame, and the time each took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Bodies whose world bounds were refit (those that moved).
    pub refit: usize,
    /// Pairs whose tree leaves overlap (layer filtering included).
    pub tree_candidates: usize,
    /// Of those, pairs whose world spheres overlap.
    pub after_spheres: usize,
    /// Of those, pairs whose world OBBs overlap.
    pub after_obbs: usize,
    /// Of those, pairs whose shapes touch.
    pub touching: usize,
    /// Time to refit the world bounds of the bodies that moved.
    pub bounds_time: Duration,
    /// Time of tree upkeep and the pair search.
    pub tree_time: Duration,
    /// Time of the sphere test.
    pub spheres_time: Duration,
    /// Time of the OBB test.
    pub obbs_time: Duration,
    /// Time of the hull test and the contact events (the pairs' sort by
    /// slot that matches them with last frame's included).
    pub narrow_time: Duration,
}

impl FrameStats {
    /// The whole frame's time.
    pub fn total_time(&self) -> Duration {
        self.bounds_time + self.tree_time + self.spheres_time + self.obbs_time + self.narrow_time
    }
}

/// Bodies refit per rayon task: the refit is a few dozen ns a body.
const REFIT_CHUNK: usize = 4096;
/// The refit scans every slot when at least one in this many moved.
const DENSE_REFIT: usize = 8;
/// Bodies refit at once on SIMD lanes.
const LANES: usize = 4;
/// How many bodies ahead the refit asks for the slots it will read and
/// write, and `World::set_poses` for the pose slots it will write: seven
/// arrays in step are more streams than the processor follows on its own
/// (the refit of 100 000 bodies: 2.2-2.4 -> 1.6-1.7 ms; 8 or 32 ahead did
/// no better).
pub(crate) const BODIES_AHEAD: usize = 16;
/// Pairs tested per rayon task by the sphere and OBB stages (a few ns a pair).
const PAIR_CHUNK: usize = 1024;
/// How many pairs ahead the narrow phase asks for the second body's data.
const AHEAD: usize = 8;
/// How many pairs ahead the sphere and OBB stages ask for it: a test takes a
/// few ns, and 8 ahead left them waiting on memory (100 000 cubes, one
/// thread: spheres 2.16-2.21 -> 1.98-2.04 ms, OBBs 4.06-4.19 -> 3.72-3.77;
/// 24 or 32 ahead did no better on both).
const FILTER_AHEAD: usize = 16;
/// Pairs tested per rayon task by the narrow phase, at least: a hull pair
/// takes microseconds, so a thousand-body pile's thousand pairs still split.
const NARROW_CHUNK: usize = 32;
/// Runs of pairs a thread in the narrow phase, at most: enough for work
/// stealing to even out, few enough that joining their events costs little.
const RUNS_A_THREAD: usize = 16;

impl World {
    /// Runs one frame: the bodies moved since the last update get their world
    /// bounds and tree leaves updated, candidate pairs come from the trees,
    /// and each stage passes on the pairs it cannot rule out. Then
    /// [`events`](World::events) and [`stats`](World::stats) hold its result.
    /// The same world and poses give the same events in the same order on
    /// any number of threads.
    pub fn update(&mut self) -> &FrameStats {
        let mut stats = FrameStats::default();
        let start = Instant::now();
        let refit = self.refit_bounds();
        stats.refit = refit.len();
        let t = Instant::now();
        stats.bounds_time = t - start;
        // This frame's lists go in last frame's buffers (see `Scratch`).
        let mut scratch = std::mem::take(&mut self.scratch);
        self.update_trees(&refit, &mut scratch.leaves);
        // The list's buffer serves the next frame's moved bodies.
        self.bodies.dirty = refit;
        self.bodies.dirty.clear();
        self.candidates(&mut scratch.found);
        let Scratch { found, near, nearer, starts, sorted, states, runs, .. } = &mut scratch;
        stats.tree_candidates = found.len();
        let t2 = Instant::now();
        stats.tree_time = t2 - t;
        let bodies = &self.bodies;
        filter(found, |b| prefetch(&bodies.spheres[b]), |a, b| bodies.spheres_overlap(a, b), near);
        stats.after_spheres = near.len();
        let t3 = Instant::now();
        stats.spheres_time = t3 - t2;
        filter(
            near,
            |b| prefetch(&bodies.obbs[b]),
            |a, b| bodies.obbs[a].overlaps(&bodies.obbs[b]),
            nearer,
        );
        stats.after_obbs = nearer.len();
        let t4 = Instant::now();
        stats.obbs_time = t4 - t3;
        // Sorted for the narrow phase's merge with last frame's states, where
        // the fewest pairs are left (sorted as the trees gave them, 200 000 a
        // frame on 100 000 cubes, of which 87 000 reach the narrow phase,
        // the sort took 2.5 ms, here 1.0).
        sort_by_slot(nearer, bodies.shapes.len(), starts, sorted);
        stats.touching = self.narrow_phase(sorted, states, runs);
        self.scratch = scratch;
        stats.narrow_time = t4.elapsed();
        self.stats = stats;
        &self.stats
    }

    /// Refits the world sphere, OBB and leaf box of every live body moved
    /// since the last update; returns their slots. When many moved, one
    /// parallel pass over every slot writes them in place, four neighbours
    /// at a time on SIMD lanes (reading a flag a slot costs less than
    /// gathering the moved ones by slot); when few did, a loop over those.
    fn refit_bounds(&mut self) -> Vec<u32> {
        let b = &mut self.bodies;
        let mut dirty = std::mem::take(&mut b.dirty);
        if dirty.len() * DENSE_REFIT >= b.shapes.len() {
            let chunks = (
                b.spheres.par_chunks_mut(REFIT_CHUNK),
                b.obbs.par_chunks_mut(REFIT_CHUNK),
                b.leaves.par_chunks_mut(REFIT_CHUNK),
                b.is_dirty.par_chunks_mut(REFIT_CHUNK),
                b.shapes.par_chunks(REFIT_CHUNK),
                b.poses.par_chunks(REFIT_CHUNK),
            );
            // Written out here: the same loop as a function of its own ran
            // 10-15% slower (three runs a side), inlined or not.
            chunks.into_par_iter().for_each(|(spheres, obbs, leaves, flags, shapes, poses)| {
                let n = spheres.len();
                for start in (0..n).step_by(LANES) {
                    let ahead = start + BODIES_AHEAD;
                    if ahead < n {
                        prefetch(&spheres[ahead]);
                        prefetch(&obbs[ahead]);
                        prefetch(&leaves[ahead]);
                        prefetch(&poses[ahead]);
                    }
                    let end = (start + LANES).min(n);
                    let (spheres, obbs) = (&mut spheres[start..end], &mut obbs[start..end]);
                    let (leaves, flags) = (&mut leaves[start..end], &mut flags[start..end]);
                    let (shapes, poses) = (&shapes[start..end], &poses[start..end]);
                    let mut store = |k: usize, w: WorldBounds| {
                        (spheres[k], obbs[k], leaves[k]) = (w.sphere, w.obb, w.aabb);
                    };
                    if let ([true, true, true, true], [Some(s0), Some(s1), Some(s2), Some(s3)]) =
                        (&*flags, shapes)
                    {
                        let shapes = [s0, s1, s2, s3].map(|s| s.bounds());
                        let placed = BodyBounds::at4(shapes, std::array::from_fn(|k| &poses[k]));
                        placed.into_iter().enumerate().for_each(|(k, w)| store(k, w));
                    } else {
                        for (k, (&moved, shape)) in flags.iter().zip(shapes).enumerate() {
                            if let (true, Some(shape)) = (moved, shape) {
                                store(k, shape.bounds().at(&poses[k]));
                            }
                        }
                    }
                    flags.fill(false);
                }
            });
        } else {
            for &s in &dirty {
                let i = s as usize;
                b.is_dirty[i] = false;
                if let Some(shape) = &b.shapes[i] {
                    let w = shape.bounds().at(&b.poses[i]);
                    (b.spheres[i], b.obbs[i], b.leaves[i]) = (w.sphere, w.obb, w.aabb);
                }
            }
        }
        // A pass over the moved slots, only when one may have been freed.
        if std::mem::take(&mut b.removed) {
            dirty.retain(|&s| b.shapes[s as usize].is_some());
        }
        dirty
    }

    /// Moves the refit bodies' leaves and adds the new ones, each tree in
    /// one call for each: moves pick per-leaf updates or a refit by the
    /// fraction moved; many new leaves at once (a level load) take one
    /// batch build.
    fn update_trees(&mut self, refit: &[u32], leaves: &mut [Vec<(u32, Aabb)>; 4]) {
        let [moving, resting, new_moving, new_resting] = leaves;
        for list in [&mut *moving, &mut *resting, &mut *new_moving, &mut *new_resting] {
            list.clear();
        }
        // Where many moved, the moving tree reads its leaves' boxes from the
        // slot array, in its own order: a list of them, placed a leaf at a
        // time wherever each one's parent lies, cost more.
        let dense = refit.len() * DENSE_SHARE >= self.moving.len();
        for &slot in refit {
            let leaf = self.bodies.leaves[slot as usize];
            let dynamic = self.bodies.kinds[slot as usize] == BodyKind::Dynamic;
            let (tree, moved, new) = if dynamic {
                (&self.moving, &mut *moving, &mut *new_moving)
            } else {
                (&self.resting, &mut *resting, &mut *new_resting)
            };
            if !tree.contains(slot) {
                new.push((slot, leaf));
            } else if !(dynamic && dense) {
                moved.push((slot, leaf));
            }
        }
        // Every id is live, in its tree or new to it, and every box finite:
        // none of these can fail.
        if dense {
            self.moving.update_from(&self.bodies.leaves).ok();
        } else {
            self.moving.update_moved(moving).ok();
        }
        self.resting.update_moved(resting).ok();
        self.moving.insert_many(new_moving).ok();
        self.resting.insert_many(new_resting).ok();
    }

    /// Pairs of overlapping leaves that the bodies' filters allow, each as
    /// `(lower slot, higher slot)`, in the trees' order, into `pairs`.
    fn candidates(&self, pairs: &mut Vec<(u32, u32)>) {
        self.moving.pairs_into(pairs);
        pairs.extend(
            self.moving.pairs_with(&self.resting).into_iter().map(|(a, b)| (a.min(b), a.max(b))),
        );
        // Every pair passes while no body filters (each on some layer, and
        // colliding with all): the pass over them is skipped (0.6 ms on the
        // 200 000 candidates of 100 000 cubes).
        let b = &self.bodies;
        if b.filtering > 0 {
            pairs.retain(|&(x, y)| {
                let (x, y) = (x as usize, y as usize);
                b.layers[x] & b.masks[y] != 0 && b.layers[y] & b.masks[x] != 0
            });
        }
    }

    /// The hull test on each pair, with its warm starts from last frame;
    /// then the events, from the pairs that touch now and those that did.
    /// Returns how many touch. `pairs` is sorted, as last frame's states
    /// are: one merge pass moves each pair's state into `spare`, where the
    /// test reads and updates it in place (a state, 88 bytes with its warm
    /// start, is moved once a frame). `spare` and `runs` are buffers (see
    /// `Scratch`).
    fn narrow_phase(
        &mut self,
        pairs: &[(u32, u32)],
        spare: &mut PairStates,
        runs: &mut Vec<Vec<ContactEvent>>,
    ) -> usize {
        let mut last = std::mem::take(&mut self.pairs);
        let mut next = std::mem::take(spare);
        let left = carry_over(&mut last, pairs, &mut next);
        *spare = last;
        // Pairs no longer candidates that touched have ended, unless both
        // bodies rest: a pile that falls asleep keeps its contacts, unchanged
        // and unreported, until one of them moves again.
        let kinds = &self.bodies.kinds;
        let resting = |(a, b): (u32, u32)| {
            kinds[a as usize] != BodyKind::Dynamic && kinds[b as usize] != BodyKind::Dynamic
        };
        let (kept, ended): (PairStates, PairStates) = left
            .into_iter()
            .filter(|(_, state)| state.touching)
            .partition(|&(key, _)| resting(key));
        let ended: Vec<(u32, u32)> = ended.into_iter().map(|(key, _)| key).collect();
        let mut events = std::mem::take(&mut self.events);
        events.clear();
        let orphans = !self.orphaned.is_empty();
        events.append(&mut self.orphaned);
        let bodies = &self.bodies;
        let touching = if rayon::current_num_threads() == 1 || next.is_empty() {
            bodies.events(&mut next, pairs, &ended, &mut events)
        } else {
            bodies.events_in_runs(&mut next, pairs, &ended, runs, &mut events)
        };
        if !kept.is_empty() {
            // Two sorted runs: the stable sort merges them in one pass.
            next.extend(kept);
            next.sort_by_key(|&(key, _)| key);
        }
        if orphans {
            events.sort_by_key(|e| (e.a.index, e.b.index));
        }
        self.pairs = next;
        self.events = events;
        touching
    }
}

/// The pairs `(a, b)`, `a < b < slots`, sorted: a counting sort on `a` (slots
/// are dense: one pass counts, one places; Knuth, TAOCP vol. 3, 5.2), then
/// each slot's few pairs by `b`. On the 200 000 candidates of 100 000 bodies
/// (sorted before the sphere and OBB stages, as it once ran) this took 1 ms
/// where a comparison sort took 6 (on an earlier host; on a later one,
/// 2.4 ms, of which ordering the runs 1.1).
/// `starts` is scratch; the result goes in `sorted`.
fn sort_by_slot(
    pairs: &[(u32, u32)],
    slots: usize,
    starts: &mut Vec<u32>,
    sorted: &mut Vec<(u32, u32)>,
) {
    starts.clear();
    starts.resize(slots + 1, 0);
    for &(a, _) in pairs {
        starts[a as usize + 1] += 1;
    }
    for i in 1..starts.len() {
        starts[i] += starts[i - 1];
    }
    sorted.clear();
    sorted.resize(pairs.len(), (0, 0));
    for &(a, b) in pairs {
        let at = &mut starts[a as usize];
        sorted[*at as usize] = (a, b);
        *at += 1;
    }
    // Each slot's place now ends its run. Most runs hold a pair or two: an
    // insertion sort in line, where a library sort called for every run (and
    // runs found by comparing neighbours) took half the sort's time.
    let mut begin = 0;
    for &end in &starts[..slots] {
        let run = &mut sorted[begin as usize..end as usize];
        if run.len() > SHORT_RUN {
            run.sort_unstable();
        } else {
            for i in 1..run.len() {
                let mut j = i;
                while j > 0 && run[j - 1].1 > run[j].1 {
                    run.swap(j - 1, j);
                    j -= 1;
                }
            }
        }
        begin = end;
    }
}

/// The moving tree reads every leaf's box from the slot array when at least
/// one body in this many of those it holds was refit (see `update_trees`).
const DENSE_SHARE: usize = 2;

/// Runs of [`sort_by_slot`] longer than this take the library's sort.
const SHORT_RUN: usize = 16;

/// Last frame's pair states (sorted by key) matched with this frame's
/// sorted `pairs`: `next` gets each pair with its state (a fresh one for a
/// new pair); the old pairs that are not among them are returned, in order.
/// `old` is left empty, its buffer kept.
fn carry_over(old: &mut PairStates, pairs: &[(u32, u32)], next: &mut PairStates) -> PairStates {
    let mut old = old.drain(..).peekable();
    next.clear();
    let mut left = Vec::new();
    for &key in pairs {
        while let Some(gone) = old.next_if(|(k, _)| *k < key) {
            left.push(gone);
        }
        let state = old.next_if(|(k, _)| *k == key).map(|(_, state)| state);
        next.push((key, state.unwrap_or_default()));
    }
    left.extend(old);
    left
}

/// The pairs for which `keep` holds, in order, tested in parallel chunks.
/// The pairs come in the trees' order, their bodies scattered in the slots:
/// `ahead` asks for the data `keep` will read of both bodies
/// [`FILTER_AHEAD`] pairs early (about twice as fast on 100 000 bodies,
/// whose bounds are past the caches). Into `out`.
fn filter(
    pairs: &[(u32, u32)],
    ahead: impl Fn(usize) + Sync,
    keep: impl Fn(usize, usize) -> bool + Sync,
    out: &mut Vec<(u32, u32)>,
) {
    out.clear();
    out.par_extend(pairs.par_chunks(PAIR_CHUNK).flat_map_iter(|chunk| {
        let kept = chunk.iter().enumerate().filter(|&(k, &(a, b))| {
            if let Some(&(first, second)) = chunk.get(k + FILTER_AHEAD) {
                ahead(first as usize);
                ahead(second as usize);
            }
            keep(a as usize, b as usize)
        });
        kept.map(|(_, &pair)| pair)
    }));
}

impl Bodies {
    /// Whether the world spheres of two bodies overlap or touch. In f32,
    /// with the sum of radii padded by a few roundings so that no touching
    /// pair is lost.
    #[inline]
    fn spheres_overlap(&self, a: usize, b: usize) -> bool {
        let (a, b) = (&self.spheres[a], &self.spheres[b]);
        let d = a.center - b.center;
        let r = (a.radius + b.radius) * (1.0 + 4.0 * f32::EPSILON);
        d.length_squared() <= r * r
    }

    /// [`Bodies::events`] over `states` (not empty; with their `pairs`) in
    /// runs, a rayon task each, each with the `ended` pairs whose keys fall
    /// in its run merged in (the first run's from the start, the last's to
    /// the end): the events come out sorted with no sort, and the runs'
    /// lists (in `runs`, buffers kept from frame to frame) are joined in
    /// order, so they are the same on any number of threads. (One pass after
    /// the tests, over their contacts gathered in a list, took a tenth of the
    /// stage on 100 000 cubes.) Returns how many touch.
    fn events_in_runs(
        &self,
        states: &mut [((u32, u32), PairState)],
        pairs: &[(u32, u32)],
        ended: &[(u32, u32)],
        runs: &mut Vec<Vec<ContactEvent>>,
        events: &mut Vec<ContactEvent>,
    ) -> usize {
        let run = states.len().div_ceil(RUNS_A_THREAD * rayon::current_num_threads());
        let run = run.max(NARROW_CHUNK);
        let firsts: Vec<(u32, u32)> = states.iter().step_by(run).map(|&(key, _)| key).collect();
        runs.resize_with(firsts.len(), Vec::new);
        // The ended keys below run `r`'s first.
        let below =
            |r: usize| firsts.get(r).map_or(ended.len(), |&k| ended.partition_point(|&e| e < k));
        let touching = states
            .par_chunks_mut(run)
            .zip(runs.par_iter_mut())
            .enumerate()
            .map(|(r, (chunk, out))| {
                let gone = &ended[if r == 0 { 0 } else { below(r) }..below(r + 1)];
                out.clear();
                self.events(chunk, &pairs[r * run..], gone, out)
            })
            .sum();
        runs.iter().for_each(|out| events.extend_from_slice(out));
        touching
    }

    /// Tests a run of sorted pairs, updating their states, and appends their
    /// events to `events`, with the `ended` pairs (sorted, among the run's
    /// keys) merged in; returns how many touch. `ahead` is the pairs from the
    /// run's first on: it asks for a later pair's second body [`AHEAD`] pairs
    /// early.
    fn events(
        &self,
        run: &mut [((u32, u32), PairState)],
        ahead: &[(u32, u32)],
        ended: &[(u32, u32)],
        events: &mut Vec<ContactEvent>,
    ) -> usize {
        let mut ended = ended.iter().peekable();
        let mut touching = 0;
        for (k, &mut ((a, b), ref mut state)) in run.iter_mut().enumerate() {
            if let Some(&(_, later)) = ahead.get(k + AHEAD) {
                prefetch(&self.poses[later as usize]);
                prefetch(&self.shapes[later as usize]);
            }
            let contact = self.collide(a, b, state);
            let was = state.touching;
            state.touching = contact.is_some();
            touching += usize::from(state.touching);
            let kind = match (was, state.touching) {
                (false, true) => EventKind::Began,
                (true, true) => EventKind::Persisting,
                (true, false) => EventKind::Ended,
                (false, false) => continue,
            };
            while let Some(&gone) = ended.next_if(|&&key| key < (a, b)) {
                events.push(self.ended(gone.0, gone.1));
            }
            events.push(ContactEvent { kind, a: self.id_of(a), b: self.id_of(b), contact });
        }
        events.extend(ended.map(|&(a, b)| self.ended(a, b)));
        touching
    }

    /// The end of the contact of the bodies in slots `a` and `b`.
    pub(crate) fn ended(&self, a: u32, b: u32) -> ContactEvent {
        ContactEvent::ended(self.id_of(a), self.id_of(b))
    }

    /// The handle of the body in `slot` now.
    pub(crate) fn id_of(&self, slot: u32) -> BodyId {
        BodyId { index: slot, generation: self.generations[slot as usize] }
    }

    /// How bodies `a` and `b` touch, if they do: the deepest contact over
    /// their pairs of convex parts, the normal from `a` to `b`.
    fn collide(&self, a: u32, b: u32, state: &mut PairState) -> Option<Contact> {
        let (a, b) = (a as usize, b as usize);
        let (shape_a, shape_b) = (self.shapes[a].as_ref()?, self.shapes[b].as_ref()?);
        let (parts_a, parts_b) = (shape_a.parts(), shape_b.parts());
        let more = parts_a.len() * parts_b.len() - 1;
        if state.more.len() != more {
            state.more = vec![WarmStart::default(); more].into_boxed_slice();
        }
        let mut deepest: Option<Contact> = None;
        for (i, pa) in parts_a.iter().enumerate() {
            for (j, pb) in parts_b.iter().enumerate() {
                let cache = match i * parts_b.len() + j {
                    0 => &mut state.warm,
                    k => &mut state.more[k - 1],
                };
                let found = part_contact(pa, &self.poses[a], pb, &self.poses[b], cache);
                if let Some(c) = found.filter(|c| deepest.is_none_or(|d| c.depth > d.depth)) {
                    deepest = Some(c);
                }
            }
        }
        deepest
    }
}

/// How two convex parts touch, if they do, the normal from `pa` to `pb`.
/// Poses were checked when set, so the tests cannot fail.
fn part_contact(pa: &Part, a: &Pose, pb: &Part, b: &Pose, warm: &mut WarmStart) -> Option<Contact> {
    let collision = match (pa, pb) {
        (Part::Hull(x), Part::Hull(y)) => hull_hull(&x.polyhedron, a, &y.polyhedron, b, warm),
        (Part::Ball(x), Part::Hull(y)) => sphere_hull(x, a, &y.polyhedron, b),
        (Part::Hull(x), Part::Ball(y)) => sphere_hull(y, b, &x.polyhedron, a).map(flip),
        (Part::Ball(x), Part::Ball(y)) => sphere_sphere(x, a, y, b),
    };
    collision.ok()?.contact().copied()
}

/// The same collision seen from the other body: the normal reversed.
fn flip(c: Collision) -> Collision {
    match c {
        Collision::Separated { axis, distance } => Collision::Separated { axis: -axis, distance },
        Collision::Touching(mut contact) => {
            contact.normal = -contact.normal;
            Collision::Touching(contact)
        }
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::sort_by_slot;

    proptest! {
        /// The counting sort gives the order of a comparison sort, on pairs
        /// `a < b` of slots below the count, repeats of a first slot included:
        /// with few slots, runs far longer than `SHORT_RUN`.
        #[test]
        fn sort_by_slot_matches_a_comparison_sort(
            slots in 2u32..300,
            raw in prop::collection::vec((0u32..300, 0u32..300), 0..2000),
        ) {
            // Each pair once, in the generated (arbitrary) order.
            let mut seen = std::collections::HashSet::new();
            let pairs: Vec<(u32, u32)> = raw
                .into_iter()
                .map(|(a, b)| (a % slots, b % slots))
                .filter(|(a, b)| a != b)
                .map(|(a, b)| (a.min(b), a.max(b)))
                .filter(|&pair| seen.insert(pair))
                .collect();
            let mut want = pairs.clone();
            want.sort_unstable();
            let (mut starts, mut sorted) = (vec![7; 3], vec![(1, 2); 5]);
            sort_by_slot(&pairs, slots as usize, &mut starts, &mut sorted);
            prop_assert_eq!(sorted, want);
        }
    }
}
