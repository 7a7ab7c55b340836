//! The exact sign of the 3-D orientation determinant, after Shewchuk, "Adaptive
//! Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates"
//! (1997): a floating-point filter with his error bound, and where it cannot
//! decide, the determinant summed exactly as a floating-point expansion.
//!
//! Quickhull's topology (which faces a new point sees) rests on this sign: an
//! exact answer keeps the visible region a disk with one horizon loop, so the
//! triangulation stays a closed 2-manifold whatever the input.

use glam::DVec3;

/// Shewchuk's epsilon: half an ulp of 1, the relative rounding error.
const EPS: f64 = f64::EPSILON / 2.0;
/// Bound on the relative error of the filtered determinant (Shewchuk's `o3derrboundA`).
const ERR_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
/// 2^27 + 1: splits a double into two halves of 26 bits for Dekker's product.
const SPLITTER: f64 = 134_217_729.0;
/// Terms of the exact determinant: 6 products of 3 two-part differences, each
/// product exact in 4 doubles.
const MAX_TERMS: usize = 6 * 8 * 4;

/// `det[b - a, c - a, d - a]`, exact in sign: positive when `d` lies on the side of
/// plane `abc` that `(b - a) x (c - a)` points to, zero when the four are coplanar.
///
/// The coordinates must be finite and of f32 range (as hull input is), so that no
/// product of three differences overflows or underflows.
pub(super) fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    // Shewchuk's orient3d evaluates det[a - d, b - d, c - d], the opposite sign.
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let (bdxcdy, cdxbdy) = (bd.x * cd.y, cd.x * bd.y);
    let (cdxady, adxcdy) = (cd.x * ad.y, ad.x * cd.y);
    let (adxbdy, bdxady) = (ad.x * bd.y, bd.x * ad.y);
    let det = ad.z * (bdxcdy - cdxbdy) + bd.z * (cdxady - adxcdy) + cd.z * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * ad.z.abs()
        + (cdxady.abs() + adxcdy.abs()) * bd.z.abs()
        + (adxbdy.abs() + bdxady.abs()) * cd.z.abs();
    if det.abs() > ERR_BOUND * permanent {
        return -det;
    }
    -exact_det(a, b, c, d)
}

/// `(b - a) x (c - a)`, each component rounded from its exact value (the
/// differences and products kept exactly, as expansions). Its direction is right
/// to a few ulps however thin the triangle, where the plainly rounded cross
/// product of a sliver tilts by about the rounding times its length over its
/// height, and points far along it would then seem in front of its plane.
pub(super) fn cross_exact(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (u, v) = (diff(b, a), diff(c, a));
    // u[i] v[j] - u[j] v[i], summed exactly.
    let component = |i: usize, j: usize| {
        let mut sum = Expansion::default();
        for (s, (p, q)) in [(1.0, (u[i], v[j])), (-1.0, (u[j], v[i]))] {
            for x in p {
                for y in q {
                    let (product, error) = two_product(s * x, y);
                    sum.add(error);
                    sum.add(product);
                }
            }
        }
        sum.estimate()
    };
    DVec3::new(component(1, 2), component(2, 0), component(0, 1))
}

/// `det[a - d, b - d, c - d]` rounded from its exact value, which is kept as a
/// non-overlapping expansion; only its sign (that of its largest part) is exact.
fn exact_det(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    // Each difference is exact as a two-part sum; the determinant is then a sum of
    // products of parts, each product exact in four doubles.
    let rows = [diff(a, d), diff(b, d), diff(c, d)];
    const TERMS: [(f64, [usize; 3]); 6] = [
        (1.0, [0, 1, 2]),
        (-1.0, [0, 2, 1]),
        (-1.0, [1, 0, 2]),
        (1.0, [1, 2, 0]),
        (1.0, [2, 0, 1]),
        (-1.0, [2, 1, 0]),
    ];
    let mut sum = Expansion::default();
    for (sign, [i, j, k]) in TERMS {
        for x in rows[0][i] {
            for y in rows[1][j] {
                for z in rows[2][k] {
                    if x != 0.0 && y != 0.0 && z != 0.0 {
                        let (p, e) = two_product(sign * x, y);
                        let (p1, e1) = two_product(p, z);
                        let (p2, e2) = two_product(e, z);
                        for part in [e2, p2, e1, p1] {
                            sum.add(part);
                        }
                    }
                }
            }
        }
    }
    sum.most_significant()
}

/// The exact difference `p - q` per coordinate, as (rounded, roundoff) pairs.
fn diff(p: DVec3, q: DVec3) -> [[f64; 2]; 3] {
    [two_diff(p.x, q.x), two_diff(p.y, q.y), two_diff(p.z, q.z)]
}

/// A sum of doubles held exactly: non-overlapping parts of increasing magnitude,
/// zeros left out (Shewchuk's `grow_expansion_zeroelim`).
struct Expansion {
    parts: [f64; MAX_TERMS],
    len: usize,
}

impl Default for Expansion {
    fn default() -> Self {
        Expansion { parts: [0.0; MAX_TERMS], len: 0 }
    }
}

impl Expansion {
    /// Adds `b` exactly. At most one part is added per call, so `MAX_TERMS` calls fit.
    fn add(&mut self, b: f64) {
        let mut q = b;
        let mut out = 0;
        for i in 0..self.len {
            let (sum, err) = two_sum(q, self.parts[i]);
            q = sum;
            if err != 0.0 {
                self.parts[out] = err;
                out += 1;
            }
        }
        if q != 0.0 && out < MAX_TERMS {
            self.parts[out] = q;
            out += 1;
        }
        self.len = out;
    }

    /// The largest part: it carries the sign of the whole sum (0 for an empty sum).
    fn most_significant(&self) -> f64 {
        if self.len == 0 { 0.0 } else { self.parts[self.len - 1] }
    }

    /// The sum, rounded: the parts added smallest first (Shewchuk's `estimate`).
    fn estimate(&self) -> f64 {
        self.parts[..self.len].iter().sum()
    }
}

/// `a + b` as the rounded sum and its exact roundoff (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let b_virtual = x - a;
    let a_virtual = x - b_virtual;
    (x, (a - a_virtual) + (b - b_virtual))
}

/// `a - b` as the rounded difference and its exact roundoff.
#[inline]
fn two_diff(a: f64, b: f64) -> [f64; 2] {
    let (x, y) = two_sum(a, -b);
    [x, y]
}

/// Splits `a` into two non-overlapping 26-bit halves (Dekker).
#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = SPLITTER * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a * b` as the rounded product and its exact roundoff (Dekker's product,
/// portable where no fused multiply-add is compiled in).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    let (ahi, alo) = split(a);
    let (bhi, blo) = split(b);
    let err = ((x - ahi * bhi) - alo * bhi) - ahi * blo;
    (x, alo * blo - err)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn sign_follows_the_right_hand_rule() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!(orient3d(a, b, c, DVec3::Z) > 0.0);
        assert!(orient3d(a, b, c, -DVec3::Z) < 0.0);
        assert_eq!(orient3d(a, b, c, DVec3::new(3.0, -7.0, 0.0)), 0.0);
    }

    #[test]
    fn near_coplanar_points_get_the_exact_sign() {
        // Points on the plane x + y + z = 1, far from the origin along it, where
        // the filtered determinant is all roundoff; then nudged off by one ulp.
        let big = 1.0e7_f32;
        let on = |x: f32, y: f32| DVec3::new(x as f64, y as f64, 1.0 - x as f64 - y as f64);
        let (a, b, c) = (on(big, 0.5), on(0.25, big), on(-big, -big));
        let d = on(3.0, 5.0);
        assert_eq!(orient3d(a, b, c, d), 0.0);
        let up = DVec3::new(d.x, d.y, d.z.next_up());
        let down = DVec3::new(d.x, d.y, d.z.next_down());
        // The normal (b - a) x (c - a) of this winding points towards +z.
        let n = (b - a).cross(c - a);
        assert!(n.z > 0.0);
        assert!(orient3d(a, b, c, up) > 0.0);
        assert!(orient3d(a, b, c, down) < 0.0);
    }

    #[test]
    fn cross_product_of_a_sliver_is_right_to_the_ulp() {
        // f32 corners: a tiny, b large, c = b / 2, so a, b, c lie almost on a
        // line. The differences take 40 bits, their products more than 53, and
        // the plain cross product is mostly roundoff. The exact one is
        // (b - a) x (b / 2 - a) = (a x b) / 2, whose products of f32 are exact in
        // f64: right to the ulp.
        let f = |bits: [u32; 3]| Vec3::from_array(bits.map(f32::from_bits)).as_dvec3();
        let a = f([0x3530_8bd3, 0x3566_00f8, 0x351e_bc4c]);
        let b = f([0x492b_96f9, 0x495f_6326, 0x491a_8151]);
        let c = b * 0.5;
        let want = a.cross(b) * 0.5;
        let got = cross_exact(a, b, c);
        for (g, w) in got.to_array().into_iter().zip(want.to_array()) {
            assert!((g - w).abs() <= 2.0 * f64::EPSILON * w.abs(), "{got} vs {want}");
        }
        let plain = (b - a).cross(c - a);
        assert!((plain - want).length() > 1e3 * f64::EPSILON * want.length());
    }

    #[test]
    fn exact_products_recover_the_roundoff() {
        let (a, b) = (1.0 + f64::EPSILON, 1.0 - f64::EPSILON);
        let (x, y) = two_product(a, b);
        assert_eq!((x, y), (1.0, -f64::EPSILON * f64::EPSILON));
    }
}
