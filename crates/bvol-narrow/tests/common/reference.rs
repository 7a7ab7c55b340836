//! An exact separating-axis reference in f64, written apart from bvol-narrow.
//!
//! The bodies are the f32 inputs taken as exact: the hull's f32 vertices and
//! the pose's f32 position, with its f32 quaternion normalised in f64. Two
//! convex polyhedra are disjoint iff one of their face normals or one of the
//! cross products of an edge of each separates them (Gottschalk, Lin & Manocha
//! 1996; Ericson, Real-Time Collision Detection 4.4). Over that finite axis set:
//! - the verdict "separated iff some axis has a positive gap" is exact;
//! - when they touch, the least overlap over the set is exactly the penetration
//!   depth (the minimum translation distance): it is the distance from the
//!   origin to the nearest face of the Minkowski difference, and every face
//!   normal of that difference is in the set, while any other direction's
//!   overlap is at least the depth;
//! - when they are apart the greatest gap is a lower bound on their distance.
//!
//! Shortcuts keep it fast on hulls of hundreds of vertices; the tests check
//! them against the plain version (every face normal and edge-pair cross
//! product, both ways, extents from every vertex):
//! - only the axes that may be faces of the Minkowski difference are tried,
//!   each oriented from A to B: A's face normals, minus B's, and the edge pairs
//!   whose Gauss-map arcs cross (Gregorius, GDC 2013), found through a grid
//!   over the arcs' centres and tested with a generous slack: extra axes are
//!   harmless (any direction is a valid test, its overlap at least the depth),
//!   so the pruning can only keep too many;
//! - extents come from hill climbing on the vertex graph, from where the
//!   support is known to be (the face's or edge's vertices): on a convex
//!   polytope, a vertex no neighbour of which is higher along a direction is
//!   the highest (the simplex method's optimality condition). The gap is never
//!   read off the edges alone: merged faces are flat only to the hull's
//!   tolerance, so an edge can be off its faces' arc by that tolerance over
//!   its length, and on a near-degenerate crossing not be the support at all.
//!
//! The faces are those bvol-volumes' quickhull merged within its tolerance
//! (about 4e-7 of the size), which bounds how far this is from the exact hull
//! of the points.

use bvol_volumes::{ConvexHull, Pose};
use glam::{DMat3, DVec3};
use std::cell::OnceCell;
use std::collections::HashMap;

/// Slack on the Gauss-map crossing products: pairs within it are kept.
const ARC_SLACK: f64 = 1e-9;

/// Hulls up to this many vertices take extents from every vertex, larger ones
/// by hill climbing.
const CLIMB_FROM: usize = 48;

/// Edge pairs closer to parallel than this (sine of their angle) are skipped:
/// their Minkowski face is a sliver under 1e-12 of the size across.
const PARALLEL_SINE: f64 = 1e-12;

/// A rigid placement in f64.
#[derive(Clone, Copy, Debug)]
pub struct Place {
    /// Linear part (a rotation, up to the rounding of its f32 source).
    pub rotation: DMat3,
    /// Translation.
    pub position: DVec3,
}

impl Place {
    /// The pose taken as exact, its quaternion normalised in f64.
    pub fn of(pose: &Pose) -> Place {
        Place {
            rotation: DMat3::from_quat(pose.rotation.as_dquat().normalize()),
            position: pose.position.as_dvec3(),
        }
    }

    /// `outer` after `self`: a body-local placement moved by the body's pose.
    pub fn then(&self, outer: &Place) -> Place {
        Place {
            rotation: outer.rotation * self.rotation,
            position: outer.rotation * self.position + outer.position,
        }
    }

    /// A local point in the world.
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.position
    }

    /// A world point in local space (the linear part taken as orthonormal).
    pub fn local_point(&self, p: DVec3) -> DVec3 {
        self.rotation.transpose() * (p - self.position)
    }
}

/// An edge with the outward normals of its two faces, in local space.
#[derive(Clone, Copy, Debug)]
struct Edge {
    /// Index of one end.
    tail: u32,
    direction: DVec3,
    normals: [DVec3; 2],
    /// Unit centre of its arc on the Gauss map, from one normal to the other.
    mid: DVec3,
    /// Half the arc's angle.
    half_angle: f64,
}

/// A solid convex polyhedron in f64, local space.
#[derive(Clone, Debug)]
pub struct RefHull {
    vertices: Vec<DVec3>,
    faces: Vec<Vec<u32>>,
    normals: Vec<DVec3>,
    offsets: Vec<f64>,
    edges: Vec<Edge>,
    /// Each vertex's neighbours along the edges.
    neighbours: Vec<Vec<u32>>,
    /// Where hill climbing may start: the extremes along the six axis directions.
    seeds: Vec<u32>,
}

impl RefHull {
    /// From a solid hull of bvol-volumes (panics on a flat one).
    pub fn new(hull: &ConvexHull) -> RefHull {
        assert_eq!(hull.dimension(), 3, "the reference takes solid hulls");
        let faces = (0..hull.face_count()).map(|f| hull.face(f).to_vec()).collect();
        let normals = (0..hull.face_count()).map(|f| hull.face_normal(f)).collect();
        let offsets = (0..hull.face_count()).map(|f| hull.face_offset(f)).collect();
        let vertices = hull.vertices().iter().map(|v| v.as_dvec3()).collect();
        RefHull::assemble(vertices, faces, normals, offsets)
    }

    /// The box `|x_i| <= half[i]`, with exact planes.
    pub fn cuboid(half: DVec3) -> RefHull {
        let corner = |i: u32| {
            DVec3::new(
                if i & 1 == 0 { -half.x } else { half.x },
                if i & 2 == 0 { -half.y } else { half.y },
                if i & 4 == 0 { -half.z } else { half.z },
            )
        };
        let vertices = (0..8).map(corner).collect();
        // Counter-clockwise from outside: -x, +x, -y, +y, -z, +z.
        let faces: Vec<Vec<u32>> = vec![
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
        ];
        let normals: Vec<DVec3> =
            [-DVec3::X, DVec3::X, -DVec3::Y, DVec3::Y, -DVec3::Z, DVec3::Z].into_iter().collect();
        let offsets = normals.iter().map(|n| n.abs().dot(half)).collect();
        RefHull::assemble(vertices, faces, normals, offsets)
    }

    fn assemble(
        vertices: Vec<DVec3>,
        faces: Vec<Vec<u32>>,
        normals: Vec<DVec3>,
        offsets: Vec<f64>,
    ) -> RefHull {
        // Each directed edge a -> b runs along exactly one face loop.
        let mut owner = HashMap::new();
        for (f, face) in faces.iter().enumerate() {
            for k in 0..face.len() {
                owner.insert((face[k], face[(k + 1) % face.len()]), f);
            }
        }
        // HashMap order is not deterministic: sort, so that ties break the same
        // way every run.
        let mut ends: Vec<(u32, u32)> = owner.keys().copied().filter(|(a, b)| a < b).collect();
        ends.sort_unstable();
        let edges = ends
            .iter()
            .map(|&(a, b)| {
                let pair = [normals[owner[&(a, b)]], normals[owner[&(b, a)]]];
                let sum = pair[0] + pair[1];
                Edge {
                    tail: a,
                    direction: vertices[b as usize] - vertices[a as usize],
                    normals: pair,
                    mid: sum.normalize(),
                    half_angle: (pair[0] - pair[1]).length().atan2(sum.length()),
                }
            })
            .collect();
        let mut neighbours = vec![Vec::new(); vertices.len()];
        for &(a, b) in &ends {
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
        }
        let seeds = [-1.0, 1.0]
            .into_iter()
            .flat_map(|s| [DVec3::X * s, DVec3::Y * s, DVec3::Z * s])
            .map(|d| highest(&vertices, d))
            .collect();
        RefHull { vertices, faces, normals, offsets, edges, neighbours, seeds }
    }

    /// Vertices, local.
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Vertex indices of face `f`, counter-clockwise from outside.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.faces[f]
    }

    /// Outward unit normal of face `f`, local.
    pub fn normal(&self, f: usize) -> DVec3 {
        self.normals[f]
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Direction of edge `e` and the outward normals of its two faces, local.
    pub fn edge(&self, e: usize) -> (DVec3, [DVec3; 2]) {
        (self.edges[e].direction, self.edges[e].normals)
    }

    /// Largest distance of a vertex from the local origin.
    pub fn radius(&self) -> f64 {
        self.vertices.iter().map(|v| v.length()).fold(0.0, f64::max)
    }

    /// Least and greatest `n . x` over the placed hull.
    pub fn extent(&self, place: &Place, n: DVec3) -> (f64, f64) {
        (-self.highest(place, -n, None), self.highest(place, n, None))
    }

    /// Greatest `d . x` over the placed hull: every vertex on a small hull,
    /// else by hill climbing from `start` (or the best seed): step to a
    /// strictly higher neighbour until there is none.
    fn highest(&self, place: &Place, d: DVec3, start: Option<u32>) -> f64 {
        let local = place.rotation.transpose() * d;
        let at = |i: u32| self.vertices[i as usize].dot(local);
        let top = if self.vertices.len() <= CLIMB_FROM {
            self.vertices.iter().map(|v| v.dot(local)).fold(f64::NEG_INFINITY, f64::max)
        } else {
            let best_seed = || self.seeds.iter().copied().max_by(|&i, &j| at(i).total_cmp(&at(j)));
            let mut v = start.or_else(best_seed).expect("seeds");
            let mut height = at(v);
            'up: loop {
                for &w in &self.neighbours[v as usize] {
                    if at(w) > height {
                        (v, height) = (w, at(w));
                        continue 'up;
                    }
                }
                break height;
            }
        };
        top + d.dot(place.position)
    }

    /// Least and greatest `n . x` over the placed hull, from every vertex.
    pub fn extent_brute(&self, place: &Place, n: DVec3) -> (f64, f64) {
        let local = place.rotation.transpose() * n;
        let (lo, hi) = self
            .vertices
            .iter()
            .map(|v| v.dot(local))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)));
        let shift = n.dot(place.position);
        (lo + shift, hi + shift)
    }

    /// The greatest excess of a world point over the placed face planes: `<= r`
    /// when the point lies in the hull grown by `r` (each plane pushed out by
    /// `r`, a superset of the hull's `r`-neighbourhood), `<= 0` inside.
    pub fn plane_excess(&self, place: &Place, p: DVec3) -> f64 {
        let q = place.local_point(p);
        self.normals.iter().zip(&self.offsets).map(|(n, d)| n.dot(q) - d).fold(f64::MIN, f64::max)
    }

    /// The closest point of the surface to a local point (Ericson 5.1.5 on every
    /// fan triangle).
    pub fn closest_on_surface(&self, p: DVec3) -> DVec3 {
        let mut best = (DVec3::ZERO, f64::INFINITY);
        for face in &self.faces {
            let at = |k: usize| self.vertices[face[k] as usize];
            for k in 1..face.len() - 1 {
                let q = closest_on_triangle(p, at(0), at(k), at(k + 1));
                let d = q.distance_squared(p);
                if d < best.1 {
                    best = (q, d);
                }
            }
        }
        best.0
    }
}

/// Index of the vertex highest along `d` (the first of equals).
fn highest(vertices: &[DVec3], d: DVec3) -> u32 {
    let mut best = 0;
    for (i, v) in vertices.iter().enumerate() {
        if v.dot(d) > vertices[best].dot(d) {
            best = i;
        }
    }
    best as u32
}

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
pub fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Hull `a` at `pa` and hull `b` at `pb`.
#[derive(Clone, Copy, Debug)]
pub struct Pair<'a> {
    pub a: &'a RefHull,
    pub pa: Place,
    pub b: &'a RefHull,
    pub pb: Place,
}

/// The reference's answer.
#[derive(Clone, Copy, Debug)]
pub struct Sat {
    /// Greatest gap over the axis set: `> 0` apart (a lower bound on the
    /// distance), `<= 0` touching, and then `-separation` is the depth.
    pub separation: f64,
    /// The unit axis with that gap, pointing from A to B.
    pub axis: DVec3,
}

impl Sat {
    /// Penetration depth, 0 when apart.
    pub fn depth(&self) -> f64 {
        (-self.separation).max(0.0)
    }
}

/// The candidate axes of a pair (see [`Pair::candidates`]).
pub struct Candidates(Vec<Candidate>);

/// A candidate axis, unit, oriented from A to B, and how its gap is read.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    axis: DVec3,
    kind: Kind,
}

/// Where the gap along a candidate comes from.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// The normal of A's face `f`: A's highest point along it is on that face.
    FaceA(usize),
    /// Minus the normal of B's face `f`: B's lowest point is on that face.
    FaceB(usize),
    /// The common normal of an edge of each whose Gauss-map arcs clearly
    /// cross: A's highest and B's lowest points are at (or next to, as merged
    /// faces are flat only to the hull's tolerance) the edges' ends `a` and `b`.
    Edges { a: u32, b: u32 },
    /// An edge pair whose arcs only may cross: both orientations taken.
    Any,
}

impl Pair<'_> {
    /// Gap of B beyond A along unit `n` (from A to B): `min_B n.x - max_A n.x`;
    /// its negation is the overlap along `n`.
    pub fn gap(&self, n: DVec3) -> f64 {
        self.b.extent(&self.pb, n).0 - self.a.extent(&self.pa, n).1
    }

    /// The gap along a candidate and its axis, from A to B: extents by hill
    /// climbing from where the supports are known to be.
    fn candidate_gap(&self, c: &Candidate) -> (f64, DVec3) {
        let n = c.axis;
        let gap = |a: Option<u32>, b: Option<u32>| {
            -self.b.highest(&self.pb, -n, b) - self.a.highest(&self.pa, n, a)
        };
        match c.kind {
            Kind::FaceA(f) => (gap(Some(self.a.faces[f][0]), None), n),
            Kind::FaceB(f) => (gap(None, Some(self.b.faces[f][0])), n),
            Kind::Edges { a, b } => (gap(Some(a), Some(b)), n),
            Kind::Any => self.oriented(n, false),
        }
    }

    /// The better orientation of unit axis `n`: its gap and the oriented axis.
    fn oriented(&self, n: DVec3, brute: bool) -> (f64, DVec3) {
        let extent = if brute { RefHull::extent_brute } else { RefHull::extent };
        let (a_lo, a_hi) = extent(self.a, &self.pa, n);
        let (b_lo, b_hi) = extent(self.b, &self.pb, n);
        let (forward, backward) = (b_lo - a_hi, a_lo - b_hi);
        if forward >= backward { (forward, n) } else { (backward, -n) }
    }

    /// The world axes that may be faces of the Minkowski difference, each
    /// oriented from A to B: A's face normals, minus B's, and the common normals
    /// of the edge pairs whose Gauss-map arcs may cross. They depend on the
    /// rotations only: a pair moved without turning keeps them.
    pub fn candidates(&self) -> Candidates {
        Candidates(self.candidate_list())
    }

    fn candidate_list(&self) -> Vec<Candidate> {
        let (ra, rb) = (self.pa.rotation, self.pb.rotation);
        let faces_a = (0..self.a.face_count())
            .map(|f| Candidate { axis: ra * self.a.normals[f], kind: Kind::FaceA(f) });
        let faces_b = (0..self.b.face_count())
            .map(|f| Candidate { axis: -(rb * self.b.normals[f]), kind: Kind::FaceB(f) });
        let mut all: Vec<Candidate> = faces_a.chain(faces_b).collect();
        let arcs_a: Vec<Arc> = self.a.edges.iter().map(|e| Arc::new(e, &self.pa, 1.0)).collect();
        let arcs_b: Vec<Arc> = self.b.edges.iter().map(|e| Arc::new(e, &self.pb, -1.0)).collect();
        for_crossing_arcs(&arcs_a, &arcs_b, |e, f, strict| {
            let n = e.direction.cross(f.direction);
            if n.length() <= PARALLEL_SINE * e.direction.length() * f.direction.length() {
                return;
            }
            // On both arcs, the crossing point is on the side of A's arc's centre.
            let n = n.normalize();
            let axis = if n.dot(e.mid) >= 0.0 { n } else { -n };
            let kind = if strict { Kind::Edges { a: e.tail, b: f.tail } } else { Kind::Any };
            all.push(Candidate { axis, kind });
        });
        all
    }

    /// The exact answer: the greatest gap over the candidates.
    pub fn sat(&self) -> Sat {
        self.sat_with(&self.candidates())
    }

    /// The exact answer over candidates from a pair with the same rotations.
    pub fn sat_with(&self, candidates: &Candidates) -> Sat {
        let mut best = Sat { separation: f64::NEG_INFINITY, axis: DVec3::X };
        for c in &candidates.0 {
            let (gap, axis) = self.candidate_gap(c);
            if gap > best.separation {
                best = Sat { separation: gap, axis };
            }
        }
        best
    }

    /// The exact answer the plain way: every face normal and every edge-pair
    /// cross product, each both ways, extents from every vertex.
    pub fn sat_brute(&self) -> Sat {
        let (ra, rb) = (self.pa.rotation, self.pb.rotation);
        let mut axes: Vec<DVec3> = (self.a.normals.iter().map(|&n| ra * n))
            .chain(self.b.normals.iter().map(|&n| rb * n))
            .collect();
        for e in &self.a.edges {
            for f in &self.b.edges {
                let (d, g) = (ra * e.direction, rb * f.direction);
                let n = d.cross(g);
                if n.length() > PARALLEL_SINE * d.length() * g.length() {
                    axes.push(n.normalize());
                }
            }
        }
        self.sat_over(&axes)
    }

    /// The answer over the given axes, each both ways, extents from every vertex.
    pub fn sat_over(&self, axes: &[DVec3]) -> Sat {
        let mut best = Sat { separation: f64::NEG_INFINITY, axis: DVec3::X };
        for &n in axes {
            let (gap, axis) = self.oriented(n, true);
            if gap > best.separation {
                best = Sat { separation: gap, axis };
            }
        }
        best
    }

    /// The candidate axes whose overlap is within `tol` of the least.
    pub fn minimal_axes(&self, tol: f64) -> Vec<DVec3> {
        let gaps: Vec<(f64, DVec3)> =
            self.candidate_list().iter().map(|c| self.candidate_gap(c)).collect();
        let best = gaps.iter().map(|g| g.0).fold(f64::NEG_INFINITY, f64::max);
        gaps.into_iter().filter(|(g, _)| *g >= best - tol).map(|g| g.1).collect()
    }

    /// How far B must move along unit `u` from where it is to just touch A (the
    /// first translation at which the gap closes, exactly): along each
    /// candidate the gap grows by `t (n . u)`, so contact ends at the least
    /// `-gap / (n . u)` over candidates with `n . u > 0`. Needs the pair to
    /// touch now, and its candidates.
    pub fn touching_offset(&self, u: DVec3, candidates: &Candidates) -> f64 {
        let mut t = f64::INFINITY;
        for c in &candidates.0 {
            let (gap, n) = self.candidate_gap(c);
            let k = n.dot(u);
            if k > 0.0 {
                t = t.min(-gap / k);
            }
        }
        t
    }
}

/// Calls `visit(e, f, strict)` for every arc `e` of A and `f` of B that may
/// cross, `strict` when they cross without the slack.
///
/// Arcs that cross have centres at most the sum of their half angles apart,
/// so the boxes around their centres as wide as their half angles overlap.
/// B's narrow arcs are put in the cells of a grid over the cube [-1, 1]^3 that
/// their boxes meet, and each arc of A looks in the cells its box meets; wide
/// arcs (few but for coarse hulls) are tried against every arc.
fn for_crossing_arcs(arcs_a: &[Arc], arcs_b: &[Arc], mut visit: impl FnMut(&Arc, &Arc, bool)) {
    let mut try_pair = |e: &Arc, f: &Arc| {
        let near = (f.mid - e.mid).abs().max_element() <= e.half_angle + f.half_angle + ARC_SLACK;
        if let Some(strict) = near.then(|| e.crossing(f)).flatten() {
            visit(e, f, strict);
        }
    };
    let (wide, narrow): (Vec<&Arc>, Vec<&Arc>) =
        arcs_b.iter().partition(|f| f.half_angle > WIDE_ARC);
    let grid = Grid::new(&narrow);
    let mut seen = vec![usize::MAX; narrow.len()];
    for (i, e) in arcs_a.iter().enumerate() {
        if e.half_angle > WIDE_ARC {
            narrow.iter().for_each(|f| try_pair(e, f));
        } else {
            Grid::for_cells(e.mid, e.half_angle + ARC_SLACK, |cell| {
                for &j in grid.arcs_in(cell) {
                    if std::mem::replace(&mut seen[j as usize], i) != i {
                        try_pair(e, narrow[j as usize]);
                    }
                }
            });
        }
        wide.iter().for_each(|f| try_pair(e, f));
    }
}

/// Arcs up to this half angle (radians) go in the grid of [`for_crossing_arcs`].
const WIDE_ARC: f64 = 0.25;
/// Cells of that grid per side of the cube [-1, 1]^3.
const GRID_CELLS: usize = 16;

/// Which arcs' boxes meet each cell: arc indices grouped by cell.
struct Grid {
    starts: Vec<u32>,
    arcs: Vec<u32>,
}

impl Grid {
    /// The grid of `arcs` (a counting sort of their cells).
    fn new(arcs: &[&Arc]) -> Grid {
        let mut starts = vec![0u32; GRID_CELLS.pow(3) + 1];
        for f in arcs {
            Grid::for_cells(f.mid, f.half_angle, |c| starts[c as usize + 1] += 1);
        }
        for c in 0..GRID_CELLS.pow(3) {
            starts[c + 1] += starts[c];
        }
        let mut next = starts.clone();
        let mut grouped = vec![0u32; starts[GRID_CELLS.pow(3)] as usize];
        for (i, f) in arcs.iter().enumerate() {
            Grid::for_cells(f.mid, f.half_angle, |c| {
                grouped[next[c as usize] as usize] = i as u32;
                next[c as usize] += 1;
            });
        }
        Grid { starts, arcs: grouped }
    }

    fn arcs_in(&self, cell: u32) -> &[u32] {
        &self.arcs[self.starts[cell as usize] as usize..self.starts[cell as usize + 1] as usize]
    }

    /// Calls `f` with each cell that the box of half width `r` around `m` meets.
    fn for_cells(m: DVec3, r: f64, mut f: impl FnMut(u32)) {
        let n = GRID_CELLS as f64;
        let index = |x: f64| (((x + 1.0) * 0.5 * n).floor().clamp(0.0, n - 1.0)) as u32;
        let (lo, hi) = ((m - r).to_array().map(index), (m + r).to_array().map(index));
        let side = GRID_CELLS as u32;
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    f((x * side + y) * side + z);
                }
            }
        }
    }
}

/// An edge's arc on the Gauss map, in world space: from one face normal to the
/// other (negated for B, whose map enters the Minkowski difference B - A
/// reflected), with a local point of the edge.
struct Arc {
    /// Index of one end of the edge.
    tail: u32,
    direction: DVec3,
    normals: [DVec3; 2],
    /// Unit centre of the arc.
    mid: DVec3,
    /// Half the arc's angle.
    half_angle: f64,
}

impl Arc {
    fn new(e: &Edge, place: &Place, sign: f64) -> Arc {
        let r = place.rotation;
        let normals = [r * e.normals[0] * sign, r * e.normals[1] * sign];
        Arc {
            tail: e.tail,
            direction: r * e.direction,
            normals,
            mid: r * e.mid * sign,
            half_angle: e.half_angle,
        }
    }

    /// Whether the arcs cross (Gregorius, GDC 2013, "IsMinkowskiFace": the arc
    /// `a`-`b` meets the great circle through `c`-`d` and the other way round,
    /// on the same hemisphere): `Some(true)` if they clearly do (every sign
    /// test by more than the slack, so rounding cannot flip it), `Some(false)`
    /// if they may, within the slack, `None` if not. Near-parallel edges have
    /// arcs on nearly one great circle, where the tests are products of tiny
    /// numbers: only a clear crossing may have its gap read off the edges.
    fn crossing(&self, other: &Arc) -> Option<bool> {
        let [a, b] = self.normals;
        let [c, d] = other.normals;
        let (bxa, dxc) = (b.cross(a), d.cross(c));
        let (cba, dba) = (c.dot(bxa), d.dot(bxa));
        let (adc, bdc) = (a.dot(dxc), b.dot(dxc));
        let (p, q, r) = (cba * dba, adc * bdc, cba * bdc);
        if p < -ARC_SLACK && q < -ARC_SLACK && r > ARC_SLACK {
            Some(true)
        } else {
            (p < ARC_SLACK && q < ARC_SLACK && r > -ARC_SLACK).then_some(false)
        }
    }
}

/// A sphere against a hull, exactly.
#[derive(Clone, Copy, Debug)]
pub struct SphereHull<'a> {
    /// World centre of the sphere (body A).
    pub center: DVec3,
    /// Its radius.
    pub radius: f64,
    /// The hull (body B) and its placement.
    pub hull: &'a RefHull,
    pub place: Place,
}

impl SphereHull<'_> {
    /// Gap of the hull beyond the sphere along unit `n`.
    pub fn gap(&self, n: DVec3) -> f64 {
        self.hull.extent(&self.place, n).0 - (self.center.dot(n) + self.radius)
    }

    /// Whether another axis than `axis`, more than `angle` radians from it,
    /// is within `tol` of the least overlap: when the centre is inside, the
    /// face planes as near as the nearest; outside, only a centre on the
    /// surface leaves the normal open.
    pub fn tied(&self, axis: DVec3, angle: f64, tol: f64) -> bool {
        let c = self.place.local_point(self.center);
        let hull = self.hull;
        let excess: Vec<f64> =
            (0..hull.face_count()).map(|f| hull.normals[f].dot(c) - hull.offsets[f]).collect();
        let nearest = excess.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if nearest > 0.0 {
            return (hull.closest_on_surface(c) - c).length() <= tol;
        }
        let near = (0..hull.face_count()).filter(|&f| excess[f] >= nearest - tol);
        any_apart(near.map(|f| -(self.place.rotation * hull.normals[f])), axis, angle)
    }

    /// The exact answer: `separation` is the distance between the surfaces
    /// (minus the depth when they touch), `axis` from the sphere to the hull.
    pub fn sat(&self) -> Sat {
        let c = self.place.local_point(self.center);
        let hull = self.hull;
        let excess = |f: usize| hull.normals[f].dot(c) - hull.offsets[f];
        let nearest = (0..hull.face_count()).max_by(|&i, &j| excess(i).total_cmp(&excess(j)));
        let nearest = nearest.expect("faces");
        if excess(nearest) <= 0.0 {
            // Inside: the nearest face plane is the nearest boundary, and the
            // hull leaves the sphere by moving against that face's normal.
            let axis = -(self.place.rotation * hull.normals[nearest]);
            return Sat { separation: excess(nearest) - self.radius, axis };
        }
        let q = hull.closest_on_surface(c);
        let d = q - c;
        Sat { separation: d.length() - self.radius, axis: self.place.rotation * d.normalize() }
    }
}

/// What the checks ask of an exact answer, for any pair of bodies.
pub trait Exact {
    /// The exact verdict, depth (or separation) and axis.
    fn sat(&self) -> Sat;
    /// Gap of B beyond A along unit `n` (minus the overlap).
    fn gap(&self, n: DVec3) -> f64;
    /// Whether another axis, more than `angle` radians from `axis` (the
    /// answer's), overlaps by no more than `tol` over the least: then either
    /// is a right normal.
    fn tied(&self, axis: DVec3, angle: f64, tol: f64) -> bool;
}

/// Whether some of `axes` are more than `angle` radians from `axis`.
fn any_apart(axes: impl IntoIterator<Item = DVec3>, axis: DVec3, angle: f64) -> bool {
    axes.into_iter().any(|m| m.cross(axis).length().atan2(m.dot(axis)) > angle)
}

impl Exact for Pair<'_> {
    fn sat(&self) -> Sat {
        Pair::sat(self)
    }
    fn gap(&self, n: DVec3) -> f64 {
        Pair::gap(self, n)
    }
    fn tied(&self, axis: DVec3, angle: f64, tol: f64) -> bool {
        any_apart(self.minimal_axes(tol), axis, angle)
    }
}

/// A pair whose candidates are computed once, when first needed, or handed
/// over from the same pair before it moved without turning.
pub struct Prepared<'a> {
    pub pair: Pair<'a>,
    candidates: OnceCell<Candidates>,
}

impl<'a> Prepared<'a> {
    pub fn new(pair: Pair<'a>, candidates: Option<Candidates>) -> Prepared<'a> {
        let cell = OnceCell::new();
        if let Some(c) = candidates {
            let _ = cell.set(c);
        }
        Prepared { pair, candidates: cell }
    }
}

impl Exact for Prepared<'_> {
    fn sat(&self) -> Sat {
        self.pair.sat_with(self.candidates.get_or_init(|| self.pair.candidates()))
    }
    fn gap(&self, n: DVec3) -> f64 {
        self.pair.gap(n)
    }
    fn tied(&self, axis: DVec3, angle: f64, tol: f64) -> bool {
        self.pair.tied(axis, angle, tol)
    }
}

impl Exact for SphereHull<'_> {
    fn sat(&self) -> Sat {
        SphereHull::sat(self)
    }
    fn gap(&self, n: DVec3) -> f64 {
        SphereHull::gap(self, n)
    }
    fn tied(&self, axis: DVec3, angle: f64, tol: f64) -> bool {
        SphereHull::tied(self, axis, angle, tol)
    }
}
