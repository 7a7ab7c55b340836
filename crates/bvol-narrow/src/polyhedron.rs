//! Convex polyhedra with what the separating-axis test reads precomputed.

use std::ops::Range;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use bvol_volumes::ConvexHull;
use glam::{DVec3, Vec3};

use crate::ShapeError;
use crate::arc::Arc;
use crate::box_numbering::BoxNumbering;
use crate::cluster::{Cap, Cluster, group};
use crate::convex::Convex;
use crate::flat::solid_hull;
use crate::grid::{SEEDS, seed_direction, seed_slot};
use crate::lanes::{CapLanes, Witness, lanes_left};
use crate::plane::Plane;
use crate::topology::Topology;

/// A convex polyhedron in its local space, with what the separating-axis test
/// reads laid out for it, computed once per shape: the vertices contiguous
/// (f32 as given, and in f64, exactly, as the tests read them), the face planes as `(unit normal, offset)` pairs
/// in f64 (from the exact hull), and a half-edge structure (origin, twin, next,
/// face) that gives the neighbours of a vertex for hill-climbing support
/// points, the loops of faces for clipping, and each undirected edge once with
/// the two face normals it joins: its arc on the Gauss map.
///
/// ```
/// use bvol_narrow::Polyhedron;
/// use glam::Vec3;
/// let tetra = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::splat(0.1)]; // the last is inside
/// let p = Polyhedron::from_points(&tetra)?;
/// assert_eq!((p.vertices().len(), p.face_count(), p.edge_count()), (4, 4, 6));
/// # Ok::<(), bvol_narrow::ShapeError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Polyhedron {
    pub(crate) vertices: Vec<Vec3>,
    /// The vertices in f64, as the queries read them: converted once here,
    /// not at every read.
    pub(crate) points: Vec<DVec3>,
    pub(crate) planes: Vec<Plane>,
    pub(crate) topology: Topology,
    pub(crate) size: f64,
    /// The greatest distance of a vertex from the origin: how far a vertex
    /// can move as the shape turns about its origin is at most this times
    /// the chord of the turn.
    pub(crate) reach: f64,
    /// A number no other of the last 2^32 shapes built in this process has
    /// (clones share it: they are the same shape), so that a warm start can
    /// tell that it is used with the shapes it was made with.
    pub(crate) id: u32,
    /// The mean of the vertices, and its least distance to a face plane.
    pub(crate) inner_ball: (DVec3, f64),
    /// The Gauss-map arc of each edge of `topology.edges`.
    pub(crate) arcs: Vec<Arc>,
    /// The faces' normals (as caps of no radius) and depths on f32 lanes,
    /// four a block: the deep cold face queries' first bounds.
    pub(crate) face_lanes: Vec<CapLanes>,
    /// The arcs' caps and depths on f32 lanes likewise, for the edge query.
    pub(crate) arc_lanes: Vec<CapLanes>,
    /// The faces, numbered so that those facing alike are consecutive, in groups.
    pub(crate) face_clusters: Vec<Cluster>,
    /// The edges, ordered so that those whose arcs point alike are consecutive, in groups.
    pub(crate) edge_clusters: Vec<Cluster>,
    /// The lowest vertex along each of the grid directions of
    /// [`seed_slot`].
    pub(crate) seeds: [u32; SEEDS],
    /// The face most along each of those directions.
    pub(crate) face_seeds: [u32; SEEDS],
    /// Its half extents and feature numbering when it is a box centred on
    /// its origin, square to its axes (see [`BoxNumbering::of`]).
    pub(crate) box_shape: Option<(DVec3, BoxNumbering)>,
}

/// The next [`Polyhedron::id`].
static NEXT_ID: AtomicU32 = AtomicU32::new(0);

impl Polyhedron {
    /// The convex hull of the points, as a polyhedron. Flat points (all
    /// within the hull's tolerance, about 1e-7 of their extent, of a plane:
    /// a floor tile, a sheet) are given a thickness of
    /// [`FLAT_THICKNESS`](crate::FLAT_THICKNESS) of their size, centred on
    /// their plane, and touch on either face.
    ///
    /// No points is [`ShapeError::Empty`]; a NaN or infinite coordinate is
    /// [`ShapeError::NonFinite`], one beyond
    /// [`MAX_COORDINATE`](bvol_volumes::MAX_COORDINATE)
    /// [`ShapeError::OutOfRange`]; a point, points on a line, and flat points
    /// whose plane is too far from the origin for the thickness to show at
    /// f32 precision are [`ShapeError::Degenerate`].
    ///
    /// ```
    /// use bvol_narrow::{Collision, Polyhedron, Pose, WarmStart, hull_hull};
    /// use glam::{Quat, Vec3};
    /// // A 2 x 2 tile in the plane y = 0, and a unit cube sunk 0.1 into it from below.
    /// let tile = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, z)| Vec3::new(x, 0.0, z));
    /// let tile = Polyhedron::from_points(&tile)?;
    /// let cube = Polyhedron::cuboid(Vec3::splat(0.5))?;
    /// let below = Pose::new(Vec3::new(0.0, -0.4, 0.0), Quat::IDENTITY);
    /// let hit = hull_hull(&tile, &Pose::IDENTITY, &cube, &below, &mut WarmStart::default())?;
    /// let Collision::Touching(contact) = hit else { panic!("the cube reaches 0.1 above the tile") };
    /// assert_eq!(contact.normal, -Vec3::Y);
    /// assert!((contact.depth - 0.1).abs() < 1e-4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_points(points: &[Vec3]) -> Result<Polyhedron, ShapeError> {
        Polyhedron::from_hull(&solid_hull(points)?)
    }

    /// A polyhedron from a convex hull: its vertices, its faces (convex
    /// polygons, coplanar triangles merged) and their planes.
    ///
    /// A hull that is not solid (a point, a segment or a flat polygon) is
    /// [`ShapeError::Degenerate`] with its dimension.
    pub fn from_hull(hull: &ConvexHull) -> Result<Polyhedron, ShapeError> {
        let dimension = hull.dimension();
        let faces = (0..hull.face_count()).map(|f| hull.face(f));
        // A solid hull's faces close up (each edge once each way); checked
        // here anyway, so a broken hull is an error and not a walk that never ends.
        let topology = (dimension == 3)
            .then(|| Topology::from_faces(hull.vertices().len(), faces))
            .flatten()
            .ok_or(ShapeError::Degenerate { dimension })?;
        let planes = (0..hull.face_count())
            .map(|f| Plane { normal: hull.face_normal(f), offset: hull.face_offset(f) })
            .collect();
        Ok(Polyhedron::assemble(hull.vertices().to_vec(), planes, topology))
    }

    /// The box `[-half_extents, half_extents]`: the unit cube scaled, the same
    /// numbers that [`obb_obb`](crate::obb_obb) uses for a box.
    ///
    /// Half extents that are not all finite and `> 0` are
    /// [`ShapeError::BadHalfExtents`].
    pub fn cuboid(half_extents: Vec3) -> Result<Polyhedron, ShapeError> {
        if !(half_extents.is_finite() && half_extents.cmpgt(Vec3::ZERO).all()) {
            return Err(ShapeError::BadHalfExtents);
        }
        let unit = Polyhedron::unit_cube();
        let half = half_extents.as_dvec3();
        Ok(Polyhedron::assemble(
            unit.vertices.iter().map(|&v| v * half_extents).collect(),
            unit.planes.iter().map(|&p| p.scaled_to_box(half)).collect(),
            unit.topology.clone(),
        ))
    }

    /// The polyhedron from its parts, with what the queries read measured:
    /// its size, a ball inside it, the hill-climbing seeds, the edges' arcs,
    /// and the faces and edges renumbered into clusters by direction.
    fn assemble(vertices: Vec<Vec3>, planes: Vec<Plane>, topology: Topology) -> Polyhedron {
        let points: Vec<DVec3> = vertices.iter().map(|v| v.as_dvec3()).collect();
        let (lo, hi) = points
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let size = ((hi - lo) * 0.5).length();
        let reach = points.iter().map(|p| p.length()).fold(0.0, f64::max);
        // The mean of the vertices is inside; a ball about it reaching no face
        // plane is inside too.
        let centre = points.iter().sum::<DVec3>() / points.len() as f64;
        let radius = planes.iter().map(|p| -p.distance(centre)).fold(f64::INFINITY, f64::min);
        let faces: Vec<(Cap, f64)> =
            planes.iter().map(|p| (Cap::new(p.normal, 0.0), -p.distance(centre))).collect();
        let (face_order, face_clusters) = group(&faces);
        let face_caps: Vec<(Cap, f64)> = face_order.iter().map(|&f| faces[f as usize]).collect();
        let planes: Vec<Plane> = face_order.iter().map(|&f| planes[f as usize]).collect();
        let mut topology = topology.with_face_order(&face_order);
        let arcs: Vec<Arc> = topology
            .edges
            .iter()
            .map(|&h| {
                let face = |f: u32| planes[f as usize];
                Arc::new(face(topology.half_edge(h).face), face(topology.twin_face(h)), centre)
            })
            .collect();
        let arc_caps: Vec<(Cap, f64)> = arcs.iter().map(|a| (a.cap, a.inner)).collect();
        let (edge_order, edge_clusters) = group(&arc_caps);
        let arc_caps: Vec<(Cap, f64)> = edge_order.iter().map(|&e| arc_caps[e as usize]).collect();
        topology.edges = edge_order.iter().map(|&e| topology.edges[e as usize]).collect();
        let arcs: Vec<Arc> = edge_order.iter().map(|&e| arcs[e as usize]).collect();
        // First on ties, so the grid's centre slot (no direction) holds 0.
        let first_min = |m: (u32, f64), x: (u32, f64)| if x.1 < m.1 { x } else { m };
        let seeds = std::array::from_fn(|slot| {
            let dir = seed_direction(slot);
            (0u32..)
                .zip(&points)
                .map(|(i, p)| (i, dir.dot(*p)))
                .fold((0, f64::INFINITY), first_min)
                .0
        });
        let face_seeds = std::array::from_fn(|slot| {
            let dir = seed_direction(slot);
            let along = (0u32..).zip(&planes).map(|(f, p)| (f, -dir.dot(p.normal)));
            along.fold((0, f64::INFINITY), first_min).0
        });
        let box_shape = BoxNumbering::of(&points, &planes, &topology);
        Polyhedron {
            vertices,
            points,
            planes,
            topology,
            size,
            reach,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            inner_ball: (centre, radius.max(0.0)),
            arcs,
            face_lanes: CapLanes::pack(&face_caps),
            arc_lanes: CapLanes::pack(&arc_caps),
            face_clusters,
            edge_clusters,
            seeds,
            face_seeds,
            box_shape,
        }
    }

    /// The vertices, in local space.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// Number of faces (convex polygons).
    pub fn face_count(&self) -> usize {
        self.planes.len()
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.topology.edges.len()
    }

    /// The cube `[-1, 1]^3`, built once.
    pub(crate) fn unit_cube() -> &'static Polyhedron {
        static CUBE: OnceLock<Polyhedron> = OnceLock::new();
        CUBE.get_or_init(|| {
            // The box hull's corner order, which `Shape::cuboid` pairs with
            // this cube scaled.
            let hull = ConvexHull::cuboid(Vec3::ONE).expect("a unit cube has a hull");
            Polyhedron::from_hull(&hull).expect("eight cube corners span a solid")
        })
    }
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

/// [`Convex::support_min`] by hill climbing on the vertex graph, to the
/// steepest neighbour while one is strictly lower, from `start`: the
/// previous face's, arc's or last call's answer (often a step away), or the
/// [`seed`](Convex::seed) for `dir` where there is none (never far). On a
/// convex polyhedron a vertex no neighbour improves on is a global minimum
/// (up to the hull's coplanarity tolerance), whatever the start, so the
/// start is not compared with the seed: it is near already. Stops early at
/// or below `limit`: a query that only needs to know whether the least beats
/// a bar climbs no further.
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
