//! Arithmetic written once for one body (`f32`) or for four at a time
//! (`Vec4`, a body a lane): the world bounds of a frame's moved bodies are
//! computed four at a time on SIMD lanes, and a lone body through the same
//! code gets the same result to the bit (every operation is one IEEE
//! operation per lane, in the same order).

use std::ops::{Add, Div, Mul, Sub};

use glam::{Mat3, Vec3, Vec4};

/// One value per body: `f32` for one body, `Vec4` for four.
pub(crate) trait Lane:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The same value in every lane.
    fn splat(x: f32) -> Self;
    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    /// The next float up, for values in `[+0, +inf]` (radii and half
    /// lengths grown to cover rounding): the bits' successor, `+inf` kept.
    fn next_up(self) -> Self;
}

impl Lane for f32 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        f32::from_bits(self.to_bits() + u32::from(self < f32::INFINITY))
    }
}

impl Lane for Vec4 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Vec4::splat(x)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Vec4::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Vec4::from_array(self.to_array().map(f32::sqrt))
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        Vec4::min(self, other)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        Vec4::max(self, other)
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        Vec4::from_array(self.to_array().map(Lane::next_up))
    }
}

/// A 3-vector of lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3<L> {
    pub(crate) x: L,
    pub(crate) y: L,
    pub(crate) z: L,
}

impl<L: Lane> V3<L> {
    #[inline(always)]
    pub(crate) fn splat(v: L) -> Self {
        V3 { x: v, y: v, z: v }
    }
    #[inline(always)]
    pub(crate) fn map(self, f: impl Fn(L) -> L) -> Self {
        V3 { x: f(self.x), y: f(self.y), z: f(self.z) }
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(L, L) -> L) -> Self {
        V3 { x: f(self.x, o.x), y: f(self.y, o.y), z: f(self.z, o.z) }
    }
    #[inline(always)]
    pub(crate) fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b)
    }
    #[inline(always)]
    pub(crate) fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b)
    }
    #[inline(always)]
    pub(crate) fn min(self, o: Self) -> Self {
        self.zip(o, L::min)
    }
    #[inline(always)]
    pub(crate) fn max(self, o: Self) -> Self {
        self.zip(o, L::max)
    }
    #[inline(always)]
    pub(crate) fn scale(self, s: L) -> Self {
        self.map(|a| a * s)
    }
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        self.map(L::abs)
    }
    /// `x + y + z`, in that order (as glam's `element_sum`).
    #[inline(always)]
    pub(crate) fn sum(self) -> L {
        self.x + self.y + self.z
    }
}

/// A 3x3 matrix of lanes, by columns.
#[derive(Clone, Copy, Debug)]
pub(crate) struct M3<L> {
    pub(crate) x_axis: V3<L>,
    pub(crate) y_axis: V3<L>,
    pub(crate) z_axis: V3<L>,
}

impl<L: Lane> M3<L> {
    /// `self * v`, summed as glam's `Mat3 * Vec3`.
    #[inline(always)]
    pub(crate) fn mul_vec(&self, v: V3<L>) -> V3<L> {
        self.x_axis.scale(v.x).add(self.y_axis.scale(v.y)).add(self.z_axis.scale(v.z))
    }
    #[inline(always)]
    pub(crate) fn mul_mat(&self, m: &Self) -> Self {
        M3 {
            x_axis: self.mul_vec(m.x_axis),
            y_axis: self.mul_vec(m.y_axis),
            z_axis: self.mul_vec(m.z_axis),
        }
    }
}

impl From<Vec3> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        V3 { x: v.x, y: v.y, z: v.z }
    }
}

impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl From<Mat3> for M3<f32> {
    #[inline(always)]
    fn from(m: Mat3) -> Self {
        M3 { x_axis: m.x_axis.into(), y_axis: m.y_axis.into(), z_axis: m.z_axis.into() }
    }
}

impl From<M3<f32>> for Mat3 {
    #[inline(always)]
    fn from(m: M3<f32>) -> Self {
        Mat3::from_cols(m.x_axis.into(), m.y_axis.into(), m.z_axis.into())
    }
}

impl V3<Vec4> {
    /// Lane `k`'s vector.
    #[inline(always)]
    pub(crate) fn lane(&self, k: usize) -> Vec3 {
        Vec3::new(self.x[k], self.y[k], self.z[k])
    }
}

impl M3<Vec4> {
    /// Lane `k`'s matrix.
    #[inline(always)]
    pub(crate) fn lane(&self, k: usize) -> Mat3 {
        Mat3::from_cols(self.x_axis.lane(k), self.y_axis.lane(k), self.z_axis.lane(k))
    }
}
