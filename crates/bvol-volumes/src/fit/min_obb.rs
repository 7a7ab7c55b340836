//! Near-minimum-volume boxes on the convex hull.
//!
//! A box is fixed by one unit axis `n` and its rotation about `n`. For a given
//! `n` the best rotation is the minimum-area rectangle around the hull's
//! shadow on the plane of `n` (see `min_rect`), so the volume becomes a
//! function of `n` alone, `V(n) = height(n) * rect(n)`, over two degrees of
//! freedom. It is evaluated at the candidates that the exact algorithms
//! enumerate, and the best few are polished by local descent:
//!
//! - a box face flush with each hull face (`n` a face normal; the optimum when
//!   some box face is flush with a hull face);
//! - two opposite box faces flush with two hull edges (`n = e1 x e2` for edges
//!   whose Gauss-map arcs are antipodal: one edge on the top support plane,
//!   the other on the bottom one). O'Rourke (1985, "Finding minimal enclosing
//!   boxes") shows that minimal boxes have faces flush with hull edges where no
//!   face is flush with a hull face; the regular tetrahedron's optimum, its
//!   circumscribed cube, is one of these and no face-flush box;
//! - the axes of the PCA-hull and DiTO boxes;
//! - Nelder-Mead descent on `V(n)` (Nelder & Mead 1965) from the best few of
//!   them (several on small hulls, whose volume has many local minima), then
//!   from the best result, cycling `n` through the three axes of the current
//!   box, so that each box axis in turn gets its rotation optimised: a descent
//!   over all three degrees of freedom of a rotation.
//!
//! Candidates are evaluated best-first by a lower bound, `height(n)` times the
//! area of the shadow (which costs a fraction of the rectangle), until the
//! bound reaches the best volume found. Every box kept is measured on the
//! vertices, so that rounding in a shadow can never pass off a box as smaller
//! than it is. On large hulls the work is bounded: the largest faces and the
//! longest edges go first.
//!
//! The result is never worse than the PCA-hull or DiTO boxes of the same input:
//! those are compared last, as the f32 boxes they are.

use glam::{DMat3, DVec2, DVec3, Vec3};

use super::min_rect::min_area_rect;
use super::{dito::dito, pca::hull_axes};
use crate::obb::basis;
use crate::{ConvexHull, Obb};

/// A bound on the work of the edge-pair search, in face and edge tests: every
/// pair of edges while the hull is small, the longest first edges against all
/// others on large hulls.
const PAIR_WORK: usize = 1 << 21;

/// A bound on the work of the face candidates, in vertices, faces and edges
/// visited (each evaluation visits them all): every face up to hulls of a few
/// thousand vertices, the largest faces on larger ones.
const FACE_WORK: usize = 1 << 25;

/// Nelder-Mead's first step, in radians: a few degrees, about the reach of one
/// candidate's basin.
const FIRST_STEP: f64 = 0.05;

/// Nelder-Mead stops when its simplex is this small, in radians: a change of
/// axes that moves the box's volume by about that fraction, at the limit of
/// what f32 boxes show.
const LAST_STEP: f64 = 1e-6;

/// A bound on function evaluations per descent.
const MAX_EVALS: usize = 60;

/// A bound on the work of the descents from several starts, in vertices,
/// faces and edges visited.
const DESCENT_WORK: usize = 1 << 17;

/// The most starts for descent.
const MAX_STARTS: usize = 8;

/// Rounds of cycling the descent through the three axes of the best box.
const MAX_ROUNDS: usize = 4;

/// The near-minimum-volume box.
pub(crate) fn min_volume(points: &[Vec3]) -> Obb {
    let Ok(hull) = ConvexHull::new(points) else {
        // Checked input always has a hull; keep a fast fit should that change.
        return dito::<13>(points);
    };
    let pca = hull_axes(&hull);
    let baselines = [Obb::on_basis(pca, points), dito::<7>(points), dito::<13>(points)];
    let axes = match hull.dimension() {
        3 => search(&hull, &baselines),
        // Flat: the plane's normal is the principal axis of least variance.
        2 => flat_axes(&hull, pca.z_axis),
        // A segment or a point: the principal axis runs along it.
        _ => pca,
    };
    let searched = Obb::on_basis(axes, points);
    baselines
        .into_iter()
        .fold(searched, |best, b| if b.volume() < best.volume() { b } else { best })
}

/// The box of a flat hull: its plane's normal, and the minimum-area rectangle
/// of its vertices in that plane.
fn flat_axes(hull: &ConvexHull, normal: DVec3) -> DMat3 {
    let (t1, t2) = normal.any_orthonormal_pair();
    let mut flat: Vec<DVec2> = hull
        .vertices()
        .iter()
        .map(|p| DVec2::new(p.as_dvec3().dot(t1), p.as_dvec3().dot(t2)))
        .collect();
    let rect = min_area_rect(&mut flat, &mut Vec::new());
    basis(normal, t1 * rect.side.x + t2 * rect.side.y)
}

/// The axes of the best box found on a solid hull: candidates, then descent.
fn search(hull: &ConvexHull, baselines: &[Obb]) -> DMat3 {
    let shape = Shape::new(hull);
    let mut eval = Evaluator::new(&shape);
    let mut axes: Vec<DVec3> = baselines
        .iter()
        .flat_map(|b| b.axes.as_dmat3().to_cols_array_2d())
        .map(DVec3::from_array)
        .collect();
    axes.extend(shape.largest_faces().map(|f| shape.normal(f)));
    edge_pairs(&shape, |n| axes.push(n));
    // Unit axes only (the f32 baselines are unit to rounding; a degenerate
    // face could have no normal).
    let axes: Vec<DVec3> = axes.into_iter().filter_map(DVec3::try_normalize).collect();
    // Best-first by the lower bound, until it reaches the best box.
    let mut order: Vec<(f64, usize)> =
        axes.iter().enumerate().map(|(i, &n)| (eval.lower_bound(n), i)).collect();
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut best = Best::new(starts(&shape));
    for (bound, i) in order {
        if bound >= best.volume() {
            break;
        }
        let c = eval.fit(axes[i]);
        if c.volume < best.bound() {
            best.offer(eval.verified(c));
        }
    }
    // With several starts, one descent from each; then every axis of the best.
    let start = match best.kept[..] {
        [] => return DMat3::IDENTITY,
        [only] => only,
        ref several => several
            .iter()
            .map(|&c| descend(&mut eval, c.axes.x_axis, c))
            .reduce(Candidate::min)
            .unwrap_or(several[0]),
    };
    polish(&mut eval, start).axes
}

/// How many candidates the local descent starts from: several on small hulls,
/// where the volume has many local minima and a descent is cheap; one on
/// large ones.
fn starts(shape: &Shape) -> usize {
    let per_descent = MAX_EVALS * (shape.vertices.len() + shape.areas.len() + shape.edges.len());
    (DESCENT_WORK / per_descent).clamp(1, MAX_STARTS)
}

/// The best few candidates so far, least volume first, each a different box.
struct Best {
    kept: Vec<Candidate>,
    room: usize,
}

impl Best {
    /// Room for `room >= 1` candidates.
    fn new(room: usize) -> Self {
        Best { kept: Vec::with_capacity(room + 1), room }
    }

    /// The least volume so far.
    fn volume(&self) -> f64 {
        self.kept.first().map_or(f64::INFINITY, |c| c.volume)
    }

    /// The volume a candidate must beat to be kept.
    fn bound(&self) -> f64 {
        if self.kept.len() < self.room { f64::INFINITY } else { self.kept[self.room - 1].volume }
    }

    /// Keeps a candidate that beats the bound, unless it is a box kept already
    /// (the same first axis: found twice, from coplanar faces or edges).
    fn offer(&mut self, c: Candidate) {
        let same = |k: &Candidate| k.axes.x_axis.dot(c.axes.x_axis).abs() > 1.0 - 1e-12;
        if c.volume >= self.bound() || self.kept.iter().any(same) {
            return;
        }
        let at = self.kept.partition_point(|k| k.volume <= c.volume);
        self.kept.insert(at, c);
        self.kept.truncate(self.room);
    }
}

/// A convex hull as the search reads it, in f64 about the mean of its
/// vertices: unit outward face normals, face areas, and each edge with the two
/// faces that meet there.
struct Shape {
    /// Vertices, relative to their mean.
    vertices: Vec<DVec3>,
    /// The normals' coordinates, apart so that passes over faces run on vectors.
    normals: [Vec<f64>; 3],
    /// Face areas.
    areas: Vec<f64>,
    edges: Vec<Edge>,
}

/// An edge of the hull: its two vertices, and the faces on either side.
#[derive(Clone, Copy)]
struct Edge {
    ends: [u32; 2],
    faces: [u32; 2],
}

impl Shape {
    /// The shape of a solid hull.
    fn new(hull: &ConvexHull) -> Shape {
        let raw = hull.vertices();
        let origin = raw.iter().fold(DVec3::ZERO, |s, p| s + p.as_dvec3()) / raw.len() as f64;
        let vertices: Vec<DVec3> = raw.iter().map(|p| p.as_dvec3() - origin).collect();
        let faces = hull.face_count();
        let normals: Vec<DVec3> = (0..faces).map(|f| hull.face_normal(f)).collect();
        // Newell's formula: twice the area vector is the sum of cross products
        // of consecutive vertices.
        let areas = (0..faces)
            .map(|f| {
                let ring = hull.face(f);
                let twice = ring
                    .iter()
                    .zip(ring.iter().cycle().skip(1))
                    .fold(DVec3::ZERO, |s, (&a, &b)| {
                        s + vertices[a as usize].cross(vertices[b as usize])
                    });
                0.5 * twice.dot(normals[f]).abs()
            })
            .collect();
        Shape {
            edges: edges(hull),
            vertices,
            normals: std::array::from_fn(|k| normals.iter().map(|n| n[k]).collect()),
            areas,
        }
    }

    /// The faces whose normals are candidates: all of them, or the largest
    /// when evaluating all would cost more than `FACE_WORK`.
    fn largest_faces(&self) -> impl Iterator<Item = usize> {
        let mut faces: Vec<usize> = (0..self.areas.len()).collect();
        let per_face = self.vertices.len() + self.areas.len() + self.edges.len();
        if faces.len() * per_face > FACE_WORK {
            faces.sort_by(|&f, &g| self.areas[g].total_cmp(&self.areas[f]).then(f.cmp(&g)));
            faces.truncate(FACE_WORK / per_face);
        }
        faces.into_iter()
    }

    /// The unit outward normal of face `f`.
    fn normal(&self, f: usize) -> DVec3 {
        DVec3::new(self.normals[0][f], self.normals[1][f], self.normals[2][f])
    }

    /// An edge as a vector, from its first vertex to its second.
    fn edge_vector(&self, e: &Edge) -> DVec3 {
        self.vertices[e.ends[1] as usize] - self.vertices[e.ends[0] as usize]
    }
}

/// The edges of the hull's faces, each with the two faces it borders: the
/// sides of every face polygon, matched in sorted order. A side that is not
/// shared by exactly two faces (which a closed hull never has) is left out.
fn edges(hull: &ConvexHull) -> Vec<Edge> {
    let mut sides: Vec<([u32; 2], u32)> = (0..hull.face_count())
        .flat_map(|f| {
            let ring = hull.face(f);
            ring.iter()
                .zip(ring.iter().cycle().skip(1))
                .map(move |(&a, &b)| ([a.min(b), a.max(b)], f as u32))
        })
        .collect();
    sides.sort_unstable();
    sides
        .chunk_by(|x, y| x.0 == y.0)
        .filter_map(|c| match c {
            [(ends, f), (_, g)] => Some(Edge { ends: *ends, faces: [*f, *g] }),
            _ => None,
        })
        .collect()
}

/// A box: its volume in f64 and its axes, the first the `n` it was fitted along.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    volume: f64,
    axes: DMat3,
}

impl Candidate {
    /// The one of less volume, `self` on ties.
    fn min(self, other: Candidate) -> Candidate {
        if other.volume < self.volume { other } else { self }
    }
}

/// Evaluates `V(n)` on a shape, with scratch space reused between calls.
struct Evaluator<'a> {
    shape: &'a Shape,
    /// Whether each face faces along `n`.
    front: Vec<bool>,
    /// The call in which each vertex was last put in the shadow, to put it in
    /// once (a u64 count never wraps).
    stamp: Vec<u64>,
    call: u64,
    /// The silhouette vertices projected on the plane of `n`, and their hull.
    shadow: Vec<DVec2>,
    ring: Vec<DVec2>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator for `shape`.
    fn new(shape: &'a Shape) -> Self {
        Evaluator {
            shape,
            front: vec![false; shape.areas.len()],
            stamp: vec![0; shape.vertices.len()],
            call: 0,
            shadow: Vec::new(),
            ring: Vec::new(),
        }
    }

    /// A lower bound on `V(n)`, `n` unit: the height times the area of the
    /// hull's shadow on the plane of `n` (half the sum of `|n . normal| area`
    /// over the faces), which the rectangle encloses. Also marks the faces
    /// that face along `n`, for [`Evaluator::fit`]. Returns the height too.
    fn measure(&mut self, n: DVec3) -> (f64, f64) {
        let s = self.shape;
        // Four independent running extremes and sums: a single one would be
        // a chain of dependent instructions, four keep the pipeline full.
        let (mut lo, mut hi) = ([f64::INFINITY; 4], [f64::NEG_INFINITY; 4]);
        let chunks = s.vertices.chunks_exact(4);
        let rest = chunks.remainder();
        for quad in chunks {
            for (j, v) in quad.iter().enumerate() {
                let k = v.dot(n);
                lo[j] = if k < lo[j] { k } else { lo[j] };
                hi[j] = if k > hi[j] { k } else { hi[j] };
            }
        }
        for (j, v) in rest.iter().enumerate() {
            let k = v.dot(n);
            lo[j] = if k < lo[j] { k } else { lo[j] };
            hi[j] = if k > hi[j] { k } else { hi[j] };
        }
        let height = hi.into_iter().fold(f64::NEG_INFINITY, f64::max)
            - lo.into_iter().fold(f64::INFINITY, f64::min);
        let mut shadow = [0.0; 4];
        let [x, y, z] = &s.normals;
        let faces = self.front.iter_mut().zip(x).zip(y).zip(z).zip(&s.areas);
        for (f, ((((front, x), y), z), area)) in faces.enumerate() {
            let k = x * n.x + y * n.y + z * n.z;
            *front = k > 0.0;
            shadow[f & 3] += k.abs() * area;
        }
        (height * 0.5 * shadow.iter().sum::<f64>(), height)
    }

    /// A lower bound on `V(n)`: see [`Evaluator::measure`].
    fn lower_bound(&mut self, n: DVec3) -> f64 {
        self.measure(n).0
    }

    /// A candidate with its volume measured on the vertices: the true volume
    /// of its box, whatever rounding did to the shadow or the rectangle. Every
    /// box that the search keeps is measured so.
    fn verified(&self, c: Candidate) -> Candidate {
        let at = c.axes.transpose();
        let (lo, hi) = self.shape.vertices.iter().fold(
            (DVec3::INFINITY, DVec3::NEG_INFINITY),
            |(lo, hi), &v| {
                let k = at * v;
                (lo.min(k), hi.max(k))
            },
        );
        let l = hi - lo;
        Candidate { volume: l.x * l.y * l.z, axes: c.axes }
    }

    /// `V(n)` and its box, `n` unit: the height times the minimum-area
    /// rectangle around the hull's shadow.
    fn fit(&mut self, n: DVec3) -> Candidate {
        let s = self.shape;
        let (_, height) = self.measure(n);
        // The shadow's outline comes from the silhouette: edges between a face
        // facing along n and one that does not. Every vertex of the shadow's
        // hull is on it, a small fraction of the vertices.
        let (t1, t2) = n.any_orthonormal_pair();
        self.call += 1;
        self.shadow.clear();
        for e in &s.edges {
            if self.front[e.faces[0] as usize] == self.front[e.faces[1] as usize] {
                continue;
            }
            for v in e.ends {
                if std::mem::replace(&mut self.stamp[v as usize], self.call) != self.call {
                    let p = s.vertices[v as usize];
                    self.shadow.push(DVec2::new(p.dot(t1), p.dot(t2)));
                }
            }
        }
        let rect = min_area_rect(&mut self.shadow, &mut self.ring);
        let axes = basis(n, t1 * rect.side.x + t2 * rect.side.y);
        Candidate { volume: height * rect.area, axes }
    }
}

/// Visits `n = e1 x e2` for every pair of hull edges with antipodal Gauss-map
/// arcs: `n` on the arc of `e1` (between its faces' normals) and `-n` on that
/// of `e2`, so that the support planes of normal `n` and `-n` hold `e1` and
/// `e2`. The arc test is Gregorius's (GDC 2013, "The Separating Axis Test
/// between Convex Polyhedra"), on arcs `(a, b)` and `(-c, -d)`. The first
/// part, which rejects most pairs, is a sign test per face, done once per
/// first edge.
fn edge_pairs(shape: &Shape, mut visit: impl FnMut(DVec3)) {
    let (nf, ne) = (shape.areas.len(), shape.edges.len());
    let every_pair = ne * (nf + ne) / 2 <= PAIR_WORK;
    let mut firsts: Vec<usize> = (0..ne).collect();
    if !every_pair {
        let length = |i: &usize| shape.edge_vector(&shape.edges[*i]).length_squared();
        firsts.sort_by(|i, j| length(j).total_cmp(&length(i)).then(i.cmp(j)));
        firsts.truncate(PAIR_WORK / (nf + ne).max(1));
    }
    let mut side = vec![0.0; nf];
    let normal = |f: u32| shape.normal(f as usize);
    let [nx, ny, nz] = &shape.normals;
    for i in firsts {
        let e1 = shape.edges[i];
        let (a, b) = (normal(e1.faces[0]), normal(e1.faces[1]));
        let bxa = b.cross(a);
        for (((s, x), y), z) in side.iter_mut().zip(nx).zip(ny).zip(nz) {
            *s = x * bxa.x + y * bxa.y + z * bxa.z;
        }
        let d1 = shape.edge_vector(&e1);
        let seconds = if every_pair { i + 1..ne } else { 0..ne };
        for e2 in &shape.edges[seconds] {
            // side = n . (b x a) = -(c . (b x a)) for c the negated normal.
            let (sc, sd) = (side[e2.faces[0] as usize], side[e2.faces[1] as usize]);
            if sc * sd >= 0.0 {
                continue;
            }
            let dxc = normal(e2.faces[1]).cross(normal(e2.faces[0])); // (-d) x (-c)
            let (adc, bdc) = (a.dot(dxc), b.dot(dxc));
            if adc * bdc < 0.0
                && -sc * bdc > 0.0
                && let Some(n) = d1.cross(shape.edge_vector(e2)).try_normalize()
            {
                visit(n);
            }
        }
    }
}

/// Local descent from a candidate: Nelder-Mead on `V(n)` about each of its
/// axes in turn, until a round gains nothing. Every box has its three axes
/// among the `n` that `V` is a function of, so this descends over rotations.
fn polish(eval: &mut Evaluator, start: Candidate) -> Candidate {
    let mut best = start;
    for _ in 0..MAX_ROUNDS {
        let before = best.volume;
        for j in 0..3 {
            best = descend(eval, best.axes.col(j), best);
        }
        if best.volume >= before * (1.0 - 1e-9) {
            break;
        }
    }
    best
}

/// Nelder-Mead on `V(n)` near `n0`, over the tangent plane: `n = normalize(n0 +
/// x t1 + y t2)`. Returns the better of its result (measured) and `best`.
fn descend(eval: &mut Evaluator, n0: DVec3, best: Candidate) -> Candidate {
    let (t1, t2) = n0.any_orthonormal_pair();
    let along = |x: DVec2| (n0 + t1 * x.x + t2 * x.y).normalize();
    let x = nelder_mead(|x| eval.fit(along(x)).volume, FIRST_STEP, LAST_STEP, MAX_EVALS);
    let c = eval.fit(along(x));
    best.min(eval.verified(c))
}

/// Minimises `f` over the plane from the origin by Nelder-Mead (Nelder & Mead
/// 1965, with the usual coefficients: reflect 1, expand 2, contract and shrink
/// 1/2), until the simplex is smaller than `last` or `max_evals` are spent.
fn nelder_mead(mut f: impl FnMut(DVec2) -> f64, first: f64, last: f64, max_evals: usize) -> DVec2 {
    let mut s = [DVec2::ZERO, DVec2::new(first, 0.0), DVec2::new(0.0, first)].map(|x| (x, f(x)));
    let mut evals = 3;
    while evals < max_evals {
        s.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (s[1].0 - s[0].0).length().max((s[2].0 - s[0].0).length()) < last {
            break;
        }
        let centre = (s[0].0 + s[1].0) * 0.5;
        let worst = s[2];
        let mut probe = |t: f64| {
            evals += 1;
            let x = centre + (centre - worst.0) * t;
            (x, f(x))
        };
        let r = probe(1.0);
        if r.1 < s[0].1 {
            let e = probe(2.0);
            s[2] = if e.1 < r.1 { e } else { r };
        } else if r.1 < s[1].1 {
            s[2] = r;
        } else {
            // Contract toward the better of the reflected and the worst point.
            let c = probe(if r.1 < worst.1 { 0.5 } else { -0.5 });
            if c.1 < r.1.min(worst.1) {
                s[2] = c;
            } else {
                for k in 1..3 {
                    let x = (s[0].0 + s[k].0) * 0.5;
                    s[k] = (x, f(x));
                }
                evals += 2;
            }
        }
    }
    s.iter().min_by(|a, b| a.1.total_cmp(&b.1)).map_or(DVec2::ZERO, |b| b.0)
}
