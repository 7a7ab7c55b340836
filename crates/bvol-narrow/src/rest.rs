//! What a touching pair's warm start keeps of its last full test, to reuse
//! its feature while the pair barely moves: the bodies' rotations and the
//! offset between them then, and the greatest separation over all axes
//! (minus the least penetration depth) then.
//!
//! Every separation moves no further than the points it is measured from:
//! along any axis fixed in A, the separation of B beyond A changes by at
//! most how far any point of B moved in A's space, and the same with A and
//! B swapped. So the greatest separation now is at most the one then plus
//! that motion, which, while it stays below zero, proves the pair still
//! touches without searching a face or an edge; and the kept feature's
//! separation, measured now, is then within a known amount of the least
//! penetration. The persistent manifolds of Bullet and PhysX reuse a pair's
//! contact the same way, bounded by a tolerance on the motion.

use bvol_volumes::Pose;
use glam::{DQuat, DVec3};

use crate::Polyhedron;
use crate::rounding::{ROUNDING, STORED, offset, up};

/// A touching pair's record of its last full test (stored in f32, as
/// [`Apart`](crate::warm::Apart) is: 56 bytes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rest {
    /// A's and B's rotations then, as `[x, y, z, w]`.
    rotations: [[f32; 4]; 2],
    /// B's position less A's then, rounded to f32 (the bound allows for it).
    offset: [f32; 3],
    /// An upper bound of the greatest separation over all axes then
    /// (negative: minus the least penetration depth).
    least: f32,
    /// A's and B's shapes (their ids): the record holds for these alone.
    shapes: [u32; 2],
}

impl Rest {
    /// The record of a pair of shapes `a` and `b` found touching at these
    /// poses, with greatest separation `least` over all axes.
    pub(crate) fn measured(
        least: f64,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
    ) -> Rest {
        let offset = offset(pose_a, pose_b);
        Rest {
            rotations: [pose_a.rotation.to_array(), pose_b.rotation.to_array()],
            offset: offset.as_vec3().to_array(),
            least: up(least + ROUNDING * (least.abs() + a.reach + b.reach)),
            shapes: [a.id, b.id],
        }
    }

    /// An upper bound of how far any point of either shape has moved in the
    /// other's space since the record, at these (finite) poses; `None` for
    /// other shapes than recorded.
    ///
    /// B's points seen from A are `Q y + t` with `Q = A^-1 B` and `t =
    /// A^-1 (p_B - p_A)`; they moved by at most `|t - t_then| + |Q -
    /// Q_then| |y|`, and `|Q - Q_then|` is `2 sin(theta / 2)` for the angle
    /// of `Q Q_then^-1`: twice the length of its vector part, `|y|` at
    /// most B's reach. A's points seen from B likewise, with A's reach (the
    /// turn is the same angle).
    pub(crate) fn motion(
        &self,
        (a, pose_a): (&Polyhedron, &Pose),
        (b, pose_b): (&Polyhedron, &Pose),
    ) -> Option<f64> {
        if self.shapes != [a.id, b.id] {
            return None;
        }
        let unit = |q: DQuat| q * (1.0 / q.length());
        let (qa, qb) = (unit(pose_a.rotation.as_dquat()), unit(pose_b.rotation.as_dquat()));
        let [then_a, then_b] = self.rotations.map(|r| unit(glam::Quat::from_array(r).as_dquat()));
        let turn = (qa.conjugate() * qb) * (then_a.conjugate() * then_b).conjugate();
        let turned = 2.0 * DVec3::new(turn.x, turn.y, turn.z).length();
        let (now, then) = (offset(pose_a, pose_b), glam::Vec3::from_array(self.offset).as_dvec3());
        let seen_from_a = (qa.conjugate() * now - then_a.conjugate() * then).length();
        let seen_from_b = (qb.conjugate() * now - then_b.conjugate() * then).length();
        let moved = (seen_from_a + turned * b.reach).max(seen_from_b + turned * a.reach);
        // The offset then was rounded to f32; the sums here are off by a few
        // units in the last place of the largest term.
        let rounding = STORED * then.abs().element_sum()
            + ROUNDING * (now.abs().element_sum() + then.abs().element_sum() + a.reach + b.reach);
        Some(moved + rounding)
    }

    /// An upper bound of the greatest separation over all axes then.
    pub(crate) fn least(&self) -> f64 {
        f64::from(self.least)
    }
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};

    use super::*;

    /// The motion bound holds for the shapes recorded and their clones
    /// alone; nothing moved, it is the allowance for rounding the offset
    /// kept to f32 alone (`2^-23` of its coordinates' sum); a turn of B about its
    /// own origin moves its farthest vertex by `2 sin(theta / 2)` times its
    /// reach, and, seen from B, A's origin by that times their distance: the
    /// bound is A's farthest point, to rounding.
    #[test]
    fn motion_is_bounded_for_the_shapes_recorded() {
        let cube = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
        let other = Polyhedron::cuboid(Vec3::splat(0.5)).expect("a box");
        let (pa, pb) = (Pose::IDENTITY, Pose::new(Vec3::new(0.0, 0.9, 0.0), Quat::IDENTITY));
        let rest = Rest::measured(-0.1, (&cube, &pa), (&cube, &pb));
        assert!(rest.least() >= -0.1 && rest.least() < -0.1 + 1e-6);
        let still = rest.motion((&cube, &pa), (&cube.clone(), &pb)).expect("the same shapes");
        let rounding = 0.9 / f64::from(1u32 << 23);
        assert!(still >= rounding && still < rounding * (1.0 + 1e-6), "{still}");
        assert_eq!(rest.motion((&other, &pa), (&cube, &pb)), None);
        let angle = 1e-3f32;
        let turned = Pose::new(pb.position, Quat::from_rotation_z(angle));
        let moved = rest.motion((&cube, &pa), (&cube, &turned)).expect("the same shapes");
        let want = 2.0 * (f64::from(angle) / 2.0).sin() * (0.9 + cube.reach);
        assert!(moved >= want && moved < want * (1.0 + 1e-6) + rounding * 1.01, "{moved} {want}");
    }
}
