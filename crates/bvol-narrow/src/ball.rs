//! The ball kind of part: an exact sphere.

use std::f64::consts::PI;

use bvol_volumes::{Aabb, Obb, Ray, Sphere};
use glam::{DMat3, DVec3, Mat3, Vec3};

use crate::{Body, MassProperties, NarrowError, PartKind, ShapeError};

impl PartKind for Sphere {
    fn local_bounds(&self) -> Aabb {
        self.aabb()
    }

    /// The centre moved by the radius along `direction`, in f64; the centre
    /// when `direction` has no length.
    fn support(&self, direction: Vec3) -> Vec3 {
        let unit = direction.as_dvec3().try_normalize().unwrap_or(DVec3::ZERO);
        (self.center.as_dvec3() + unit * f64::from(self.radius)).as_vec3()
    }

    fn ray_entry(&self, ray: &Ray, max_t: f32) -> Option<f32> {
        Sphere::ray_entry(self, ray, max_t)
    }

    /// The corners of the ball's cube: points on the ball itself would not
    /// do, their hull lying inside the ball.
    fn fit_points(&self) -> Vec<Vec3> {
        (0..8)
            .map(|i| {
                let corner = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32);
                self.center + (corner * 2.0 - 1.0) * self.radius
            })
            .collect()
    }

    /// The ball itself.
    fn enclosing_sphere(&self) -> Option<Sphere> {
        Some(*self)
    }

    /// The ball, and its cube: no box holds a ball in less.
    fn smallest_bounds(&self) -> Option<(Sphere, Obb)> {
        let cube = Obb {
            center: self.center,
            axes: Mat3::IDENTITY,
            half_extents: Vec3::splat(self.radius),
        };
        Some((*self, cube))
    }

    /// Its centre and radius scaled, by one factor on every axis.
    fn scaled(&self, factor: Vec3) -> Result<Sphere, ShapeError> {
        uniform(factor).map(|s| Sphere::new(self.center * s, self.radius * s))
    }

    /// `4/3 π r³`, centred on the centre, `2/5 m r²` about every axis.
    fn mass_properties(&self) -> MassProperties {
        let r = f64::from(self.radius);
        let volume = 4.0 / 3.0 * PI * r.powi(3);
        let inertia = DMat3::from_diagonal(DVec3::splat(0.4 * volume * r * r));
        MassProperties::from_f64(volume, self.center.as_dvec3(), inertia)
    }
}

/// The one factor of `factor` when its three are equal, as a round part
/// needs: [`ShapeError::NonUniformScale`] otherwise.
pub(crate) fn uniform(factor: Vec3) -> Result<f32, ShapeError> {
    if factor.x == factor.y && factor.y == factor.z {
        Ok(factor.x)
    } else {
        Err(ShapeError::NonUniformScale)
    }
}

/// [`NarrowError::NonFiniteShape`] unless the sphere's fields are finite and
/// its radius not negative.
pub(crate) fn check_sphere(sphere: &Sphere, body: Body) -> Result<(), NarrowError> {
    if sphere.center.is_finite() && sphere.radius.is_finite() && sphere.radius >= 0.0 {
        Ok(())
    } else {
        Err(NarrowError::NonFiniteShape { body })
    }
}
