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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct WorldConfig {
    /// The threads [`World::update`](crate::World::update) runs on: `None`
    /// (the default), rayon's current pool (the global one unless the
    /// caller runs the update inside another); `Some(n)`, a pool of `n`
    /// threads of the world's own, from 1 to [`MAX_THREADS`](Self::MAX_THREADS),
    /// started when the world is made.
    pub threads: Option<usize>,
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
}
