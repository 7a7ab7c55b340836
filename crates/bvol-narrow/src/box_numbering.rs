//! A box's faces, corners and edges by direction, in a polyhedron's own
//! numbering: what the closed-form box queries name their answers by.

use glam::DVec3;

use crate::plane::Plane;
use crate::topology::Topology;

/// A box's features by direction: what the closed-form queries need to name
/// the face, vertex or edge they pick in the shape's own numbering.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BoxNumbering {
    /// The face whose outward normal is `+e_i` (`[i][0]`) or `-e_i` (`[i][1]`).
    pub face: [[u32; 2]; 3],
    /// The vertex at each corner, by corner code: bit `k` set when
    /// coordinate `k` is positive.
    pub vertex: [u32; 8],
    /// The edge (index into the topology's edge list) between two corners, by
    /// corner codes; `u32::MAX` for corners that share no edge.
    pub edge: [[u32; 8]; 8],
    /// The same edges' half-edges (those the edge list names).
    pub half_edge: [[u32; 8]; 8],
}

impl BoxNumbering {
    /// The half extents and numbering of the polyhedron of these vertices,
    /// face planes and topology if it is a box centred on its origin with
    /// its faces square to the axes, exactly (its corners at `±half` on every
    /// axis, its face normals the axes): `None` otherwise.
    pub fn of(
        points: &[DVec3],
        planes: &[Plane],
        topology: &Topology,
    ) -> Option<(DVec3, BoxNumbering)> {
        if topology.vertex_count() != 8 || topology.face_count() != 6 {
            return None;
        }
        let vertex = |v: u32| points[v as usize];
        let half = vertex(0).abs();
        let mut numbering = BoxNumbering {
            face: [[u32::MAX; 2]; 3],
            vertex: [u32::MAX; 8],
            edge: [[u32::MAX; 8]; 8],
            half_edge: [[u32::MAX; 8]; 8],
        };
        for f in 0..6 {
            let n = planes[f as usize].normal;
            let i = n.abs().max_position();
            if n.abs() != DVec3::AXES[i] {
                return None;
            }
            numbering.face[i][usize::from(n[i] < 0.0)] = f;
        }
        for v in 0..8 {
            let p = vertex(v);
            if p.abs() != half {
                return None;
            }
            numbering.vertex[Self::highest(p)] = v;
        }
        for (e, &h) in (0u32..).zip(&topology.edges) {
            let (a, b) = (topology.half_edge(h).origin, topology.head(h));
            let (ca, cb) = (Self::highest(vertex(a)), Self::highest(vertex(b)));
            (numbering.edge[ca][cb], numbering.edge[cb][ca]) = (e, e);
            (numbering.half_edge[ca][cb], numbering.half_edge[cb][ca]) = (h, h);
        }
        let complete = numbering.face.iter().flatten().all(|&f| f != u32::MAX)
            && numbering.vertex.iter().all(|&v| v != u32::MAX)
            && (0..8).all(|c| (0..3).all(|k| numbering.edge[c][c ^ (1 << k)] != u32::MAX));
        complete.then_some((half, numbering))
    }

    /// The corner highest along `dir` (on a tie, the positive side).
    pub fn highest(dir: DVec3) -> usize {
        usize::from(dir.x >= 0.0) | usize::from(dir.y >= 0.0) << 1 | usize::from(dir.z >= 0.0) << 2
    }
}
