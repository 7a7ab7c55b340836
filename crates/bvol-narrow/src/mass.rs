//! Mass properties of solids of unit density, and of several together.

use glam::{DMat3, DVec3, Mat3, Vec3};

/// The mass properties of a solid of unit density: its mass is its volume.
/// Scale `volume` and `inertia` by a density to get another's.
///
/// ```
/// use bvol_narrow::{Capsule, MassProperties, Part};
/// use bvol_volumes::Sphere;
/// use glam::Vec3;
/// let ball = Part::Ball(Sphere::new(Vec3::new(0.0, 2.0, 0.0), 1.0)).mass_properties();
/// let rod = Part::Capsule(Capsule::new(0.5, 1.0)).mass_properties();
/// let both = MassProperties::combine([ball, rod]);
/// assert!((both.volume - (ball.volume + rod.volume)).abs() < 1e-5);
/// assert!(both.center.y > 0.0 && both.center.y < 2.0); // between the two centres
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MassProperties {
    /// The volume: the mass at unit density.
    pub volume: f32,
    /// The centre of mass, in the solid's frame.
    pub center: Vec3,
    /// The inertia tensor about `center`, in the solid's axes, at unit
    /// density: symmetric, its diagonal the moments about the axes through
    /// `center`, off the diagonal the products of inertia negated.
    pub inertia: Mat3,
}

impl MassProperties {
    /// Mass properties computed in f64, stored in f32.
    pub(crate) fn from_f64(volume: f64, center: DVec3, inertia: DMat3) -> MassProperties {
        MassProperties {
            volume: volume as f32,
            center: center.as_vec3(),
            inertia: inertia.as_mat3(),
        }
    }

    /// The inertia tensor about `point` instead of the centre of mass, in the
    /// same axes (the parallel axis theorem: `I + m (|d|² E - d dᵀ)`, `d` from
    /// `point` to the centre of mass), computed in f64.
    pub fn inertia_about(&self, point: Vec3) -> Mat3 {
        let d = self.center.as_dvec3() - point.as_dvec3();
        (self.inertia.as_dmat3() + shift(f64::from(self.volume), d)).as_mat3()
    }

    /// The mass properties of several solids taken together, in f64: the
    /// volumes add, the centre of mass is their volume-weighted mean, and each
    /// inertia is moved to that centre by the parallel axis theorem before
    /// they add. Solids that overlap are counted twice where they overlap,
    /// as if each were a body of its own glued to the others. None at all
    /// (or none with volume) is the default: no volume, no inertia, centred
    /// on the origin.
    pub fn combine(solids: impl IntoIterator<Item = MassProperties>) -> MassProperties {
        let solids: Vec<MassProperties> = solids.into_iter().collect();
        let volume: f64 = solids.iter().map(|s| f64::from(s.volume)).sum();
        if volume.is_nan() || volume <= 0.0 {
            return MassProperties::default();
        }
        let moment: DVec3 = solids.iter().map(|s| s.center.as_dvec3() * f64::from(s.volume)).sum();
        let center = moment / volume;
        let inertia = solids.iter().fold(DMat3::ZERO, |sum, s| {
            let d = s.center.as_dvec3() - center;
            sum + s.inertia.as_dmat3() + shift(f64::from(s.volume), d)
        });
        MassProperties::from_f64(volume, center, inertia)
    }
}

/// What the parallel axis theorem adds to an inertia tensor when the axes
/// move by `d` from the centre of mass of a solid of mass `m`:
/// `m (|d|² E - d dᵀ)`.
pub(crate) fn shift(m: f64, d: DVec3) -> DMat3 {
    (DMat3::from_diagonal(DVec3::splat(d.length_squared())) - outer(d, d)) * m
}

/// The outer product `a bᵀ`.
pub(crate) fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}
