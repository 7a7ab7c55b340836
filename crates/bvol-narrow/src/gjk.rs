//! The closest points of two convex shapes that are apart: GJK (Gilbert,
//! Johnson & Keerthi 1988), as van den Bergen gives it for distances
//! (Collision Detection in Interactive 3D Environments, 4.3): the point of
//! the Minkowski difference nearest the origin, approached through simplices
//! of its support points. Each simplex's nearest point is found by Johnson's
//! sub-algorithm, here over every face of the simplex (at most fifteen): the
//! nearest of the faces whose own nearest point lies inside them.

use glam::{DMat3, DVec3};

use crate::Polyhedron;
use crate::convex::Convex;
use crate::isometry::DIsometry3;
use crate::segment::Segment;

/// Steps at most: a polytope's simplices never repeat, and hulls of
/// thousands of vertices take a few dozen.
const MAX_STEPS: usize = 128;
/// The search stops once the nearest point so far is within this share of
/// its distance of the least the next support point allows (the upper and
/// lower bounds of the distance meet to this relative width).
const RELATIVE_GAP: f64 = 1e-12;

/// What GJK reads of a shape: the core of a part, in the first shape's space
/// (a rounded part is its core swept by a ball; the ball is the caller's).
pub(crate) enum Core<'a> {
    /// A point: a ball's centre.
    Point(DVec3),
    /// A segment: a capsule's core.
    Segment(Segment),
    /// A polyhedron, placed by the isometry from its space.
    Hull(&'a Polyhedron, DIsometry3),
}

impl Core<'_> {
    /// A point of the core farthest along `dir`; `start` is the vertex a
    /// hull's hill climb begins at, and gets the one it ends at.
    fn support(&self, dir: DVec3, start: &mut Option<u32>) -> DVec3 {
        match self {
            Core::Point(p) => *p,
            Core::Segment(s) => {
                if s.delta.dot(dir) > 0.0 {
                    s.end()
                } else {
                    s.start
                }
            }
            Core::Hull(hull, to) => {
                let local = -to.unrotate(dir);
                let from = start.unwrap_or_else(|| hull.seed(local));
                let (v, _) = hull.support_min(local, from, f64::NEG_INFINITY);
                *start = Some(v);
                to.apply(hull.vertex(v))
            }
        }
    }

    /// A point of the core.
    fn any_point(&self) -> DVec3 {
        match self {
            Core::Point(p) => *p,
            Core::Segment(s) => s.start,
            Core::Hull(hull, to) => to.apply(hull.vertex(0)),
        }
    }
}

/// A vertex of the simplex: a point of the difference `a - b`, with the
/// support points of `a` and `b` it came from.
#[derive(Clone, Copy, Debug, Default)]
struct Vertex {
    a: DVec3,
    b: DVec3,
}

impl Vertex {
    fn w(&self) -> DVec3 {
        self.a - self.b
    }
}

/// Up to four vertices, and the weights of the point they make.
#[derive(Clone, Copy, Debug, Default)]
struct Simplex {
    vertices: [Vertex; 4],
    weights: [f64; 4],
    len: usize,
}

impl Simplex {
    fn vertices(&self) -> &[Vertex] {
        &self.vertices[..self.len]
    }

    fn push(&mut self, v: Vertex) {
        self.vertices[self.len] = v;
        self.len += 1;
    }

    /// The weighted sum of a side of the vertices.
    fn point(&self, side: impl Fn(&Vertex) -> DVec3) -> DVec3 {
        self.vertices().iter().zip(&self.weights).map(|(v, &l)| side(v) * l).sum()
    }
}

/// The closest points of cores `a` and `b`, one on each, if they are apart:
/// `None` when the search finds them meeting (the nearest point of the
/// difference is the origin, to rounding). `size` is the length that the
/// tolerances are relative to.
pub(crate) fn closest_points(a: &Core, b: &Core, size: f64) -> Option<(DVec3, DVec3)> {
    let (mut from_a, mut from_b) = (None, None);
    let mut simplex = Simplex::default();
    simplex.push(Vertex { a: a.any_point(), b: b.any_point() });
    simplex.weights[0] = 1.0;
    let tiny = (size * 1e-12).powi(2);
    for _ in 0..MAX_STEPS {
        let v = simplex.point(Vertex::w);
        let vv = v.length_squared();
        if vv <= tiny {
            return None;
        }
        let next = Vertex { a: a.support(-v, &mut from_a), b: b.support(v, &mut from_b) };
        let w = next.w();
        // `v . w / |v|` is a lower bound of the distance and |v| an upper
        // one: once they meet, or `w` is no new point, |v| is the distance.
        if vv - v.dot(w) <= RELATIVE_GAP * vv || simplex.vertices().iter().any(|s| s.w() == w) {
            break;
        }
        let mut grown = simplex;
        grown.push(next);
        let nearer = nearest_face(&grown);
        if nearer.point(Vertex::w).length_squared() >= vv {
            // Rounding: the grown simplex came no nearer, so the last is best.
            break;
        }
        simplex = nearer;
    }
    Some((simplex.point(|v| v.a), simplex.point(|v| v.b)))
}

/// The face of `simplex` (a subset of its vertices), with its weights, whose
/// nearest point to the origin lies inside it and is nearest of all such:
/// Johnson's sub-algorithm by brute force over the subsets.
fn nearest_face(simplex: &Simplex) -> Simplex {
    let n = simplex.len;
    let mut best: Option<(Simplex, f64)> = None;
    for mask in 1u32..(1 << n) {
        let mut face = Simplex::default();
        (0..n).filter(|&i| mask & (1 << i) != 0).for_each(|i| face.push(simplex.vertices[i]));
        let Some(weights) = interior_weights(face.vertices()) else { continue };
        face.weights = weights;
        let d = face.point(Vertex::w).length_squared();
        if best.as_ref().is_none_or(|(kept, e)| d < *e || (d == *e && face.len < kept.len)) {
            best = Some((face, d));
        }
    }
    // A single vertex always has its weight, so some face is found.
    best.map_or(*simplex, |(face, _)| face)
}

/// The weights (summing to 1) of `face`'s vertices at the point of their
/// affine hull nearest the origin, if it lies strictly inside the face
/// (every weight positive) and the face spans its dimension: with
/// `e_i = w_i - w_0`, the `mu` solving the normal equations
/// `G mu = -E^T w_0` are the weights of `w_1..`, and `1 - sum mu` that of
/// `w_0`. A face whose Gram determinant is within rounding of zero does not
/// span its dimension: its nearest point is some smaller face's.
fn interior_weights(face: &[Vertex]) -> Option<[f64; 4]> {
    let w0 = face[0].w();
    let k = face.len() - 1;
    let mut edges = [DVec3::ZERO; 3];
    for (e, v) in edges.iter_mut().zip(&face[1..]) {
        *e = v.w() - w0;
    }
    let mut gram = DMat3::IDENTITY;
    let mut rhs = DVec3::ZERO;
    for i in 0..k {
        for j in 0..k {
            gram.col_mut(j)[i] = edges[i].dot(edges[j]);
        }
        rhs[i] = -w0.dot(edges[i]);
    }
    let scale: f64 = (0..k).map(|i| gram.col(i)[i]).product();
    // A NaN determinant (from a NaN point) fails too.
    let spans = gram.determinant() > 1e-12 * scale;
    if !spans {
        return None;
    }
    let mu = gram.inverse() * rhs;
    let mut weights = [0.0; 4];
    weights[1..=k].copy_from_slice(&mu.to_array()[..k]);
    weights[0] = 1.0 - weights[1..].iter().sum::<f64>();
    weights[..face.len()].iter().all(|&l| l > 0.0).then_some(weights)
}
