//! The hull kind of part: a convex polyhedron (the hull of a mesh object or
//! of a primitive's corners).

use bvol_volumes::{Aabb, ConvexHull, Obb, Ray, Sphere};
use glam::{DMat3, DVec3, Mat3, Vec3};

use crate::flat::solid_hull;
use crate::mass::outer;
use crate::{MassProperties, PartKind, Polyhedron, ShapeError};

/// A convex polyhedron part: the same solid twice, as each reader wants it.
#[derive(Clone, Debug)]
pub struct HullPart {
    /// What the separating-axis tests read.
    pub polyhedron: Polyhedron,
    /// Its faces as planes and triangles, for ray casts and mass properties.
    pub hull: ConvexHull,
}

impl HullPart {
    /// The hull of `points` as a part, flat points given a thickness as
    /// [`Polyhedron::from_points`] gives them, with its errors.
    pub fn from_points(points: &[Vec3]) -> Result<HullPart, ShapeError> {
        let hull = solid_hull(points)?;
        Ok(HullPart { polyhedron: Polyhedron::from_hull(&hull)?, hull })
    }
}

/// What builds a hull part again, bit for bit: the form a saved part takes.
#[derive(Clone, Debug)]
pub enum HullSource {
    /// A box: [`Polyhedron::cuboid`] and [`ConvexHull::cuboid`] of these
    /// half extents.
    Cuboid(Vec3),
    /// A hull: [`Polyhedron::from_hull`] of it, beside it.
    Hull(ConvexHull),
}

impl HullPart {
    /// What builds this part again, bit for bit ([`HullSource::build`]):
    /// `None` for a part put together by hand whose polyhedron is not the
    /// one its hull or its box makes (every part this crate makes has a
    /// source). It builds the part again to compare, so it costs what
    /// building the part did.
    ///
    /// ```
    /// use bvol_narrow::HullPart;
    /// use glam::Vec3;
    /// let part = HullPart::from_points(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z])?;
    /// let again = part.source().expect("made here").build()?;
    /// assert_eq!(again.polyhedron.vertices(), part.polyhedron.vertices());
    /// # Ok::<(), bvol_narrow::ShapeError>(())
    /// ```
    pub fn source(&self) -> Option<HullSource> {
        if let Some((half, _)) = &self.polyhedron.box_shape {
            let source = HullSource::Cuboid(half.as_vec3());
            if source.build().is_ok_and(|part| part.same_as(self)) {
                return Some(source);
            }
        }
        let source = HullSource::Hull(self.hull.clone());
        source.build().is_ok_and(|part| part.same_as(self)).then_some(source)
    }

    /// Whether two parts have the same polyhedron and hull, to the bit.
    fn same_as(&self, other: &HullPart) -> bool {
        let (p, q) = (&self.polyhedron, &other.polyhedron);
        let same_solid =
            p.vertices == q.vertices && p.planes == q.planes && p.topology == q.topology;
        let (h, k) = (&self.hull, &other.hull);
        fn faces(h: &ConvexHull) -> impl Iterator<Item = (&[u32], DVec3, f64)> {
            (0..h.face_count()).map(|f| (h.face(f), h.face_normal(f), h.face_offset(f)))
        }
        same_solid
            && h.vertices() == k.vertices()
            && h.tolerance() == k.tolerance()
            && faces(h).eq(faces(k))
    }
}

impl HullSource {
    /// The part it builds; the polyhedron's errors where that is not a
    /// solid.
    pub fn build(&self) -> Result<HullPart, ShapeError> {
        match self {
            HullSource::Cuboid(half) => {
                let polyhedron = Polyhedron::cuboid(*half)?;
                let hull = ConvexHull::cuboid(*half).map_err(|_| ShapeError::BadHalfExtents)?;
                Ok(HullPart { polyhedron, hull })
            }
            HullSource::Hull(hull) => {
                Ok(HullPart { polyhedron: Polyhedron::from_hull(hull)?, hull: hull.clone() })
            }
        }
    }
}

impl PartKind for HullPart {
    fn local_bounds(&self) -> Aabb {
        let v = self.polyhedron.vertices();
        let (min, max) = v.iter().fold((v[0], v[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        Aabb::new(min, max)
    }

    /// The vertex farthest along `direction` (the first of ties), measured
    /// in f64.
    fn support(&self, direction: Vec3) -> Vec3 {
        let d = direction.as_dvec3();
        let height = |p: &Vec3| p.as_dvec3().dot(d);
        let v = self.polyhedron.vertices();
        v.iter().fold(v[0], |best, p| if height(p) > height(&best) { *p } else { best })
    }

    /// The ray's parameter interval clipped by every face plane (Ericson,
    /// Real-Time Collision Detection 5.3.8), in f64.
    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        let valid = ray.origin.is_finite() && ray.direction.is_finite();
        if !(valid && ray.direction != Vec3::ZERO && max_t >= 0.0) {
            return None;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
        let (mut enter, mut exit) = (0.0f64, max_t as f64);
        let hull = &self.hull;
        for f in 0..hull.face_count() {
            let (n, offset) = (hull.face_normal(f), hull.face_offset(f));
            let (dist, rate) = (n.dot(o) - offset, n.dot(d));
            if rate == 0.0 {
                if dist > 0.0 {
                    return None;
                }
            } else {
                let t = -dist / rate;
                if rate < 0.0 { enter = enter.max(t) } else { exit = exit.min(t) }
            }
            if enter > exit {
                return None;
            }
        }
        Some(enter as f32)
    }

    /// The vertices: the hull of them is the part.
    fn fit_points(&self) -> Vec<Vec3> {
        self.polyhedron.vertices().to_vec()
    }

    /// None: a hull's sphere is fitted to its vertices.
    fn enclosing_sphere(&self) -> Option<Sphere> {
        None
    }

    /// For a box centred on the origin and square to its axes, itself and
    /// the sphere through its corners (its diagonal is a diameter of any
    /// sphere holding it; no box holds it in less than its own volume).
    fn smallest_bounds(&self) -> Option<(Sphere, Obb)> {
        let (half, _) = self.polyhedron.box_shape.as_ref()?;
        // Rounded to nearest, then one step up: above the exact length.
        let radius = (half.length() as f32).next_up();
        let half_extents = half.as_vec3();
        let obb = Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents };
        Some((Sphere::new(Vec3::ZERO, radius), obb))
    }

    /// A box its half extents scaled, as [`Polyhedron::cuboid`] makes it;
    /// any other hull rebuilt from its vertices scaled (an affine map keeps
    /// a convex hull's vertices its vertices).
    fn scaled(&self, factor: Vec3) -> Result<HullPart, ShapeError> {
        // The polyhedron's vertices are finite and span a solid: what a hull
        // of them needs.
        let hull_error = |_| ShapeError::Empty;
        match &self.polyhedron.box_shape {
            Some((half, _)) => {
                let half = half.as_vec3() * factor;
                let hull = ConvexHull::cuboid(half).map_err(hull_error)?;
                Ok(HullPart { polyhedron: Polyhedron::cuboid(half)?, hull })
            }
            // A thin slab stretched along its plane may come out flat at
            // its new size: thickened again, as a flat set is.
            None => {
                let vertices: Vec<Vec3> =
                    self.polyhedron.vertices().iter().map(|&v| v * factor).collect();
                HullPart::from_points(&vertices)
            }
        }
    }

    /// The exact integrals over the polyhedron, in f64: the solid cut into
    /// tetrahedra from the mean of its vertices to each face triangle, each
    /// adding its signed volume, first moment and second moment (its
    /// covariance about the origin, `V/20 (Σ wᵢwᵢᵀ + (Σ wᵢ)(Σ wᵢ)ᵀ)` over its
    /// corners: Tonon, "Explicit exact formulas for the 3-D tetrahedron
    /// inertia tensor in terms of its vertex coordinates", J. Math. Stat.
    /// 2004; Blow & Binstock, "How to find the inertia tensor (or other mass
    /// properties) of a 3D solid body represented by a triangle mesh", 2004).
    /// The inertia is `tr(C) E - C` of the covariance `C` about the centre of
    /// mass. Corners are taken relative to the vertices' mean, which lies
    /// inside, so that far from the origin nothing cancels.
    fn mass_properties(&self) -> MassProperties {
        let vertices = self.hull.vertices();
        let mean = vertices.iter().map(|v| v.as_dvec3()).sum::<DVec3>() / vertices.len() as f64;
        let at = |i: u32| vertices[i as usize].as_dvec3() - mean;
        let (mut volume, mut moment, mut covariance) = (0.0, DVec3::ZERO, DMat3::ZERO);
        for [a, b, c] in self.hull.triangles() {
            let [a, b, c] = [at(a), at(b), at(c)];
            let det = a.dot(b.cross(c));
            let sum = a + b + c;
            volume += det / 6.0;
            moment += sum * (det / 24.0);
            let squares = outer(a, a) + outer(b, b) + outer(c, c);
            covariance += (squares + outer(sum, sum)) * (det / 120.0);
        }
        if volume.is_nan() || volume <= 0.0 {
            return MassProperties::from_f64(0.0, mean, DMat3::ZERO);
        }
        let centre = moment / volume;
        let about_centre = covariance - outer(centre, centre) * volume;
        let trace = about_centre.x_axis.x + about_centre.y_axis.y + about_centre.z_axis.z;
        let inertia = DMat3::from_diagonal(DVec3::splat(trace)) - about_centre;
        MassProperties::from_f64(volume, mean + centre, inertia)
    }
}
