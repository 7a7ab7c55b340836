//! New inputs from old: byte-level mutations in the manner of libFuzzer's
//! and AFL's (bit flips, edge values, insertions, deletions, copies, splices
//! of another input, tokens of the format), several stacked, from a seeded
//! generator so that a run is repeatable.

use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// Bytes and 32-bit words that sit on the edges of what readers check:
/// zero, one, sign bits, all ones, and the f32 edges (infinity, NaN, the
/// largest finite, the smallest normal, 1e18, 1e-44).
const EDGE_BYTES: &[u8] = &[0, 1, 0x7f, 0x80, 0xff, b'0', b'9', b'-', b'.', b'e', b' ', b'\n'];
const EDGE_WORDS: &[u32] = &[
    0,
    1,
    2,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x7f80_0000,
    0xff80_0000,
    0x7fc0_0000,
    0x7f7f_ffff,
    0x0080_0000,
    0x5d5e_0b6b,
    0x0000_001f,
    0x3f80_0000,
];

/// A seeded source of mutants.
pub struct Mutator {
    rng: SmallRng,
}

impl Mutator {
    /// A mutator whose mutants depend only on `seed` and the calls made.
    pub fn new(seed: u64) -> Mutator {
        Mutator { rng: SmallRng::seed_from_u64(seed) }
    }

    /// A number below `n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        self.rng.random_range(0..n)
    }

    /// `base` changed by one to eight mutations, at most `max_len` bytes;
    /// `other` is spliced from and `dictionary` tokens inserted.
    pub fn mutate(
        &mut self,
        base: &[u8],
        other: &[u8],
        dictionary: &[&[u8]],
        max_len: usize,
    ) -> Vec<u8> {
        let mut data = base.to_vec();
        let count = 1 + self.rng.random_range(0..8u32).trailing_zeros().min(3) as usize * 2;
        for _ in 0..count {
            self.once(&mut data, other, dictionary);
        }
        data.truncate(max_len);
        data
    }

    fn once(&mut self, data: &mut Vec<u8>, other: &[u8], dictionary: &[&[u8]]) {
        let len = data.len();
        let at = |rng: &mut SmallRng| rng.random_range(0..=len);
        match self.rng.random_range(0..11u8) {
            0 if len > 0 => {
                let i = self.below(len);
                data[i] ^= 1 << self.rng.random_range(0..8);
            }
            1 if len > 0 => {
                let i = self.below(len);
                data[i] = self.rng.random();
            }
            2 if len > 0 => {
                let i = self.below(len);
                data[i] = EDGE_BYTES[self.below(EDGE_BYTES.len())];
            }
            3 if len >= 4 => {
                let i = self.below(len - 3);
                let word = EDGE_WORDS[self.below(EDGE_WORDS.len())];
                data[i..i + 4].copy_from_slice(&word.to_le_bytes());
            }
            4 => {
                let i = at(&mut self.rng);
                let n = self.rng.random_range(1..=8);
                let bytes: Vec<u8> = (0..n).map(|_| self.rng.random()).collect();
                data.splice(i..i, bytes);
            }
            5 if len > 0 => {
                let i = self.below(len);
                let n = self.rng.random_range(1..=(len - i).min(1 + len / 4));
                data.drain(i..i + n);
            }
            6 if len > 0 => {
                let (i, to) = (self.below(len), at(&mut self.rng));
                let n = self.rng.random_range(1..=(len - i).min(64));
                let chunk = data[i..i + n].to_vec();
                data.splice(to..to, chunk);
            }
            7 if !other.is_empty() => {
                let i = self.below(other.len());
                let n = self.rng.random_range(1..=(other.len() - i).min(256));
                let to = at(&mut self.rng);
                data.splice(to..to, other[i..i + n].iter().copied());
            }
            8 | 9 if !dictionary.is_empty() => {
                let token = dictionary[self.below(dictionary.len())];
                let i = at(&mut self.rng);
                let end = if self.rng.random() { i } else { (i + token.len()).min(len) };
                data.splice(i..end, token.iter().copied());
            }
            10 if len > 0 => data.truncate(self.below(len)),
            _ => {
                let i = at(&mut self.rng);
                data.insert(i, self.rng.random());
            }
        }
    }
}
