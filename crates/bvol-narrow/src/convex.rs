//! What the separating-axis code reads of a convex shape, whether a stored
//! [`Polyhedron`](crate::Polyhedron) or a box made on the spot from its half
//! extents.

use std::ops::Range;

use glam::DVec3;

use crate::arc::Arc;
use crate::box_numbering::BoxNumbering;
use crate::cluster::Cluster;
use crate::lanes::{Witness, live_mask};
use crate::plane::Plane;
use crate::topology::Topology;

/// A convex polyhedron as the tests read it, in its local space, in f64.
pub(crate) trait Convex {
    /// How its vertices, edges and faces meet.
    fn topology(&self) -> &Topology;

    /// Vertex `v`.
    fn vertex(&self, v: u32) -> DVec3;

    /// The plane of face `f`.
    fn plane(&self, f: u32) -> Plane;

    /// Half the diagonal of its local bounding box: the length that relative
    /// tolerances are measured against.
    fn size(&self) -> f64;

    /// A point inside it, and the radius of a ball about that point that is
    /// inside it too: then `min over x of n . x <= n . centre - radius` for
    /// any unit `n`, the bound that lets the queries skip most axes.
    fn inner_ball(&self) -> (DVec3, f64);

    /// A vertex to start hill climbing from, for the lowest vertex along `dir`.
    fn seed(&self, dir: DVec3) -> u32;

    /// A face whose normal is near `dir`: the one most along the grid
    /// direction nearest it.
    fn face_seed(&self, dir: DVec3) -> u32;

    /// The Gauss-map arc of edge `e` (an index into `topology().edges`).
    fn arc(&self, e: u32) -> Arc;

    /// The faces grouped by the directions of their normals.
    fn face_clusters(&self) -> impl Iterator<Item = Cluster> + '_;

    /// The faces of `run` (at most 64) whose planes' distances to all
    /// `witnesses` (points from the inner centre, less their `less`) leave
    /// above `bar`, as a bit mask ([`lanes_left`]): every face whose bounds
    /// beat the bar, and perhaps a few more.
    fn faces_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        let centre = self.inner_ball().0;
        live_mask(run, |f| {
            let plane = self.plane(f);
            witnesses.iter().all(|w| plane.distance(centre + w.at) - w.less > bar)
        })
    }

    /// The arcs of `run` (at most 64) whose cap bounds by all `witnesses`
    /// leave above `bar`, as a bit mask ([`lanes_left`]): every arc whose
    /// bounds beat the bar, and perhaps a few more.
    fn arcs_left<const N: usize>(
        &self,
        run: Range<u32>,
        witnesses: &[Witness; N],
        bar: f64,
    ) -> u64 {
        live_mask(run, |e| {
            let arc = self.arc(e);
            witnesses.iter().all(|w| w.bound(&arc.cap, arc.inner) > bar)
        })
    }

    /// The edges grouped by the directions of their arcs.
    fn edge_clusters(&self) -> impl Iterator<Item = Cluster> + '_;

    /// The vertex least far along `dir`, and `dir . vertex` (its support
    /// point against `dir`), searched from vertex `start`. The search may
    /// stop at the first vertex it meets at or below `limit`, when the caller
    /// only needs to know the least is that low: a value `<= limit` is then
    /// only an upper bound of the least. `-inf` asks for the least.
    fn support_min(&self, dir: DVec3, start: u32, limit: f64) -> (u32, f64);

    /// Its half extents and feature numbering if it is a box centred on its
    /// origin, square to its axes: two boxes take the closed-form queries.
    fn as_box(&self) -> Option<(DVec3, &BoxNumbering)> {
        None
    }
}
