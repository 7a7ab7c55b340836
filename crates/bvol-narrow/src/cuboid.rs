//! A box made on the spot from its half extents, read as a convex shape
//! without allocating.

use glam::{DVec3, Vec3};

use crate::Polyhedron;
use crate::arc::Arc;
use crate::box_numbering::BoxNumbering;
use crate::cluster::Cluster;
use crate::convex::Convex;
use crate::plane::Plane;
use crate::topology::Topology;

/// The box `[-half, half]`: the unit cube's topology, scaled, made without
/// allocating; the same numbers as [`Polyhedron::cuboid`] of the same half
/// extents, so a box and its polyhedron collide alike.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cuboid {
    unit: &'static Polyhedron,
    half: DVec3,
}

impl Cuboid {
    /// The box with these half extents, each `>= 0`.
    pub fn new(half_extents: Vec3) -> Cuboid {
        Cuboid { unit: Polyhedron::unit_cube(), half: half_extents.as_dvec3() }
    }
}

impl Convex for Cuboid {
    fn topology(&self) -> &Topology {
        &self.unit.topology
    }

    fn vertex(&self, v: u32) -> DVec3 {
        self.unit.vertex(v) * self.half
    }

    fn plane(&self, f: u32) -> Plane {
        self.unit.plane(f).scaled_to_box(self.half)
    }

    fn size(&self) -> f64 {
        self.half.length()
    }

    fn inner_ball(&self) -> (DVec3, f64) {
        (DVec3::ZERO, self.half.min_element())
    }

    fn seed(&self, dir: DVec3) -> u32 {
        self.unit.seed(dir)
    }

    fn face_seed(&self, dir: DVec3) -> u32 {
        self.unit.face_seed(dir)
    }

    /// Scaling the cube along its axes keeps its face normals, so its arcs'
    /// shapes; the depth behind the edge is the lesser of its faces' offsets.
    fn arc(&self, e: u32) -> Arc {
        let topology = self.topology();
        let h = topology.edges[e as usize];
        let offset = |f: u32| self.plane(f).offset;
        let inner = offset(topology.half_edge(h).face).min(offset(topology.twin_face(h)));
        Arc { inner, ..self.unit.arc(e) }
    }

    /// The unit cube's clusters, their depths taken at this scale.
    fn face_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.unit.face_clusters.iter().map(|c| Cluster {
            inner: c.members.clone().map(|f| self.plane(f).offset).fold(f64::INFINITY, f64::min),
            ..c.clone()
        })
    }

    fn edge_clusters(&self) -> impl Iterator<Item = Cluster> + '_ {
        self.unit.edge_clusters.iter().map(|c| Cluster {
            inner: c.members.clone().map(|e| self.arc(e).inner).fold(f64::INFINITY, f64::min),
            ..c.clone()
        })
    }

    /// The corner against `dir` on every axis, at once: the unit cube's seed
    /// for the diagonal of `dir`'s signs.
    fn support_min(&self, dir: DVec3, _start: u32, _limit: f64) -> (u32, f64) {
        let level = |x: f64| if x < 0.0 { 0 } else { 2 };
        let v = self.unit.seeds[level(dir.x) + 3 * level(dir.y) + 9 * level(dir.z)];
        (v, dir.dot(self.vertex(v)))
    }

    fn as_box(&self) -> Option<(DVec3, &BoxNumbering)> {
        self.unit.box_shape.as_ref().map(|(_, numbering)| (self.half, numbering))
    }
}
