//! A body's bounds placed at its pose each frame: its world sphere, world
//! OBB and the axis-aligned box of their overlap (a tree leaf), for one pose
//! or for four at once on SIMD lanes (a body a lane) with the same
//! arithmetic, so that both give the same bounds to the bit.

use glam::{Mat4, Vec3, Vec4};

use crate::lane::{Lane, M3, V3};
use crate::pose::rotation;
use crate::{Aabb, Obb, Pose, Sphere, obb, sphere};

/// A shape's bounding sphere and oriented box, in its own frame: what a
/// body's bounds are made from when it moves.
///
/// ```
/// use bvol_volumes::{BodyBounds, Obb, Pose, Sphere};
/// use glam::{Mat3, Quat, Vec3};
///
/// let cube = BodyBounds {
///     sphere: Sphere::new(Vec3::ZERO, 3f32.sqrt() / 2.0),
///     obb: Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::splat(0.5) },
/// };
/// let pose = Pose::new(Vec3::new(10.0, 0.0, 0.0), Quat::from_rotation_z(0.3));
/// let world = cube.at(&pose);
/// assert_eq!(world.sphere, cube.sphere.transformed(&pose));
/// assert_eq!(world.obb, cube.obb.transformed(&pose));
/// // The leaf box holds the world box's corners, and is no larger than the sphere's box.
/// assert!(world.aabb.contains_point(pose.transform_point(Vec3::splat(0.5))));
/// assert!(world.aabb.max.x <= 10.0 + 3f32.sqrt() / 2.0 + 1e-5);
///
/// // Four bodies at once: the same bounds, to the bit.
/// let poses = [pose, Pose::IDENTITY, pose.inverse(), Pose::new(Vec3::Y, Quat::IDENTITY)];
/// let four = BodyBounds::at4([&cube; 4], [&poses[0], &poses[1], &poses[2], &poses[3]]);
/// assert!((0..4).all(|k| four[k] == cube.at(&poses[k])));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyBounds {
    /// The bounding sphere.
    pub sphere: Sphere,
    /// The oriented bounding box.
    pub obb: Obb,
}

/// A body's bounds at a pose, each holding the exact image of the local one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorldBounds {
    /// [`Sphere::transformed`] of the local sphere.
    pub sphere: Sphere,
    /// [`Obb::transformed`] of the local box.
    pub obb: Obb,
    /// A box around the overlap of the two (each holds the body, so this
    /// box does): the overlap of their axis-aligned boxes, each padded for
    /// its rounding.
    pub aabb: Aabb,
}

impl WorldBounds {
    /// The bounds grown by `pad` (finite, `>= 0`) all round, rounded
    /// outward: each holds every point within `pad` of what it held. A
    /// world with a margin grows each body's bounds by half of it, so that
    /// bodies within the margin of each other have bounds that overlap.
    ///
    /// ```
    /// use bvol_volumes::{Aabb, Obb, Sphere, WorldBounds};
    /// use glam::{Mat3, Vec3};
    /// let tight = WorldBounds {
    ///     sphere: Sphere::new(Vec3::ZERO, 1.0),
    ///     obb: Obb { center: Vec3::ZERO, axes: Mat3::IDENTITY, half_extents: Vec3::ONE },
    ///     aabb: Aabb::new(Vec3::splat(-1.0), Vec3::ONE),
    /// };
    /// let grown = tight.grown(0.25);
    /// assert!(grown.sphere.radius >= 1.25 && grown.obb.half_extents.cmpge(Vec3::splat(1.25)).all());
    /// assert!(grown.aabb.contains(&Aabb::new(Vec3::splat(-1.25), Vec3::splat(1.25))));
    /// ```
    pub fn grown(self, pad: f32) -> WorldBounds {
        let up = |x: f32| (x + pad).next_up();
        let Obb { center, axes, half_extents } = self.obb;
        let h = Vec3::new(up(half_extents.x), up(half_extents.y), up(half_extents.z));
        let (min, max) = (self.aabb.min, self.aabb.max);
        WorldBounds {
            sphere: Sphere { center: self.sphere.center, radius: up(self.sphere.radius) },
            obb: Obb { center, axes, half_extents: h },
            aabb: Aabb::new(
                Vec3::new(
                    (min.x - pad).next_down(),
                    (min.y - pad).next_down(),
                    (min.z - pad).next_down(),
                ),
                Vec3::new(up(max.x), up(max.y), up(max.z)),
            ),
        }
    }
}

impl BodyBounds {
    /// The bounds at `pose` (a few dozen operations).
    #[inline(always)]
    pub fn at(&self, pose: &Pose) -> WorldBounds {
        let (r, position) = pose.lane();
        let (sphere, local) = self.lanes(|x| x);
        let placed = place(&r, position, sphere, local);
        let ((center, radius), (c, axes, h), (min, max)) = placed;
        WorldBounds {
            sphere: Sphere { center: center.into(), radius },
            obb: Obb { center: c.into(), axes: axes.into(), half_extents: h.into() },
            aabb: Aabb::new(min.into(), max.into()),
        }
    }

    /// The bounds of four bodies at their poses, on SIMD lanes: each the
    /// same as [`at`](Self::at) gives, one body a lane, so that the work of
    /// four calls shares its instructions.
    #[inline(always)]
    pub fn at4(bounds: [&BodyBounds; 4], poses: [&Pose; 4]) -> [WorldBounds; 4] {
        let [qx, qy, qz, qw] = transpose(poses.map(|p| Vec4::from(p.rotation)));
        let [px, py, pz, _] = transpose(poses.map(|p| p.position.extend(0.0)));
        let v = |x, y, z| V3 { x, y, z };
        let r = rotation([qx, qy, qz, qw]);
        let (sphere, local) = if bounds.iter().all(|b| std::ptr::eq(*b, bounds[0])) {
            bounds[0].lanes(Vec4::splat)
        } else {
            let packed = bounds.map(BodyBounds::packed);
            let column =
                |i: usize| transpose([packed[0][i], packed[1][i], packed[2][i], packed[3][i]]);
            let [sx, sy, sz, radius] = column(0);
            let [cx, cy, cz, hx] = column(1);
            let [ax, ay, az, hy] = column(2);
            let [bx, by, bz, hz] = column(3);
            let [dx, dy, dz, _] = column(4);
            let axes = M3 { x_axis: v(ax, ay, az), y_axis: v(bx, by, bz), z_axis: v(dx, dy, dz) };
            ((v(sx, sy, sz), radius), (v(cx, cy, cz), axes, v(hx, hy, hz)))
        };
        let placed = place(&r, v(px, py, pz), sphere, local);
        let ((center, radius), (c, axes, h), (min, max)) = placed;
        std::array::from_fn(|k| WorldBounds {
            sphere: Sphere { center: center.lane(k), radius: radius[k] },
            obb: Obb { center: c.lane(k), axes: axes.lane(k), half_extents: h.lane(k) },
            aabb: Aabb::new(min.lane(k), max.lane(k)),
        })
    }

    /// The sphere `(centre, radius)` and box `(centre, axes, half lengths)`,
    /// each number put on lanes by `lane`.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn lanes<L: Lane>(&self, lane: impl Fn(f32) -> L) -> ((V3<L>, L), (V3<L>, M3<L>, V3<L>)) {
        let v = |p: Vec3| V3 { x: lane(p.x), y: lane(p.y), z: lane(p.z) };
        let (s, o) = (&self.sphere, &self.obb);
        let axes =
            M3 { x_axis: v(o.axes.x_axis), y_axis: v(o.axes.y_axis), z_axis: v(o.axes.z_axis) };
        ((v(s.center), lane(s.radius)), (v(o.center), axes, v(o.half_extents)))
    }

    /// The 19 numbers in five lanes' worth: sphere centre and radius, box
    /// centre and each axis, each with a half length.
    #[inline(always)]
    fn packed(&self) -> [Vec4; 5] {
        let (s, o) = (&self.sphere, &self.obb);
        let h = o.half_extents;
        [
            s.center.extend(s.radius),
            o.center.extend(h.x),
            o.axes.x_axis.extend(h.y),
            o.axes.y_axis.extend(h.z),
            o.axes.z_axis.extend(0.0),
        ]
    }
}

/// Four vectors' `x`s, `y`s, `z`s and `w`s.
#[inline(always)]
fn transpose(v: [Vec4; 4]) -> [Vec4; 4] {
    Mat4::from_cols(v[0], v[1], v[2], v[3]).transpose().to_cols_array_2d().map(Vec4::from_array)
}

/// Sphere `(centre, radius)` and box `(centre, axes, half lengths)` placed by
/// rotation `r` and translation `position`, and the box `(min, max)` of
/// their overlap.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn place<L: Lane>(
    r: &M3<L>,
    position: V3<L>,
    (center, radius): (V3<L>, L),
    local: (V3<L>, M3<L>, V3<L>),
) -> ((V3<L>, L), (V3<L>, M3<L>, V3<L>), (V3<L>, V3<L>)) {
    let ball = sphere::place(r, position, center, radius);
    let boxed = obb::place(r, position, local);
    (ball, boxed, overlap_box(ball, boxed))
}

/// The box of the overlap of a sphere and an oriented box (both placed in
/// f32): the box's own axis-aligned box, taken in f32 with a pad of 64
/// epsilons of the magnitudes (rounding, and the axes' departure from
/// orthonormal) rather than from its exact corners, cut by the sphere's box
/// padded by its rounding. Exact corners would cost more each frame than a
/// box a few ulps larger costs the tree.
#[inline(always)]
fn overlap_box<L: Lane>(
    (center, radius): (V3<L>, L),
    (c, a, h): (V3<L>, M3<L>, V3<L>),
) -> (V3<L>, V3<L>) {
    let eps = L::splat(f32::EPSILON);
    let extent =
        a.x_axis.abs().scale(h.x).add(a.y_axis.abs().scale(h.y)).add(a.z_axis.abs().scale(h.z));
    let pad = extent.add(c.abs()).add(V3::splat(h.sum())).scale(L::splat(64.0 * f32::EPSILON));
    let (lo, hi) = (c.sub(extent).sub(pad), c.add(extent).add(pad));
    let r = V3::splat(radius * L::splat(1.0 + 2.0 * f32::EPSILON));
    let (sl, sh) = (center.sub(r), center.add(r));
    (lo.max(sl.sub(sl.abs().scale(eps))), hi.min(sh.add(sh.abs().scale(eps))))
}
