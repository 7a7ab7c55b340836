//! Fitting bounds to point sets: every method selectable by name.
//!
//! Every fitter works in f64 inside and ends with a pass over all the points
//! that makes the f32 bound hold each of them after rounding.

mod dito;
mod eigen;
mod epos;
mod extremes;
mod min_obb;
mod min_rect;
mod min_sphere;
mod pca;
mod simple_sphere;

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::error::check_points;
use crate::{Aabb, FitError, Obb, Sphere, UnknownMethod};

/// Defines a method enum with its names, `ALL`, `Display` and `FromStr`.
macro_rules! methods {
    ($(#[$doc:meta])* $name:ident { $($(#[$vdoc:meta])* $variant:ident = $text:literal,)* }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vdoc])* $variant,)*
        }

        impl $name {
            /// Every method, in the order they are listed.
            pub const ALL: &'static [$name] = &[$($name::$variant,)*];
            const NAMES: &'static [&'static str] = &[$($text,)*];

            /// The method's name, as `FromStr` accepts it.
            pub const fn name(self) -> &'static str {
                Self::NAMES[self as usize]
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }

        impl FromStr for $name {
            type Err = UnknownMethod;
            fn from_str(s: &str) -> Result<Self, UnknownMethod> {
                Self::ALL
                    .iter()
                    .copied()
                    .find(|m| m.name().eq_ignore_ascii_case(s))
                    .ok_or_else(|| UnknownMethod { name: s.to_string(), expected: Self::NAMES })
            }
        }
    };
}

methods! {
    /// How to fit a bounding sphere.
    ///
    /// ```
    /// use bvol_volumes::SphereMethod;
    /// assert_eq!("epos14".parse::<SphereMethod>().unwrap(), SphereMethod::Epos14);
    /// assert!("nope".parse::<SphereMethod>().is_err());
    /// ```
    SphereMethod {
        /// Centre of the AABB, radius from a second pass (squared distances).
        AabbCenter = "aabb",
        /// Mean of the points, radius to the farthest.
        Centroid = "centroid",
        /// Ritter 1990: widest pair of the 6 axis extremes, then grow.
        Ritter = "ritter",
        /// The exact minimum sphere (Gaertner's move-to-front with pivoting).
        Exact = "exact",
        /// EPOS-6 (Larsson 2008): exact sphere of the 6 axis extremes, then grow.
        Epos6 = "epos6",
        /// EPOS-14: extremes along 7 directions.
        Epos14 = "epos14",
        /// EPOS-26: extremes along 13 directions.
        Epos26 = "epos26",
    }
}

methods! {
    /// How to fit an oriented bounding box.
    ///
    /// ```
    /// use bvol_volumes::ObbMethod;
    /// assert_eq!("min-volume".parse::<ObbMethod>().unwrap(), ObbMethod::MinVolume);
    /// ```
    ObbMethod {
        /// Principal axes of the points' covariance.
        PcaPoints = "pca-points",
        /// Principal axes of the convex hull's surface (area-weighted triangles).
        PcaHull = "pca-hull",
        /// DiTO-14 (Larsson & Kallberg 2011): 7 slab directions.
        Dito14 = "dito14",
        /// DiTO-26: 13 slab directions.
        Dito26 = "dito26",
        /// Near-minimum volume on the convex hull: face- and edge-flush
        /// candidates, then local refinement over rotations.
        MinVolume = "min-volume",
    }
}

impl Sphere {
    /// Fits a sphere holding every point, by the chosen method.
    ///
    /// Empty input and non-finite coordinates are errors; degenerate sets (one
    /// point, duplicates, collinear, coplanar) give valid, tight spheres.
    pub fn fit(points: &[Vec3], method: SphereMethod) -> Result<Sphere, FitError> {
        check_points(points)?;
        Ok(match method {
            SphereMethod::AabbCenter => simple_sphere::aabb_center(points),
            SphereMethod::Centroid => simple_sphere::centroid(points),
            SphereMethod::Ritter => simple_sphere::ritter(points),
            SphereMethod::Exact => min_sphere::exact(points),
            SphereMethod::Epos6 => epos::epos::<3>(points),
            SphereMethod::Epos14 => epos::epos::<7>(points),
            SphereMethod::Epos26 => epos::epos::<13>(points),
        })
    }
}

impl Obb {
    /// Fits an oriented box holding every point, by the chosen method.
    ///
    /// Empty input and non-finite coordinates are errors; degenerate sets give
    /// valid boxes with zero extent where the points have none.
    pub fn fit(points: &[Vec3], method: ObbMethod) -> Result<Obb, FitError> {
        check_points(points)?;
        Ok(match method {
            ObbMethod::PcaPoints => pca::pca_points(points),
            ObbMethod::PcaHull => pca::pca_hull(points),
            ObbMethod::Dito14 => dito::dito::<7>(points),
            ObbMethod::Dito26 => dito::dito::<13>(points),
            ObbMethod::MinVolume => min_obb::min_volume(points),
        })
    }
}

impl Aabb {
    /// The tight box of a point set (exact: min and max of the coordinates).
    pub fn fit(points: &[Vec3]) -> Result<Aabb, FitError> {
        check_points(points)?;
        Ok(Aabb::of_points(points))
    }
}
