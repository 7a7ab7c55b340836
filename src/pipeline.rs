//! One frame of a world, top to bottom, as ../shared/DESIGN.md "One frame"
//! has it: the world bounds of the bodies that moved, the broadphases'
//! upkeep and candidate pairs, the layer filter, the sphere test, the OBB
//! test, and the narrow phase with the contact events. Each stage counts what
//! it lets through and times itself.

use std::time::Instant;

use bvol_tree::sort_pairs;
use bvol_volumes::{Aabb, BodyBounds, WorldBounds, prefetch};
use rayon::prelude::*;

use crate::bodies::BODIES_AHEAD;
use crate::broadphase::Broadphase;
use crate::narrow_phase::{Still, narrow_phase};
use crate::scratch::Scratch;
use crate::stats::FrameStats;
use crate::{BodyKind, World};

/// Bodies placed per rayon task: placing one takes a few dozen ns.
const PLACE_CHUNK: usize = 4096;
/// Placing scans every slot when at least one in this many moved.
const DENSE_PLACE: usize = 8;
/// Bodies placed at once on SIMD lanes.
const LANES: usize = 4;
/// Pairs tested per rayon task by the sphere and OBB stages (a few ns a pair).
const PAIR_CHUNK: usize = 1024;
/// How many pairs ahead the sphere and OBB stages ask for a pair's bodies'
/// data: a test takes a few ns, so the loads must be asked for further ahead
/// than the narrow phase's.
const FILTER_AHEAD: usize = 16;

impl<B: Broadphase> World<B> {
    /// Runs one frame: the bodies moved since the last update get their world
    /// bounds and broadphase leaves updated, candidate pairs come from the
    /// broadphases, and each stage passes on the pairs it cannot rule out. Then
    /// [`events`](World::events) and [`stats`](World::stats) hold its result.
    /// The same world and poses give the same events in the same order on
    /// any number of threads.
    ///
    /// It runs on the world's own thread pool when its
    /// [`WorldConfig::threads`](crate::WorldConfig::threads) names one, and
    /// on rayon's current pool otherwise.
    pub fn update(&mut self) -> &FrameStats {
        match self.pool.clone() {
            Some(pool) => pool.install(|| self.run_frame()),
            None => self.run_frame(),
        }
        &self.stats
    }

    /// The frame of [`update`](Self::update), on the current pool.
    fn run_frame(&mut self) {
        let mut stats = FrameStats::default();
        let start = Instant::now();
        let moved = self.place_bounds();
        stats.moved = moved.len();
        let mut placed = std::mem::take(&mut self.scratch.placed);
        placed.clear();
        placed.resize(self.bodies.shapes.len().div_ceil(64), 0);
        for &s in &moved {
            placed[s as usize / 64] |= 1 << (s % 64);
        }
        let t = Instant::now();
        stats.bounds_time = t - start;
        // This frame's lists go in last frame's buffers (see `Scratch`).
        let mut scratch = std::mem::take(&mut self.scratch);
        self.update_broadphases(&moved, &mut scratch.leaves);
        // The list's buffer serves the next frame's moved bodies.
        self.bodies.dirty = moved;
        self.bodies.dirty.clear();
        self.candidates(&mut scratch.found);
        let Scratch { found, near, nearer, starts, sorted, states, runs, events: spare, .. } =
            &mut scratch;
        stats.candidates = found.len();
        let t2 = Instant::now();
        stats.broadphase_time = t2 - t;
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
        // Sorted for the narrow phase's merge with last frame's states here,
        // where the fewest pairs are left.
        sort_pairs(nearer, bodies.shapes.len(), starts, sorted);
        // Last frame's events stay where they are until the kept pairs'
        // contacts are read from them.
        let mut events = std::mem::take(spare);
        events.clear();
        events.append(&mut self.orphaned);
        let still = Still { placed: &placed, last: &self.events };
        let config = &self.config;
        let (counts, kept) =
            narrow_phase(bodies, still, config, sorted, &mut self.pairs, states, runs, &mut events);
        (stats.touching, stats.near) = (counts.touching, counts.near);
        // A kept pair touched at the last update: its contact is among that
        // update's events or its kept contacts.
        let rested = kept.into_iter().filter_map(|(a, b)| {
            let (a, b) = (bodies.id_of(a), bodies.id_of(b));
            Some(((a.index, b.index), self.last_contact(a, b)?))
        });
        let rested = rested.collect();
        self.rested = rested;
        *spare = std::mem::replace(&mut self.events, events);
        scratch.placed = placed;
        self.scratch = scratch;
        stats.narrow_time = t4.elapsed();
        self.stats = stats;
    }

    /// Places the world sphere, OBB and leaf box of every live body moved
    /// since the last update; returns their slots. When many moved, one
    /// parallel pass over every slot writes them in place, four neighbours
    /// at a time on SIMD lanes (reading a flag a slot costs less than
    /// gathering the moved ones by slot); when few did, a loop over those.
    fn place_bounds(&mut self) -> Vec<u32> {
        let b = &mut self.bodies;
        let mut dirty = std::mem::take(&mut b.dirty);
        if dirty.len() * DENSE_PLACE >= b.shapes.len() {
            let chunks = (
                b.spheres.par_chunks_mut(PLACE_CHUNK),
                b.obbs.par_chunks_mut(PLACE_CHUNK),
                b.leaves.par_chunks_mut(PLACE_CHUNK),
                b.is_dirty.par_chunks_mut(PLACE_CHUNK),
                b.shapes.par_chunks(PLACE_CHUNK),
                b.poses.par_chunks(PLACE_CHUNK),
            );
            // Written out here: the same loop as a function of its own was
            // measurably slower, inlined or not (docs/performance.md).
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
        // Half the margin a body, so that bodies within it of each other
        // overlap, and a position's f32 rounding, so that the bounds hold
        // the body where its f64 position puts it: a pass of its own, which
        // a world with neither skips.
        let half = self.config.margin * 0.5;
        if half > 0.0 || b.far {
            for &s in &dirty {
                let i = s as usize;
                let rounding = (b.position(i) - b.poses[i].position.as_dvec3()).length();
                let pad = (f64::from(half) + rounding) as f32;
                let tight = WorldBounds { sphere: b.spheres[i], obb: b.obbs[i], aabb: b.leaves[i] };
                let w = tight.grown(pad.next_up());
                (b.spheres[i], b.obbs[i], b.leaves[i]) = (w.sphere, w.obb, w.aabb);
            }
        }
        dirty
    }

    /// Moves the moved bodies' leaves and adds the new ones, each
    /// broadphase in one call for each (the tree picks per-leaf updates or a
    /// refit by the fraction moved, and takes many new leaves at once, a
    /// level load, in one batch build).
    fn update_broadphases(&mut self, placed: &[u32], leaves: &mut [Vec<(u32, Aabb)>; 4]) {
        let [moving, resting, new_moving, new_resting] = leaves;
        for list in [&mut *moving, &mut *resting, &mut *new_moving, &mut *new_resting] {
            list.clear();
        }
        // Where many moved, the moving broadphase reads its leaves' boxes from
        // the slot array, in its own order: the tree then refits in parallel
        // subtrees, where a list is placed a leaf at a time.
        let dense = placed.len() * DENSE_SHARE >= self.moving.len();
        for &slot in placed {
            let leaf = self.bodies.leaves[slot as usize];
            let dynamic = self.bodies.kinds[slot as usize] == BodyKind::Dynamic;
            let (broadphase, moved, new) = if dynamic {
                (&self.moving, &mut *moving, &mut *new_moving)
            } else {
                (&self.resting, &mut *resting, &mut *new_resting)
            };
            if !broadphase.contains(slot) {
                new.push((slot, leaf));
            } else if !(dynamic && dense) {
                moved.push((slot, leaf));
            }
        }
        // Every id is live, in its broadphase or new to it, and every box
        // finite: none of these can fail.
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
    /// `(lower slot, higher slot)`, in the broadphases' order, into `pairs`.
    fn candidates(&mut self, pairs: &mut Vec<(u32, u32)>) {
        self.moving.cached_pairs_into(&mut self.moving_pairs, pairs);
        let within = pairs.len();
        self.moving.pairs_with(&self.resting, pairs);
        for (a, b) in &mut pairs[within..] {
            (*a, *b) = (*a.min(b), *a.max(b));
        }
        // Every pair passes while no body filters (each on some layer, and
        // colliding with all): then the pass over them is skipped.
        let b = &self.bodies;
        if b.filtering > 0 {
            pairs.retain(|&(x, y)| {
                let (x, y) = (x as usize, y as usize);
                b.layers[x] & b.masks[y] != 0 && b.layers[y] & b.masks[x] != 0
            });
        }
    }
}

/// The moving broadphase reads every leaf's box from the slot array when at
/// least one body in this many of those it holds moved (see
/// `update_broadphases`).
const DENSE_SHARE: usize = 2;

/// The pairs for which `keep` holds, in order, tested in parallel chunks.
/// The pairs come in the broadphases' order, their bodies scattered in the
/// slots: `ahead` asks for the data `keep` will read of both bodies
/// [`FILTER_AHEAD`] pairs early, since a large world's bounds are past the
/// caches. Into `out`.
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
