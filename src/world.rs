//! The world: bodies in structure-of-arrays slots, their world bounds, two
//! broadphases (moving bodies, and resting ones: static and sleeping), and
//! the per-pair state the frame keeps. Its frame, [`World::update`], is in
//! `pipeline.rs`.

use std::sync::Arc;

use bvol_narrow::{Contact, WarmStart};
use bvol_tree::Tree;
use bvol_volumes::{Aabb, DPose, Obb, Pose, Ray, Sphere, prefetch};
use glam::{DVec3, Vec3};
use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::bodies::{BODIES_AHEAD, Bodies};
use crate::broadphase::Broadphase;
use crate::config::WorldConfig;
use crate::event::{ContactEvent, contact_of};
use crate::limits::{MAX_COORDINATE, placeable};
use crate::narrow_phase::{PairStates, anchored_contact, points_at};
use crate::scratch::Scratch;
use crate::stats::FrameStats;
use crate::{BodyDesc, BodyId, BodyKind, Shape, WorldError};

/// Bodies that collide: add them, move them, and [`update`](World::update)
/// once per frame for the contacts that began, persist and ended (see the
/// crate docs for a whole loop).
///
/// ```
/// use std::sync::Arc;
/// use bvol::volumes::{Pose, Ray};
/// use bvol::{BodyDesc, Shape, World};
/// use glam::{Quat, Vec3};
///
/// let mut world = World::new();
/// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
/// let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY).with_user_data(7))?;
/// world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 0.9, Quat::IDENTITY)))?;
/// world.update();
/// assert_eq!(world.events().len(), 1); // the two cubes overlap by 0.1
/// let hit = world.ray_cast(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), 100.0).unwrap();
/// assert_eq!((hit.body, hit.user_data), (a, 7));
/// assert!((hit.t - 4.5).abs() < 1e-5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Two bodies touch when their shapes overlap or meet: touching exactly, a
/// contact of depth 0, counts (rapier, for one, does not count it).
/// [`contacts`](World::contacts) lists the pairs touching at the last
/// update and [`contact`](World::contact) answers for one pair. A world made
/// with a [`margin`](WorldConfig::margin) counts pairs apart by at most the
/// margin as in contact too: their events, listed contacts and answers
/// have negative depths.
///
/// Its broadphase is the dynamic tree unless another is named:
/// `World::<BruteForce>::default()` tests every pair (see [`Broadphase`]).
#[derive(Debug, Default)]
pub struct World<B: Broadphase = Tree<Aabb>> {
    pub(crate) bodies: Bodies,
    /// Dynamic bodies, by slot.
    pub(crate) moving: B,
    /// The moving broadphase's pairs, kept from update to update.
    pub(crate) moving_pairs: B::Cache,
    /// Static and sleeping bodies, by slot: never tested against each other.
    pub(crate) resting: B,
    /// State of each pair that reached the narrow phase last frame, by
    /// `(lower slot, higher slot)`, sorted.
    pub(crate) pairs: PairStates,
    /// Pairs that touched and lost a body since the last update.
    pub(crate) orphaned: Vec<ContactEvent>,
    pub(crate) events: Vec<ContactEvent>,
    /// The contacts of the touching pairs kept untested at the last update
    /// (both bodies resting), by `(lower slot, higher slot)`, sorted: the
    /// touching pairs are these and those of the events.
    pub(crate) rested: Vec<((u32, u32), Contact)>,
    pub(crate) config: WorldConfig,
    /// The thread pool of `config.threads`, if it names one.
    pub(crate) pool: Option<Arc<ThreadPool>>,
    pub(crate) stats: FrameStats,
    /// The buffers of a frame's lists, kept from frame to frame.
    pub(crate) scratch: Scratch,
}

impl World {
    /// An empty world, its broadphase the dynamic tree, with the default
    /// [`WorldConfig`].
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty world set up by `config`, its broadphase the dynamic tree;
    /// its own thread pool, if `config` names one, started now.
    pub fn with_config(config: WorldConfig) -> Result<Self, WorldError> {
        let margin = config.margin;
        if !(0.0..=MAX_COORDINATE).contains(&margin) {
            return Err(WorldError::BadMargin { margin });
        }
        if WarmStart::reusing(config.reuse).is_err() {
            return Err(WorldError::BadReuse { reuse: config.reuse });
        }
        let pool = match config.threads {
            None => None,
            Some(threads @ 1..=WorldConfig::MAX_THREADS) => {
                let pool = ThreadPoolBuilder::new().num_threads(threads).build();
                Some(Arc::new(pool.map_err(|_| WorldError::BadThreads { threads })?))
            }
            Some(threads) => return Err(WorldError::BadThreads { threads }),
        };
        Ok(World { config, pool, ..Self::default() })
    }
}

impl<B: Broadphase> World<B> {
    /// How the world was set up.
    pub fn config(&self) -> &WorldConfig {
        &self.config
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.bodies.count
    }

    /// Whether there is no body.
    pub fn is_empty(&self) -> bool {
        self.bodies.count == 0
    }

    /// Adds a body. Its bounds enter the broadphase at the next update. Its pose
    /// must be one a world can place a body at (see [`WorldError::BadPose`]).
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyId, WorldError> {
        let b = &mut self.bodies;
        let index = match b.free.last() {
            Some(&i) => i,
            None if b.shapes.len() < B::ID_LIMIT as usize => b.shapes.len() as u32,
            None => return Err(WorldError::Full),
        };
        // A free slot's generation is even; a live body's is the next, odd.
        let generation = b.generations.get(index as usize).map_or(1, |g| g.wrapping_add(1));
        let id = BodyId { index, generation };
        check_pose(id, &desc.pose)?;
        if b.free.pop().is_none() {
            b.grow();
        }
        let i = index as usize;
        b.generations[i] = generation;
        b.poses[i] = desc.pose;
        b.positions[i] = desc.pose.position.as_dvec3();
        b.kinds[i] = desc.kind;
        b.user_data[i] = desc.user_data;
        b.layers[i] = desc.layers;
        b.masks[i] = desc.mask;
        b.shapes[i] = Some(desc.shape);
        b.count += 1;
        b.filtering += usize::from(b.filters(index));
        b.mark_dirty(index);
        Ok(id)
    }

    /// Removes a body. Its contacts end at the next update.
    pub fn remove_body(&mut self, id: BodyId) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        self.broadphase_of(self.bodies.kinds[i]).remove(id.index).ok();
        let mut orphaned = Vec::new();
        self.pairs.retain(|&((a, b), ref state)| {
            let gone = a == id.index || b == id.index;
            if gone && state.in_contact {
                orphaned.push((a, b));
            }
            !gone
        });
        for (a, b) in orphaned {
            self.orphaned.push(self.bodies.ended(a, b));
        }
        self.rested.retain(|&((a, b), _)| a != id.index && b != id.index);
        let b = &mut self.bodies;
        b.filtering -= usize::from(b.filters(id.index));
        b.shapes[i] = None;
        b.removed = true;
        // Even again: no handle given out matches a free slot.
        b.generations[i] = b.generations[i].wrapping_add(1);
        b.free.push(id.index);
        b.count -= 1;
        Ok(())
    }

    /// Moves one body.
    pub fn set_pose(&mut self, id: BodyId, pose: Pose) -> Result<(), WorldError> {
        self.set_poses(&[id], &[pose])
    }

    /// Moves many bodies: `poses[k]` is the new pose of `ids[k]`. Every id
    /// and pose is checked first (a pose as [`WorldError::BadPose`] says): on
    /// error nothing has moved.
    ///
    /// A pose equal to the body's current one moves nothing, so handing
    /// over every pose each frame costs little for bodies at rest: the next
    /// update neither places their bounds again nor tests a pair of two of
    /// them, whose contact stays the last one (what a test would give).
    pub fn set_poses(&mut self, ids: &[BodyId], poses: &[Pose]) -> Result<(), WorldError> {
        if ids.len() != poses.len() {
            return Err(WorldError::LengthMismatch { bodies: ids.len(), poses: poses.len() });
        }
        // One pass tells whether all are good; the first bad one is named.
        if let Some(k) = ids.iter().zip(poses).position(|(&id, p)| !self.live(id) || !placeable(p))
        {
            self.slot(ids[k])?;
            check_pose(ids[k], &poses[k])?;
        }
        let b = &mut self.bodies;
        for (k, (&id, &pose)) in ids.iter().zip(poses).enumerate() {
            // Asked for ahead, the poses' slots (in any order the caller
            // likes) do not hold up the copy.
            if let Some(later) = ids.get(k + BODIES_AHEAD) {
                prefetch(&b.poses[later.index as usize]);
            }
            b.move_to(id.index as usize, pose, pose.position.as_dvec3());
        }
        Ok(())
    }

    /// Moves many bodies to poses whose positions are f64: for worlds that
    /// reach far from the origin, where f32 steps are coarser than the
    /// bodies (about 1e-3 at 1e4, 8 at 1e8). Checked as
    /// [`set_poses`](Self::set_poses) checks (a position is checked as its
    /// f32 rounding); on error nothing has moved.
    ///
    /// A pair is then tested on the second body's position relative to the
    /// first's, taken in f64, so its contact is as precise wherever the
    /// pair is (and [`contact_points_f64`](Self::contact_points_f64) gives
    /// its points in f64). The bounds and the broadphase stay f32: each
    /// body's bounds grow by its position's rounding, so no pair is missed,
    /// but where f32 steps are much coarser than the bodies, their bounds
    /// are that much larger and the broadphase passes on more pairs
    /// (`World::stats` shows how many). Positions given in f32 are exact
    /// in f64, and a world given only those works as before.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::glam::{DVec3, Quat, Vec3};
    /// use bvol::volumes::{DPose, Pose};
    /// use bvol::{BodyDesc, Shape, World};
    ///
    /// let mut world = World::new();
    /// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
    /// let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
    /// let b = world.add_body(BodyDesc::new(cube, Pose::IDENTITY))?;
    /// let far = DVec3::new(1e8, -3e7, 5e6);
    /// let poses = [far, far + DVec3::X * 0.9].map(|p| DPose::new(p, Quat::IDENTITY));
    /// world.set_poses_f64(&[a, b], &poses)?;
    /// world.update();
    /// let contact = world.contact(a, b)?.expect("0.1 deep");
    /// assert!((contact.depth - 0.1).abs() < 1e-5);
    /// let points = world.contact_points_f64(a, b)?;
    /// assert!(points.iter().all(|p| (p.x - (far.x + 0.45)).abs() < 1e-5));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_poses_f64(&mut self, ids: &[BodyId], poses: &[DPose]) -> Result<(), WorldError> {
        if ids.len() != poses.len() {
            return Err(WorldError::LengthMismatch { bodies: ids.len(), poses: poses.len() });
        }
        for (&id, pose) in ids.iter().zip(poses) {
            self.slot(id)?;
            check_pose(id, &pose.to_pose())?;
        }
        let b = &mut self.bodies;
        for (&id, pose) in ids.iter().zip(poses) {
            let rounded = pose.to_pose();
            if rounded.position.as_dvec3() != pose.position {
                b.go_far();
            }
            b.move_to(id.index as usize, rounded, pose.position);
        }
        Ok(())
    }

    /// A body's pose with its position as given, in f64 (see
    /// [`set_poses_f64`](Self::set_poses_f64)).
    pub fn pose_f64(&self, id: BodyId) -> Result<DPose, WorldError> {
        let i = self.slot(id)?;
        Ok(DPose::new(self.bodies.position(i), self.bodies.poses[i].rotation))
    }

    /// The points of bodies `a` and `b`'s contact at their poses now, in
    /// f64: those of [`contact`](Self::contact)'s after an update, in the
    /// same order, to the precision of the bodies' f64 positions (the
    /// contact's own are f32). Empty if they are not in contact.
    pub fn contact_points_f64(&self, a: BodyId, b: BodyId) -> Result<Vec<DVec3>, WorldError> {
        let (i, j) = (self.slot(a)? as u32, self.slot(b)? as u32);
        let (lo, hi) = (i.min(j), i.max(j));
        let found = anchored_contact(&self.bodies, lo, hi, &self.config);
        Ok(found.map_or_else(Vec::new, |(contact, anchor)| points_at(&contact, anchor).collect()))
    }

    /// Changes how a body takes part: a sleeping or static body moves to
    /// the resting broadphase, a dynamic one to the moving broadphase.
    pub fn set_kind(&mut self, id: BodyId, kind: BodyKind) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        let old = self.bodies.kinds[i];
        if (old == BodyKind::Dynamic) != (kind == BodyKind::Dynamic) {
            self.broadphase_of(old).remove(id.index).ok();
            self.bodies.mark_dirty(id.index);
        }
        self.bodies.kinds[i] = kind;
        Ok(())
    }

    /// A body's pose.
    pub fn pose(&self, id: BodyId) -> Result<Pose, WorldError> {
        Ok(self.bodies.poses[self.slot(id)?])
    }

    /// A body's kind.
    pub fn kind(&self, id: BodyId) -> Result<BodyKind, WorldError> {
        Ok(self.bodies.kinds[self.slot(id)?])
    }

    /// A body's user data.
    pub fn user_data(&self, id: BodyId) -> Result<u64, WorldError> {
        Ok(self.bodies.user_data[self.slot(id)?])
    }

    /// A body's shape.
    pub fn shape(&self, id: BodyId) -> Result<&Arc<Shape>, WorldError> {
        let i = self.slot(id)?;
        Ok(self.bodies.shapes[i].as_ref().expect("slot checked"))
    }

    /// A body's bounding sphere in the world, as of the last update (grown
    /// by half the world's [`margin`](WorldConfig::margin), as its OBB and
    /// box are).
    pub fn world_sphere(&self, id: BodyId) -> Result<Sphere, WorldError> {
        let i = self.slot(id)?;
        Ok(self.bodies.spheres[i])
    }

    /// A body's oriented bounding box in the world, as of the last update.
    pub fn world_obb(&self, id: BodyId) -> Result<Obb, WorldError> {
        Ok(self.bodies.obbs[self.slot(id)?])
    }

    /// Every body, in slot order.
    pub fn bodies(&self) -> impl Iterator<Item = BodyId> + '_ {
        let b = &self.bodies;
        (0..b.shapes.len())
            .filter(|&i| b.shapes[i].is_some())
            .map(|i| BodyId { index: i as u32, generation: b.generations[i] })
    }

    /// A body's box in the broadphase (around its world sphere and OBB), as
    /// of the last update.
    pub fn world_aabb(&self, id: BodyId) -> Result<Aabb, WorldError> {
        Ok(self.bodies.leaves[self.slot(id)?])
    }

    /// The dynamic bodies' broadphase (its leaves are slots), for
    /// inspection: its nodes are what a debug view draws.
    pub fn moving_broadphase(&self) -> &B {
        &self.moving
    }

    /// The static and sleeping bodies' broadphase, for inspection.
    pub fn resting_broadphase(&self) -> &B {
        &self.resting
    }

    /// The nearest body a ray meets within `max_t`, as of the last update:
    /// the broadphases give candidates nearest first, each tested on its OBB and
    /// then on its shape. Ties go to the lower slot.
    pub fn ray_cast(&self, ray: &Ray, max_t: f32) -> Option<RayHit> {
        // The shape lies inside its leaf: its entry is never before the
        // leaf's, but rounding may say so by an ulp, and the tree's search
        // needs it not to.
        let exact = |slot: u32, t: f32| self.ray_entry(slot, ray, max_t).map(|d| d.max(t));
        let hits =
            [self.moving.ray_cast(ray, max_t, exact), self.resting.ray_cast(ray, max_t, exact)];
        let (slot, t) =
            hits.into_iter().flatten().min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))?;
        let body = self.bodies.id_of(slot);
        let user_data = self.bodies.user_data[slot as usize];
        Some(RayHit { body, t, point: ray.origin + ray.direction * t, user_data })
    }

    /// Calls `found` for every body whose box (see
    /// [`world_aabb`](Self::world_aabb)) overlaps or touches `region`, as of
    /// the last update: the moving bodies, then the resting ones, each in
    /// its broadphase's order.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::volumes::{Aabb, Pose};
    /// use bvol::{BodyDesc, Shape, World};
    /// use glam::{Quat, Vec3};
    ///
    /// let mut world = World::new();
    /// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
    /// let near = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
    /// world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 5.0, Quat::IDENTITY)))?;
    /// world.update();
    /// let mut found = Vec::new();
    /// world.query(&Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)), |id| found.push(id));
    /// assert_eq!(found, [near]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query(&self, region: &Aabb, mut found: impl FnMut(BodyId)) {
        for broadphase in [&self.moving, &self.resting] {
            broadphase.query(region, |slot| found(self.bodies.id_of(slot)));
        }
    }

    /// Where a ray meets body `slot`: its world OBB first, then its shape in
    /// the body's frame (a rigid map keeps the ray's parameter).
    fn ray_entry(&self, slot: u32, ray: &Ray, max_t: f32) -> Option<f32> {
        let i = slot as usize;
        self.bodies.obbs[i].ray_entry(ray, max_t)?;
        let inverse = self.bodies.poses[i].inverse();
        let local =
            Ray::new(inverse.transform_point(ray.origin), inverse.transform_vector(ray.direction));
        self.bodies.shapes[i].as_ref()?.ray_entry(&local, max_t)
    }

    /// The events of the last update: contacts that began, persisted and
    /// ended, ordered by the bodies' slots.
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// Every pair of bodies touching at the last update, with its contact
    /// (the normal from the first body to the second), ordered by the
    /// bodies' slots, the lower slot first: those tested (whose events
    /// began or persist) and those kept untested because both bodies rest,
    /// with the contact they had when last tested. A pair that lost a body
    /// since is left out. Touching includes touching exactly: a contact of
    /// depth 0. With a [`margin`](WorldConfig::margin), the pairs apart by
    /// at most the margin are listed too, with their negative depths.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::glam::{Quat, Vec3};
    /// use bvol::volumes::Pose;
    /// use bvol::{BodyDesc, Shape, World};
    ///
    /// let mut world = World::new();
    /// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
    /// let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
    /// let b = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 0.9, Quat::IDENTITY)))?;
    /// world.update();
    /// let touching: Vec<_> = world.contacts().map(|(a, b, _)| (a, b)).collect();
    /// assert_eq!(touching, [(a, b)]);
    /// let contact = world.contact(b, a)?.expect("they overlap");
    /// assert!(contact.normal.x < -0.99); // from b to a
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn contacts(&self) -> impl Iterator<Item = (BodyId, BodyId, Contact)> + '_ {
        let key = |p: &(BodyId, BodyId, Contact)| (p.0.index, p.1.index);
        let mut tested = self.events.iter().filter_map(|e| Some((e.a, e.b, e.contact?))).peekable();
        let mut rested = self
            .rested
            .iter()
            .map(|&((a, b), c)| (self.bodies.id_of(a), self.bodies.id_of(b), c))
            .peekable();
        // Two sorted lists of distinct pairs, merged.
        let merged = std::iter::from_fn(move || match (tested.peek(), rested.peek()) {
            (Some(t), Some(r)) if key(r) < key(t) => rested.next(),
            (Some(_), _) => tested.next(),
            (None, _) => rested.next(),
        });
        merged.filter(|&(a, b, _)| self.live(a) && self.live(b))
    }

    /// How bodies `a` and `b` touched at the last update (as
    /// [`contacts`](Self::contacts) has it), the normal pointing from `a` to
    /// `b` whichever of them has the lower slot; `None` if they did not
    /// touch (or, with a [`margin`](WorldConfig::margin), come within it).
    pub fn contact(&self, a: BodyId, b: BodyId) -> Result<Option<Contact>, WorldError> {
        self.slot(a)?;
        self.slot(b)?;
        if a.index <= b.index {
            return Ok(self.last_contact(a, b));
        }
        // The points lie midway between the surfaces: only the normal turns.
        let flip = |mut c: Contact| {
            c.normal = -c.normal;
            c
        };
        Ok(self.last_contact(b, a).map(flip))
    }

    /// The contact of the pair of bodies `a` and `b` (`a` in the lower
    /// slot) at the last update, if they touched: among its events (those
    /// of these very bodies: a removed body's slot may be held by another
    /// since) or its kept contacts.
    pub(crate) fn last_contact(&self, a: BodyId, b: BodyId) -> Option<Contact> {
        let key = (a.index, b.index);
        let from = self.events.partition_point(|e| e.slots() < key);
        let tested = contact_of(&self.events[from..], a, b);
        let rested = || {
            let k = self.rested.binary_search_by_key(&key, |&(k, _)| k).ok()?;
            Some(self.rested[k].1)
        };
        tested.or_else(rested)
    }

    /// The counts and times of the last update's stages.
    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    /// The slot of a live body.
    pub(crate) fn slot(&self, id: BodyId) -> Result<usize, WorldError> {
        if self.live(id) { Ok(id.index as usize) } else { Err(WorldError::UnknownBody(id)) }
    }

    /// Whether `id` names a body in this world. Handles are given out with
    /// odd generations and a slot's generation is odd only while a body
    /// holds it (wrapping keeps the parity), so one compare tells, without
    /// reading the shapes (`set_poses` checks every id it is given).
    #[inline]
    fn live(&self, id: BodyId) -> bool {
        self.bodies.generations.get(id.index as usize) == Some(&id.generation)
    }

    /// Whether a broadphase holds the body in `slot`: it was placed since
    /// it was added or changed broadphase.
    #[cfg(feature = "serde")]
    pub(crate) fn broadphase_holds(&self, slot: u32) -> bool {
        self.moving.contains(slot) || self.resting.contains(slot)
    }

    /// The broadphase that holds bodies of `kind`.
    pub(crate) fn broadphase_of(&mut self, kind: BodyKind) -> &mut B {
        if kind == BodyKind::Dynamic { &mut self.moving } else { &mut self.resting }
    }
}

/// Where a ray met a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The body.
    pub body: BodyId,
    /// The ray's parameter at the hit (a distance for a unit direction).
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// The body's user data.
    pub user_data: u64,
}

/// `Ok` when a body can be placed at `pose` (see [`placeable`]).
fn check_pose(body: BodyId, pose: &Pose) -> Result<(), WorldError> {
    if placeable(pose) { Ok(()) } else { Err(WorldError::BadPose { body, pose: *pose }) }
}
