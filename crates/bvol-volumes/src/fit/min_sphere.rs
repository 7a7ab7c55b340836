//! The exact minimum enclosing sphere: Welzl's move-to-front algorithm (1991)
//! in the form of Gärtner, "Fast and robust smallest enclosing balls" (ESA
//! 1999): move-to-front only on the few points of the current support, a
//! pivoting loop over all points, and balls through up to 4 support points
//! built incrementally, without solving linear systems.
//!
//! The pivoting loop picks, each round, the point farthest outside the current
//! ball (the pivot) and solves the problem on the old support set plus the pivot
//! alone. Its result does not depend on the order of the points (ties aside),
//! so no shuffle is needed: Welzl's random order only matters to move-to-front
//! over the whole list, which pivoting replaces.

use glam::{DVec3, Vec3};

use crate::Sphere;
use crate::fit::extremes::extremes;

/// A point counts as outside the ball when its excess `|p - c|^2 - r^2` is above
/// this fraction of `r^2` (a relative distance of half as much). Support points
/// on the sphere then never re-enter for rounding noise, while the radius stays
/// within 1e-12 of the exact one; the final pass of [`Sphere::enclosing`] makes
/// up for the difference.
const OUTSIDE: f64 = 1e-12;

/// A point joins the support only if its distance to the affine hull of the
/// support, squared and doubled, exceeds this fraction of `r^2` (the test
/// `z_m < eps * r^2` of Gärtner's `push`): a nearly dependent point would give
/// a huge, ill-conditioned ball. Such a point is dropped here; if it is really
/// outside, the pivoting loop brings it back as the first point of a support.
const DEPENDENT: f64 = 1e-20;

/// The exact minimum sphere of the points (Gärtner 1999), rounded by the final
/// containment pass.
///
/// The pivoting runs on a core set rather than on all the points: the 26
/// extreme points along 13 directions first, then, after each solve, every
/// point found outside the core's ball by one pass over the set. The ball
/// of a subset holding every point is the ball of the set, and a cloud's
/// ball rests on a few points near its rim, so a few passes over the set
/// do what a pass per pivot did: the solve-on-a-subset, add-the-violators
/// scheme of Clarkson's algorithm for LP-type problems ("Las Vegas
/// algorithms for linear and integer programming when the dimension is
/// small", J. ACM 42(2), 1995).
pub(crate) fn exact(points: &[Vec3]) -> Sphere {
    // Work relative to a point of the set: coordinates are then of the order of
    // the radius, whatever the offset, and the differences are exact in f64.
    let origin = points[0].as_dvec3();
    let local = |p: Vec3| p.as_dvec3() - origin;
    let mut core: Vec<DVec3> =
        extremes::<13>(points).iter().flatten().map(|&i| local(points[i])).collect();
    let mut grown = f64::NEG_INFINITY;
    let center = loop {
        let (center, radius2) = pivot(&core, |p| p);
        if radius2 <= grown {
            break center; // rounding stalled the growth: as good as it gets
        }
        grown = radius2;
        let before = core.len();
        let outside = |p: &DVec3| (*p - center).length_squared() - radius2 > OUTSIDE * radius2;
        core.extend(points.iter().map(|&p| local(p)).filter(outside));
        if core.len() == before {
            break center;
        }
    };
    Sphere::enclosing(center + origin, points)
}

/// The exact minimum sphere of a non-empty f64 point set: its centre and radius
/// (for EPOS on the extreme points, and anywhere a small set needs its ball).
pub(crate) fn min_sphere_f64(points: &[DVec3]) -> (DVec3, f64) {
    let origin = points[0];
    let (center, radius2) = pivot(points, |p| p - origin);
    (center + origin, radius2.sqrt())
}

/// Gärtner's `pivot_mb` over all points, given in local coordinates by
/// `local`: returns the centre (local) and the squared radius.
///
/// The ball is always the smallest one with the pivot on its boundary holding
/// the previous support; its radius grows strictly each round, so the loop
/// ends, and it ends with no point outside: the ball of a subset holding every
/// point is the minimum ball of the whole set.
fn pivot<P: Copy>(points: &[P], local: impl Fn(P) -> DVec3) -> (DVec3, f64) {
    let mut ball = Basis::default();
    // The first point alone is its own ball.
    let mut front = [local(points[0]); 4];
    let mut support = 1;
    ball.push(front[0]);
    ball.pop();
    loop {
        let (index, d2) = farthest(points, &local, ball.center);
        if d2 - ball.radius2 <= OUTSIDE * ball.radius2 {
            break;
        }
        let pivot = local(points[index]);
        let old = ball.radius2;
        ball.push(pivot);
        let kept = move_to_front(&mut ball, &mut front, support);
        ball.pop();
        // The pivot goes to the front, ahead of the points that support the ball.
        front.copy_within(0..kept, 1);
        front[0] = pivot;
        support = kept + 1;
        if ball.radius2 <= old {
            break; // rounding stalled the growth: the ball is as good as it gets
        }
    }
    (ball.center, ball.radius2)
}

/// The index and squared distance of the point farthest from `center`: the hot
/// loop of the algorithm, one subtraction and a squared length per point.
fn farthest<P: Copy>(points: &[P], local: impl Fn(P) -> DVec3, center: DVec3) -> (usize, f64) {
    let mut best = (0, f64::NEG_INFINITY);
    for (i, &p) in points.iter().enumerate() {
        let d2 = (local(p) - center).length_squared();
        if d2 > best.1 {
            best = (i, d2);
        }
    }
    best
}

/// Welzl's move-to-front recursion (Gärtner's `mtf_mb`) over `front[..end]`,
/// with the points already in `ball` held on the boundary. Points found
/// outside are pushed, solved for recursively, and moved to the front of the
/// list. Returns how many points at the front of `front` support the ball.
///
/// The list never holds more than 4 points and the recursion is at most 4
/// deep: nothing is allocated.
fn move_to_front(ball: &mut Basis, front: &mut [DVec3; 4], end: usize) -> usize {
    let mut support = 0;
    if ball.len == 4 {
        return support; // 4 boundary points fix the sphere
    }
    for k in 0..end {
        let p = front[k];
        if ball.excess(p) > OUTSIDE * ball.radius2 && ball.push(p) {
            support = move_to_front(ball, front, k) + 1;
            ball.pop();
            front[..=k].rotate_right(1);
        }
    }
    support
}

/// The smallest ball through up to 4 affinely independent points, built one
/// point at a time (Gärtner 1999, class `Miniball_b`). Each new point
/// `q_m` adds `v_m`, the part of `q_m - q_0` orthogonal to the earlier ones
/// (Gram-Schmidt), and moves the centre along `v_m` just far enough to put
/// `q_m` on the sphere: no linear system, no division by a determinant.
///
/// `center` and `radius2` are the last ball computed, which [`Basis::pop`]
/// leaves in place: it is the answer of the sub-problem just solved, and the
/// ball the move-to-front loop tests the next points against.
#[derive(Default)]
struct Basis {
    /// Number of points on the boundary.
    len: usize,
    /// The first boundary point, origin of the `v_i`.
    q0: DVec3,
    /// `v[i]`: the part of `q_i - q_0` orthogonal to `v[1..i]`.
    v: [DVec3; 4],
    /// `z[i] = 2 |v_i|^2`.
    z: [f64; 4],
    /// Centres of the smallest balls through `q_0..=q_i`.
    c: [DVec3; 4],
    /// Their squared radii.
    r2: [f64; 4],
    /// The current ball.
    center: DVec3,
    radius2: f64,
}

impl Basis {
    /// How far outside the current ball `p` lies, as `|p - c|^2 - r^2`.
    fn excess(&self, p: DVec3) -> f64 {
        (p - self.center).length_squared() - self.radius2
    }

    /// Adds `p` to the boundary and makes the current ball the smallest one
    /// through the boundary points. Refuses (returns `false`) a point that is
    /// nearly in the affine hull of the others, see [`DEPENDENT`].
    fn push(&mut self, p: DVec3) -> bool {
        let m = self.len;
        if m == 0 {
            self.q0 = p;
            self.c[0] = p;
            self.r2[0] = 0.0;
        } else {
            // Modified Gram-Schmidt: the part of q_m - q_0 orthogonal to v_1..v_m-1.
            let mut v = p - self.q0;
            for i in 1..m {
                v -= self.v[i] * (2.0 * self.v[i].dot(v) / self.z[i]);
            }
            let z = 2.0 * v.length_squared();
            if z <= DEPENDENT * self.radius2 {
                return false;
            }
            // Moving the centre by f v keeps the old points equidistant (v is
            // orthogonal to their hull) and puts p on the sphere when f = e / z.
            let e = (p - self.c[m - 1]).length_squared() - self.r2[m - 1];
            let f = e / z;
            self.v[m] = v;
            self.z[m] = z;
            self.c[m] = self.c[m - 1] + v * f;
            self.r2[m] = self.r2[m - 1] + e * f / 2.0;
        }
        self.center = self.c[m];
        self.radius2 = self.r2[m];
        self.len = m + 1;
        true
    }

    /// Removes the last boundary point; the current ball stays.
    fn pop(&mut self) {
        self.len -= 1;
    }
}
