//! What a pair test answers: apart along an axis, or touching with a contact manifold.

use glam::{DVec3, Vec3};

use crate::isometry::DIsometry3;
use crate::manifold::{MAX_POINTS, Manifold};

/// One point of a contact manifold.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactPoint {
    /// World position, midway between the two surfaces.
    pub position: Vec3,
    /// Penetration of this point along the contact normal: `>= 0` where
    /// the bodies touch; where they are apart (a contact within a margin,
    /// [`contact_within`](crate::contact_within)), minus their distance.
    pub depth: f32,
}

/// How two touching bodies touch: the normal, the depth and up to four points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Unit world direction pointing from A to B.
    pub normal: Vec3,
    /// `>= 0` where they touch: the distance B must move along `normal` (or
    /// A against it) to separate them. Negative where they are apart, in a
    /// contact within a margin ([`contact_within`](crate::contact_within)):
    /// minus their distance, B as far from touching along `normal`.
    pub depth: f32,
    points: [ContactPoint; MAX_POINTS],
    count: u8,
}

impl Contact {
    /// A contact from its normal, depth and points (at most [`MAX_POINTS`]
    /// are kept): as a test makes one, or as a saved one is loaded.
    ///
    /// ```
    /// use bvol_narrow::{Contact, ContactPoint};
    /// use glam::Vec3;
    /// let point = ContactPoint { position: Vec3::ZERO, depth: 0.1 };
    /// let contact = Contact::new(Vec3::Y, 0.1, &[point; 6]);
    /// assert_eq!(contact.points().len(), bvol_narrow::MAX_POINTS);
    /// ```
    pub fn new(normal: Vec3, depth: f32, points: &[ContactPoint]) -> Contact {
        let count = points.len().min(MAX_POINTS);
        let mut all = [ContactPoint::default(); MAX_POINTS];
        all[..count].copy_from_slice(&points[..count]);
        Contact { normal, depth, points: all, count: count as u8 }
    }

    /// The contact points: one to four.
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.count as usize]
    }

    /// Whether the bodies touch (overlap or meet: `depth >= 0`), rather
    /// than lie apart within a margin.
    pub fn is_touching(&self) -> bool {
        self.depth >= 0.0
    }
}

/// The answer of a pair test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Collision {
    /// The bodies are apart: `axis` separates them.
    Separated {
        /// Unit world direction from A to B along which they are apart.
        axis: Vec3,
        /// The gap along `axis`, `> 0`, or a lower bound of it: a lower bound
        /// of their distance. The gap itself when measured at this call; when
        /// a warm start answered from the bodies' motion alone, the gap last
        /// measured less how far the motion can have closed it.
        distance: f32,
    },
    /// The bodies overlap or touch exactly (depth 0).
    Touching(Contact),
}

impl Collision {
    /// Apart along `axis` (unit, world space, from A to B) by `gap > 0`, in f32:
    /// a gap too small for f32 is kept positive.
    pub(crate) fn separated(axis: DVec3, gap: f64) -> Collision {
        Collision::Separated { axis: axis.as_vec3(), distance: (gap as f32).max(f32::MIN_POSITIVE) }
    }

    /// Touching along `normal` (unit, world space, from A to B) by `depth`, with
    /// the manifold's points mapped to the world by `to_world`.
    pub(crate) fn touching(
        normal: DVec3,
        depth: f64,
        manifold: &Manifold,
        to_world: &DIsometry3,
    ) -> Collision {
        let mut points = [ContactPoint::default(); MAX_POINTS];
        for (out, &(p, d)) in points.iter_mut().zip(&manifold.points[..manifold.count]) {
            *out = ContactPoint { position: to_world.apply(p).as_vec3(), depth: d as f32 };
        }
        let contact =
            Contact::new(normal.as_vec3(), depth.max(0.0) as f32, &points[..manifold.count]);
        Collision::Touching(contact)
    }

    /// The same answer seen from B: the axis or the normal reversed, all
    /// else kept (the contact points are where they were).
    ///
    /// ```
    /// use bvol_narrow::Collision;
    /// use glam::Vec3;
    /// let apart = Collision::Separated { axis: Vec3::X, distance: 0.5 };
    /// assert_eq!(apart.flipped(), Collision::Separated { axis: -Vec3::X, distance: 0.5 });
    /// assert_eq!(apart.flipped().flipped(), apart);
    /// ```
    pub fn flipped(self) -> Collision {
        match self {
            Collision::Separated { axis, distance } => {
                Collision::Separated { axis: -axis, distance }
            }
            Collision::Touching(mut contact) => {
                contact.normal = -contact.normal;
                Collision::Touching(contact)
            }
        }
    }

    /// Whether the bodies overlap or touch.
    pub fn is_touching(&self) -> bool {
        matches!(self, Collision::Touching(_))
    }

    /// The contact, when they touch.
    pub fn contact(&self) -> Option<&Contact> {
        match self {
            Collision::Touching(c) => Some(c),
            Collision::Separated { .. } => None,
        }
    }
}
