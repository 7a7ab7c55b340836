//! Coplanar triangles of the exact hull merged into convex polygon faces.
//!
//! Regions grow from the largest triangles first, so each is seeded by its
//! best-conditioned plane; a neighbour joins when its far corner lies within the
//! tolerance of that plane and the region stays a disk (the rule that keeps a
//! region's boundary one simple loop). A region whose loop is not convex within
//! tolerance falls back to its triangles. Then a vertex left on only two faces,
//! in line with its neighbours within tolerance, is taken out of both, so faces
//! meet in straight edges; chains of such vertices are thinned by Douglas-Peucker.
//! The result keeps the exact hull's topology: every edge in two faces, in
//! opposite directions, and V - E + F = 2.

use glam::DVec3;

use super::Frame;
use super::quickhull::Triangulation;

/// No region.
const NONE: u32 = u32::MAX;

/// Convex polygon faces over the vertices of a [`Triangulation`].
pub(super) struct Polygons {
    /// Vertex loops, counter-clockwise from outside, indices into the
    /// triangulation's vertices, concatenated.
    pub loops: Vec<u32>,
    /// Where each face's loop starts in `loops`, plus the end.
    pub starts: Vec<u32>,
}

impl Polygons {
    /// The loop of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.loops[self.starts[f] as usize..self.starts[f + 1] as usize]
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.starts.len() - 1
    }

    fn push(&mut self, face: impl IntoIterator<Item = u32>) {
        self.loops.extend(face);
        self.starts.push(self.loops.len() as u32);
    }
}

/// The faces of the hull: coplanar triangles merged, collinear edge vertices removed.
pub(super) fn merge(frame: &Frame, hull: &Triangulation) -> Polygons {
    let pos: Vec<DVec3> = hull.vertices.iter().map(|&i| frame.at(i)).collect();
    let regions = grow_regions(frame.eps, &pos, hull);
    let mut faces = Polygons { loops: Vec::new(), starts: vec![0] };
    let mut marks = vec![NONE; pos.len()];
    let mut ring = Vec::new();
    for (r, region) in regions.iter().enumerate() {
        let convex = boundary_loop(hull, &regions.of, r as u32, region.tris, &mut ring)
            && is_simple(&ring, &mut marks, r as u32)
            && is_convex(&ring, &pos, region.normal, frame.eps);
        if convex {
            faces.push(ring.iter().copied());
        } else {
            for &t in region.tris {
                faces.push(hull.corners[t as usize]);
            }
        }
    }
    remove_edge_vertices(&mut faces, &pos, frame.eps);
    faces
}

/// A region: its triangles and the unit normal of its seed.
struct Region<'a> {
    tris: &'a [u32],
    normal: DVec3,
}

/// Triangles grouped into planar disks.
struct Regions {
    /// Region of each triangle.
    of: Vec<u32>,
    /// Triangles in region order, and where each region starts.
    members: Vec<u32>,
    starts: Vec<usize>,
    normals: Vec<DVec3>,
}

impl Regions {
    fn iter(&self) -> impl Iterator<Item = Region<'_>> {
        self.normals.iter().enumerate().map(|(r, &normal)| Region {
            tris: &self.members[self.starts[r]..self.starts[r + 1]],
            normal,
        })
    }
}

/// Groups the triangles into regions within `eps` of their seed's plane, each a
/// topological disk, seeds taken largest first (ties by index, for determinism).
fn grow_regions(eps: f64, pos: &[DVec3], hull: &Triangulation) -> Regions {
    let (corners, adjacent) = (&hull.corners, &hull.adjacent);
    let area_normal = |t: usize| {
        let [a, b, c] = corners[t].map(|v| pos[v as usize]);
        (b - a).cross(c - a)
    };
    let areas: Vec<f64> = (0..corners.len()).map(|t| area_normal(t).length()).collect();
    let mut order: Vec<u32> = (0..corners.len() as u32).collect();
    order.sort_by(|&x, &y| areas[y as usize].total_cmp(&areas[x as usize]).then(x.cmp(&y)));

    let mut of = vec![NONE; corners.len()];
    let mut marks = vec![NONE; pos.len()];
    let mut members = Vec::with_capacity(corners.len());
    let (mut starts, mut normals) = (vec![0], Vec::new());
    for seed in order {
        if of[seed as usize] != NONE {
            continue;
        }
        let r = normals.len() as u32;
        let normal = area_normal(seed as usize).normalize_or_zero();
        let [a, b, c] = corners[seed as usize];
        let offset = normal.dot(pos[a as usize] + pos[b as usize] + pos[c as usize]) / 3.0;
        of[seed as usize] = r;
        members.push(seed);
        for v in [a, b, c] {
            marks[v as usize] = r;
        }
        // Breadth first, with the member list as the queue.
        let mut next = starts[r as usize];
        while next < members.len() {
            let t = members[next] as usize;
            next += 1;
            for e in 0..3 {
                let u = adjacent[t][e] as usize;
                if of[u] != NONE {
                    continue;
                }
                let (x, y) = (corners[t][e], corners[t][(e + 1) % 3]);
                let w = corners[u].into_iter().find(|&v| v != x && v != y).unwrap_or(x);
                if (normal.dot(pos[w as usize]) - offset).abs() > eps {
                    continue;
                }
                // A corner already in the region: joining keeps a disk only if u
                // also shares a second edge with it (it fills a notch).
                if marks[w as usize] == r
                    && adjacent[u].iter().filter(|&&n| of[n as usize] == r).count() != 2
                {
                    continue;
                }
                of[u] = r;
                marks[w as usize] = r;
                members.push(u as u32);
            }
        }
        starts.push(members.len());
        normals.push(normal);
    }
    Regions { of, members, starts, normals }
}

/// Walks the boundary of region `r` (triangles `tris`) into `ring`, turning
/// around each corner inside the region to find the next boundary edge. False if
/// the boundary is not one loop.
fn boundary_loop(hull: &Triangulation, of: &[u32], r: u32, tris: &[u32], ring: &mut Vec<u32>) -> bool {
    ring.clear();
    let (corners, adjacent) = (&hull.corners, &hull.adjacent);
    let outside = |t: usize, e: usize| of[adjacent[t][e] as usize] != r;
    let boundary = tris.iter().map(|&t| (0..3).filter(|&e| outside(t as usize, e)).count()).sum();
    let Some(start) = tris
        .iter()
        .find_map(|&t| (0..3).find(|&e| outside(t as usize, e)).map(|e| (t as usize, e)))
    else {
        return false;
    };
    let (mut t, mut e) = start;
    loop {
        ring.push(corners[t][e]);
        // Turn about the edge's head through the region's triangles.
        e = (e + 1) % 3;
        let mut turns = 0;
        while !outside(t, e) {
            let u = adjacent[t][e] as usize;
            let back = adjacent[u].iter().position(|&x| x as usize == t).unwrap_or(0);
            (t, e) = (u, (back + 1) % 3);
            turns += 1;
            if turns > tris.len() {
                return false;
            }
        }
        if (t, e) == start {
            return ring.len() == boundary;
        }
        if ring.len() >= boundary {
            return false;
        }
    }
}

/// Whether no vertex repeats in `ring` (`marks` holds a per-vertex stamp; `r` is fresh).
fn is_simple(ring: &[u32], marks: &mut [u32], r: u32) -> bool {
    ring.iter().all(|&v| std::mem::replace(&mut marks[v as usize], r) != r)
}

/// Whether the loop turns left about `normal` at every vertex, or bends right by
/// no more than `eps` (the vertex's distance inside the chord of its neighbours).
fn is_convex(ring: &[u32], pos: &[DVec3], normal: DVec3, eps: f64) -> bool {
    let n = ring.len();
    n >= 3
        && (0..n).all(|i| {
            let [p, v, q] = [ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]].map(|k| pos[k as usize]);
            let chord = (q - p).length();
            chord > 0.0 && (v - p).cross(q - v).dot(normal) >= -eps * chord
        })
}

/// Takes out of the faces every vertex that lies on exactly two faces and within
/// `eps` of the straight edge that replaces its chain; both faces lose it, so the
/// faces stay consistent. A face that would keep fewer than 3 vertices keeps all.
fn remove_edge_vertices(faces: &mut Polygons, pos: &[DVec3], eps: f64) {
    let mut count = vec![0u32; pos.len()];
    for &v in &faces.loops {
        count[v as usize] += 1;
    }
    let mut removed = vec![false; pos.len()];
    let mut decided = vec![false; pos.len()];
    let mut chain = Vec::new();
    for f in 0..faces.len() {
        let face = faces.face(f);
        let n = face.len();
        let Some(first) = face.iter().position(|&v| count[v as usize] >= 3) else {
            continue;
        };
        // Chains of two-face vertices between corners of three or more faces; the
        // face on the other side sees the same chain reversed and finds it decided.
        chain.clear();
        chain.push(face[first]);
        for k in 1..=n {
            let v = face[(first + k) % n];
            chain.push(v);
            if count[v as usize] >= 3 {
                if chain.len() > 2 && !decided[chain[1] as usize] {
                    simplify(&chain, pos, eps, &mut removed);
                    chain.iter().for_each(|&c| decided[c as usize] = true);
                }
                chain.clear();
                chain.push(v);
            }
        }
    }
    // Keep every face a polygon: restore the vertices of one left too small, until none is.
    while let Some(f) =
        (0..faces.len()).find(|&f| faces.face(f).iter().filter(|&&v| !removed[v as usize]).count() < 3)
    {
        faces.face(f).iter().for_each(|&v| removed[v as usize] = false);
    }
    let mut kept = Polygons { loops: Vec::with_capacity(faces.loops.len()), starts: vec![0] };
    for f in 0..faces.len() {
        kept.push(faces.face(f).iter().copied().filter(|&v| !removed[v as usize]));
    }
    *faces = kept;
}

/// Douglas-Peucker on a chain whose two ends stay: an inner vertex goes if it is
/// within `eps` of the segment's line that spans it, else it stays and splits.
fn simplify(chain: &[u32], pos: &[DVec3], eps: f64, removed: &mut [bool]) {
    let mut spans = vec![(0, chain.len() - 1)];
    while let Some((lo, hi)) = spans.pop() {
        if hi - lo < 2 {
            continue;
        }
        let (a, b) = (pos[chain[lo] as usize], pos[chain[hi] as usize]);
        let line = (b - a).normalize_or_zero();
        let dist = |k: usize| {
            let d = pos[chain[k] as usize] - a;
            (d - line * d.dot(line)).length()
        };
        let (far, far_dist) = (lo + 1..hi).map(|k| (k, dist(k))).fold((lo, -1.0), |m, x| if x.1 > m.1 { x } else { m });
        if far_dist <= eps {
            chain[lo + 1..hi].iter().for_each(|&v| removed[v as usize] = true);
        } else {
            spans.push((lo, far));
            spans.push((far, hi));
        }
    }
}
