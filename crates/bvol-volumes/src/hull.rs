//! The 3-D convex hull: quickhull (Barber, Dobkin & Huhdanpaa 1996) with exact
//! orientation signs for its topology, then coplanar triangles merged into convex
//! polygon faces; flat, collinear and single-point sets get their own hulls.
//!
//! Input points are f32, so their positions carry a relative error of about
//! 2^-24 of the set's size: faces coplanar to that precision are one face, and a
//! point that close to a face or an edge is not a vertex. That tolerance is
//! relative to the set's extent about its box centre (qhull's
//! `3 * maxabs_sum * epsilon`, with f32's epsilon and centred coordinates), so the
//! same shape scaled or moved gives the same faces. The exact signs (Shewchuk's
//! predicates, on the f32 values held exactly in f64) keep every intermediate
//! hull a closed manifold, so no input, however degenerate, can break it; and a
//! solid's face planes are planes of that exact hull, so every input point lies
//! behind every one of them, up to rounding.

mod merge;
mod planar;
mod predicates;
mod quickhull;

use std::sync::OnceLock;

use glam::{DVec3, Vec3};

use crate::{FitError, HullError, MAX_COORDINATE};

/// A point set seen from its box centre, with its distance tolerance.
struct CentredPoints<'a> {
    points: &'a [Vec3],
    centre: DVec3,
    /// Distances below this are noise of the f32 input.
    eps: f64,
}

impl<'a> CentredPoints<'a> {
    /// The centred view of a non-empty set of finite points.
    fn new(points: &'a [Vec3]) -> Self {
        let (lo, hi) =
            points.iter().fold((points[0], points[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        let half = (hi - lo) * 0.5;
        let eps = 3.0 * (half.x + half.y + half.z) * f64::from(f32::EPSILON);
        CentredPoints { points, centre: (lo + hi) * 0.5, eps }
    }

    /// Point `i` relative to the centre: rounded, for plane distances.
    fn at(&self, i: u32) -> DVec3 {
        self.relative(self.points[i as usize])
    }

    /// A point relative to the centre.
    fn relative(&self, p: Vec3) -> DVec3 {
        p.as_dvec3() - self.centre
    }

    /// Point `i` as given, exact in f64: for the orientation predicate.
    fn exact(&self, i: u32) -> DVec3 {
        self.points[i as usize].as_dvec3()
    }

    /// The point with the greatest `measure` of its centred position (first on ties).
    fn farthest(&self, measure: impl Fn(DVec3) -> f64) -> (u32, f64) {
        (0..self.points.len() as u32)
            .map(|i| (i, measure(self.at(i))))
            .fold((0, f64::NEG_INFINITY), |best, x| if x.1 > best.1 { x } else { best })
    }
}

/// The convex hull of a point set, in a flat, data-oriented layout: the vertices
/// (input points, each once), the faces as index loops into them with their unit
/// outward normals and plane offsets.
///
/// A solid hull's faces are convex polygons, coplanar triangles merged, each
/// counter-clockwise seen from outside; every edge lies in exactly two faces, in
/// opposite directions, and `V - E + F = 2`. A flat hull has two faces, its
/// polygon seen from each side. Segments and single points have no faces.
///
/// ```
/// use bvol_volumes::ConvexHull;
/// use glam::Vec3;
/// let mut points: Vec<Vec3> = (0..8)
///     .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32))
///     .collect();
/// points.push(Vec3::splat(0.5)); // inside
/// let hull = ConvexHull::new(&points)?;
/// assert_eq!((hull.dimension(), hull.vertices().len(), hull.face_count()), (3, 8, 6));
/// assert!((hull.volume() - 1.0).abs() < 1e-12 && (hull.surface_area() - 6.0).abs() < 1e-12);
/// # Ok::<(), bvol_volumes::FitError>(())
/// ```
#[derive(Clone, Debug)]
pub struct ConvexHull {
    vertices: Vec<Vec3>,
    /// Face loops, concatenated; face `f` is `face_vertices[face_starts[f]..face_starts[f + 1]]`.
    face_vertices: Vec<u32>,
    face_starts: Vec<u32>,
    normals: Vec<DVec3>,
    offsets: Vec<f64>,
    dimension: u8,
    tolerance: f64,
}

impl ConvexHull {
    /// Builds the hull of a point set.
    ///
    /// Empty input is [`FitError::Empty`]; a NaN or infinite coordinate is
    /// [`FitError::NonFinite`], one beyond [`MAX_COORDINATE`](crate::MAX_COORDINATE)
    /// [`FitError::OutOfRange`]. Any other set gives a hull: solid, flat (all
    /// points within [`tolerance`](Self::tolerance) of a plane), a segment, or
    /// one point.
    pub fn new(points: &[Vec3]) -> Result<ConvexHull, FitError> {
        crate::error::check_points(points)?;
        let centred = CentredPoints::new(points);
        // Initial simplex from extreme points (Barber et al. section 3): the
        // widest pair of axis extremes, the point farthest from their line, then
        // the point farthest from that plane. Each that is within tolerance
        // lowers the dimension.
        let (a, b) = widest_axis_extremes(&centred);
        let (pa, pb) = (centred.at(a), centred.at(b));
        let Some(axis) = (pb - pa).try_normalize().filter(|_| pa.distance(pb) > centred.eps) else {
            return Ok(Self::point(&centred, a));
        };
        let (c, off_line) = centred.farthest(|p| (p - pa).cross(axis).length());
        if off_line <= centred.eps {
            return Ok(Self::segment(&centred, axis));
        }
        let normal = axis.cross(centred.at(c) - pa).normalize();
        let (d, off_plane) = centred.farthest(|p| normal.dot(p - pa).abs());
        if off_plane <= centred.eps {
            return Ok(Self::flat(&centred, normal, axis));
        }
        match quickhull::triangulate(&centred, [a, b, c, d]) {
            Some(tris) => {
                let faces = merge::merge(&centred, &tris);
                if faces.len() >= 4 {
                    return Ok(Self::solid(&centred, &tris.vertices, &faces));
                }
                // Merging within tolerance left a sliver with two sides: it is flat.
                Ok(Self::flat(&centred, normal, axis))
            }
            None => Ok(Self::flat(&centred, normal, axis)),
        }
    }

    /// The hull of the box `[-half_extents, half_extents]`: its 8 corners
    /// (corner `i` on the positive side of x, y, z as bits 0, 1, 2 of `i`
    /// are set) and 6 square faces, as [`new`](Self::new) builds it from
    /// those corners, without building it: the unit cube's hull, made once,
    /// scaled. Half extents that are not all finite and within
    /// [`MAX_COORDINATE`](crate::MAX_COORDINATE), or a box within a few
    /// tolerances of flat, go through `new` and take its answer (an error,
    /// or a flat, segment or point hull).
    ///
    /// ```
    /// use bvol_volumes::ConvexHull;
    /// use glam::Vec3;
    /// let plank = ConvexHull::cuboid(Vec3::new(2.0, 0.125, 0.5))?;
    /// assert_eq!((plank.dimension(), plank.vertices().len(), plank.face_count()), (3, 8, 6));
    /// assert_eq!(plank.volume(), 1.0); // 4 x 0.25 x 1, every number exact
    /// # Ok::<(), bvol_volumes::FitError>(())
    /// ```
    pub fn cuboid(half_extents: Vec3) -> Result<ConvexHull, FitError> {
        let corners = box_corners(half_extents);
        if crate::error::check_points(&corners).is_err() {
            return ConvexHull::new(&corners);
        }
        // A box thin within the tolerance is flat to `new`, and one near
        // that is left to it too, whose merging decides such slivers.
        let tolerance = CentredPoints::new(&corners).eps;
        if f64::from(half_extents.min_element()) * 2.0 <= 16.0 * tolerance {
            return ConvexHull::new(&corners);
        }
        static UNIT: OnceLock<ConvexHull> = OnceLock::new();
        let unit = UNIT.get_or_init(|| {
            ConvexHull::new(&box_corners(Vec3::ONE)).expect("a unit cube's corners have a hull")
        });
        let half = half_extents.as_dvec3();
        Ok(ConvexHull {
            // The unit cube's vertices are its corners in input order.
            vertices: corners,
            face_vertices: unit.face_vertices.clone(),
            face_starts: unit.face_starts.clone(),
            // Scaling along the axes keeps the faces' axis normals; each
            // face's plane moves out to the half extent along its normal.
            normals: unit.normals.clone(),
            offsets: unit.normals.iter().map(|n| n.abs().dot(half)).collect(),
            dimension: 3,
            tolerance,
        })
    }

    /// The hull of a set whose points all coincide.
    fn point(centred: &CentredPoints, i: u32) -> Self {
        Self::assemble(centred, 0, vec![i], &[], &[], &[])
    }

    /// The hull of a set within tolerance of a line along `axis`: its two ends.
    fn segment(centred: &CentredPoints, axis: DVec3) -> Self {
        let (hi, _) = centred.farthest(|p| p.dot(axis));
        let (lo, _) = centred.farthest(|p| -p.dot(axis));
        if lo == hi {
            // Not reached: callers pass the axis of two points apart along it.
            return Self::point(centred, lo);
        }
        Self::assemble(centred, 1, vec![lo.min(hi), lo.max(hi)], &[], &[], &[])
    }

    /// The hull of a set within tolerance of a plane with unit `normal`: its
    /// polygon, once facing `normal` and once facing away.
    fn flat(centred: &CentredPoints, normal: DVec3, axis: DVec3) -> Self {
        let ring = planar::polygon(centred, normal, axis);
        if ring.len() < 3 {
            return Self::segment(centred, axis);
        }
        // The normal fitted to the polygon (Newell): its area vector.
        let corners: Vec<DVec3> = ring.iter().map(|&i| centred.at(i)).collect();
        let o = corners[0];
        let normal = corners
            .windows(2)
            .map(|w| (w[0] - o).cross(w[1] - o))
            .sum::<DVec3>()
            .try_normalize()
            .unwrap_or(normal);
        // Its two sides through the points farthest each way, not through the
        // polygon's mean: the fitted plane can tilt from the one every point
        // was found near, and a point 0.17 off a 0.16 tolerance was left in
        // front of it (a needle 2e4 long with a blob at one end).
        let front = centred.farthest(|p| normal.dot(p)).1;
        let back_offset = centred.farthest(|p| -normal.dot(p)).1;
        let back: Vec<u32> = ring.iter().rev().copied().collect();
        let n = ring.len() as u32;
        let mut vertices = ring.clone();
        vertices.sort_unstable();
        let local = |i: &u32| vertices.binary_search(i).unwrap_or(0) as u32;
        let loops: Vec<u32> = ring.iter().chain(&back).map(local).collect();
        let planes = [(normal, front), (-normal, back_offset)];
        Self::assemble(centred, 2, vertices, &loops, &[0, n, 2 * n], &planes)
    }

    /// A solid hull from the merged faces over the triangulation's vertices
    /// (input indices, ascending); vertices no face uses are left out.
    fn solid(centred: &CentredPoints, tri_vertices: &[u32], faces: &merge::Polygons) -> Self {
        let mut used: Vec<u32> = faces.loops.clone();
        used.sort_unstable();
        used.dedup();
        let vertices: Vec<u32> = used.iter().map(|&v| tri_vertices[v as usize]).collect();
        let loops: Vec<u32> =
            faces.loops.iter().map(|v| used.binary_search(v).unwrap_or(0) as u32).collect();
        Self::assemble(centred, 3, vertices, &loops, &faces.starts, &faces.planes)
    }

    /// The hull from its vertices (input indices, ascending), face loops
    /// (indices into them, concatenated, with their starts) and face planes in
    /// the centred.
    fn assemble(
        centred: &CentredPoints,
        dimension: u8,
        vertices: Vec<u32>,
        loops: &[u32],
        starts: &[u32],
        planes: &[(DVec3, f64)],
    ) -> Self {
        ConvexHull {
            vertices: vertices.iter().map(|&i| centred.points[i as usize]).collect(),
            face_vertices: loops.to_vec(),
            face_starts: if starts.is_empty() { vec![0] } else { starts.to_vec() },
            normals: planes.iter().map(|p| p.0).collect(),
            // Offsets about the box centre, moved to the input's origin.
            offsets: planes.iter().map(|&(n, d)| d + n.dot(centred.centre)).collect(),
            dimension,
            tolerance: centred.eps,
        }
    }

    /// A solid hull from its parts, as [`vertices`](Self::vertices),
    /// [`face`](Self::face), [`face_normal`](Self::face_normal),
    /// [`face_offset`](Self::face_offset) and [`tolerance`](Self::tolerance)
    /// give them: what a saved hull is loaded from. The parts are checked to
    /// make a hull as [`new`](Self::new) makes one, or [`HullError`] names
    /// the first that does not: every vertex finite and within
    /// [`MAX_COORDINATE`](crate::MAX_COORDINATE), at least four faces of at
    /// least three vertices each, every index in range, unit normals, finite
    /// offsets, each face's vertices within the tolerance of its plane and
    /// every vertex behind every plane or within the tolerance. (That the
    /// faces close up is the reader's to check.)
    ///
    /// ```
    /// use bvol_volumes::ConvexHull;
    /// use glam::Vec3;
    /// let cube = ConvexHull::cuboid(Vec3::ONE)?;
    /// let faces = (0..cube.face_count()).map(|f| cube.face(f).to_vec()).collect();
    /// let normals = (0..cube.face_count()).map(|f| cube.face_normal(f)).collect();
    /// let offsets = (0..cube.face_count()).map(|f| cube.face_offset(f)).collect();
    /// let again = ConvexHull::from_parts(cube.vertices().to_vec(), faces, normals, offsets, cube.tolerance())?;
    /// assert_eq!(again.volume(), 8.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_parts(
        vertices: Vec<Vec3>,
        faces: Vec<Vec<u32>>,
        normals: Vec<DVec3>,
        offsets: Vec<f64>,
        tolerance: f64,
    ) -> Result<ConvexHull, HullError> {
        check_parts(&vertices, &faces, &normals, &offsets, tolerance)?;
        let mut face_starts = vec![0u32];
        let mut face_vertices = Vec::new();
        for face in &faces {
            face_vertices.extend_from_slice(face);
            face_starts.push(face_vertices.len() as u32);
        }
        Ok(ConvexHull {
            vertices,
            face_vertices,
            face_starts,
            normals,
            offsets,
            dimension: 3,
            tolerance,
        })
    }

    /// 0 for a single point (all input points equal), 1 for a segment (collinear
    /// within tolerance), 2 for a flat polygon (coplanar within tolerance), 3 for
    /// a solid.
    pub fn dimension(&self) -> u8 {
        self.dimension
    }

    /// The hull's vertices: exact copies of input points, each once, in input
    /// order.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// Number of faces: the convex polygons of a solid, 2 for a flat hull (one
    /// per side), 0 for a segment or a point.
    pub fn face_count(&self) -> usize {
        self.face_starts.len() - 1
    }

    /// Vertex indices (into [`vertices`](Self::vertices)) of face `i`,
    /// counter-clockwise seen from outside (looking against the normal).
    ///
    /// Panics if `i >= face_count()`.
    pub fn face(&self, i: usize) -> &[u32] {
        &self.face_vertices[self.face_starts[i] as usize..self.face_starts[i + 1] as usize]
    }

    /// Unit outward normal of face `i`. A solid's face has the plane of its
    /// largest triangle of the exact hull (so every input point lies behind it,
    /// up to rounding); a flat hull's, the polygon's fitted normal, through the point farthest along it.
    ///
    /// Panics if `i >= face_count()`.
    pub fn face_normal(&self, i: usize) -> DVec3 {
        self.normals[i]
    }

    /// Offset of face `i`'s plane: `face_normal(i) . x = face_offset(i)` on it.
    /// Every vertex of the face lies within [`tolerance`](Self::tolerance) of
    /// the plane, and every input point behind it or within tolerance.
    ///
    /// Panics if `i >= face_count()`.
    pub fn face_offset(&self, i: usize) -> f64 {
        self.offsets[i]
    }

    /// The distance tolerance the hull was built with: `3 * f32::EPSILON` times
    /// the sum of the set's half extents along the axes. Points closer than this
    /// to a face plane count as on it.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Fan triangulation of every face, counter-clockwise from outside.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        (0..self.face_count()).flat_map(move |f| {
            let face = self.face(f);
            face.windows(2).skip(1).map(move |w| [face[0], w[0], w[1]])
        })
    }

    /// Each undirected edge once, as `[a, b]` with `a < b`: the one segment of
    /// a 1-D hull, none for a point.
    pub fn edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        // Every edge of a solid or flat hull runs once each way round the faces.
        let segment = (self.dimension == 1).then_some([0, 1]);
        (0..self.face_count())
            .flat_map(move |f| {
                let face = self.face(f);
                (0..face.len()).map(move |k| [face[k], face[(k + 1) % face.len()]])
            })
            .filter(|[a, b]| a < b)
            .chain(segment)
    }

    /// Number of undirected edges: `edges().count()`, without walking them.
    pub fn edge_count(&self) -> usize {
        if self.dimension == 1 { 1 } else { self.face_vertices.len() / 2 }
    }

    /// Enclosed volume, 0 unless the hull is solid: the tetrahedra from the
    /// first vertex to every face triangle, in f64.
    pub fn volume(&self) -> f64 {
        if self.dimension < 3 {
            return 0.0;
        }
        let o = self.vertices[0].as_dvec3();
        let at = |v: u32| self.vertices[v as usize].as_dvec3() - o;
        self.triangles().map(|[a, b, c]| at(a).dot(at(b).cross(at(c)))).sum::<f64>() / 6.0
    }

    /// Surface area, in f64; a flat hull counts both sides (twice its polygon).
    pub fn surface_area(&self) -> f64 {
        let at = |v: u32| self.vertices[v as usize].as_dvec3();
        self.triangles().map(|[a, b, c]| (at(b) - at(a)).cross(at(c) - at(a)).length()).sum::<f64>()
            / 2.0
    }
}

/// Douglas-Peucker on a polyline whose two ends stay: clears `keep` for each
/// inner point within `eps` of the segment that spans it in the result, so every
/// dropped point stays within `eps` of the simplified line.
fn douglas_peucker(points: &[DVec3], eps: f64, keep: &mut [bool]) {
    let mut spans = vec![(0, points.len() - 1)];
    while let Some((lo, hi)) = spans.pop() {
        if hi < lo + 2 {
            continue;
        }
        let (a, b) = (points[lo], points[hi]);
        let dist = |p: DVec3| {
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            p.distance(if t.is_finite() { a + (b - a) * t } else { a })
        };
        let (far, far_dist) = (lo + 1..hi)
            .map(|k| (k, dist(points[k])))
            .fold((lo, -1.0), |m, x| if x.1 > m.1 { x } else { m });
        if far_dist <= eps {
            keep[lo + 1..hi].iter_mut().for_each(|k| *k = false);
        } else {
            spans.push((lo, far));
            spans.push((far, hi));
        }
    }
}

/// The farthest apart pair among the points with the least and greatest
/// coordinate on each axis (first on ties).
fn widest_axis_extremes(centred: &CentredPoints) -> (u32, u32) {
    let mut extremes = [0u32; 6];
    for (i, p) in (0..).zip(centred.points) {
        for k in 0..3 {
            if p[k] < centred.points[extremes[2 * k] as usize][k] {
                extremes[2 * k] = i;
            }
            if p[k] > centred.points[extremes[2 * k + 1] as usize][k] {
                extremes[2 * k + 1] = i;
            }
        }
    }
    let mut best = (extremes[0], extremes[0], -1.0);
    for (i, &a) in extremes.iter().enumerate() {
        for &b in &extremes[i + 1..] {
            let d = centred.at(a).distance_squared(centred.at(b));
            if d > best.2 {
                best = (a, b, d);
            }
        }
    }
    (best.0, best.1)
}

/// The corners of the box `[-half, half]`: corner `i` on the positive side
/// of x, y and z where bits 0, 1 and 2 of `i` are set.
fn box_corners(half: Vec3) -> Vec<Vec3> {
    let sign = |i: usize, bit: usize| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
    (0..8).map(|i| Vec3::new(sign(i, 0), sign(i, 1), sign(i, 2)) * half).collect()
}

/// [`ConvexHull::from_parts`]' checks.
fn check_parts(
    vertices: &[Vec3],
    faces: &[Vec<u32>],
    normals: &[DVec3],
    offsets: &[f64],
    tolerance: f64,
) -> Result<(), HullError> {
    let limit = Vec3::splat(MAX_COORDINATE);
    if let Some(index) =
        vertices.iter().position(|v| !(v.is_finite() && v.abs().cmple(limit).all()))
    {
        return Err(HullError::BadVertex { index });
    }
    if faces.len() < 4 || normals.len() != faces.len() || offsets.len() != faces.len() {
        return Err(HullError::FaceCount { faces: faces.len() });
    }
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(HullError::BadTolerance);
    }
    // Rounding of the distances here, beyond the hull's own.
    let slack = tolerance * (1.0 + 1e-9) + 1e-300;
    for (face, ((loop_, &normal), &offset)) in faces.iter().zip(normals).zip(offsets).enumerate() {
        let unit = normal.is_finite() && (normal.length() - 1.0).abs() <= 1e-9;
        let indices_ok = loop_.len() >= 3 && loop_.iter().all(|&v| (v as usize) < vertices.len());
        if !(unit && offset.is_finite() && indices_ok) {
            return Err(HullError::BadFace { face });
        }
        let height = |v: Vec3| normal.dot(v.as_dvec3()) - offset;
        let on = loop_.iter().all(|&v| height(vertices[v as usize]).abs() <= slack);
        if !(on && vertices.iter().all(|&v| height(v) <= slack)) {
            return Err(HullError::NotConvex { face });
        }
    }
    Ok(())
}
