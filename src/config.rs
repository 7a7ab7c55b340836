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
}
