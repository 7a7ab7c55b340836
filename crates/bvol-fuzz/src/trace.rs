//! Box traces: parsed from any bytes, written back, and replayed through the
//! tree against brute force.

use bvol::tree::Tree;
use bvol::volumes::Aabb;
use bvol_cli::trace::BoxTrace;

use crate::checks::one_line_error;

/// The magic, the version, and counts at the edges of 32 bits.
pub const DICTIONARY: &[&[u8]] = &[
    b"BPHF",
    &[1, 0, 0, 0],
    &[2, 0, 0, 0],
    &[0, 0, 0, 0],
    &[0xff, 0xff, 0xff, 0xff],
    &[0, 0, 0, 0x80],
    &[0x00, 0xe1, 0xf5, 0x05],
    &[0x00, 0x00, 0x80, 0x7f],
    &[0x00, 0x00, 0xc0, 0x7f],
    &[0xff, 0xff, 0x7f, 0x7f],
];

/// Most boxes replayed against brute force (all pairs of each frame).
const REPLAYED: usize = 4096;

/// Parses `data` as a box trace, and again with its header's counts made
/// to fit its length (most mutants change the length, and would otherwise
/// never reach the boxes). An error is one line; an accepted trace writes
/// back to the same bytes and, replayed, the tree's pairs in every frame
/// are the brute-force ones.
pub fn run(data: &[u8]) {
    check(data);
    if let Some(fitted) = fitted(data) {
        check(&fitted);
    }
}

/// `data` with its counts set to fit its length: 1 to 3 frames (from the
/// frame count's low bits) of as many boxes as the bytes hold, cut to them.
fn fitted(data: &[u8]) -> Option<Vec<u8>> {
    let frames = 1 + *data.get(12)? as usize % 3;
    let n = (data.len().checked_sub(HEADER)? / BOX_BYTES / frames).max(1);
    let mut out = data.get(..HEADER + n * frames * BOX_BYTES)?.to_vec();
    out[8..12].copy_from_slice(&(n as u32).to_le_bytes());
    out[12..16].copy_from_slice(&(frames as u32).to_le_bytes());
    Some(out)
}

const HEADER: usize = 16;
const BOX_BYTES: usize = 24;

fn check(data: &[u8]) {
    let trace = match BoxTrace::from_bytes(data) {
        Ok(trace) => trace,
        Err(e) => return one_line_error(&e.to_string(), None),
    };
    let mut written = Vec::new();
    trace.write_to(&mut written).expect("an accepted trace writes");
    assert_eq!(written, data, "the trace does not write back to its bytes");
    if trace.n() * trace.frames() > REPLAYED || trace.frames() == 0 {
        return;
    }
    let mut tree = Tree::from_bounds(trace.frame(0)).expect("the tree takes an accepted frame");
    for f in 0..trace.frames() {
        if f > 0 {
            tree.update(trace.frame(f)).expect("the tree takes an accepted frame");
        }
        let mut pairs = Vec::new();
        tree.pairs_into(&mut pairs);
        let mut pairs: Vec<(u32, u32)> = pairs.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        pairs.sort_unstable();
        assert_eq!(pairs, brute_force(trace.frame(f)), "frame {f}: tree pairs differ");
    }
}

fn brute_force(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for (i, a) in boxes.iter().enumerate() {
        for (j, b) in boxes.iter().enumerate().skip(i + 1) {
            if a.overlaps(b) {
                pairs.push((i as u32, j as u32));
            }
        }
    }
    pairs
}
