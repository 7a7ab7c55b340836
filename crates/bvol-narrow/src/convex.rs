//! What the separating-axis code reads of a convex shape, whether a stored
//! [`Polyhedron`] or a box made on the spot from its half extents.

use std::ops::Range;
use std::sync::OnceLock;

use glam::{DVec3, Vec3};

use crate::Polyhedron;
use crate::box_sat::BoxNumbering;
use crate::cluster::{Cap, Cluster};
use crate::lanes::{Witness, lanes_left, live_mask};
use crate::topology::Topology;

/// A face's plane: `normal . x = offset` on it, `normal` unit and outward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Plane {
    /// Unit outward normal.
    pub normal: DVec3,
    /// Signed distance of the plane from the origin along `normal`.
    pub offset: f64,
}

impl Plane {
    /// Signed distance of `p` above the plane.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// An edge's arc on the Gauss map (the great-circle arc between its two
/// faces' normals), for the bounds that let the edge query skip it: its two
/// ends, the cap it lies in (about its midpoint, of its half angle), the unit
/// pole of its great circle, and how deep the shape's inner centre is behind
/// the edge along any direction of the arc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arc {
    /// The two face normals it joins, from the face of the edge's half-edge
    /// to its twin's: kept here so that the edge query reads them in one place.
    pub ends: (DVec3, DVec3),
    /// The cap about the arc's midpoint whose radius is its half angle.
    pub cap: Cap,
    /// Unit normal of the arc's plane (zero if the two normals coincide).
    pub pole: DVec3,
    /// The lesser of the inner centre's distances behind the two faces: along
    /// any direction `d` of the arc, `d . (edge - centre)` is at least this
    /// (`d` is a combination of the normals with weights summing to at least 1).
    pub inner: f64,
}

impl Arc {
    /// The arc of the edge between faces `p1` and `p2` (not opposite), of a
    /// shape with inner centre `centre`.
    pub fn new(p1: Plane, p2: Plane, centre: DVec3) -> Arc {
        let (n1, n2) = (p1.normal, p2.normal);
        let mid = (n1 + n2).normalize_or_zero();
        Arc {
            ends: (n1, n2),
            cap: Cap { axis: mid, cos: mid.dot(n1), sin: mid.cross(n1).length() },
            pole: n1.cross(n2).normalize_or_zero(),
            inner: (-p1.distance(centre)).min(-p2.distance(centre)),
        }
    }

    /// The greatest `d . w` over the directions `d` of the arc, exactly: `w`'s
    /// part in the arc's plane if its direction falls within the arc (its
    /// angle from the midpoint at most the half angle), else at the nearer end.
    pub fn max(&self, w: DVec3) -> f64 {
        let along = self.cap.axis.dot(w);
        let across = self.pole.dot(w);
        let in_plane2 = (w.length_squared() - across * across).max(0.0);
        if along > 0.0 && along * along >= self.cap.cos * self.cap.cos * in_plane2 {
            in_plane2.sqrt()
        } else {
            self.ends.0.dot(w).max(self.ends.1.dot(w))
        }
    }
}

/// A convex polyhedron as the tests read it, in its local space, in f64.
pub(crate) trait Convex {
    /// How its vertices, edges and faces meet.
    fn topology(&self) -> &Topology;

    /// Vertex `v`.
    fn vertex(&self, v: u32) -> DVec3;

    /// The plane of face `f`.
    fn plane(&self, f: u32) -> Plane;

    /// Half the diagonal of its local bounding box: the length that relative
    /// tolerances are measured against.
    fn size(&self) -> f64;

    /// A point inside it, and the radius of a ball about that point that is
    /// inside it too: then `min over x of n . x <= n . centre - radius` for
    /// any unit `n`, the bound that lets the queries skip most axes.
    fn inner_ball(&self) -> (DVec3, f64);

    /// A vertex to start hill climbing from, for the lowest vertex along `dir`.
    fn seed(&self, dir: DVec3) -> u32;

    /// A face whose normal is near `dir`: the one most along the grid
    /// direction nearest it.
    fn face_seed(&self, dir: DVec3) -> u32;

    /// The Gauss-map arc of edge `e` (an index into `topology().edges`).
    fn arc(&self, e: u32) -> Arc;

    /// The cap and depth of arc `e` alone: what its first bounds read.
    fn arc_cap(&self, e: u32) -> (Cap, f64) {
        let arc = self.arc(e);
        (arc.cap, arc.inner)
    }

    /// The faces grouped by the directions of their normals.
    fn face_clusters(&self) -> impl Iterator<Item = Cluster> + '_;

    /// The faces of `run` (at most 64) whose planes' distances to all
    /// `witnesses` (points from the inner centre, less their `less`) leave
    /// above `bar`, as a bit mask ([`lanes_left`]): every face whose bounds
    /// beat the bar, and perhaps a few more.
    fn faces_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        let centre = self.inner_ball().0;
        live_mask(run, |f| {
            let plane = self.plane(f);
            witnesses.iter().all(|w| plane.distance(centre + w.at) - w.less > bar)
        })
    }

    /// The arcs of `run` (at most 64) whose cap bounds by all `witnesses`
    /// leave above `bar`, as a bit mask ([`lanes_left`]): every arc whose
    /// bounds beat the bar, and perhaps a few more.
    fn arcs_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        live_mask(run, |e| {
            let (cap, inner) = self.arc_cap(e);
            witnesses.iter().all(|w| cap.max(w.at, w.length) - inner - w.less > bar)
        })
    }

    /// The edges grouped by the directions of their arcs.
    fn edge_clusters(&self) -> impl Iterator<Item = Cluster> + '_;

    /// The vertex least far along `dir`, and `dir . vertex` (its support
    /// point against `dir`), searched from vertex `start`. The search may
    /// stop at the first vertex it meets at or below `limit`, when the caller
    /// only needs to know the least is that low: a value `<= limit` is then
    /// only an upper bound of the least. `-inf` asks for the least.
    fn support_min(&self, dir: DVec3, start: u32, limit: f64) -> (u32, f64);

    /// Its half extents and feature numbering if it is a box centred on its
    /// origin, square to its axes: two boxes take the closed-form queries.
    fn as_box(&self) -> Option<(DVec3, &BoxNumbering)> {
        None
    }
}

/// [`Convex::support_min`] by hill climbing on the vertex graph, to the
/// steepest neighbour while one is strictly lower, from `start`: the
/// previous face's, arc's or frame's answer (often a step away), or the
/// [`seed`](Convex::seed) for `dir` where there is none (never far). On a
/// convex polyhedron a vertex no neighbour improves on is a global minimum
/// (up to the hull's coplanarity tolerance), whatever the start. Comparing
/// each start with the seed as well cost more than the steps it saved: the
/// moving hull pairs of the narrow bench took 18% less time without it.
/// Stops early at or below `limit`: a query that only needs to know whether
/// the least beats a bar climbs no further.
fn hill_climb<S: Convex + ?Sized>(shape: &S, dir: DVec3, start: u32, limit: f64) -> (u32, f64) {
    let topology = shape.topology();
    let (mut v, mut low) = (start, dir.dot(shape.vertex(start)));
    loop {
        if low <= limit {
            return (v, low);
        }
        let mut next = v;
        for &w in topology.neighbours(v) {
            let d = dir.dot(shape.vertex(w));
            if d < low {
                (next, low) = (w, d);
            }
        }
        if next == v {
            return (v, low);
        }
        v = next;
    }
}

/// Up to this many vertices, a support point is found by reading them all:
/// a short straight run beats the hops of hill climbing.
const SCAN_ALL: usize = 16;

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

impl Convex for Polyhedron {
    fn topology(&self) -> &Topology {
        &self.topology
    }

    fn vertex(&self, v: u32) -> DVec3 {
        self.points[v as usize]
    }

    fn plane(&self, f: u32) -> Plane {
        self.planes[f as usize]
    }

    fn size(&self) -> f64 {
        self.size
    }

    fn inner_ball(&self) -> (DVec3, f64) {
        self.inner_ball
    }

    fn seed(&self, dir: DVec3) -> u32 {
        self.seeds[seed_slot(dir)]
    }

    fn face_seed(&self, dir: DVec3) -> u32 {
        self.face_seeds[seed_slot(dir)]
    }

    fn support_min(&self, dir: DVec3, start: u32, limit: f64) -> (u32, f64) {
        if self.points.len() > SCAN_ALL {
            return hill_climb(self, dir, start, limit);
        }
        let along = (0u32..).zip(&self.points).map(|(i, &v)| (i, dir.dot(v)));
        along.fold((0, f64::INFINITY), |m, x| if x.1 < m.1 { x } else { m })
    }

    fn as_box(&self) -> Option<(DVec3, &BoxNumbering)> {
        self.box_shape.as_ref().map(|(half, numbering)| (*half, numbering))
    }

    fn arc(&self, e: u32) -> Arc {
        self.arcs[e as usize]
    }

    fn arc_cap(&self, e: u32) -> (Cap, f64) {
        self.arc_caps[e as usize]
    }

    fn face_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.face_clusters.iter().cloned()
    }

    /// On f32 lanes, four faces at a time.
    fn faces_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        lanes_left(&self.face_lanes, run, witnesses, 2.0 * self.size, bar)
    }

    /// On f32 lanes, four arcs at a time.
    fn arcs_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        lanes_left(&self.arc_lanes, run, witnesses, 2.0 * self.size, bar)
    }

    fn edge_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.edge_clusters.iter().cloned()
    }
}

/// The box `[-half, half]`: the unit cube's topology, scaled, made without
/// allocating; the same numbers as [`Polyhedron::cuboid`] of the same half
/// extents, so a box and its polyhedron collide alike.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cuboid {
    unit: &'static Polyhedron,
    half: DVec3,
}

impl Cuboid {
    /// The box with these half extents, each `>= 0`.
    pub fn new(half_extents: Vec3) -> Cuboid {
        Cuboid { unit: unit_cube(), half: half_extents.as_dvec3() }
    }

    /// The plane of face `f` of a box of half extents `half`: the unit cube's
    /// faces are axis-aligned, so scaling moves each out to `half` on its axis.
    pub fn scaled_plane(unit: Plane, half: DVec3) -> Plane {
        Plane { normal: unit.normal, offset: unit.normal.abs().dot(half) }
    }
}

impl Convex for Cuboid {
    fn topology(&self) -> &Topology {
        &self.unit.topology
    }

    fn vertex(&self, v: u32) -> DVec3 {
        self.unit.vertex(v) * self.half
    }

    fn plane(&self, f: u32) -> Plane {
        Cuboid::scaled_plane(self.unit.plane(f), self.half)
    }

    fn size(&self) -> f64 {
        self.half.length()
    }

    fn inner_ball(&self) -> (DVec3, f64) {
        (DVec3::ZERO, self.half.min_element())
    }

    fn seed(&self, dir: DVec3) -> u32 {
        self.unit.seed(dir)
    }

    fn face_seed(&self, dir: DVec3) -> u32 {
        self.unit.face_seed(dir)
    }

    /// Scaling the cube along its axes keeps its face normals, so its arcs'
    /// shapes; the depth behind the edge is the lesser of its faces' offsets.
    fn arc(&self, e: u32) -> Arc {
        let topology = self.topology();
        let h = topology.edges[e as usize];
        let offset = |f: u32| self.plane(f).offset;
        let inner = offset(topology.half_edge(h).face).min(offset(topology.twin_face(h)));
        Arc { inner, ..self.unit.arc(e) }
    }

    /// The unit cube's clusters, their depths taken at this scale.
    fn face_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.unit.face_clusters.iter().map(|c| Cluster {
            inner: c.members.clone().map(|f| self.plane(f).offset).fold(f64::INFINITY, f64::min),
            ..c.clone()
        })
    }

    fn edge_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.unit.edge_clusters.iter().map(|c| Cluster {
            inner: c.members.clone().map(|e| self.arc(e).inner).fold(f64::INFINITY, f64::min),
            ..c.clone()
        })
    }

    /// The corner against `dir` on every axis, at once: the unit cube's seed
    /// for the diagonal of `dir`'s signs.
    fn support_min(&self, dir: DVec3, _start: u32, _limit: f64) -> (u32, f64) {
        let level = |x: f64| if x < 0.0 { 0 } else { 2 };
        let v = self.unit.seeds[level(dir.x) + 3 * level(dir.y) + 9 * level(dir.z)];
        (v, dir.dot(self.vertex(v)))
    }

    fn as_box(&self) -> Option<(DVec3, &BoxNumbering)> {
        self.unit.box_shape.as_ref().map(|(_, numbering)| (self.half, numbering))
    }
}

/// The cube `[-1, 1]^3`, built once.
pub(crate) fn unit_cube() -> &'static Polyhedron {
    static CUBE: OnceLock<Polyhedron> = OnceLock::new();
    CUBE.get_or_init(|| {
        let corners: Vec<Vec3> = (0..8)
            .map(|i| {
                let s = |bit: u32| if i & bit == 0 { -1.0 } else { 1.0 };
                Vec3::new(s(1), s(2), s(4))
            })
            .collect();
        Polyhedron::from_points(&corners).expect("eight cube corners span a solid")
    })
}
