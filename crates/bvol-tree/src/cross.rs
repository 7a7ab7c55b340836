//! The four pairings of two internal nodes' children, `2 i + j` for child
//! `i` of the first against child `j` of the second, worked out at once for
//! a step of the pair search: which pairings are of two leaves, the pair of
//! references each would report, and the visit each would lead to. Each
//! pair and visit is one 64-bit word (two 32-bit halves, the first node's
//! low), stored in one go.

use crate::Bound;
use crate::node::Node;

/// The four pairings of two nodes' children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Cross {
    /// Bit `2 i + j` set when both children are leaves.
    pub(crate) leaves: u32,
    /// The two children's references, pairing `2 i + j` at index `2 i + j`.
    pub(crate) refs: [u64; 4],
    /// The two children's visit sides, the same way.
    pub(crate) visits: [u64; 4],
}

/// Bits `i` (of one node's children) spread over the four outcomes of a
/// visit, `2 i + j`: the same on both of `j`'s.
#[inline(always)]
pub(crate) fn spread_first(bits: u32) -> u32 {
    ((bits & 1) * 0b0011) | ((bits >> 1) * 0b1100)
}

/// Bits `j` (of the other node's children) spread over the four outcomes,
/// `2 i + j`: the same on both of `i`'s.
#[inline(always)]
pub(crate) fn spread_second(bits: u32) -> u32 {
    bits * 0b0101
}

/// On SSE2 lanes: each node's references and visit sides are 16 bytes side
/// by side, one load; two shuffles a node repeat its children as the four
/// pairings need them (`[0, 0, 1, 1]` and `[0, 1, 0, 1]`), one mask of the
/// references' sign bits (a leaf's flag) names the pairings of two leaves,
/// and interleaving the two nodes' lanes makes the words.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn cross<B: Bound>(a: &Node<B>, b: &Node<B>) -> Cross {
    use std::arch::x86_64::{
        __m128i, _mm_and_si128, _mm_castsi128_ps, _mm_cvtsi128_si64, _mm_movemask_ps,
        _mm_set_epi32, _mm_shuffle_epi32, _mm_unpackhi_epi32, _mm_unpackhi_epi64,
        _mm_unpacklo_epi32,
    };
    let ([c0, c1], [v0, v1]) = (a.child, a.visit());
    let ([d0, d1], [w0, w1]) = (b.child, b.visit());
    // SAFETY: SSE2 is part of every x86_64 target, and these intrinsics
    // only compute on values: no pointer is read or written.
    unsafe {
        let la = _mm_set_epi32(v1 as i32, v0 as i32, c1.0 as i32, c0.0 as i32);
        let lb = _mm_set_epi32(w1 as i32, w0 as i32, d1.0 as i32, d0.0 as i32);
        // Child i of `a` on lanes 2 i and 2 i + 1; child j of `b` on lanes j and j + 2.
        let (ca, cb) = (_mm_shuffle_epi32::<0x50>(la), _mm_shuffle_epi32::<0x44>(lb));
        let (va, vb) = (_mm_shuffle_epi32::<0xFA>(la), _mm_shuffle_epi32::<0xEE>(lb));
        let leaves = _mm_movemask_ps(_mm_castsi128_ps(_mm_and_si128(ca, cb))) as u32;
        let word = |v: __m128i| _mm_cvtsi128_si64(v) as u64;
        let words = |x: __m128i, y: __m128i| {
            let (low, high) = (_mm_unpacklo_epi32(x, y), _mm_unpackhi_epi32(x, y));
            let (low1, high1) = (_mm_unpackhi_epi64(low, low), _mm_unpackhi_epi64(high, high));
            [word(low), word(low1), word(high), word(high1)]
        };
        Cross { leaves, refs: words(ca, cb), visits: words(va, vb) }
    }
}

/// The same in 64-bit words, on other targets.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
pub(crate) fn cross<B: Bound>(a: &Node<B>, b: &Node<B>) -> Cross {
    cross_words(a, b)
}

/// [`cross`] in 64-bit words, on any target.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline(always)]
fn cross_words<B: Bound>(a: &Node<B>, b: &Node<B>) -> Cross {
    let words = |[first, second]: [u32; 2]| u64::from(first) | u64::from(second) << 32;
    let crossed = |x: u64, y: u64| {
        let (x0, x1) = (x & u64::from(u32::MAX), x >> 32);
        let (y0, y1) = (y << 32, y & !u64::from(u32::MAX));
        [x0 | y0, x0 | y1, x1 | y0, x1 | y1]
    };
    let flags = |n: &Node<B>| (n.child[0].0 >> 31) | ((n.child[1].0 >> 31) << 1);
    let (fa, fb) = (flags(a), flags(b));
    let leaves = spread_first(fa) & spread_second(fb);
    Cross {
        leaves,
        refs: crossed(words(a.child.map(|c| c.0)), words(b.child.map(|c| c.0))),
        visits: crossed(words(a.visit()), words(b.visit())),
    }
}

#[cfg(test)]
mod tests {
    use bvol_volumes::Aabb;
    use proptest::prelude::*;

    use super::*;
    use crate::node::{BOTH, ID_LIMIT, Ref};

    /// A node at `at` whose children are leaves or internal nodes as
    /// `leaf` says, with the given indices.
    fn node(at: u32, leaf: [bool; 2], index: [u32; 2]) -> Node<Aabb> {
        let child = [0, 1].map(|i| if leaf[i] { Ref::leaf(index[i]) } else { Ref::node(index[i]) });
        Node::new([Aabb::default(); 2], child, at)
    }

    proptest! {
        /// The lanes' pairings are those worked out child by child: the
        /// leaves' mask, each pairing's references, each one's visit.
        #[test]
        fn pairings_are_those_of_the_children(
            at in (0..ID_LIMIT, 0..ID_LIMIT),
            leaf in any::<[[bool; 2]; 2]>(),
            index in any::<[[u32; 2]; 2]>(),
        ) {
            let index = index.map(|pair| pair.map(|i| i % ID_LIMIT));
            let (a, b) = (node(at.0, leaf[0], index[0]), node(at.1, leaf[1], index[1]));
            let got = cross(&a, &b);
            prop_assert_eq!(got, cross_words(&a, &b));
            for k in 0..4 {
                let (i, j) = (k >> 1, k & 1);
                prop_assert_eq!(got.leaves >> k & 1 != 0, leaf[0][i] && leaf[1][j]);
                prop_assert_eq!(got.refs[k], u64::from(a.child[i].0) | u64::from(b.child[j].0) << 32);
                let side = |n: &Node<Aabb>, at: u32, i: usize| match n.child[i].is_node() {
                    true => n.child[i].index() | BOTH,
                    false => at | 1 << (30 + i),
                };
                let visit = u64::from(side(&a, at.0, i)) | u64::from(side(&b, at.1, j)) << 32;
                prop_assert_eq!(got.visits[k], visit);
            }
        }
    }
}
