//! Snapshots (feature `serde`): a world saved as plain data in any serde
//! format, and loaded back to run on exactly as the original would have.
//!
//! What a world's next updates and queries read is saved: its settings,
//! its shapes (each once, however many bodies share it; a hull part as its
//! hull, from which its polyhedron is built again to the bit), its bodies
//! and slots with their world bounds as of the last update, which of them
//! moved since, the state of each pair (whether it was in contact, whether
//! it was tested) and the last update's events and kept contacts. The rest
//! is built again on loading: the broadphases, from the saved boxes (their
//! pairs are the same, in whatever tree order, and are sorted by slot
//! before the narrow phase; their queries' order may differ), and the warm
//! starts, which speed a pair's test but never change its answer, unless
//! the world reuses contact features ([`WorldConfig::reuse`]): then a
//! loaded world tests its touching pairs in full at its first update, and
//! its contacts may differ from the saved world's there within the reuse's
//! bound (whether pairs touch, and so the events, are the same).

use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use bvol_narrow::{Capsule, Contact, ContactPoint, HullPart, HullSource, Part};
use bvol_volumes::{Aabb, BodyBounds, ConvexHull, DPose, Obb, Sphere};
use glam::{DVec3, Mat3, Vec3};
use serde::{Deserialize, Serialize};

use crate::event::{ContactEvent, EventKind};
use crate::limits::{placeable, within_limit};
use crate::narrow_phase::PairState;
use crate::{BodyId, BodyKind, FitOptions, Shape, World, WorldConfig, WorldError};

/// The snapshot format's version: a snapshot of another is refused.
const VERSION: u32 = 1;

/// A world saved ([`World::snapshot`]), to be written in any serde format
/// and loaded back ([`World::from_snapshot`]). The format must give floats
/// back to the bit: serde_json does with its `float_roundtrip` feature (its
/// default parser may be off by an ulp, and a hull's plane so moved changes
/// contacts), binary formats do.
///
/// ```
/// use std::sync::Arc;
/// use bvol::glam::{Quat, Vec3};
/// use bvol::volumes::Pose;
/// use bvol::{BodyDesc, Shape, Snapshot, World};
///
/// let mut world = World::new();
/// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
/// let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
/// let b = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 0.9, Quat::IDENTITY)))?;
/// world.update();
/// let saved = serde_json::to_string(&world.snapshot())?;
/// let mut loaded = World::from_snapshot(&serde_json::from_str::<Snapshot>(&saved)?)?;
/// assert_eq!(loaded.contact(a, b)?, world.contact(a, b)?);
/// let moved = Pose::new(Vec3::X * 0.8, Quat::IDENTITY);
/// for w in [&mut world, &mut loaded] {
///     w.set_pose(b, moved)?;
///     w.update();
/// }
/// assert_eq!(loaded.events(), world.events());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshot {
    version: u32,
    threads: Option<usize>,
    margin: f32,
    /// The reuse tolerance; absent in snapshots of worlds before it (none).
    #[serde(default)]
    reuse: f32,
    shapes: Vec<ShapeData>,
    /// Each slot's generation, and its body if it holds one.
    slots: Vec<(u32, Option<BodyData>)>,
    /// The free slots, the next taken last.
    free: Vec<u32>,
    /// The bodies whose poses changed since the last update, in order.
    dirty: Vec<u32>,
    /// Whether the world tests pairs on relative f64 positions (once given
    /// one that is not an f32's, it does from then on).
    far: bool,
    /// `(lower slot, higher slot, in contact, tested)`, sorted.
    pairs: Vec<(u32, u32, bool, bool)>,
    events: Vec<EventData>,
    orphaned: Vec<EventData>,
    rested: Vec<(u32, u32, ContactData)>,
}

/// A sphere saved: its centre and radius.
type SphereData = (Vec3, f32);
/// An OBB saved: its centre, axes and half extents.
type ObbData = (Vec3, Mat3, Vec3);

#[derive(Clone, Debug, Serialize, Deserialize)]
struct ShapeData {
    parts: Vec<PartData>,
    sphere: SphereData,
    obb: ObbData,
    fit: (String, String),
}

#[derive(Clone, Debug, Serialize, Deserialize)]
enum PartData {
    Ball { center: Vec3, radius: f32 },
    Capsule { radius: f32, half_height: f32 },
    Cuboid { half_extents: Vec3 },
    Hull { vertices: Vec<Vec3>, faces: Vec<Vec<u32>>, planes: Vec<(DVec3, f64)>, tolerance: f64 },
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct BodyData {
    shape: usize,
    /// As given: in f64.
    position: DVec3,
    rotation: glam::Quat,
    kind: u8,
    user_data: u64,
    layers: u32,
    mask: u32,
    /// Its world sphere, OBB and box as of the last update, if it is in a
    /// broadphase (placed since it was added or changed broadphase).
    placed: Option<PlacedData>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct PlacedData {
    sphere: SphereData,
    obb: ObbData,
    leaf: (Vec3, Vec3),
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct EventData {
    kind: u8,
    a: u64,
    b: u64,
    user_data: (u64, u64),
    contact: Option<ContactData>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct ContactData {
    normal: Vec3,
    depth: f32,
    points: Vec<(Vec3, f32)>,
}

/// Why a snapshot could not be loaded: what in it is wrong, and where.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SnapshotError {
    /// It was written by another version of the format.
    Version {
        /// Its version.
        found: u32,
    },
    /// Its settings are refused ([`World::with_config`]).
    Config(WorldError),
    /// A shape, or one of its parts, cannot be built.
    Shape {
        /// The shape's index in the snapshot.
        shape: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A slot's body or generation, or the free list, is not one a world has.
    Slot {
        /// The slot.
        slot: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A pair's state names a free slot, or the pairs are out of order.
    Pair {
        /// Its index among the pairs.
        pair: usize,
    },
    /// An event or kept contact is out of order, names a slot beyond the
    /// world, or has a contact that is not finite (or none where it needs one).
    Event {
        /// Its index among the events, then the removed bodies' events,
        /// then the kept contacts.
        event: usize,
    },
}

impl fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SnapshotError::Version { found } => {
                write!(f, "snapshot version {found}; this bvol reads version {VERSION}")
            }
            SnapshotError::Config(e) => write!(f, "snapshot settings: {e}"),
            SnapshotError::Shape { shape, reason } => write!(f, "snapshot shape {shape}: {reason}"),
            SnapshotError::Slot { slot, reason } => write!(f, "snapshot slot {slot}: {reason}"),
            SnapshotError::Pair { pair } => {
                write!(f, "snapshot pair {pair}: out of order, or a body that is not there")
            }
            SnapshotError::Event { event } => write!(
                f,
                "snapshot event {event}: out of order, beyond the slots, or with a bad contact"
            ),
        }
    }
}

impl std::error::Error for SnapshotError {}

impl World {
    /// The world saved: what its next updates read (see [`Snapshot`]).
    /// A world of many distinct hull shapes takes about as long as building
    /// them did: each hull part is built again to check that its hull
    /// makes it.
    pub fn snapshot(&self) -> Snapshot {
        let b = &self.bodies;
        let mut shapes: Vec<ShapeData> = Vec::new();
        // Each shape once, by the address all its bodies share.
        let mut index: HashMap<*const Shape, usize> = HashMap::new();
        let slots = (0..b.shapes.len())
            .map(|i| {
                let body = b.shapes[i].as_ref().map(|shape| {
                    let shape = *index.entry(Arc::as_ptr(shape)).or_insert_with(|| {
                        shapes.push(shape_data(shape));
                        shapes.len() - 1
                    });
                    BodyData {
                        shape,
                        position: b.position(i),
                        rotation: b.poses[i].rotation,
                        kind: kind_code(b.kinds[i]),
                        user_data: b.user_data[i],
                        layers: b.layers[i],
                        mask: b.masks[i],
                        placed: self.broadphase_holds(i as u32).then(|| placed_data(b, i)),
                    }
                });
                (b.generations[i], body)
            })
            .collect();
        let pairs = self.pairs.iter().map(|&((x, y), ref s)| (x, y, s.in_contact, s.tested));
        Snapshot {
            version: VERSION,
            threads: self.config.threads,
            margin: self.config.margin,
            reuse: self.config.reuse,
            shapes,
            slots,
            free: b.free.clone(),
            dirty: b.dirty.iter().copied().filter(|&s| b.shapes[s as usize].is_some()).collect(),
            far: b.far,
            pairs: pairs.collect(),
            events: self.events.iter().map(event_data).collect(),
            orphaned: self.orphaned.iter().map(event_data).collect(),
            rested: self.rested.iter().map(|&((x, y), c)| (x, y, contact_data(&c))).collect(),
        }
    }

    /// The world a snapshot saved, to run on as that world would have: the
    /// same events, update after update, for the same calls, on any number
    /// of threads. Data no world could have saved (truncated, out of order,
    /// not finite, a hull that is not one) is a [`SnapshotError`] naming
    /// what and where; the format's own errors come from its reader.
    pub fn from_snapshot(snapshot: &Snapshot) -> Result<World, SnapshotError> {
        let s = snapshot;
        if s.version != VERSION {
            return Err(SnapshotError::Version { found: s.version });
        }
        let config = WorldConfig { threads: s.threads, margin: s.margin, reuse: s.reuse };
        let mut world = World::with_config(config).map_err(SnapshotError::Config)?;
        let shapes = (0..s.shapes.len())
            .map(|k| {
                let error = |reason: String| SnapshotError::Shape { shape: k, reason };
                shape_of(&s.shapes[k]).map(Arc::new).map_err(error)
            })
            .collect::<Result<Vec<_>, _>>()?;
        restore_slots(&mut world, s, &shapes)?;
        restore_broadphases(&mut world, s)?;
        let live = |slot: u32| world.bodies.shapes.get(slot as usize).is_some_and(Option::is_some);
        let mut pairs = Vec::with_capacity(s.pairs.len());
        for (k, &(x, y, in_contact, tested)) in s.pairs.iter().enumerate() {
            let ordered = pairs.last().is_none_or(|&(key, _)| key < (x, y));
            if !(x < y && live(x) && live(y) && ordered) {
                return Err(SnapshotError::Pair { pair: k });
            }
            pairs.push(((x, y), PairState { in_contact, tested, ..PairState::default() }));
        }
        let slots = world.bodies.shapes.len();
        let events = events_of(&s.events, slots, 0, true)?;
        let orphaned = events_of(&s.orphaned, slots, s.events.len(), false)?;
        let mut rested = Vec::with_capacity(s.rested.len());
        for (k, (x, y, c)) in s.rested.iter().enumerate() {
            let event = s.events.len() + s.orphaned.len() + k;
            let ordered = rested.last().is_none_or(|&(key, _)| key < (*x, *y));
            let contact = contact_of(c).filter(|_| x < y && live(*x) && live(*y) && ordered);
            rested.push(((*x, *y), contact.ok_or(SnapshotError::Event { event })?));
        }
        (world.pairs, world.events, world.orphaned, world.rested) =
            (pairs, events, orphaned, rested);
        Ok(world)
    }
}

/// The slots, their bodies and the free list into `world` (empty).
fn restore_slots(
    world: &mut World,
    s: &Snapshot,
    shapes: &[Arc<Shape>],
) -> Result<(), SnapshotError> {
    let b = &mut world.bodies;
    b.far = s.far;
    if s.slots.len() > <bvol_tree::Tree<Aabb> as crate::Broadphase>::ID_LIMIT as usize {
        return Err(SnapshotError::Slot {
            slot: s.slots.len(),
            reason: "more slots than a world has",
        });
    }
    for (i, (generation, body)) in s.slots.iter().enumerate() {
        let bad = |reason| SnapshotError::Slot { slot: i, reason };
        b.grow();
        b.generations[i] = *generation;
        let Some(body) = body else {
            if generation % 2 == 1 {
                return Err(bad("a free slot with the generation of a live one (odd)"));
            }
            continue;
        };
        if generation % 2 == 0 {
            return Err(bad("a body in a slot with the generation of a free one (even)"));
        }
        let shape = shapes.get(body.shape).ok_or(bad("a body of a shape not in the snapshot"))?;
        let pose = DPose::new(body.position, body.rotation).to_pose();
        if !placeable(&pose) {
            return Err(bad("a pose a world cannot place a body at"));
        }
        b.shapes[i] = Some(shape.clone());
        (b.poses[i], b.positions[i]) = (pose, body.position);
        if !s.far && pose.position.as_dvec3() != body.position {
            return Err(bad("an f64 position that is not an f32's in a world that had none"));
        }
        b.kinds[i] = kind_of(body.kind).ok_or(bad("a kind that is not 0, 1 or 2"))?;
        (b.user_data[i], b.layers[i], b.masks[i]) = (body.user_data, body.layers, body.mask);
        b.count += 1;
        b.filtering += usize::from(b.filters(i as u32));
    }
    let mut seen = vec![false; s.slots.len()];
    for &slot in &s.free {
        let bad = |reason| SnapshotError::Slot { slot: slot as usize, reason };
        let free = b.shapes.get(slot as usize).is_some_and(Option::is_none);
        if !free || std::mem::replace(&mut seen[slot as usize], true) {
            return Err(bad("the free list names a slot that holds a body, twice, or none"));
        }
    }
    if s.free.len() + b.count != s.slots.len() {
        return Err(SnapshotError::Slot {
            slot: s.slots.len(),
            reason: "a free slot not on the free list",
        });
    }
    b.free = s.free.clone();
    Ok(())
}

/// The saved bodies' bounds into `world`'s arrays and broadphases, and its
/// moved bodies marked.
fn restore_broadphases(world: &mut World, s: &Snapshot) -> Result<(), SnapshotError> {
    let (mut moving, mut resting) = (Vec::new(), Vec::new());
    for (i, (_, body)) in s.slots.iter().enumerate() {
        let Some(placed) = body.as_ref().and_then(|body| body.placed.as_ref()) else { continue };
        let bad = SnapshotError::Slot { slot: i, reason: "bounds that are not finite or empty" };
        let (sphere, obb, leaf) = placed_of(placed).ok_or(bad)?;
        let b = &mut world.bodies;
        (b.spheres[i], b.obbs[i], b.leaves[i]) = (sphere, obb, leaf);
        let list = if b.kinds[i] == BodyKind::Dynamic { &mut moving } else { &mut resting };
        list.push((i as u32, leaf));
    }
    // Finite, ordered boxes of distinct live slots: a tree takes them.
    world.moving.insert_many(&moving).ok();
    world.resting.insert_many(&resting).ok();
    for &slot in &s.dirty {
        let b = &mut world.bodies;
        let live = b.shapes.get(slot as usize).is_some_and(Option::is_some);
        if !live || b.is_dirty[slot as usize] {
            let reason = "the moved bodies name a free slot, or one twice";
            return Err(SnapshotError::Slot { slot: slot as usize, reason });
        }
        b.mark_dirty(slot);
    }
    // A body in no broadphase was added or changed broadphase since the
    // last update: it is among the moved ones.
    let b = &world.bodies;
    if let Some(slot) = (0..s.slots.len())
        .find(|&i| b.shapes[i].is_some() && !b.is_dirty[i] && !world.broadphase_holds(i as u32))
    {
        let reason = "a body with no bounds that did not move since the last update";
        return Err(SnapshotError::Slot { slot, reason });
    }
    Ok(())
}

/// A placed body's saved bounds.
fn placed_data(b: &crate::bodies::Bodies, i: usize) -> PlacedData {
    let leaf = b.leaves[i];
    PlacedData {
        sphere: sphere_data(&b.spheres[i]),
        obb: obb_data(&b.obbs[i]),
        leaf: (leaf.min, leaf.max),
    }
}

/// The bounds saved: finite, the box not empty.
fn placed_of(p: &PlacedData) -> Option<(Sphere, Obb, Aabb)> {
    let (sphere, obb) = (sphere_of(p.sphere)?, obb_of(p.obb)?);
    let (min, max) = p.leaf;
    let box_ok = min.is_finite() && max.is_finite() && min.cmple(max).all();
    box_ok.then(|| (sphere, obb, Aabb::new(min, max)))
}

fn sphere_data(sphere: &Sphere) -> SphereData {
    (sphere.center, sphere.radius)
}

fn obb_data(obb: &Obb) -> ObbData {
    (obb.center, obb.axes, obb.half_extents)
}

/// A saved sphere, if finite.
fn sphere_of((center, radius): SphereData) -> Option<Sphere> {
    (center.is_finite() && radius.is_finite()).then(|| Sphere::new(center, radius))
}

/// A saved OBB, if finite.
fn obb_of((center, axes, half_extents): ObbData) -> Option<Obb> {
    let finite = center.is_finite() && axes.is_finite() && half_extents.is_finite();
    finite.then_some(Obb { center, axes, half_extents })
}

/// A shape's saved form.
fn shape_data(shape: &Shape) -> ShapeData {
    let fit = shape.fit_options();
    ShapeData {
        parts: shape.parts().iter().map(part_data).collect(),
        sphere: sphere_data(&shape.sphere()),
        obb: obb_data(&shape.obb()),
        fit: (fit.sphere.name().to_owned(), fit.obb.name().to_owned()),
    }
}

/// A part's saved form: a hull part as its source, which builds it again
/// to the bit (every part a shape is made of has one).
fn part_data(part: &Part) -> PartData {
    match part {
        Part::Ball(ball) => PartData::Ball { center: ball.center, radius: ball.radius },
        Part::Capsule(c) => PartData::Capsule { radius: c.radius, half_height: c.half_height },
        Part::Hull(hull) => match hull.source() {
            Some(HullSource::Cuboid(half_extents)) => PartData::Cuboid { half_extents },
            Some(HullSource::Hull(h)) => hull_data(&h),
            // Shapes are made only by this crate's constructors, whose hull
            // parts all have a source; their hull is saved all the same.
            None => hull_data(&hull.hull),
        },
        _ => unreachable!("a shape's parts are hulls, balls and capsules"),
    }
}

/// A hull's saved form.
fn hull_data(h: &ConvexHull) -> PartData {
    let n = h.face_count();
    PartData::Hull {
        vertices: h.vertices().to_vec(),
        faces: (0..n).map(|f| h.face(f).to_vec()).collect(),
        planes: (0..n).map(|f| (h.face_normal(f), h.face_offset(f))).collect(),
        tolerance: h.tolerance(),
    }
}

/// The shape a saved form describes, its bounds as saved.
fn shape_of(data: &ShapeData) -> Result<Shape, String> {
    let parts = data.parts.iter().map(part_of).collect::<Result<Vec<_>, _>>()?;
    let bad = || "no parts, or bounds that are not finite".to_string();
    let (sphere, obb) = sphere_of(data.sphere).zip(obb_of(data.obb)).ok_or_else(bad)?;
    let Mat3 { x_axis, y_axis, z_axis } = obb.axes;
    let coordinates = [sphere.center, Vec3::splat(sphere.radius), obb.center, obb.half_extents];
    if parts.is_empty()
        || !coordinates.into_iter().chain([x_axis, y_axis, z_axis]).all(within_limit)
    {
        return Err(bad());
    }
    let sphere_method = data.fit.0.parse().map_err(|e| format!("{e}"))?;
    let obb_method = data.fit.1.parse().map_err(|e| format!("{e}"))?;
    let fit = FitOptions { sphere: sphere_method, obb: obb_method };
    Ok(Shape::restore(parts, BodyBounds { sphere, obb }, fit))
}

/// The part a saved form describes.
fn part_of(data: &PartData) -> Result<Part, String> {
    let sized = |x: f32| x.is_finite() && x >= 0.0 && within_limit(Vec3::splat(x));
    match data {
        PartData::Ball { center, radius } if sized(*radius) && within_limit(*center) => {
            Ok(Part::Ball(Sphere::new(*center, *radius)))
        }
        PartData::Capsule { radius, half_height } if sized(*radius) && sized(*half_height) => {
            Ok(Part::Capsule(Capsule::new(*radius, *half_height)))
        }
        PartData::Ball { .. } | PartData::Capsule { .. } => {
            Err("a ball or capsule of a size that is not finite and positive".into())
        }
        PartData::Cuboid { half_extents } => build(&HullSource::Cuboid(*half_extents)),
        PartData::Hull { vertices, faces, planes, tolerance } => {
            let (normals, offsets) = planes.iter().copied().unzip();
            let hull = ConvexHull::from_parts(
                vertices.clone(),
                faces.clone(),
                normals,
                offsets,
                *tolerance,
            );
            build(&HullSource::Hull(hull.map_err(|e| e.to_string())?))
        }
    }
}

/// The hull part a source builds.
fn build(source: &HullSource) -> Result<Part, String> {
    let part: HullPart = source.build().map_err(|e| e.to_string())?;
    Ok(Part::Hull(Box::new(part)))
}

fn kind_code(kind: BodyKind) -> u8 {
    match kind {
        BodyKind::Dynamic => 0,
        BodyKind::Static => 1,
        BodyKind::Sleeping => 2,
    }
}

fn kind_of(code: u8) -> Option<BodyKind> {
    [BodyKind::Dynamic, BodyKind::Static, BodyKind::Sleeping].get(code as usize).copied()
}

fn event_data(e: &ContactEvent) -> EventData {
    let kind = match e.kind {
        EventKind::Began => 0,
        EventKind::Persisting => 1,
        EventKind::Ended => 2,
    };
    EventData {
        kind,
        a: e.a.to_bits(),
        b: e.b.to_bits(),
        user_data: (e.user_data_a, e.user_data_b),
        contact: e.contact.as_ref().map(contact_data),
    }
}

fn contact_data(c: &Contact) -> ContactData {
    let points = c.points().iter().map(|p| (p.position, p.depth)).collect();
    ContactData { normal: c.normal, depth: c.depth, points }
}

/// The contact a saved form describes: a unit normal, finite depths and
/// positions, one to four points.
fn contact_of(c: &ContactData) -> Option<Contact> {
    let finite = c.points.iter().all(|(p, d)| p.is_finite() && d.is_finite());
    let unit = c.normal.is_finite() && (c.normal.length() - 1.0).abs() <= 1e-3;
    let count = (1..=bvol_narrow::MAX_POINTS).contains(&c.points.len());
    let points: Vec<ContactPoint> =
        c.points.iter().map(|&(position, depth)| ContactPoint { position, depth }).collect();
    (finite && unit && count && c.depth.is_finite())
        .then(|| Contact::new(c.normal, c.depth, &points))
}

/// Saved events, checked: sorted by slots if `sorted` (the last update's;
/// the removed bodies' come in the order of removal), each pair's slots in
/// order and within the world's, a contact on each that has not ended.
/// `first` is the index the first has among all a snapshot's events, for
/// errors.
fn events_of(
    saved: &[EventData],
    slots: usize,
    first: usize,
    sorted: bool,
) -> Result<Vec<ContactEvent>, SnapshotError> {
    let mut events: Vec<ContactEvent> = Vec::with_capacity(saved.len());
    for (k, e) in saved.iter().enumerate() {
        let bad = SnapshotError::Event { event: first + k };
        let (a, b) = (BodyId::from_bits(e.a), BodyId::from_bits(e.b));
        let kind = [EventKind::Began, EventKind::Persisting, EventKind::Ended].get(e.kind as usize);
        let contact = e.contact.as_ref().map(|c| contact_of(c).ok_or(bad.clone())).transpose()?;
        let ordered = events.last().is_none_or(|last| last.slots() <= (a.index, b.index));
        let within = a.index < b.index && (b.index as usize) < slots;
        let Some(&kind) = kind.filter(|_| (ordered || !sorted) && within) else { return Err(bad) };
        if contact.is_some() == (kind == EventKind::Ended) {
            return Err(bad);
        }
        let (user_data_a, user_data_b) = e.user_data;
        events.push(ContactEvent { kind, a, b, user_data_a, user_data_b, contact });
    }
    Ok(events)
}
