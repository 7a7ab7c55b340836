//! Shapes: what a body is, in its own frame. Built once and shared between
//! bodies (through `Arc`): the convex parts the narrow phase tests, and the
//! bounding sphere and OBB of the whole, fitted by the methods the user picks.

use std::fmt;
use std::path::Path;

use bvol_narrow::{Capsule, HullPart, MassProperties, Part, Polyhedron};
use bvol_volumes::{
    Aabb, BodyBounds, ConvexHull, FitError, Obb, ObbMethod, Ray, Sphere, SphereMethod,
};
use glam::Vec3;

use crate::limits::{MAX_COORDINATE, within_limit};
use crate::mesh::{Mesh, MeshError, load_obj};

/// The fitting methods of a shape's bounds. The defaults are the tightest:
/// the exact minimum sphere and the near-minimum-volume OBB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FitOptions {
    /// How the bounding sphere is fitted.
    pub sphere: SphereMethod,
    /// How the oriented bounding box is fitted.
    pub obb: ObbMethod,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions { sphere: SphereMethod::Exact, obb: ObbMethod::MinVolume }
    }
}

/// A body's geometry in its own frame: convex parts (several when a mesh file
/// has several objects, which is how a concave body is given), and the
/// bounding sphere and OBB of all of them.
///
/// ```
/// use bvol::Shape;
/// use glam::Vec3;
/// let crate_box = Shape::cuboid(Vec3::new(1.0, 0.5, 0.5))?;
/// assert!((crate_box.sphere().radius - 1.5f32.sqrt()).abs() < 1e-5);
/// assert!((crate_box.obb().volume() - 2.0).abs() < 1e-4);
/// # Ok::<(), bvol::ShapeError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Shape {
    parts: Vec<Part>,
    bounds: BodyBounds,
    /// How `bounds` were fitted, so that a scaled copy fits its own alike.
    fit: FitOptions,
}

/// Why a shape could not be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ShapeError {
    /// The OBJ file could not be loaded.
    Mesh(MeshError),
    /// The file has no object of that name.
    NoSuchObject {
        /// The name asked for.
        name: String,
        /// The names the file has.
        found: Vec<String>,
    },
    /// A part is not a solid or has bad coordinates.
    Part {
        /// The part's name (the mesh object's, or the primitive's).
        part: String,
        /// What is wrong with it.
        reason: bvol_narrow::ShapeError,
    },
    /// The points could not be bounded.
    Fit(FitError),
    /// A primitive's size is not finite and positive, or beyond
    /// [`MAX_COORDINATE`].
    BadSize {
        /// The primitive.
        primitive: &'static str,
    },
    /// A scale factor is not finite and positive on every axis, or would
    /// take a part's coordinates beyond [`MAX_COORDINATE`] or shrink a part
    /// to nothing in f32.
    BadScale {
        /// The factor asked for.
        factor: Vec3,
    },
    /// A point has a coordinate beyond [`MAX_COORDINATE`].
    OutOfRange {
        /// The part's name (the mesh object's, or the primitive's).
        part: String,
        /// The point's index among the part's points.
        point: usize,
    },
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShapeError::Mesh(e) => e.fmt(f),
            ShapeError::NoSuchObject { name, found } => {
                write!(f, "no object named {name:?}; the file has {found:?}")
            }
            ShapeError::Part { part, reason } => write!(f, "part {part:?}: {reason}"),
            ShapeError::Fit(e) => write!(f, "cannot bound the shape: {e}"),
            ShapeError::BadSize { primitive } => write!(
                f,
                "{primitive}: sizes must be finite, greater than zero and at most {MAX_COORDINATE:e}"
            ),
            ShapeError::BadScale { factor } => write!(
                f,
                "scale factor {factor}: must be finite and greater than zero on every axis, \
                 keeping every part within ±{MAX_COORDINATE:e} and of some size"
            ),
            ShapeError::OutOfRange { part, point } => {
                write!(
                    f,
                    "part {part:?}: point {point} has a coordinate beyond ±{MAX_COORDINATE:e}"
                )
            }
        }
    }
}

impl std::error::Error for ShapeError {}

impl From<MeshError> for ShapeError {
    fn from(e: MeshError) -> Self {
        ShapeError::Mesh(e)
    }
}

impl From<FitError> for ShapeError {
    fn from(e: FitError) -> Self {
        ShapeError::Fit(e)
    }
}

impl Shape {
    /// A shape of one convex part, the hull of `points`, with default fits.
    pub fn convex(points: &[Vec3]) -> Result<Shape, ShapeError> {
        Self::from_parts(vec![hull_part("points", points)?], FitOptions::default())
    }

    /// A shape with one convex part per mesh (the hull of its vertices).
    pub fn from_meshes(meshes: &[Mesh], fit: FitOptions) -> Result<Shape, ShapeError> {
        let parts = meshes
            .iter()
            .map(|m| hull_part(&m.name, &m.positions))
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_parts(parts, fit)
    }

    /// Every object of an OBJ file, one convex part each.
    pub fn from_obj(path: impl AsRef<Path>, fit: FitOptions) -> Result<Shape, ShapeError> {
        Self::from_meshes(&load_obj(path)?, fit)
    }

    /// The object named `name` of an OBJ file, as one convex part.
    pub fn from_obj_object(
        path: impl AsRef<Path>,
        name: &str,
        fit: FitOptions,
    ) -> Result<Shape, ShapeError> {
        let meshes = load_obj(path)?;
        match meshes.iter().find(|m| m.name == name) {
            Some(m) => Self::from_meshes(std::slice::from_ref(m), fit),
            None => Err(ShapeError::NoSuchObject {
                name: name.to_owned(),
                found: meshes.into_iter().map(|m| m.name).collect(),
            }),
        }
    }

    /// A box centred on the origin.
    pub fn cuboid(half_extents: Vec3) -> Result<Shape, ShapeError> {
        if !(half_extents.cmpgt(Vec3::ZERO).all() && within_limit(half_extents)) {
            return Err(ShapeError::BadSize { primitive: "cuboid" });
        }
        let polyhedron = Polyhedron::cuboid(half_extents)
            .map_err(|reason| ShapeError::Part { part: "cuboid".into(), reason })?;
        let hull = ConvexHull::cuboid(half_extents)?;
        Self::from_parts(
            vec![Part::Hull(Box::new(HullPart { polyhedron, hull }))],
            FitOptions::default(),
        )
    }

    /// A ball of `radius` centred on the origin, tested exactly.
    pub fn ball(radius: f32) -> Result<Shape, ShapeError> {
        if !(radius > 0.0 && within_limit(Vec3::splat(radius))) {
            return Err(ShapeError::BadSize { primitive: "ball" });
        }
        Self::from_parts(vec![Part::Ball(Sphere::new(Vec3::ZERO, radius))], FitOptions::default())
    }

    /// A capsule along y (a segment of half length `half_height` swept by a
    /// ball of `radius`), tested exactly: its sphere is the smallest, its OBB
    /// its box.
    pub fn capsule(radius: f32, half_height: f32) -> Result<Shape, ShapeError> {
        if !(radius > 0.0 && half_height >= 0.0 && within_limit(Vec3::splat(radius + half_height)))
        {
            return Err(ShapeError::BadSize { primitive: "capsule" });
        }
        let capsule = Capsule::new(radius, half_height);
        Self::from_parts(vec![Part::Capsule(capsule)], FitOptions::default())
    }

    /// A regular tetrahedron with its corners at distance `radius` from the
    /// origin.
    pub fn tetrahedron(radius: f32) -> Result<Shape, ShapeError> {
        if !(radius > 0.0 && within_limit(Vec3::splat(radius))) {
            return Err(ShapeError::BadSize { primitive: "tetrahedron" });
        }
        let s = radius / 3f32.sqrt();
        let corners =
            [Vec3::new(s, s, s), Vec3::new(s, -s, -s), Vec3::new(-s, s, -s), Vec3::new(-s, -s, s)];
        Self::from_parts(vec![hull_part("tetrahedron", &corners)?], FitOptions::default())
    }

    /// The same parts, their sphere and OBB fitted by other methods.
    pub fn with_fit(&self, fit: FitOptions) -> Result<Shape, ShapeError> {
        Self::from_parts(self.parts.clone(), fit)
    }

    /// The shape scaled by `factor` along its frame's axes, about its
    /// origin: by one factor on every axis for any shape, by a factor per
    /// axis for shapes of hulls (a cuboid stays a cuboid).
    ///
    /// An equal factor scales the bounds as they are, without fitting them
    /// anew (a sphere or box that is smallest stays smallest); unequal
    /// factors fit them anew with the shape's fit options. A factor not
    /// finite and positive on every axis, or that takes a part beyond
    /// [`MAX_COORDINATE`] or to nothing, is [`ShapeError::BadScale`]; a ball
    /// or capsule with unequal factors is [`ShapeError::Part`] naming the
    /// part by its index (`"part 2"`).
    ///
    /// ```
    /// use bvol::Shape;
    /// use glam::Vec3;
    /// let plank = Shape::cuboid(Vec3::ONE)?.scaled(Vec3::new(2.0, 0.1, 0.5))?;
    /// assert!((plank.obb().volume() - 0.8).abs() < 1e-5);
    /// assert!(Shape::ball(1.0)?.scaled(Vec3::new(1.0, 2.0, 1.0)).is_err());
    /// # Ok::<(), bvol::ShapeError>(())
    /// ```
    pub fn scaled(&self, factor: Vec3) -> Result<Shape, ShapeError> {
        let bad = || ShapeError::BadScale { factor };
        if !(factor.is_finite() && factor.cmpgt(Vec3::ZERO).all()) {
            return Err(bad());
        }
        let parts = (0..self.parts.len())
            .map(|i| scale_part(&self.parts[i], i, factor))
            .collect::<Result<Vec<_>, _>>()?;
        if factor.x == factor.y && factor.y == factor.z {
            let bounds = scale_bounds(&self.bounds, factor.x);
            Ok(Shape { parts, bounds, fit: self.fit })
        } else {
            Self::from_parts(parts, self.fit)
        }
    }

    /// The convex parts.
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// The bounding sphere, in the shape's frame.
    pub fn sphere(&self) -> Sphere {
        self.bounds.sphere
    }

    /// The oriented bounding box, in the shape's frame.
    pub fn obb(&self) -> Obb {
        self.bounds.obb
    }

    /// The sphere and OBB together, as a body's world bounds are made from
    /// them.
    pub fn bounds(&self) -> &BodyBounds {
        &self.bounds
    }

    /// The nearest `t` in `[0, max_t]` at which a ray in the shape's frame
    /// meets a part (`0` when it starts inside one).
    pub fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        self.parts.iter().filter_map(|part| part.ray_entry(ray, max_t)).min_by(f32::total_cmp)
    }

    /// The volume, centre of mass and inertia about it of the parts together
    /// at unit density ([`MassProperties::combine`]): parts that overlap
    /// count twice where they do, as separate bodies glued together would.
    pub fn mass_properties(&self) -> MassProperties {
        MassProperties::combine(self.parts.iter().map(Part::mass_properties))
    }

    /// The methods its bounds were fitted by.
    #[cfg(feature = "serde")]
    pub(crate) fn fit_options(&self) -> FitOptions {
        self.fit
    }

    /// A shape of these parts and bounds, as saved: the snapshot's
    /// checks are the caller's.
    #[cfg(feature = "serde")]
    pub(crate) fn restore(parts: Vec<Part>, bounds: BodyBounds, fit: FitOptions) -> Shape {
        Shape { parts, bounds, fit }
    }

    /// The bounds of the parts' fit points, by the chosen methods. A lone
    /// part whose smallest sphere is known in closed form (a ball, a capsule)
    /// is bounded by that sphere, whatever the method; one whose smallest
    /// sphere and box are both known (those and a box square to its axes)
    /// takes both without fitting when the fits are the defaults, which aim
    /// for the smallest.
    fn from_parts(parts: Vec<Part>, fit: FitOptions) -> Result<Shape, ShapeError> {
        let lone = match parts.as_slice() {
            [part] => Some(part),
            _ => None,
        };
        let smallest =
            lone.filter(|_| fit == FitOptions::default()).and_then(Part::smallest_bounds);
        if let Some((sphere, obb)) = smallest {
            return Ok(Shape { parts, bounds: BodyBounds { sphere, obb }, fit });
        }
        let points: Vec<Vec3> = parts.iter().flat_map(Part::fit_points).collect();
        let known = lone.and_then(Part::enclosing_sphere);
        let sphere = known.map_or_else(|| Sphere::fit(&points, fit.sphere), Ok)?;
        let obb = Obb::fit(&points, fit.obb)?;
        Ok(Shape { parts, bounds: BodyBounds { sphere, obb }, fit })
    }
}

/// Part `index` of a shape scaled by `factor` (finite and positive), checked
/// to stay within [`MAX_COORDINATE`] and of some size in f32.
fn scale_part(part: &Part, index: usize, factor: Vec3) -> Result<Part, ShapeError> {
    let Aabb { min, max } = part.local_bounds();
    if !(within_limit(min * factor) && within_limit(max * factor)) {
        return Err(ShapeError::BadScale { factor });
    }
    let scaled = part
        .scaled(factor)
        .map_err(|reason| ShapeError::Part { part: format!("part {index}"), reason })?;
    let Aabb { min, max } = scaled.local_bounds();
    if max.cmpgt(min).all() { Ok(scaled) } else { Err(ShapeError::BadScale { factor }) }
}

/// Bounds scaled by `s` about the origin, grown to hold what they held once
/// scaled in f32: a product rounded to nearest is off by at most 2^-24 of
/// itself, so a scaled point and the scaled centre each move by at most
/// that of their distance from the origin, and that is at most the centre's
/// distance plus the reach from it (a margin of four times that covers the
/// f32 axes being unit to a few ulps).
fn scale_bounds(bounds: &BodyBounds, s: f32) -> BodyBounds {
    let s64 = f64::from(s);
    let grown = |exact: f64, centre: Vec3, reach: f64| {
        let drift = (2.0 * centre.as_dvec3().length() * s64 + reach) * 2f64.powi(-22);
        // Rounded to nearest, then one step up: above the sum.
        ((exact + drift) as f32).next_up()
    };
    let Sphere { center, radius } = bounds.sphere;
    let reach = f64::from(radius) * s64;
    let sphere = Sphere::new(center * s, grown(reach, center, reach));
    let obb = bounds.obb;
    let half = obb.half_extents.as_dvec3() * s64;
    let reach = half.length();
    let half_extents = Vec3::new(
        grown(half.x, obb.center, reach),
        grown(half.y, obb.center, reach),
        grown(half.z, obb.center, reach),
    );
    let obb = Obb { center: obb.center * s, axes: obb.axes, half_extents };
    BodyBounds { sphere, obb }
}

/// The convex part of a point set, named for errors.
fn hull_part(name: &str, points: &[Vec3]) -> Result<Part, ShapeError> {
    // NaN and infinite points are named by the polyhedron's own check.
    let beyond = |p: &Vec3| p.is_finite() && !within_limit(*p);
    if let Some(point) = points.iter().position(beyond) {
        return Err(ShapeError::OutOfRange { part: name.to_owned(), point });
    }
    let part = HullPart::from_points(points)
        .map_err(|reason| ShapeError::Part { part: name.to_owned(), reason })?;
    Ok(Part::Hull(Box::new(part)))
}
