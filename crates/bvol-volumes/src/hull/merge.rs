//! Coplanar triangles of the exact hull merged into convex polygon faces.
//!
//! Regions grow from the largest triangles first, so each is seeded by its
//! best-conditioned plane; a neighbour joins when its far corner lies within the
//! tolerance of that plane and the region stays a disk (the rule that keeps a
//! region's boundary one simple loop). The seed's plane is the face's plane: as
//! the plane of a triangle of the exact hull, every point kept lies behind it,
//! and every corner of the face lies within tolerance of it, however thin the
//! face. A region whose loop is not convex within tolerance falls back to its
//! triangles. Then a vertex left on only two faces, in line with its neighbours
//! within tolerance, is taken out of both, so faces meet in straight edges
//! (chains of such vertices thinned by Douglas-Peucker; a face that this would
//! leave other than convex keeps all its vertices). One not in line marks
//! two regions meeting along a bent chain, which only nearly coplanar faces can
//! do: they fall back to their triangles, so every vertex left is a corner of
//! at least three faces. The result keeps the exact hull's topology: every edge
//! in two faces, in opposite directions, and V - E + F = 2.

use glam::{DVec2, DVec3};

use super::planar::convex_chain;
use super::predicates::cross_exact;
use super::quickhull::Triangulation;
use super::{CentredPoints, douglas_peucker};

/// No region.
const NONE: u32 = u32::MAX;

/// Convex polygon faces over the vertices of a [`Triangulation`].
pub(super) struct Polygons {
    /// Vertex loops, counter-clockwise from outside, indices into the
    /// triangulation's vertices, concatenated.
    pub loops: Vec<u32>,
    /// Where each face's loop starts in `loops`, plus the end.
    pub starts: Vec<u32>,
    /// Each face's plane about the box centre: unit outward normal and offset.
    pub planes: Vec<(DVec3, f64)>,
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

    fn push(&mut self, face: impl IntoIterator<Item = u32>, plane: (DVec3, f64)) {
        self.loops.extend(face);
        self.starts.push(self.loops.len() as u32);
        self.planes.push(plane);
    }
}

/// The faces of the hull: coplanar triangles merged, collinear edge vertices removed.
pub(super) fn merge(centred: &CentredPoints, hull: &Triangulation) -> Polygons {
    let pos: Vec<DVec3> = hull.vertices.iter().map(|&i| centred.at(i)).collect();
    let area_vectors: Vec<DVec3> = hull
        .corners
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| centred.exact(hull.vertices[v as usize]));
            cross_exact(a, b, c)
        })
        .collect();
    let regions = grow_regions(centred.eps, &pos, &area_vectors, hull);
    let mut merged = vec![true; regions.planes.len()];
    loop {
        let (mut faces, owners) =
            polygons(hull, &regions, &pos, &area_vectors, centred.eps, &mut merged);
        let bent = remove_edge_vertices(&mut faces, &pos, centred.eps);
        let mut split = false;
        for (f, &r) in owners.iter().enumerate() {
            let r = r as usize;
            if merged[r] && regions.len(r) > 1 && faces.face(f).iter().any(|&v| bent[v as usize]) {
                merged[r] = false;
                split = true;
            }
        }
        // Each round splits a region, so this ends, at the latest with only
        // triangles left, which leave no bent vertex (every vertex of the
        // triangulation is a corner of three triangles at least).
        if !split {
            return faces;
        }
    }
}

/// One face per region still `merged` whose boundary is a simple convex loop,
/// else one per triangle (and the region is marked not merged); with the region
/// each face comes from.
fn polygons(
    hull: &Triangulation,
    regions: &Regions,
    pos: &[DVec3],
    area_vectors: &[DVec3],
    eps: f64,
    merged: &mut [bool],
) -> (Polygons, Vec<u32>) {
    let mut faces = Polygons { loops: Vec::new(), starts: vec![0], planes: Vec::new() };
    let mut owners = Vec::new();
    let mut marks = vec![NONE; pos.len()];
    let mut ring = Vec::new();
    for (r, region) in regions.iter().enumerate() {
        let r = r as u32;
        if let &[t] = region.tris {
            // A lone triangle is its own face, with its own plane.
            faces.push(hull.corners[t as usize], region.plane);
            owners.push(r);
            continue;
        }
        merged[r as usize] = merged[r as usize]
            && boundary_loop(hull, &regions.of, r, region.tris, &mut ring)
            && is_simple(&ring, &mut marks, r)
            && is_convex(&ring, pos, region.plane.0, eps);
        if merged[r as usize] {
            faces.push(ring.iter().copied(), region.plane);
            owners.push(r);
        } else {
            for &t in region.tris {
                let corners = hull.corners[t as usize];
                faces.push(corners, plane(area_vectors[t as usize], corners, pos));
                owners.push(r);
            }
        }
    }
    (faces, owners)
}

/// A region: its triangles and its seed's plane.
struct Region<'a> {
    tris: &'a [u32],
    plane: (DVec3, f64),
}

/// Triangles grouped into planar disks.
struct Regions {
    /// Region of each triangle.
    of: Vec<u32>,
    /// Triangles in region order, and where each region starts.
    members: Vec<u32>,
    starts: Vec<usize>,
    planes: Vec<(DVec3, f64)>,
}

impl Regions {
    /// Number of triangles in region `r`.
    fn len(&self, r: usize) -> usize {
        self.starts[r + 1] - self.starts[r]
    }

    fn iter(&self) -> impl Iterator<Item = Region<'_>> {
        self.planes.iter().enumerate().map(|(r, &plane)| Region {
            tris: &self.members[self.starts[r]..self.starts[r + 1]],
            plane,
        })
    }
}

/// The plane of a triangle with the given area vector and corners: unit normal
/// (zero if degenerate) and offset through its centroid.
fn plane(area_vector: DVec3, corners: [u32; 3], pos: &[DVec3]) -> (DVec3, f64) {
    let normal = area_vector.normalize_or_zero();
    (normal, normal.dot(corners.map(|v| pos[v as usize]).iter().sum::<DVec3>()) / 3.0)
}

/// Groups the triangles into regions within `eps` of their seed's plane and
/// facing its way, each a topological disk, seeds taken largest first (ties by
/// index, for determinism).
fn grow_regions(eps: f64, pos: &[DVec3], area_vectors: &[DVec3], hull: &Triangulation) -> Regions {
    let (corners, adjacent) = (&hull.corners, &hull.adjacent);
    let areas: Vec<f64> = area_vectors.iter().map(|a| a.length()).collect();
    let mut order: Vec<u32> = (0..corners.len() as u32).collect();
    order
        .sort_unstable_by(|&x, &y| areas[y as usize].total_cmp(&areas[x as usize]).then(x.cmp(&y)));

    let mut of = vec![NONE; corners.len()];
    let mut marks = vec![NONE; pos.len()];
    let mut members = Vec::with_capacity(corners.len());
    let (mut starts, mut planes) = (vec![0], Vec::new());
    for seed in order {
        if of[seed as usize] != NONE {
            continue;
        }
        let r = planes.len() as u32;
        let [a, b, c] = corners[seed as usize];
        let (normal, offset) = plane(area_vectors[seed as usize], [a, b, c], pos);
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
                // Near the plane, and facing its way: a region folding over
                // itself (round the tip of a needle) would hide a vertex.
                if (normal.dot(pos[w as usize]) - offset).abs() > eps
                    || normal.dot(area_vectors[u]) <= 0.0
                {
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
        planes.push((normal, offset));
    }
    Regions { of, members, starts, planes }
}

/// Walks the boundary of region `r` (triangles `tris`) into `ring`, turning
/// around each corner inside the region to find the next boundary edge. False if
/// the boundary is not one loop.
fn boundary_loop(
    hull: &Triangulation,
    of: &[u32],
    r: u32,
    tris: &[u32],
    ring: &mut Vec<u32>,
) -> bool {
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

/// Whether the loop is convex within `eps` about `normal`: seen along the
/// normal, it visits the corners of its own convex hull in order, counter-
/// clockwise, and the vertices between two corners go forward along the hull
/// edge joining them, within `eps` of it. (A test of each turn alone would let
/// small dents add up, and a thin loop double back on itself.)
fn is_convex(ring: &[u32], pos: &[DVec3], normal: DVec3, eps: f64) -> bool {
    let (u, v) = normal.any_orthonormal_pair();
    let flat = |k: usize| {
        let p = pos[ring[k] as usize];
        DVec2::new(p.dot(u), p.dot(v))
    };
    let mut corners = convex_chain((0..ring.len()).map(|k| (flat(k), k as u32)).collect());
    let n = corners.len();
    let first = (0..n).min_by_key(|&k| corners[k]).unwrap_or(0);
    corners.rotate_left(first);
    if n < 3 || corners.windows(2).any(|w| w[0] >= w[1]) {
        return false;
    }
    // Ring positions from each corner to the next, cyclically; along the edge
    // (its unit direction), then inward from it.
    let m = ring.len();
    (0..n).all(|i| {
        let (a, b) = (corners[i] as usize, corners[(i + 1) % n] as usize);
        let (pa, pb) = (flat(a), flat(b));
        let along = (pb - pa).normalize_or_zero();
        let end = if b > a { b } else { b + m };
        let mut last = 0.0;
        (a + 1..=end).all(|k| {
            let d = flat(k % m) - pa;
            let t = along.dot(d);
            let ok = t >= last - eps && along.perp_dot(d) <= eps;
            last = t;
            ok
        })
    })
}

/// Takes out of the faces every vertex that lies on exactly two faces and within
/// `eps` of the straight edge that replaces its chain; both faces lose it, so the
/// faces stay consistent. A face that would no longer be a convex polygon keeps
/// all its vertices. Returns which vertices stay on only two faces: the bends.
fn remove_edge_vertices(faces: &mut Polygons, pos: &[DVec3], eps: f64) -> Vec<bool> {
    let mut count = vec![0u32; pos.len()];
    for &v in &faces.loops {
        count[v as usize] += 1;
    }
    let mut removed = vec![false; pos.len()];
    let mut decided = vec![false; pos.len()];
    let (mut chain, mut keep) = (Vec::new(), Vec::new());
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
                    let points: Vec<DVec3> = chain.iter().map(|&c| pos[c as usize]).collect();
                    keep.clear();
                    keep.resize(chain.len(), true);
                    douglas_peucker(&points, eps, &mut keep);
                    for (&c, &k) in chain.iter().zip(&keep) {
                        (removed[c as usize], decided[c as usize]) = (!k, true);
                    }
                }
                chain.clear();
                chain.push(v);
            }
        }
    }
    // A face that lost vertices must still be a convex polygon facing its
    // normal (a face thinner than the tolerance could fold): restore all the
    // vertices of one that is not, until none is; restoring only gives back
    // vertices, so this ends.
    let mut ring = Vec::new();
    loop {
        let spoiled: Vec<usize> = (0..faces.len())
            .filter(|&f| {
                let face = faces.face(f);
                ring.clear();
                ring.extend(face.iter().copied().filter(|&v| !removed[v as usize]));
                ring.len() < face.len()
                    && (ring.len() < 3 || !is_convex(&ring, pos, faces.planes[f].0, eps))
            })
            .collect();
        if spoiled.is_empty() {
            break;
        }
        for f in spoiled {
            faces.face(f).iter().for_each(|&v| removed[v as usize] = false);
        }
    }
    let mut kept = Polygons {
        loops: Vec::with_capacity(faces.loops.len()),
        starts: vec![0],
        planes: Vec::new(),
    };
    for f in 0..faces.len() {
        kept.push(faces.face(f).iter().copied().filter(|&v| !removed[v as usize]), faces.planes[f]);
    }
    *faces = kept;
    (0..pos.len()).map(|v| count[v] == 2 && !removed[v]).collect()
}
