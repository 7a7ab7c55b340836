//! The narrow phase: each pair that no bound could rule out is tested on its
//! shapes' convex parts, with its warm starts from last frame, and its event
//! written as it is tested: runs of pairs on rayon tasks, their lists joined
//! in order, so the events are the same on any number of threads.

use bvol_narrow::{Contact, ContactPoint, WarmStart, contact_within};
use bvol_volumes::prefetch;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::bodies::Bodies;
use crate::event::{ContactEvent, EventKind, contact_of};
use crate::{BodyKind, WorldConfig};

/// How many pairs ahead the narrow phase asks for the second body's data.
const AHEAD: usize = 8;
/// Pairs tested per rayon task by the narrow phase, at least: a hull pair
/// takes microseconds, so a thousand-body pile's thousand pairs still split.
const NARROW_CHUNK: usize = 32;
/// Runs of pairs a thread in the narrow phase, at most: enough for work
/// stealing to even out, few enough that joining their events costs little.
const RUNS_A_THREAD: usize = 16;

/// How many pairs of a frame's narrow phase are in contact, of each kind.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    /// Touching.
    pub(crate) touching: usize,
    /// Apart within the margin.
    pub(crate) near: usize,
}

impl std::ops::Add for Counts {
    type Output = Counts;

    fn add(self, other: Counts) -> Counts {
        Counts { touching: self.touching + other.touching, near: self.near + other.near }
    }
}

/// Pairs' states by `(lower slot, higher slot)`, sorted by it.
pub(crate) type PairStates = Vec<((u32, u32), PairState)>;

/// What a pair carries from frame to frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairState {
    /// The warm start of the first pair of convex parts: the only one of
    /// most pairs, kept inline so that no pair allocates.
    pub(crate) warm: WarmStart,
    /// Those of the other pairs of parts, for shapes of several: a boxed
    /// slice, two words less than a `Vec` (every pair's state is moved each
    /// frame, and most have none).
    pub(crate) more: Box<[WarmStart]>,
    /// Whether it was in contact: touching, or apart within the margin.
    pub(crate) in_contact: bool,
    /// Whether it was tested at an earlier update (a fresh state was not).
    pub(crate) tested: bool,
}

/// What lets a pair go untested: which bodies this update placed (a bit a
/// slot), and last update's events, sorted by slots, which hold the contact
/// of every pair that touched. A pair neither of whose bodies was placed
/// since its last test has the same poses, and so the same answer: a warm
/// start never changes an answer ([`bvol_narrow::hull_hull`]).
#[derive(Clone, Copy)]
pub(crate) struct Still<'a> {
    pub(crate) placed: &'a [u64],
    pub(crate) last: &'a [ContactEvent],
}

impl Still<'_> {
    /// Whether neither body of the pair was placed this update.
    fn unmoved(&self, (a, b): (u32, u32)) -> bool {
        let placed = |s: u32| self.placed[s as usize / 64] & (1 << (s % 64)) != 0;
        !placed(a) && !placed(b)
    }

    /// The pair's contact at the last update, looked up from `*at` on
    /// (moved on, so a run's lookups take one pass over the events).
    fn last_contact(&self, bodies: &Bodies, (a, b): (u32, u32), at: &mut usize) -> Option<Contact> {
        while self.last.get(*at).is_some_and(|e| e.slots() < (a, b)) {
            *at += 1;
        }
        contact_of(&self.last[*at..], bodies.id_of(a), bodies.id_of(b))
    }
}

/// The narrow phase of one frame: each of `pairs` (sorted by slot) tested,
/// with its warm starts from last frame, and the events written after those
/// already in `events` (the contacts of removed bodies, sorted in with the
/// rest); a pair is in contact when it touches or is apart within the
/// config's margin, and its warm starts reuse features as the config says.
/// Returns how many are in contact, and the pairs in contact it kept
/// untested (both bodies resting), sorted.
///
/// `states` holds last frame's pair states, sorted as `pairs` are, and gets
/// this frame's: one merge pass moves each pair's state into the spare
/// buffer, where the test reads and updates it in place (a state is moved
/// once a frame). `spare` and `runs` are buffers kept from frame to frame.
pub(crate) fn narrow_phase(
    bodies: &Bodies,
    still: Still,
    config: &WorldConfig,
    pairs: &[(u32, u32)],
    states: &mut PairStates,
    spare: &mut PairStates,
    runs: &mut Vec<Vec<ContactEvent>>,
    events: &mut Vec<ContactEvent>,
) -> (Counts, Vec<(u32, u32)>) {
    let mut next = std::mem::take(spare);
    let left = carry_over(states, pairs, &mut next);
    // Pairs no longer candidates that were in contact have ended, unless both
    // bodies rest: a pile that falls asleep keeps its contacts, unchanged
    // and unreported, until one of them moves again.
    let kinds = &bodies.kinds;
    let resting = |(a, b): (u32, u32)| {
        kinds[a as usize] != BodyKind::Dynamic && kinds[b as usize] != BodyKind::Dynamic
    };
    let (kept, ended): (PairStates, PairStates) =
        left.into_iter().filter(|(_, state)| state.in_contact).partition(|&(key, _)| resting(key));
    let ended: Vec<(u32, u32)> = ended.into_iter().map(|(key, _)| key).collect();
    let orphans = !events.is_empty();
    let counts = if rayon::current_num_threads() == 1 || next.is_empty() {
        test_run(bodies, still, config, &mut next, pairs, &ended, events)
    } else {
        test_in_runs(bodies, still, config, &mut next, pairs, &ended, runs, events)
    };
    let kept_keys = kept.iter().map(|&(key, _)| key).collect();
    if !kept.is_empty() {
        // Two sorted runs: the stable sort merges them in one pass.
        next.extend(kept);
        next.sort_by_key(|&(key, _)| key);
    }
    if orphans {
        events.sort_by_key(ContactEvent::slots);
    }
    // Last frame's buffer, emptied by the merge, serves the next frame.
    *spare = std::mem::replace(states, next);
    (counts, kept_keys)
}

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

/// [`test_run`] over `states` (not empty; with their `pairs`) in
/// runs, a rayon task each, each with the `ended` pairs whose keys fall
/// in its run merged in (the first run's from the start, the last's to
/// the end): the events come out sorted with no sort, and the runs'
/// lists (in `runs`, buffers kept from frame to frame) are joined in
/// order, so they are the same on any number of threads. (One pass after
/// the tests, over their contacts gathered in a list, took a tenth of the
/// stage on 100 000 cubes.) Returns how many are in contact.
fn test_in_runs(
    bodies: &Bodies,
    still: Still,
    config: &WorldConfig,
    states: &mut [((u32, u32), PairState)],
    pairs: &[(u32, u32)],
    ended: &[(u32, u32)],
    runs: &mut Vec<Vec<ContactEvent>>,
    events: &mut Vec<ContactEvent>,
) -> Counts {
    let run = states.len().div_ceil(RUNS_A_THREAD * rayon::current_num_threads());
    let run = run.max(NARROW_CHUNK);
    let firsts: Vec<(u32, u32)> = states.iter().step_by(run).map(|&(key, _)| key).collect();
    runs.resize_with(firsts.len(), Vec::new);
    // The ended keys below run `r`'s first.
    let below =
        |r: usize| firsts.get(r).map_or(ended.len(), |&k| ended.partition_point(|&e| e < k));
    let counts = states
        .par_chunks_mut(run)
        .zip(runs.par_iter_mut())
        .enumerate()
        .map(|(r, (chunk, out))| {
            let gone = &ended[if r == 0 { 0 } else { below(r) }..below(r + 1)];
            out.clear();
            test_run(bodies, still, config, chunk, &pairs[r * run..], gone, out)
        })
        .reduce(Counts::default, |x, y| x + y);
    runs.iter().for_each(|out| events.extend_from_slice(out));
    counts
}

/// Tests a run of sorted pairs, updating their states, and appends their
/// events to `events`, with the `ended` pairs (sorted, among the run's
/// keys) merged in; returns how many are in contact. `ahead` is the pairs
/// from the run's first on: it asks for a later pair's second body
/// [`AHEAD`] pairs early.
fn test_run(
    bodies: &Bodies,
    still: Still,
    config: &WorldConfig,
    run: &mut [((u32, u32), PairState)],
    ahead: &[(u32, u32)],
    ended: &[(u32, u32)],
    events: &mut Vec<ContactEvent>,
) -> Counts {
    let mut ended = ended.iter().peekable();
    let mut counts = Counts::default();
    // Where the run's pairs begin among last update's events.
    let mut at =
        run.first().map_or(0, |&(first, _)| still.last.partition_point(|e| e.slots() < first));
    for (k, &mut ((a, b), ref mut state)) in run.iter_mut().enumerate() {
        if let Some(&(_, later)) = ahead.get(k + AHEAD) {
            prefetch(&bodies.poses[later as usize]);
            prefetch(&bodies.shapes[later as usize]);
            prefetch(&bodies.user_data[later as usize]);
        }
        let kept = match state.tested && still.unmoved((a, b)) {
            true if state.in_contact => still.last_contact(bodies, (a, b), &mut at).map(Some),
            true => Some(None),
            false => None,
        };
        let contact = kept.unwrap_or_else(|| collide(bodies, a, b, config, state));
        state.tested = true;
        let was = state.in_contact;
        state.in_contact = contact.is_some();
        match contact {
            Some(c) if c.is_touching() => counts.touching += 1,
            Some(_) => counts.near += 1,
            None => {}
        }
        let kind = match (was, state.in_contact) {
            (false, true) => EventKind::Began,
            (true, true) => EventKind::Persisting,
            (true, false) => EventKind::Ended,
            (false, false) => continue,
        };
        while let Some(&gone) = ended.next_if(|&&key| key < (a, b)) {
            events.push(bodies.ended(gone.0, gone.1));
        }
        events.push(bodies.event(kind, a, b, contact));
    }
    events.extend(ended.map(|&(a, b)| bodies.ended(a, b)));
    counts
}

/// How bodies `a` and `b` touch, or how near they are when apart within
/// the config's margin: the deepest contact over their pairs of convex parts (the
/// nearest, when none touches), the normal from `a` to `b`.
fn collide(
    bodies: &Bodies,
    a: u32,
    b: u32,
    config: &WorldConfig,
    state: &mut PairState,
) -> Option<Contact> {
    let (contact, anchor) = anchored(bodies, a, b, config, state)?;
    if anchor == DVec3::ZERO {
        return Some(contact);
    }
    let placed = points_at(&contact, anchor).zip(contact.points());
    let points: Vec<ContactPoint> = placed
        .map(|(position, p)| ContactPoint { position: position.as_vec3(), depth: p.depth })
        .collect();
    Some(Contact::new(contact.normal, contact.depth, &points))
}

/// A contact's points, found relative to `anchor`, where they are.
pub(crate) fn points_at(contact: &Contact, anchor: DVec3) -> impl Iterator<Item = DVec3> + '_ {
    contact.points().iter().map(move |p| anchor + p.position.as_dvec3())
}

/// [`collide`] tested cold, its points left relative to the anchor it
/// returns (see [`anchored`]).
pub(crate) fn anchored_contact(
    bodies: &Bodies,
    a: u32,
    b: u32,
    config: &WorldConfig,
) -> Option<(Contact, DVec3)> {
    anchored(bodies, a, b, config, &mut PairState::default())
}

/// [`collide`]'s contact with its points relative to an anchor, and the
/// anchor: the origin, or, in a world given positions that are not f32's,
/// `a`'s f64 position, the pair then tested on `b`'s position relative to
/// it (so as precisely wherever the pair is).
fn anchored(
    bodies: &Bodies,
    a: u32,
    b: u32,
    config: &WorldConfig,
    state: &mut PairState,
) -> Option<(Contact, DVec3)> {
    let (a, b) = (a as usize, b as usize);
    let (shape_a, shape_b) = (bodies.shapes[a].as_ref()?, bodies.shapes[b].as_ref()?);
    let (parts_a, parts_b) = (shape_a.parts(), shape_b.parts());
    let (mut pose_a, mut pose_b) = (bodies.poses[a], bodies.poses[b]);
    let mut anchor = DVec3::ZERO;
    if bodies.far {
        anchor = bodies.positions[a];
        pose_a.position = Vec3::ZERO;
        pose_b.position = (bodies.positions[b] - anchor).as_vec3();
    }
    // A fresh state's warm starts take the world's reuse tolerance.
    let fresh = WarmStart::reusing(config.reuse).unwrap_or_default();
    if state.warm.reuse_tolerance() != fresh.reuse_tolerance() {
        state.warm = fresh;
    }
    let more = parts_a.len() * parts_b.len() - 1;
    if state.more.len() != more
        || state.more.first().is_some_and(|w| w.reuse_tolerance() != fresh.reuse_tolerance())
    {
        state.more = vec![fresh; more].into_boxed_slice();
    }
    let mut deepest: Option<Contact> = None;
    for (i, pa) in parts_a.iter().enumerate() {
        for (j, pb) in parts_b.iter().enumerate() {
            let cache = match i * parts_b.len() + j {
                0 => &mut state.warm,
                k => &mut state.more[k - 1],
            };
            // Poses were checked when set and the margin when the world was
            // made, so the tests cannot fail.
            let found = contact_within(pa, &pose_a, pb, &pose_b, config.margin, cache);
            let contact = found.ok().flatten();
            if let Some(c) = contact.filter(|c| deepest.is_none_or(|d| c.depth > d.depth)) {
                deepest = Some(c);
            }
        }
    }
    Some((deepest?, anchor))
}
