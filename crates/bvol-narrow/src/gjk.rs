//! The closest points of two convex shapes that are apart: GJK (Gilbert,
//! Johnson & Keerthi 1988), as van den Bergen gives it for distances
//! (Collision Detection in Interactive 3D Environments, 4.3): the point of
//! the Minkowski difference nearest the origin, approached through simplices
//! of its support points, each simplex's nearest point found by the Voronoi
//! regions of its features.

use glam::DVec3;

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
/// tolerances are relative to. The search starts from the points of each
/// farthest toward the other along `towards_b` (a separating axis, from A
/// to B, makes that a near start).
pub(crate) fn closest_points(
    a: &Core,
    b: &Core,
    size: f64,
    towards_b: DVec3,
) -> Option<(DVec3, DVec3)> {
    let (mut from_a, mut from_b) = (None, None);
    let mut simplex = Simplex::default();
    let start =
        Vertex { a: a.support(towards_b, &mut from_a), b: b.support(-towards_b, &mut from_b) };
    simplex.push(start);
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
        if nearer.len == 0 {
            // The grown simplex holds the origin: the cores meet.
            return None;
        }
        if nearer.point(Vertex::w).length_squared() >= vv {
            // Rounding: the grown simplex came no nearer, so the last is best.
            break;
        }
        simplex = nearer;
    }
    Some((simplex.point(|v| v.a), simplex.point(|v| v.b)))
}

/// The point of `simplex` nearest the origin: the smallest face of it that
/// holds that point, with its weights, by the Voronoi regions of its
/// features (Ericson, Real-Time Collision Detection 5.1.2, 5.1.5, 5.1.6).
fn nearest_face(simplex: &Simplex) -> Simplex {
    match *simplex.vertices() {
        [a] => weighted(&[(a, 1.0)]),
        [a, b] => nearest_on_segment(a, b),
        [a, b, c] => nearest_on_triangle(a, b, c),
        [a, b, c, d] => nearest_on_tetrahedron(a, b, c, d),
        _ => *simplex,
    }
}

/// The simplex of the vertices with positive weights.
fn weighted(vertices: &[(Vertex, f64)]) -> Simplex {
    let mut face = Simplex::default();
    for &(v, l) in vertices.iter().filter(|(_, l)| *l > 0.0) {
        face.weights[face.len] = l;
        face.push(v);
    }
    face
}

/// The nearest point of segment `ab` (Ericson 5.1.2).
fn nearest_on_segment(a: Vertex, b: Vertex) -> Simplex {
    let ab = b.w() - a.w();
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { (-a.w().dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    weighted(&[(a, 1.0 - t), (b, t)])
}

/// The nearest point of triangle `abc`: Ericson 5.1.5's
/// `ClosestPtPointTriangle` for the origin, a degenerate triangle by its
/// nearest edge.
fn nearest_on_triangle(a: Vertex, b: Vertex, c: Vertex) -> Simplex {
    let (pa, pb, pc) = (a.w(), b.w(), c.w());
    let (ab, ac) = (pb - pa, pc - pa);
    let (d1, d2) = (-ab.dot(pa), -ac.dot(pa));
    if d1 <= 0.0 && d2 <= 0.0 {
        return weighted(&[(a, 1.0)]);
    }
    let (d3, d4) = (-ab.dot(pb), -ac.dot(pb));
    if d3 >= 0.0 && d4 <= d3 {
        return weighted(&[(b, 1.0)]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return weighted(&[(a, 1.0 - v), (b, v)]);
    }
    let (d5, d6) = (-ab.dot(pc), -ac.dot(pc));
    if d6 >= 0.0 && d5 <= d6 {
        return weighted(&[(c, 1.0)]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return weighted(&[(a, 1.0 - w), (c, w)]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return weighted(&[(b, 1.0 - w), (c, w)]);
    }
    let total = va + vb + vc;
    // Also when NaN.
    let flat = total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    if flat {
        // Flat to rounding: the nearest of its edges.
        let edges = [nearest_on_segment(a, b), nearest_on_segment(b, c), nearest_on_segment(a, c)];
        return nearest_of(edges);
    }
    let (v, w) = (vb / total, vc / total);
    weighted(&[(a, 1.0 - v - w), (b, v), (c, w)])
}

/// The nearest point of tetrahedron `abcd`: that of the faces the origin
/// lies outside of (Ericson 5.1.6), or an empty simplex when it lies inside
/// (the point nearest is the origin itself). A flat tetrahedron (its volume
/// within rounding of zero, where the sides of its faces' planes are
/// rounding's to pick) is the nearest of all its faces.
fn nearest_on_tetrahedron(a: Vertex, b: Vertex, c: Vertex, d: Vertex) -> Simplex {
    let (ab, ac, ad) = (b.w() - a.w(), c.w() - a.w(), d.w() - a.w());
    let volume = ab.dot(ac.cross(ad));
    let flat = volume.abs() <= 1e-9 * ab.length() * ac.length() * ad.length();
    let faces = [(a, b, c, d), (a, c, d, b), (a, d, b, c), (b, d, c, a)];
    let outside = |(p, q, r, s): (Vertex, Vertex, Vertex, Vertex)| {
        let n = (q.w() - p.w()).cross(r.w() - p.w());
        flat || -p.w().dot(n) * (s.w() - p.w()).dot(n) <= 0.0
    };
    let mut found =
        faces.iter().filter(|&&f| outside(f)).map(|&(p, q, r, _)| nearest_on_triangle(p, q, r));
    match found.next() {
        Some(first) => nearest_of(std::iter::once(first).chain(found)),
        None => Simplex::default(),
    }
}

/// The face whose point is nearest the origin, the first of ties.
fn nearest_of(faces: impl IntoIterator<Item = Simplex>) -> Simplex {
    let distance = |f: &Simplex| f.point(Vertex::w).length_squared();
    faces
        .into_iter()
        .reduce(|x, y| if distance(&y) < distance(&x) { y } else { x })
        .unwrap_or_default()
}
