//! The half-edge structure of a convex polyhedron's boundary: how its vertices,
//! edges and faces meet, with no coordinates.

use std::collections::HashMap;
use std::iter;
use std::ops::Range;

/// One side of an edge, running counter-clockwise round its face (seen from outside).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct HalfEdge {
    /// The vertex it leaves.
    pub origin: u32,
    /// The other side of its edge, running the other way in the neighbouring face.
    pub twin: u32,
    /// The half-edge after it round its face.
    pub next: u32,
    /// The face it bounds.
    pub face: u32,
}

/// Half-edges of a closed convex surface, with entry points per face, the
/// half-edges round each vertex laid out flat, and one representative per
/// undirected edge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Topology {
    /// All half-edges, face by face, each face's in loop order.
    pub half_edges: Vec<HalfEdge>,
    /// The half-edges leaving each vertex, round it, vertex by vertex: those
    /// of vertex `v` are `out_edges[out_starts[v]..out_starts[v + 1]]`. Hill
    /// climbing and the Gauss-map walk read a vertex's neighbours from here
    /// in one run instead of chasing twins.
    pub out_edges: Vec<u32>,
    /// The vertex each of `out_edges` enters, alongside it.
    pub out_heads: Vec<u32>,
    /// Where each vertex's run starts in `out_edges`, and the end.
    pub out_starts: Vec<u32>,
    /// The first half-edge of each face.
    pub face_edges: Vec<u32>,
    /// Each undirected edge once, as its half-edge whose face has the lower
    /// index; a polyhedron orders them by direction (see its edge clusters).
    pub edges: Vec<u32>,
}

impl Topology {
    /// The topology of faces given as vertex loops, counter-clockwise from
    /// outside, over `vertex_count` vertices. `None` unless every edge is run
    /// exactly once each way and every vertex is on a face: a closed surface.
    pub fn from_faces<'a>(
        vertex_count: usize,
        faces: impl Iterator<Item = &'a [u32]>,
    ) -> Option<Topology> {
        let mut half_edges = Vec::new();
        let mut face_edges = Vec::new();
        for (f, face) in (0u32..).zip(faces) {
            let first = half_edges.len() as u32;
            face_edges.push(first);
            let n = face.len() as u32;
            for (k, &origin) in (0u32..).zip(face) {
                let next = first + (k + 1) % n;
                half_edges.push(HalfEdge { origin, twin: u32::MAX, next, face: f });
            }
        }
        let mut by_ends = HashMap::with_capacity(half_edges.len());
        for (h, e) in (0u32..).zip(&half_edges) {
            let head = half_edges[e.next as usize].origin;
            if by_ends.insert((e.origin, head), h).is_some() {
                return None;
            }
        }
        for h in 0..half_edges.len() {
            let e = half_edges[h];
            let head = half_edges[e.next as usize].origin;
            half_edges[h].twin = *by_ends.get(&(head, e.origin))?;
        }
        let mut first = vec![u32::MAX; vertex_count];
        let mut degree = vec![0usize; vertex_count];
        for (h, e) in (0u32..).zip(&half_edges) {
            let v = e.origin as usize;
            *degree.get_mut(v)? += 1;
            if first[v] == u32::MAX {
                first[v] = h;
            }
        }
        let (mut out_edges, mut out_heads, mut out_starts) = (Vec::new(), Vec::new(), vec![0]);
        for (&h0, &n) in first.iter().zip(&degree) {
            // Round the vertex: the twin of a half-edge leaving it comes back
            // in, and the next one after that leaves again. A closed surface
            // gets back to the first after exactly the vertex's degree.
            let mut h = *half_edges.get(h0 as usize)?;
            let mut round = vec![h0];
            for _ in 1..n {
                let next = half_edges[h.twin as usize].next;
                round.push(next);
                h = half_edges[next as usize];
            }
            if half_edges[h.twin as usize].next != h0 {
                return None;
            }
            out_heads.extend(
                round.iter().map(|&g| half_edges[half_edges[g as usize].next as usize].origin),
            );
            out_edges.extend(round);
            out_starts.push(out_edges.len() as u32);
        }
        let edges = Topology::canonical_edges(&half_edges);
        Some(Topology { half_edges, out_edges, out_heads, out_starts, face_edges, edges })
    }

    /// Each undirected edge once: the half-edge whose face has the lower index.
    fn canonical_edges(half_edges: &[HalfEdge]) -> Vec<u32> {
        (0u32..)
            .zip(half_edges)
            .filter(|(_, e)| e.face < half_edges[e.twin as usize].face)
            .map(|(h, _)| h)
            .collect()
    }

    /// The same surface with its faces renumbered: new face `i` is old face
    /// `order[i]` (a permutation). The edge list is made anew, in face order.
    pub fn with_face_order(mut self, order: &[u32]) -> Topology {
        let mut new_index = vec![0; order.len()];
        for (i, &f) in (0u32..).zip(order) {
            new_index[f as usize] = i;
        }
        for e in &mut self.half_edges {
            e.face = new_index[e.face as usize];
        }
        self.face_edges = order.iter().map(|&f| self.face_edges[f as usize]).collect();
        self.edges = Topology::canonical_edges(&self.half_edges);
        self
    }

    /// Half-edge `h`.
    pub fn half_edge(&self, h: u32) -> HalfEdge {
        self.half_edges[h as usize]
    }

    /// The vertex half-edge `h` enters.
    pub fn head(&self, h: u32) -> u32 {
        self.half_edge(self.half_edge(h).next).origin
    }

    /// The face on the other side of half-edge `h`.
    pub fn twin_face(&self, h: u32) -> u32 {
        self.half_edge(self.half_edge(h).twin).face
    }

    /// Where vertex `v`'s half-edges are in `out_edges` and `out_heads`.
    fn round(&self, v: u32) -> Range<usize> {
        self.out_starts[v as usize] as usize..self.out_starts[v as usize + 1] as usize
    }

    /// The half-edges leaving vertex `v`, round it.
    pub fn outgoing(&self, v: u32) -> &[u32] {
        &self.out_edges[self.round(v)]
    }

    /// The neighbours of vertex `v`: the heads of [`outgoing`](Self::outgoing), alongside.
    pub fn neighbours(&self, v: u32) -> &[u32] {
        &self.out_heads[self.round(v)]
    }

    /// The half-edges round face `f`, in loop order.
    pub fn face_loop(&self, f: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.face_edges[f as usize];
        iter::successors(Some(first), move |&h| {
            Some(self.half_edge(h).next).filter(|&n| n != first)
        })
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.out_starts.len() - 1
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_edges.len()
    }
}
