//! Shared by the tests: bound generators, brute-force answers, a tiny PRNG.

#![allow(dead_code)] // each test file uses part of it

use bvol_tree::Bound;
use bvol_volumes::{Aabb, Ray, Sphere};
use glam::Vec3;
use proptest::prelude::*;

/// `f` run on a rayon pool of `threads` threads.
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

/// A bound type the tests run on, with the answers brute force gives.
pub trait TestBound: Bound {
    /// A bound from a corner/centre `p` and a size `s >= 0` per axis.
    fn make(p: Vec3, s: Vec3) -> Self;
    /// Whether two overlap or touch, computed independently of the tree.
    fn touch(&self, other: &Self) -> bool;
    /// The bound moved by `d`.
    fn shifted(&self, d: Vec3) -> Self;
}

impl TestBound for Aabb {
    fn make(p: Vec3, s: Vec3) -> Self {
        Aabb::new(p, p + s)
    }

    fn shifted(&self, d: Vec3) -> Self {
        Aabb::new(self.min + d, self.max + d)
    }

    /// The closed-box test of SCENE_FORMAT.md, written out.
    fn touch(&self, o: &Self) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
            && self.min.z <= o.max.z
            && o.min.z <= self.max.z
    }
}

impl TestBound for Sphere {
    fn make(p: Vec3, s: Vec3) -> Self {
        Sphere::new(p, s.x)
    }

    fn shifted(&self, d: Vec3) -> Self {
        Sphere::new(self.center + d, self.radius)
    }

    /// Squared distance against squared radius sum, in f64.
    fn touch(&self, o: &Self) -> bool {
        let d = (self.center.as_dvec3() - o.center.as_dvec3()).length_squared();
        let r = self.radius as f64 + o.radius as f64;
        d <= r * r
    }
}

/// Bounds on a small integer grid, so that touching and identical bounds are
/// common; sizes 0 (points) included.
pub fn grid_bound<B: TestBound>() -> impl Strategy<Value = B> {
    (0i32..12, 0i32..12, 0i32..12, 0i32..5, 0i32..5, 0i32..5).prop_map(|(x, y, z, a, b, c)| {
        B::make(Vec3::new(x as f32, y as f32, z as f32), Vec3::new(a as f32, b as f32, c as f32))
    })
}

/// Bounds with fractional coordinates over a wider range.
pub fn float_bound<B: TestBound>() -> impl Strategy<Value = B> {
    (prop::array::uniform3(-50.0f32..50.0), prop::array::uniform3(0.0f32..6.0))
        .prop_map(|(p, s)| B::make(Vec3::from(p), Vec3::from(s)))
}

/// Either kind.
pub fn any_bound<B: TestBound>() -> impl Strategy<Value = B> {
    prop_oneof![3 => grid_bound::<B>(), 1 => float_bound::<B>()]
}

/// Every pair `(a, b)`, `a < b` by id, of overlapping bounds, sorted.
pub fn brute_pairs<B: TestBound>(leaves: &[(u32, B)]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, (a, ba)) in leaves.iter().enumerate() {
        for (b, bb) in &leaves[i + 1..] {
            if ba.touch(bb) {
                out.push(((*a).min(*b), (*a).max(*b)));
            }
        }
    }
    out.sort_unstable();
    out
}

/// Every `(a, b)` with `a` from the first set and `b` from the second whose
/// bounds overlap, sorted.
pub fn brute_cross<B: TestBound>(first: &[(u32, B)], second: &[(u32, B)]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (a, ba) in first {
        for (b, bb) in second {
            if ba.touch(bb) {
                out.push((*a, *b));
            }
        }
    }
    out.sort_unstable();
    out
}

/// Every `(id, t)` of a bound the ray enters within `max_t`, sorted by id.
pub fn brute_ray<B: TestBound>(leaves: &[(u32, B)], ray: &Ray, max_t: f32) -> Vec<(u32, f32)> {
    let mut out: Vec<(u32, f32)> =
        leaves.iter().filter_map(|(id, b)| b.ray_entry(ray, max_t).map(|t| (*id, t))).collect();
    out.sort_unstable_by_key(|h| h.0);
    out
}

/// SplitMix64 (Steele et al. 2014): deterministic test data from a seed.
pub struct Mix(pub u64);

impl Mix {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// An integer in `0..n`.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    /// A float in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }
}
