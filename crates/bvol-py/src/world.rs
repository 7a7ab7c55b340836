//! The World: bodies, their poses, and what touches, in numpy arrays.

use std::sync::Arc;

use bvol::glam::{Quat, Vec3};
use bvol::narrow::MAX_POINTS;
use bvol::volumes::{DPose, Pose};
use bvol::{
    BodyDesc, BodyId, BodyKind, EventKind, FrameStats, Shape, Snapshot, World, WorldConfig,
    WorldError,
};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

use crate::arrays::{
    Array1, floats, integers, rows_array, same_rows, vector_array, vectors, vectors_f64,
};
use crate::batch::{check_max_t, rays};
use crate::errors::{value_error, world_error};
use crate::shape::PyShape;

/// The id that names no body: where a ray met nothing.
pub(crate) const NO_BODY: u64 = u64::MAX;

/// The event kinds by the names Python gives them (module constants
/// holding their [`event_code`]).
pub(crate) const EVENT_KINDS: [(&str, EventKind); 3] = [
    ("BEGAN", EventKind::Began),
    ("PERSISTING", EventKind::Persisting),
    ("ENDED", EventKind::Ended),
];

/// An event kind's number in the arrays.
pub(crate) fn event_code(kind: EventKind) -> u8 {
    match kind {
        EventKind::Began => 0,
        EventKind::Persisting => 1,
        EventKind::Ended => 2,
    }
}

/// Bodies and what touches among them (the Python half adds `events` and
/// `ray_cast`, which answer in structured arrays).
#[pyclass(name = "World", module = "bvol._bvol", subclass)]
pub(crate) struct PyWorld {
    world: World,
}

#[pymethods]
impl PyWorld {
    /// A world with no bodies; `threads` is the number of threads `update`
    /// runs on (by default, one per core); bodies apart by at most `margin`
    /// are in contact too, with negative depths (`WorldConfig::margin`);
    /// touching pairs that moved by at most `reuse` of their size reuse
    /// their contact feature (`WorldConfig::reuse`).
    #[new]
    #[pyo3(signature = (threads = None, margin = 0.0, reuse = 0.0))]
    fn new(threads: Option<usize>, margin: f32, reuse: f32) -> PyResult<Self> {
        let config = WorldConfig::default().with_margin(margin).with_reuse(reuse);
        let config = threads.map_or(config, |n| config.with_threads(n));
        let world = World::with_config(config).map_err(world_error)?;
        Ok(PyWorld { world })
    }

    /// Adds a body and returns its id. Its geometry is exactly one of
    /// `vertices` (an (N, 3) array: their convex hull), `primitive`
    /// (`("box", half_extents)`, `("sphere", radius)` or
    /// `("capsule", radius, half_height)`) or `shape` (a `Shape`, shared).
    /// `pose` is `(position, quaternion)`, the quaternion as (x, y, z, w);
    /// `kind` is "dynamic", "static" or "sleeping"; two bodies are tested
    /// when each one's `layers` bits meet the other's `mask`.
    #[pyo3(signature = (*, vertices = None, primitive = None, shape = None, pose = None,
        kind = "dynamic", user_data = 0, layers = 1, mask = 4294967295))]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments.
    fn add_body(
        &mut self,
        py: Python<'_>,
        vertices: Option<&Bound<'_, PyAny>>,
        primitive: Option<&Bound<'_, PyTuple>>,
        shape: Option<PyRef<'_, PyShape>>,
        pose: Option<&Bound<'_, PyAny>>,
        kind: &str,
        user_data: u64,
        layers: u32,
        mask: u32,
    ) -> PyResult<u64> {
        let shape = PyShape::of_body(py, vertices, primitive, shape.as_deref())?;
        let pose = match pose {
            Some(pose) => pose_of(pose)?,
            None => Pose::IDENTITY,
        };
        let desc = BodyDesc::new(shape.0, pose)
            .with_kind(kind_of(kind)?)
            .with_user_data(user_data)
            .with_filter(layers, mask);
        self.world.add_body(desc).map(BodyId::to_bits).map_err(world_error)
    }

    /// Adds one body at each of the (N, 3) `positions`, rotated by the
    /// (N, 4) `quaternions` (x, y, z, w; the identity if not given), all of
    /// one shape given as to `add_body`, and returns their ids, an (N,)
    /// uint64 array. `user_data` is an (N,) integer array. If any body
    /// cannot be added, none is.
    #[pyo3(signature = (positions, quaternions = None, *, vertices = None, primitive = None,
        shape = None, kind = "dynamic", user_data = None))]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments.
    fn add_bodies<'py>(
        &mut self,
        py: Python<'py>,
        positions: &Bound<'py, PyAny>,
        quaternions: Option<&Bound<'py, PyAny>>,
        vertices: Option<&Bound<'py, PyAny>>,
        primitive: Option<&Bound<'py, PyTuple>>,
        shape: Option<PyRef<'py, PyShape>>,
        kind: &str,
        user_data: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<u64>>> {
        let shape = PyShape::of_body(py, vertices, primitive, shape.as_deref())?;
        let kind = kind_of(kind)?;
        let poses = poses_of(positions, quaternions)?;
        let user_data = match user_data {
            Some(data) => integers("user_data", data)?,
            None => vec![0; poses.len()],
        };
        same_rows(&["positions", "user_data"], &[poses.len(), user_data.len()])?;
        let world = &mut self.world;
        let ids = py.detach(|| add_all(world, &shape.0, kind, &poses, &user_data));
        Ok(PyArray1::from_vec(py, ids.map_err(world_error)?))
    }

    /// Removes the body `id` (its events end at the next update).
    fn remove(&mut self, id: u64) -> PyResult<()> {
        self.world.remove_body(BodyId::from_bits(id)).map_err(world_error)
    }

    /// Moves the bodies `ids` (an (N,) integer array) to the (N, 3)
    /// `positions`, rotated by the (N, 4) `quaternions` (x, y, z, w; the
    /// identity if not given). If any pose is refused, none is set.
    #[pyo3(signature = (ids, positions, quaternions = None))]
    fn set_poses(
        &mut self,
        py: Python<'_>,
        ids: &Bound<'_, PyAny>,
        positions: &Bound<'_, PyAny>,
        quaternions: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let ids = body_ids(ids)?;
        let poses = poses_of(positions, quaternions)?;
        same_rows(&["ids", "positions"], &[ids.len(), poses.len()])?;
        let world = &mut self.world;
        py.detach(|| world.set_poses(&ids, &poses)).map_err(world_error)
    }

    /// Moves bodies to positions kept in f64 (`World::set_poses_f64`), for
    /// worlds far from the origin: `positions` an (N, 3) float64 array
    /// (float32 is widened), `quaternions` as `set_poses` takes them. Pairs
    /// are then tested on positions relative to one of their bodies; if
    /// any pose is refused, none is set.
    #[pyo3(signature = (ids, positions, quaternions = None))]
    fn set_poses_f64(
        &mut self,
        py: Python<'_>,
        ids: &Bound<'_, PyAny>,
        positions: &Bound<'_, PyAny>,
        quaternions: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let ids = body_ids(ids)?;
        let positions = vectors_f64("positions", positions)?;
        let rotations = rotations_of(quaternions, positions.len())?;
        same_rows(&["ids", "positions"], &[ids.len(), positions.len()])?;
        let poses: Vec<DPose> =
            positions.into_iter().zip(rotations).map(|(p, q)| DPose::new(p, q)).collect();
        let world = &mut self.world;
        py.detach(|| world.set_poses_f64(&ids, &poses)).map_err(world_error)
    }

    /// The body's position as given, a (3,) float64 array, and its
    /// quaternion, a (4,) float32 array.
    fn pose_f64<'py>(
        &self,
        py: Python<'py>,
        id: u64,
    ) -> PyResult<(Array1<'py, f64>, Array1<'py, f32>)> {
        let pose = self.world.pose_f64(BodyId::from_bits(id)).map_err(world_error)?;
        Ok((
            PyArray1::from_slice(py, &pose.position.to_array()),
            PyArray1::from_slice(py, &pose.rotation.to_array()),
        ))
    }

    /// The points of `a` and `b`'s contact at their poses now, a (K, 3)
    /// float64 array (those of `contact`, as precise as f64 positions).
    fn contact_points_f64<'py>(
        &self,
        py: Python<'py>,
        a: u64,
        b: u64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (a, b) = (BodyId::from_bits(a), BodyId::from_bits(b));
        let points = self.world.contact_points_f64(a, b).map_err(world_error)?;
        let rows: Vec<[f64; 3]> = points.iter().map(|p| p.to_array()).collect();
        Ok(rows_array(py, &rows))
    }

    /// The body's pose: its position, a (3,) float32 array, and its
    /// quaternion (x, y, z, w), a (4,) float32 array.
    fn pose<'py>(
        &self,
        py: Python<'py>,
        id: u64,
    ) -> PyResult<(Array1<'py, f32>, Array1<'py, f32>)> {
        let pose = self.world.pose(BodyId::from_bits(id)).map_err(world_error)?;
        Ok((
            PyArray1::from_slice(py, &pose.position.to_array()),
            PyArray1::from_slice(py, &pose.rotation.to_array()),
        ))
    }

    /// Makes the body "dynamic", "static" or "sleeping".
    fn set_kind(&mut self, id: u64, kind: &str) -> PyResult<()> {
        self.world.set_kind(BodyId::from_bits(id), kind_of(kind)?).map_err(world_error)
    }

    /// The body's kind: "dynamic", "static" or "sleeping".
    fn kind(&self, id: u64) -> PyResult<&'static str> {
        let kind = self.world.kind(BodyId::from_bits(id)).map_err(world_error)?;
        Ok(match kind {
            BodyKind::Dynamic => "dynamic",
            BodyKind::Static => "static",
            BodyKind::Sleeping => "sleeping",
        })
    }

    /// The body's user data.
    fn user_data(&self, id: u64) -> PyResult<u64> {
        self.world.user_data(BodyId::from_bits(id)).map_err(world_error)
    }

    /// Every body's id, an (N,) uint64 array in slot order.
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_vec(py, self.world.bodies().map(BodyId::to_bits).collect())
    }

    fn __len__(&self) -> usize {
        self.world.len()
    }

    /// The world saved, as JSON bytes: `World.from_snapshot` (or pickle,
    /// which calls this) loads it back to run on exactly as this world
    /// would have, event for event.
    fn snapshot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let world = &self.world;
        let data = py.detach(|| serde_json::to_vec(&world.snapshot())).map_err(value_error)?;
        Ok(PyBytes::new(py, &data))
    }

    /// Becomes the world `data` (from `snapshot`) saved; bad data is a
    /// `ValueError` naming what is wrong, and changes nothing.
    fn _load_snapshot(&mut self, py: Python<'_>, data: &[u8]) -> PyResult<()> {
        let loaded = py.detach(|| {
            let snapshot: Snapshot = serde_json::from_slice(data).map_err(|e| e.to_string())?;
            World::from_snapshot(&snapshot).map_err(|e| e.to_string())
        });
        self.world = loaded.map_err(value_error)?;
        Ok(())
    }

    fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.snapshot(py)
    }

    fn __setstate__(&mut self, py: Python<'_>, state: &[u8]) -> PyResult<()> {
        self._load_snapshot(py, state)
    }

    /// Runs one frame and returns what each stage let through and how long
    /// it took: a dict of counts ("moved", "candidates", "after_spheres",
    /// "after_obbs", "touching", "near": apart within the margin) and times
    /// in seconds ("bounds_time",
    /// "broadphase_time", "spheres_time", "obbs_time", "narrow_time",
    /// "total_time").
    fn update<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let world = &mut self.world;
        let stats = py.detach(|| *world.update());
        stats_dict(py, &stats)
    }

    /// The pairs touching (or within the margin) at the last update, an
    /// (M, 2) uint64 array of ids,
    /// the lower slot first, in the order of `events`.
    fn pairs<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u64>> {
        let pairs: Vec<[u64; 2]> =
            self.world.contacts().map(|(a, b, _)| [a.to_bits(), b.to_bits()]).collect();
        rows_array(py, &pairs)
    }

    /// How bodies `a` and `b` touched at the last update, the normal from `a`
    /// to `b`: a dict of "normal" ((3,) float32), "depth" and "points"
    /// ((K, 3) float32, with their "point_depths"), or None where they do
    /// not touch.
    fn contact<'py>(
        &self,
        py: Python<'py>,
        a: u64,
        b: u64,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        let contact =
            self.world.contact(BodyId::from_bits(a), BodyId::from_bits(b)).map_err(world_error)?;
        let Some(contact) = contact else { return Ok(None) };
        let dict = PyDict::new(py);
        let points: Vec<Vec3> = contact.points().iter().map(|p| p.position).collect();
        let depths: Vec<f32> = contact.points().iter().map(|p| p.depth).collect();
        dict.set_item("normal", PyArray1::from_slice(py, &contact.normal.to_array()))?;
        dict.set_item("depth", contact.depth)?;
        dict.set_item("points", vector_array(py, &points))?;
        dict.set_item("point_depths", PyArray1::from_vec(py, depths))?;
        Ok(Some(dict))
    }

    /// The last update's events as columns, for `World.events`.
    fn _event_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let events = self.world.events();
        let mut columns = EventColumns::with_capacity(events.len());
        for event in events {
            columns.push(event);
        }
        columns.into_dict(py)
    }

    /// Each ray's nearest hit as columns, for `World.ray_cast`.
    fn _ray_columns<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        max_t: f32,
    ) -> PyResult<Bound<'py, PyDict>> {
        check_max_t(max_t)?;
        let rays = rays(origins, directions)?;
        let world = &self.world;
        let hits: Vec<_> = py.detach(|| rays.iter().map(|r| world.ray_cast(r, max_t)).collect());
        let dict = PyDict::new(py);
        let id = |h: &Option<bvol::RayHit>| h.map_or(NO_BODY, |h| h.body.to_bits());
        let t = |h: &Option<bvol::RayHit>| h.map_or(f32::INFINITY, |h| h.t);
        let point = |h: &Option<bvol::RayHit>| h.map_or(Vec3::ZERO, |h| h.point);
        let data = |h: &Option<bvol::RayHit>| h.map_or(0, |h| h.user_data);
        dict.set_item("hit", PyArray1::from_vec(py, hits.iter().map(Option::is_some).collect()))?;
        dict.set_item("id", PyArray1::from_vec(py, hits.iter().map(id).collect()))?;
        dict.set_item("t", PyArray1::from_vec(py, hits.iter().map(t).collect()))?;
        dict.set_item("point", vector_array(py, &hits.iter().map(point).collect::<Vec<_>>()))?;
        dict.set_item("user_data", PyArray1::from_vec(py, hits.iter().map(data).collect()))?;
        Ok(dict)
    }
}

/// Adds a body of `shape` at each pose, with its user data, and returns
/// their ids; if one cannot be added, removes those added and returns why.
fn add_all(
    world: &mut World,
    shape: &Arc<Shape>,
    kind: BodyKind,
    poses: &[Pose],
    user_data: &[u64],
) -> Result<Vec<u64>, WorldError> {
    let mut ids = Vec::with_capacity(poses.len());
    for (&pose, &data) in poses.iter().zip(user_data) {
        let desc = BodyDesc::new(shape.clone(), pose).with_kind(kind).with_user_data(data);
        match world.add_body(desc) {
            Ok(id) => ids.push(id),
            Err(error) => {
                for &id in &ids {
                    world.remove_body(id)?;
                }
                return Err(error);
            }
        }
    }
    Ok(ids.into_iter().map(BodyId::to_bits).collect())
}

/// Events as columns: what `World.events` lays out as a structured array.
struct EventColumns {
    kind: Vec<u8>,
    ids: Vec<[u64; 2]>,
    user_data: Vec<[u64; 2]>,
    normal: Vec<Vec3>,
    depth: Vec<f32>,
    point_count: Vec<u8>,
    points: Vec<[f32; 3 * MAX_POINTS]>,
    point_depths: Vec<[f32; MAX_POINTS]>,
}

impl EventColumns {
    fn with_capacity(n: usize) -> Self {
        EventColumns {
            kind: Vec::with_capacity(n),
            ids: Vec::with_capacity(n),
            user_data: Vec::with_capacity(n),
            normal: Vec::with_capacity(n),
            depth: Vec::with_capacity(n),
            point_count: Vec::with_capacity(n),
            points: Vec::with_capacity(n),
            point_depths: Vec::with_capacity(n),
        }
    }

    /// Adds an event; an ended one has a zero normal, depth and no points.
    fn push(&mut self, event: &bvol::ContactEvent) {
        self.kind.push(event_code(event.kind));
        self.ids.push([event.a.to_bits(), event.b.to_bits()]);
        self.user_data.push([event.user_data_a, event.user_data_b]);
        let (mut points, mut depths) = ([0.0; 3 * MAX_POINTS], [0.0; MAX_POINTS]);
        let (normal, depth, count) = match &event.contact {
            Some(contact) => {
                for (k, p) in contact.points().iter().enumerate() {
                    points[3 * k..3 * k + 3].copy_from_slice(&p.position.to_array());
                    depths[k] = p.depth;
                }
                (contact.normal, contact.depth, contact.points().len() as u8)
            }
            None => (Vec3::ZERO, 0.0, 0),
        };
        self.normal.push(normal);
        self.depth.push(depth);
        self.point_count.push(count);
        self.points.push(points);
        self.point_depths.push(depths);
    }

    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let dict = PyDict::new(py);
        dict.set_item("kind", PyArray1::from_vec(py, self.kind))?;
        dict.set_item("ids", rows_array(py, &self.ids))?;
        dict.set_item("user_data", rows_array(py, &self.user_data))?;
        dict.set_item("normal", vector_array(py, &self.normal))?;
        dict.set_item("depth", PyArray1::from_vec(py, self.depth))?;
        dict.set_item("point_count", PyArray1::from_vec(py, self.point_count))?;
        dict.set_item("points", rows_array(py, &self.points))?;
        dict.set_item("point_depths", rows_array(py, &self.point_depths))?;
        Ok(dict)
    }
}

/// A frame's stats as a dict, times in seconds.
fn stats_dict<'py>(py: Python<'py>, s: &FrameStats) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (name, count) in [
        ("moved", s.moved),
        ("candidates", s.candidates),
        ("after_spheres", s.after_spheres),
        ("after_obbs", s.after_obbs),
        ("touching", s.touching),
        ("near", s.near),
    ] {
        dict.set_item(name, count)?;
    }
    for (name, time) in [
        ("bounds_time", s.bounds_time),
        ("broadphase_time", s.broadphase_time),
        ("spheres_time", s.spheres_time),
        ("obbs_time", s.obbs_time),
        ("narrow_time", s.narrow_time),
        ("total_time", s.total_time()),
    ] {
        dict.set_item(name, time.as_secs_f64())?;
    }
    Ok(dict)
}

/// A body kind from its name.
fn kind_of(name: &str) -> PyResult<BodyKind> {
    match name {
        "dynamic" => Ok(BodyKind::Dynamic),
        "static" => Ok(BodyKind::Static),
        "sleeping" => Ok(BodyKind::Sleeping),
        _ => Err(PyValueError::new_err(format!(
            "kind {name:?}: expected \"dynamic\", \"static\" or \"sleeping\""
        ))),
    }
}

/// A pose from `(position, quaternion)`.
fn pose_of(pose: &Bound<'_, PyAny>) -> PyResult<Pose> {
    let (position, rotation) = pose.extract::<([f32; 3], [f32; 4])>().map_err(|_| {
        PyTypeError::new_err("pose: expected (position, quaternion): three numbers and four")
    })?;
    Ok(Pose::new(Vec3::from_array(position), Quat::from_array(rotation)))
}

/// The bodies named by an (N,) integer array of ids.
fn body_ids(ids: &Bound<'_, PyAny>) -> PyResult<Vec<BodyId>> {
    Ok(integers("ids", ids)?.into_iter().map(BodyId::from_bits).collect())
}

/// Poses from (N, 3) positions and (N, 4) quaternions, or the identity
/// rotation.
fn poses_of(
    positions: &Bound<'_, PyAny>,
    quaternions: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<Pose>> {
    let positions = vectors("positions", positions)?;
    let positions = positions.vectors();
    let rotations = rotations_of(quaternions, positions.len())?;
    Ok(positions.iter().zip(rotations).map(|(&p, q)| Pose::new(p, q)).collect())
}

/// The rotations of `n` poses: an `(n, 4)` array of quaternions (x, y, z,
/// w), or the identity for each when there is none.
fn rotations_of(quaternions: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Vec<Quat>> {
    let Some(quaternions) = quaternions else { return Ok(vec![Quat::IDENTITY; n]) };
    let quaternions = floats("quaternions", quaternions, &[4])?;
    let quaternions = quaternions.rows::<4>();
    same_rows(&["positions", "quaternions"], &[n, quaternions.len()])?;
    Ok(quaternions.iter().map(|&q| Quat::from_array(q)).collect())
}
