//! The order-free digest of a pair set (../shared/SCENE_FORMAT.md, "Digest of
//! a pair set"), so that two broadphases can be compared without storing pairs.

use std::fmt;
use std::ops::AddAssign;

/// Count and two hash sums of a set of pairs `(a, b)`, `a < b`. Adding is
/// wrapping, so digests of frames add up to the digest of a trace, in any order.
///
/// ```
/// use bvol_cli::digest::PairDigest;
/// let one = PairDigest::of_pairs([(1, 2), (0, 7)]);
/// let other = PairDigest::of_pairs([(0, 7), (1, 2)]);
/// assert_eq!(one, other);
/// assert_eq!(one.count, 2);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PairDigest {
    /// How many pairs.
    pub count: u64,
    /// Wrapping sum of `mix64(key ^ 0x243F6A8885A308D3)`.
    pub h1: u64,
    /// Wrapping sum of `mix64(rotate_left(key, 17) ^ 0x13198A2E03707344)`.
    pub h2: u64,
}

/// SplitMix64's finaliser (Steele, Lea & Flood 2014), as the format specifies.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl PairDigest {
    /// Adds one pair; `a` and `b` may come in either order.
    #[inline]
    pub fn add_pair(&mut self, a: u32, b: u32) {
        let key = (a.min(b) as u64) << 32 | a.max(b) as u64;
        self.count = self.count.wrapping_add(1);
        self.h1 = self.h1.wrapping_add(mix64(key ^ 0x243F_6A88_85A3_08D3));
        self.h2 = self.h2.wrapping_add(mix64(key.rotate_left(17) ^ 0x1319_8A2E_0370_7344));
    }

    /// The digest of a set of pairs.
    pub fn of_pairs(pairs: impl IntoIterator<Item = (u32, u32)>) -> PairDigest {
        let mut d = PairDigest::default();
        for (a, b) in pairs {
            d.add_pair(a, b);
        }
        d
    }
}

impl AddAssign for PairDigest {
    fn add_assign(&mut self, o: PairDigest) {
        self.count = self.count.wrapping_add(o.count);
        self.h1 = self.h1.wrapping_add(o.h1);
        self.h2 = self.h2.wrapping_add(o.h2);
    }
}

impl fmt::Display for PairDigest {
    /// `count h1 h2`, tab-separated, the hashes as 16 lower-case hex digits.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}\t{:016x}\t{:016x}", self.count, self.h1, self.h2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64's first outputs from seed 0 are published (Vigna's reference
    /// splitmix64.c): the state advances by the golden gamma, then mix64.
    #[test]
    fn mix64_is_splitmix64() {
        let gamma = 0x9E37_79B9_7F4A_7C15u64;
        assert_eq!(mix64(gamma), 0xE220_A839_7B1D_CDAF);
        assert_eq!(mix64(gamma.wrapping_mul(2)), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn digest_is_a_sum_over_pairs() {
        let mut d = PairDigest::of_pairs([(3, 9)]);
        d += PairDigest::of_pairs([(1, 2), (4, 5)]);
        assert_eq!(d, PairDigest::of_pairs([(4, 5), (9, 3), (2, 1)]));
        assert_ne!(d, PairDigest::of_pairs([(4, 5), (3, 9), (2, 3)]));
        assert_eq!(d.count, 3);
    }
}
