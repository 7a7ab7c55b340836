//! Quickhull (Barber, Dobkin & Huhdanpaa, "The Quickhull Algorithm for Convex
//! Hulls", 1996) over triangles: each point still outside sits in the conflict
//! list of one face it sees; the farthest point of a face is added next, the faces
//! it sees are found by a walk over face adjacency, and a cone of new triangles
//! joins it to their horizon.
//!
//! Which faces a point sees is decided by the exact orientation sign, so the
//! triangles always form a closed convex 2-manifold. The approximate f64 plane
//! distances only choose which points to keep: a point within the tolerance of
//! the hull is dropped (it is within tolerance of the final hull too, since the
//! hull only grows), which keeps near-coplanar points from becoming vertices.

use glam::DVec3;

use super::Frame;
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
    /// Unit outward normal and offset in the frame (approximate: conflict lists only).
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

/// One edge of the horizon: `a -> b` of a visible triangle, and the hidden one across it.
#[derive(Clone, Copy)]
struct HorizonEdge {
    a: u32,
    b: u32,
    hidden: u32,
}

/// The hull under construction, with scratch buffers reused at every step.
struct Builder<'a> {
    frame: &'a Frame<'a>,
    tris: Vec<Tri>,
    /// Points outside each triangle (input indices), parallel to `tris`.
    conflicts: Vec<Vec<u32>>,
    /// Dead triangle slots, reused.
    free: Vec<u32>,
    /// Triangles that may have points outside.
    pending: Vec<u32>,
    step: u32,
    visible: Vec<u32>,
    horizon: Vec<HorizonEdge>,
    walk: Vec<(u32, usize, u8)>,
    orphans: Vec<u32>,
    cone: Vec<u32>,
}

/// The hull of the frame's points, grown from the tetrahedron `simplex`, whose
/// corners must not be coplanar; `None` if they are.
pub(super) fn triangulate(frame: &Frame, simplex: [u32; 4]) -> Option<Triangulation> {
    let mut builder = Builder::new(frame, simplex)?;
    while let Some(t) = builder.pending.pop() {
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
    fn new(frame: &'a Frame<'a>, simplex: [u32; 4]) -> Option<Self> {
        let [a, mut b, mut c, d] = simplex;
        let sign = orient3d(frame.exact(a), frame.exact(b), frame.exact(c), frame.exact(d));
        if sign == 0.0 {
            return None;
        }
        if sign > 0.0 {
            // d must lie behind the base a b c.
            std::mem::swap(&mut b, &mut c);
        }
        let mut builder = Builder {
            frame,
            tris: Vec::new(),
            conflicts: Vec::new(),
            free: Vec::new(),
            pending: Vec::new(),
            step: 0,
            visible: Vec::new(),
            horizon: Vec::new(),
            walk: Vec::new(),
            orphans: Vec::new(),
            cone: Vec::new(),
        };
        // Faces and the neighbours across their edges, worked out by hand:
        // each edge appears once in each direction.
        let faces = [[a, b, c], [b, a, d], [c, b, d], [a, c, d]];
        let adjacency = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
        for (v, adj) in faces.into_iter().zip(adjacency) {
            let t = builder.alloc(v);
            builder.tris[t as usize].adj = adj;
        }
        builder.orphans = (0..frame.points.len() as u32).collect();
        builder.cone = vec![0, 1, 2, 3];
        builder.assign_orphans();
        Some(builder)
    }

    /// A new live triangle with the given corners (neighbours unset).
    fn alloc(&mut self, v: [u32; 3]) -> u32 {
        let [pa, pb, pc] = v.map(|i| self.frame.at(i));
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
            self.orphans.extend(list.iter().copied().filter(|&p| p != eye));
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
        let p = self.frame.exact(eye);
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
            let [a, b, c] = tri.v.map(|i| self.frame.exact(i));
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
        self.orphans.clear();
        self.orphans.extend(self.horizon.iter().map(|h| h.a));
        self.orphans.sort_unstable();
        self.orphans.windows(2).all(|w| w[0] != w[1])
    }

    /// Removes `p` from the conflict list of `t` and picks that list's new farthest point.
    fn drop_conflict(&mut self, t: u32, p: u32) {
        let list = &mut self.conflicts[t as usize];
        list.retain(|&q| q != p);
        let tri = &mut self.tris[t as usize];
        (tri.eye, tri.eye_dist) = (NONE, f64::NEG_INFINITY);
        for &q in list.iter() {
            let dist = tri.normal.dot(self.frame.at(q)) - tri.offset;
            if dist > tri.eye_dist {
                (tri.eye, tri.eye_dist) = (q, dist);
            }
        }
        if tri.eye != NONE {
            self.pending.push(t);
        }
    }

    /// Gives each orphan to the cone triangle it is farthest outside of, or drops
    /// it if it is within tolerance of all of them (inside the hull, near enough).
    fn assign_orphans(&mut self) {
        for &p in &self.orphans {
            let q = self.frame.at(p);
            let mut best = (NONE, self.frame.eps);
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
                    (tri.eye, tri.eye_dist) = (p, dist);
                }
            }
        }
        for &t in &self.cone {
            if self.tris[t as usize].eye != NONE {
                self.pending.push(t);
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
