//! How a world is set up: the choices a user makes once, when making it.

/// A world's settings, for [`World::with_config`](crate::World::with_config).
/// The default is what [`World::new`](crate::World::new) makes.
///
/// ```
/// use bvol::{World, WorldConfig, WorldError};
///
/// let world = World::with_config(WorldConfig::default().with_threads(2))?;
/// assert_eq!(world.config().threads, Some(2));
/// let none = World::with_config(WorldConfig::default().with_threads(0));
/// assert!(matches!(none, Err(WorldError::BadThreads { threads: 0 })));
/// # Ok::<(), WorldError>(())
/// ```
///
/// Settings are added as the world learns new ones, so a config is made
/// from the default and changed by its `with_` methods rather than
/// written out field by field.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct WorldConfig {
    /// The threads [`World::update`](crate::World::update) runs on: `None`
    /// (the default), rayon's current pool (the global one unless the
    /// caller runs the update inside another); `Some(n)`, a pool of `n`
    /// threads of the world's own, from 1 to [`MAX_THREADS`](Self::MAX_THREADS),
    /// started when the world is made.
    pub threads: Option<usize>,
    /// How far apart two bodies may be and still be in contact (what a
    /// solver's speculative contacts need; rapier's prediction distance):
    /// `0` (the default), only bodies that touch; above `0`, also bodies
    /// apart by at most this, whose contacts have a negative depth, minus
    /// their distance ([`Contact::is_touching`](crate::narrow::Contact::is_touching)
    /// is false), the normal between their closest points and one point
    /// midway between them ([`contact_within`](crate::narrow::contact_within)).
    /// Each body's bounds grow by half of it, so that no such pair is
    /// missed. Finite, from 0 to [`MAX_COORDINATE`](crate::MAX_COORDINATE).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::glam::{Quat, Vec3};
    /// use bvol::volumes::Pose;
    /// use bvol::{BodyDesc, Shape, World, WorldConfig};
    ///
    /// let mut world = World::with_config(WorldConfig::default().with_margin(0.1))?;
    /// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
    /// let a = world.add_body(BodyDesc::new(cube.clone(), Pose::IDENTITY))?;
    /// let b = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::X * 1.05, Quat::IDENTITY)))?;
    /// world.update();
    /// let near = world.contact(a, b)?.expect("0.05 apart, within 0.1");
    /// assert!(!near.is_touching() && (near.depth + 0.05).abs() < 1e-6);
    /// assert_eq!(world.stats().near, 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub margin: f32,
    /// How far, relative to a pair's size, a touching pair may move and
    /// still reuse its contact feature from its last full test instead of
    /// searching every face and edge again (see
    /// [`WarmStart::reusing`](crate::narrow::WarmStart::reusing)): `0` (the
    /// default), never, and every contact is as a cold test gives it; above
    /// `0`, a pile resting in a solver, jittering by a rounding each frame,
    /// is tested in full once and then reuses its contacts. Whether a pair
    /// touches is never changed by it (so neither are events); a reused
    /// contact's depth is at most `2e-5 + 2 * reuse` of the pair's size
    /// above the least penetration depth, where a cold test's is within
    /// `2e-5`. `4e-5` keeps depths within `1e-4` of the size. From 0 to
    /// [`MAX_REUSE`](crate::narrow::MAX_REUSE).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use bvol::glam::{Quat, Vec3};
    /// use bvol::volumes::Pose;
    /// use bvol::{BodyDesc, Shape, World, WorldConfig};
    ///
    /// let mut world = World::with_config(WorldConfig::default().with_reuse(4e-5))?;
    /// let floor = Arc::new(Shape::cuboid(Vec3::new(5.0, 0.5, 5.0))?);
    /// let cube = Arc::new(Shape::cuboid(Vec3::splat(0.5))?);
    /// let a = world.add_body(BodyDesc::new(floor, Pose::IDENTITY))?;
    /// let b = world.add_body(BodyDesc::new(cube, Pose::new(Vec3::Y * 0.99, Quat::IDENTITY)))?;
    /// for frame in 0..5 {
    ///     // Resting 0.01 deep, jittering by 1e-6 as a solver leaves it.
    ///     let jitter = Vec3::X * if frame % 2 == 0 { 1e-6 } else { -1e-6 };
    ///     world.set_pose(b, Pose::new(Vec3::Y * 0.99 + jitter, Quat::IDENTITY))?;
    ///     world.update();
    ///     let contact = world.contact(a, b)?.expect("resting");
    ///     assert!((contact.depth - 0.01).abs() < 1e-5);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub reuse: f32,
}

impl WorldConfig {
    /// The most threads a world's own pool may have: far more than a
    /// machine runs at once, few enough that a mistaken count is caught.
    pub const MAX_THREADS: usize = 1024;

    /// The same settings, with updates on a pool of `threads` threads of
    /// the world's own (checked by [`World::with_config`](crate::World::with_config)).
    pub fn with_threads(self, threads: usize) -> Self {
        WorldConfig { threads: Some(threads), ..self }
    }

    /// The same settings, with contacts within `margin` (see
    /// [`margin`](Self::margin); checked by [`World::with_config`](crate::World::with_config)).
    pub fn with_margin(self, margin: f32) -> Self {
        WorldConfig { margin, ..self }
    }

    /// The same settings, reusing touching pairs' contact features while
    /// they move by at most `reuse` of their size (see
    /// [`reuse`](Self::reuse); checked by [`World::with_config`](crate::World::with_config)).
    pub fn with_reuse(self, reuse: f32) -> Self {
        WorldConfig { reuse, ..self }
    }
}
