//! Quickhull (Barber, Dobkin & Huhdanpaa, "The Quickhull Algorithm for Convex
//! Hulls", 1996) over triangles: each point still outside sits in the conflict
//! list of one face it sees; the farthest point of a face is added next, the faces
//! it sees are found by a walk over face adjacency, and a cone of new triangles
//! joins it to their horizon.
//!
//! Which faces a point sees is decided by the exact orientation sign, so the
//! triangles always form a closed convex 2-manifold: the exact hull of the points
//! added. Approximate f64 plane distances only sort the points into conflict
//! lists: a point they put behind every new face is dropped, which can lose a
//! point outside by no more than f64 rounding. Points just outside a face, by
//! less than the tolerance, are still added, because dropping them is not safe:
//! near a sharp ridge (a thin slab's rim) a point within tolerance of both
//! planes can lie far outside the faces that later replace them. Merging
//! removes such vertices from the faces instead.

use glam::{DVec3, Vec3};

use super::CentredPoints;
use super::predicates::orient3d;

/// No triangle or no point.
const NONE: u32 = u32::MAX;

/// The closed triangulated hull: corners as indices into `vertices`,
/// counter-clockwise seen from outside; `adjacent[t][i]` is the triangle across
/// the edge `corners[t][i] -> corners[t][i + 1]`.
pub(super) struct Triangulation {
    /// Input indices of the hull's vertices, ascending.
    pub vertices: Vec<u32>,
    /// Corners of each triangle, indices into `vertices`.
    pub corners: Vec<[u32; 3]>,
    /// Neighbour across each edge.
    pub adjacent: Vec<[u32; 3]>,
}

/// One triangle of the growing hull.
#[derive(Clone, Copy)]
struct Tri {
    /// Corners, input indices, counter-clockwise from outside.
    v: [u32; 3],
    /// `adj[i]`: the triangle across edge `v[i] -> v[i + 1]`.
    adj: [u32; 3],
    /// Unit outward normal and offset about the box centre (approximate: conflict lists only).
    normal: DVec3,
    offset: f64,
    /// The farthest point of the conflict list, and its distance.
    eye: u32,
    eye_dist: f64,
    alive: bool,
    /// The step at which visibility from the current eye was decided, and the answer.
    stamp: u32,
    visible: bool,
}

/// A point in a conflict list, carried with its coordinates: handing the lists
/// of deleted faces to new ones then reads memory in order, not the input at
/// random (twice as fast on a million points in a ball).
#[derive(Clone, Copy)]
struct Outside {
    point: Vec3,
    index: u32,
}

/// One edge of the horizon: `a -> b` of a visible triangle, and the hidden one across it.
#[derive(Clone, Copy)]
struct HorizonEdge {
    a: u32,
    b: u32,
    hidden: u32,
}

/// The hull under construction, with scratch buffers reused at every step.
struct Builder<'a> {
    centred: &'a CentredPoints<'a>,
    tris: Vec<Tri>,
    /// Points outside each triangle, parallel to `tris`.
    conflicts: Vec<Vec<Outside>>,
    /// Dead triangle slots, reused.
    free: Vec<u32>,
    /// Triangles that may have points outside.
    pending: std::collections::VecDeque<u32>,
    step: u32,
    visible: Vec<u32>,
    horizon: Vec<HorizonEdge>,
    walk: Vec<(u32, usize, u8)>,
    orphans: Vec<Outside>,
    cone: Vec<u32>,
    corners: Vec<u32>,
}

/// The hull of the points, grown from the tetrahedron `simplex`, whose
/// corners must not be coplanar; `None` if they are.
pub(super) fn triangulate(centred: &CentredPoints, simplex: [u32; 4]) -> Option<Triangulation> {
    let mut builder = Builder::new(centred, simplex)?;
    while let Some(t) = builder.pending.pop_front() {
        let tri = builder.tris[t as usize];
        if tri.alive && tri.eye != NONE {
            builder.add_point(t, tri.eye);
        }
    }
    Some(builder.finish())
}

impl<'a> Builder<'a> {
    /// The tetrahedron, faces outward, with every point assigned to the face it is
    /// farthest outside of.
    fn new(centred: &'a CentredPoints<'a>, simplex: [u32; 4]) -> Option<Self> {
        let [a, mut b, mut c, d] = simplex;
        let sign = orient3d(centred.exact(a), centred.exact(b), centred.exact(c), centred.exact(d));
        if sign == 0.0 {
            return None;
        }
        if sign > 0.0 {
            // d must lie behind the base a b c.
            std::mem::swap(&mut b, &mut c);
        }
        let mut builder = Builder {
            centred,
            tris: Vec::new(),
            conflicts: Vec::new(),
            free: Vec::new(),
            pending: Default::default(),
            step: 0,
            visible: Vec::new(),
            horizon: Vec::new(),
            walk: Vec::new(),
            orphans: Vec::new(),
            cone: Vec::new(),
            corners: Vec::new(),
        };
        // Faces and the neighbours across their edges, worked out by hand:
        // each edge appears once in each direction.
        let faces = [[a, b, c], [b, a, d], [c, b, d], [a, c, d]];
        let adjacency = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
        for (v, adj) in faces.into_iter().zip(adjacency) {
            let t = builder.alloc(v);
            builder.tris[t as usize].adj = adj;
        }
        builder.orphans = centred
            .points
            .iter()
            .zip(0..)
            .map(|(&point, index)| Outside { point, index })
            .collect();
        builder.cone = vec![0, 1, 2, 3];
        builder.assign_orphans();
        Some(builder)
    }

    /// A new live triangle with the given corners (neighbours unset).
    fn alloc(&mut self, v: [u32; 3]) -> u32 {
        let [pa, pb, pc] = v.map(|i| self.centred.at(i));
        let normal = (pb - pa).cross(pc - pa).normalize_or_zero();
        let tri = Tri {
            v,
            adj: [NONE; 3],
            normal,
            offset: normal.dot(pa),
            eye: NONE,
            eye_dist: f64::NEG_INFINITY,
            alive: true,
            stamp: 0,
            visible: false,
        };
        match self.free.pop() {
            Some(t) => {
                self.tris[t as usize] = tri;
                t
            }
            None => {
                self.tris.push(tri);
                self.conflicts.push(Vec::new());
                (self.tris.len() - 1) as u32
            }
        }
    }

    /// Adds `eye`, which triangle `t` sees, to the hull; drops it instead if the
    /// exact test disagrees with the approximate one that put it there.
    fn add_point(&mut self, t: u32, eye: u32) {
        self.step += 1;
        if !self.find_horizon(t, eye) {
            self.drop_conflict(t, eye);
            return;
        }
        // Points outside the faces about to go look for a new face.
        self.orphans.clear();
        for &f in &self.visible {
            let list = &mut self.conflicts[f as usize];
            self.orphans.extend(list.iter().copied().filter(|p| p.index != eye));
            list.clear();
            self.tris[f as usize].alive = false;
            self.free.push(f);
        }
        // The cone from the eye over the horizon, one triangle per horizon edge.
        self.cone.clear();
        for k in 0..self.horizon.len() {
            let HorizonEdge { a, b, hidden } = self.horizon[k];
            let t = self.alloc([a, b, eye]);
            self.tris[t as usize].adj[0] = hidden;
            let h = &mut self.tris[hidden as usize];
            if let Some(j) = (0..3).find(|&j| h.v[j] == b && h.v[(j + 1) % 3] == a) {
                h.adj[j] = t;
            }
            self.cone.push(t);
        }
        let n = self.cone.len();
        for k in 0..n {
            let t = self.cone[k] as usize;
            self.tris[t].adj[1] = self.cone[(k + 1) % n];
            self.tris[t].adj[2] = self.cone[(k + n - 1) % n];
        }
        self.assign_orphans();
    }

    /// Collects the triangles `eye` sees, starting from `start`, and the horizon
    /// around them in order (the depth-first walk of Barber et al. section 4,
    /// iterative). Returns false, marking nothing, if `start` does not see `eye`
    /// exactly or the horizon is not one simple loop (which exact signs rule out).
    fn find_horizon(&mut self, start: u32, eye: u32) -> bool {
        self.visible.clear();
        self.horizon.clear();
        self.walk.clear();
        let p = self.centred.exact(eye);
        if !self.sees(start, p) {
            return false;
        }
        self.visible.push(start);
        self.walk.push((start, 0, 3));
        while let Some(top) = self.walk.last_mut() {
            let (t, e, left) = *top;
            if left == 0 {
                self.walk.pop();
                continue;
            }
            *top = (t, (e + 1) % 3, left - 1);
            let tri = self.tris[t as usize];
            let u = tri.adj[e];
            let seen = self.tris[u as usize];
            if seen.stamp == self.step && seen.visible {
                continue;
            }
            if self.sees(u, p) {
                self.visible.push(u);
                // Go round u starting after the edge we came in by.
                let back = seen.adj.iter().position(|&x| x == t).unwrap_or(0);
                self.walk.push((u, (back + 1) % 3, 2));
            } else {
                self.horizon.push(HorizonEdge { a: tri.v[e], b: tri.v[(e + 1) % 3], hidden: u });
            }
        }
        if self.horizon_is_loop() {
            return true;
        }
        for &f in &self.visible {
            self.tris[f as usize].visible = false;
        }
        false
    }

    /// Whether triangle `t` sees point `p` strictly, memoised for the current step.
    fn sees(&mut self, t: u32, p: DVec3) -> bool {
        let tri = &mut self.tris[t as usize];
        if tri.stamp != self.step {
            let [a, b, c] = tri.v.map(|i| self.centred.exact(i));
            tri.stamp = self.step;
            tri.visible = orient3d(a, b, c, p) > 0.0;
        }
        tri.visible
    }

    /// Whether the horizon edges chain head to tail into one loop through
    /// distinct vertices.
    fn horizon_is_loop(&mut self) -> bool {
        let n = self.horizon.len();
        if n < 3 || (0..n).any(|k| self.horizon[k].b != self.horizon[(k + 1) % n].a) {
            return false;
        }
        self.corners.clear();
        self.corners.extend(self.horizon.iter().map(|h| h.a));
        self.corners.sort_unstable();
        self.corners.windows(2).all(|w| w[0] != w[1])
    }

    /// Removes `p` from the conflict list of `t` and picks that list's new farthest point.
    fn drop_conflict(&mut self, t: u32, p: u32) {
        let list = &mut self.conflicts[t as usize];
        list.retain(|q| q.index != p);
        let tri = &mut self.tris[t as usize];
        (tri.eye, tri.eye_dist) = (NONE, f64::NEG_INFINITY);
        for q in list.iter() {
            let dist = tri.normal.dot(self.centred.relative(q.point)) - tri.offset;
            if dist > tri.eye_dist {
                (tri.eye, tri.eye_dist) = (q.index, dist);
            }
        }
        if tri.eye != NONE {
            self.pending.push_back(t);
        }
    }

    /// Gives each orphan to the cone triangle it is farthest outside of, or drops
    /// it if it is behind all of them (then it is inside the hull: Barber et al.
    /// section 3).
    fn assign_orphans(&mut self) {
        for &p in &self.orphans {
            let q = self.centred.relative(p.point);
            let mut best = (NONE, 0.0);
            for &t in &self.cone {
                let tri = &self.tris[t as usize];
                let dist = tri.normal.dot(q) - tri.offset;
                if dist > best.1 {
                    best = (t, dist);
                }
            }
            let (t, dist) = best;
            if t != NONE {
                self.conflicts[t as usize].push(p);
                let tri = &mut self.tris[t as usize];
                if dist > tri.eye_dist {
                    (tri.eye, tri.eye_dist) = (p.index, dist);
                }
            }
        }
        for &t in &self.cone {
            if self.tris[t as usize].eye != NONE {
                self.pending.push_back(t);
            }
        }
    }

    /// The live triangles, renumbered densely, with their vertices.
    fn finish(self) -> Triangulation {
        let mut index = vec![NONE; self.tris.len()];
        let live: Vec<&Tri> = self.tris.iter().filter(|t| t.alive).collect();
        let mut next = 0;
        for (slot, tri) in self.tris.iter().enumerate() {
            if tri.alive {
                index[slot] = next;
                next += 1;
            }
        }
        let mut vertices: Vec<u32> = live.iter().flat_map(|t| t.v).collect();
        vertices.sort_unstable();
        vertices.dedup();
        let local = |i: u32| vertices.binary_search(&i).unwrap_or(0) as u32;
        let corners = live.iter().map(|t| t.v.map(local)).collect();
        let adjacent = live.iter().map(|t| t.adj.map(|u| index[u as usize])).collect();
        Triangulation { vertices, corners, adjacent }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// Every edge in two triangles, once each way, each the other's neighbour
    /// across it; Euler's formula for a triangulated sphere (F = 2V - 4); and
    /// every point behind or on every triangle's plane, by the exact sign.
    fn assert_exact_hull(centred: &CentredPoints, hull: &Triangulation) {
        let (v, f) = (hull.vertices.len(), hull.corners.len());
        assert_eq!(f, 2 * v - 4);
        for (t, (corners, adjacent)) in hull.corners.iter().zip(&hull.adjacent).enumerate() {
            for e in 0..3 {
                let (a, b, u) = (corners[e], corners[(e + 1) % 3], adjacent[e] as usize);
                let back =
                    (0..3).find(|&k| hull.corners[u][k] == b && hull.corners[u][(k + 1) % 3] == a);
                assert_eq!(back.map(|k| hull.adjacent[u][k] as usize), Some(t));
            }
            let [a, b, c] = corners.map(|k| centred.exact(hull.vertices[k as usize]));
            for i in 0..centred.points.len() as u32 {
                assert!(orient3d(a, b, c, centred.exact(i)) <= 0.0);
            }
        }
    }

    #[test]
    fn grid_with_many_coplanar_and_collinear_points_gives_the_exact_hull() {
        let n = 4;
        let points: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f32, (i / n % n) as f32, (i / n / n) as f32))
            .collect();
        let centred = CentredPoints::new(&points);
        let hull = triangulate(&centred, [0, 3, 12, 63]).unwrap();
        assert_exact_hull(&centred, &hull);
        assert!(triangulate(&centred, [0, 1, 2, 3]).is_none(), "a flat simplex is refused");
    }

    #[test]
    fn points_on_a_sphere_are_all_vertices() {
        // f32 points near the unit sphere, from a tiny SplitMix64 for determinism.
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        };
        let points: Vec<Vec3> =
            (0..500).map(|_| Vec3::new(next(), next(), next()).normalize()).collect();
        let centred = CentredPoints::new(&points);
        let hull = triangulate(&centred, [0, 1, 2, 3]).unwrap();
        assert_exact_hull(&centred, &hull);
        assert_eq!(hull.vertices.len(), points.len());
    }
}
