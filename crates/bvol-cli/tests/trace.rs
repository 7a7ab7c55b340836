//! Box traces: round trip through the file layout, every malformed file named,
//! and the generated scenes' properties.

use bvol::volumes::Aabb;
use bvol_cli::digest::PairDigest;
use bvol_cli::scenes::{Scene, SceneKind};
use bvol_cli::trace::{BoxTrace, TraceError, TraceWriter};
use glam::Vec3;

fn sample_trace(n: usize, frames: usize) -> BoxTrace {
    let mut scene = Scene::new(SceneKind::Uniform, n, 1);
    let mut trace = BoxTrace::new(n);
    for _ in 0..frames {
        trace.push_frame(scene.step()).unwrap();
    }
    trace
}

fn bytes_of(trace: &BoxTrace) -> Vec<u8> {
    let mut bytes = Vec::new();
    trace.write_to(&mut bytes).unwrap();
    bytes
}

#[test]
fn round_trip_through_a_file() {
    let trace = sample_trace(50, 4);
    let path = std::env::temp_dir().join(format!("bvol-trace-{}.bphf", std::process::id()));
    trace.write(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes.len(), 16 + 24 * 50 * 4);
    assert_eq!(&bytes[..4], b"BPHF");
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 50);
    assert_eq!(BoxTrace::read(&path).unwrap(), trace);
    std::fs::remove_file(path).unwrap();
}

#[test]
fn malformed_files_say_what_is_wrong() {
    let good = bytes_of(&sample_trace(3, 2));
    let with = |edit: &dyn Fn(&mut Vec<u8>)| {
        let mut b = good.clone();
        edit(&mut b);
        BoxTrace::from_bytes(&b).unwrap_err()
    };
    assert!(matches!(with(&|b| b[0] = b'X'), TraceError::BadMagic));
    assert!(matches!(with(&|b| b.truncate(2)), TraceError::BadMagic));
    assert!(matches!(with(&|b| b[4] = 2), TraceError::UnknownVersion(2)));
    assert!(matches!(with(&|b| b.truncate(10)), TraceError::Truncated { .. }));
    assert!(matches!(
        with(&|b| {
            b.pop();
        }),
        TraceError::Truncated { expected: 160, actual: 159 }
    ));
    assert!(matches!(
        with(&|b| b.push(0)),
        TraceError::TrailingBytes { expected: 160, actual: 161 }
    ));
    // Frame 1, box 2: min.x above max.x, then a NaN.
    let at = 16 + 24 * (3 + 2);
    let e = with(&|b| b[at..at + 4].copy_from_slice(&1e9f32.to_le_bytes()));
    assert!(matches!(e, TraceError::MinAboveMax { frame: 1, index: 2 }), "{e}");
    assert_eq!(e.to_string(), "frame 1, box 2: min > max");
    let e = with(&|b| b[at + 8..at + 12].copy_from_slice(&f32::NAN.to_le_bytes()));
    assert!(matches!(e, TraceError::NonFinite { frame: 1, index: 2 }));
    assert!(matches!(BoxTrace::read("/no/such/trace").unwrap_err(), TraceError::Io(_)));
    // A header whose counts imply 2^64 * 3 bytes (24 * 2^31 * 2^30), which
    // 64-bit arithmetic wraps to the header's 16: still truncated.
    let e = with(&|b| {
        b.truncate(16);
        b[8..12].copy_from_slice(&(1u32 << 31).to_le_bytes());
        b[12..16].copy_from_slice(&(1u32 << 30).to_le_bytes());
    });
    assert!(matches!(e, TraceError::Truncated { expected: u64::MAX, actual: 16 }), "{e}");
    // Building a trace checks the same things.
    let mut t = BoxTrace::new(1);
    assert!(matches!(t.push_frame(&[]), Err(TraceError::WrongCount { expected: 1, actual: 0 })));
    let inverted = Aabb::new(Vec3::ONE, Vec3::ZERO);
    assert!(matches!(
        t.push_frame(&[inverted]),
        Err(TraceError::MinAboveMax { frame: 0, index: 0 })
    ));
    assert_eq!(t.frames(), 0);
    // Counts the format cannot hold: an error, and nothing written.
    let too_many = u32::MAX as usize + 1;
    let mut out = Vec::new();
    let e = TraceWriter::new(&mut out, too_many, 1).err().unwrap();
    assert!(matches!(e, TraceError::TooMany { boxes, frames: 1 } if boxes == too_many), "{e}");
    assert!(TraceWriter::new(&mut out, 1, too_many).is_err());
    assert!(out.is_empty());
}

/// The brute-force pair set of a frame (closed boxes: touching counts).
fn brute_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for a in 0..boxes.len() {
        for b in a + 1..boxes.len() {
            if boxes[a].overlaps(&boxes[b]) {
                out.push((a as u32, b as u32));
            }
        }
    }
    out
}

#[test]
fn scenes_are_deterministic_and_have_pairs() {
    for kind in SceneKind::ALL {
        let (mut a, mut b) = (Scene::new(kind, 2000, 3), Scene::new(kind, 2000, 3));
        let mut pairs = 0;
        for _ in 0..5 {
            let frame = a.step().to_vec();
            assert_eq!(frame, b.step());
            assert!(frame.iter().all(|x| x.min.is_finite() && x.max.cmpge(x.min).all()));
            pairs += brute_pairs(&frame).len();
        }
        assert!(pairs > 5 * 2000 / 10, "{kind}: only {pairs} pairs in 5 frames");
        assert_ne!(Scene::new(kind, 2000, 4).step(), Scene::new(kind, 2000, 3).step());
    }
}

#[test]
fn the_pile_comes_to_rest_on_the_floor() {
    let mut scene = Scene::new(SceneKind::Pile, 3000, 9);
    let mut last = scene.step().to_vec();
    let mut still_at = None;
    for frame in 1..400 {
        let now = scene.step().to_vec();
        assert!(now.iter().all(|b| b.min.y >= 0.0), "a body below the floor");
        if now == last && still_at.is_none() {
            still_at = Some(frame);
        }
        last = now;
    }
    assert!(still_at.is_some(), "the pile never came to rest");
    // Resting bodies stack: many touch the one under them.
    assert!(brute_pairs(&last).len() > 3000 / 2);
}

#[test]
fn digest_of_a_trace_is_the_sum_of_its_frames() {
    let trace = sample_trace(300, 3);
    let mut total = PairDigest::default();
    let mut all = Vec::new();
    for f in 0..3 {
        let pairs = brute_pairs(trace.frame(f));
        total += PairDigest::of_pairs(pairs.iter().copied());
        all.extend(pairs);
    }
    assert_eq!(total, PairDigest::of_pairs(all));
    assert_eq!(
        format!("{}", PairDigest { count: 3, h1: 0xab, h2: u64::MAX }),
        "3\t00000000000000ab\tffffffffffffffff"
    );
}

proptest::proptest! {
    /// Any bytes after a valid magic and version, headers with any counts
    /// among them: the reader gives a trace or an error, never a panic, and
    /// a trace it gives writes back to the same bytes.
    #[test]
    fn any_bytes_read_to_a_trace_or_an_error(
        counts in proptest::array::uniform2(proptest::prelude::any::<u32>()),
        small in proptest::array::uniform2(0u32..4),
        pick_small in proptest::prelude::any::<bool>(),
        body in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..300),
    ) {
        let [n, frames] = if pick_small { small } else { counts };
        let mut bytes = b"BPHF\x01\0\0\0".to_vec();
        bytes.extend_from_slice(&n.to_le_bytes());
        bytes.extend_from_slice(&frames.to_le_bytes());
        bytes.extend_from_slice(&body);
        if pick_small {
            // The length the header implies, so that some read through.
            bytes.resize(16 + 24 * (n * frames) as usize, 0);
        }
        if let Ok(trace) = BoxTrace::from_bytes(&bytes) {
            proptest::prop_assert_eq!(bytes_of(&trace), bytes);
        }
    }
}

/// Frames of no boxes: a 16-byte header announcing 2^32 - 1 of them is
/// refused by the reader, not handed on to per-frame work.
#[test]
fn frames_of_no_boxes_are_refused() {
    let mut bytes = b"BPHF\x01\0\0\0\0\0\0\0".to_vec();
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    let e = BoxTrace::from_bytes(&bytes).unwrap_err();
    assert!(matches!(e, TraceError::NoBoxes { frames } if frames == u32::MAX as usize), "{e}");
    // No boxes and no frames is an empty trace, and reads back as one.
    bytes[12..16].copy_from_slice(&0u32.to_le_bytes());
    assert_eq!(BoxTrace::from_bytes(&bytes).unwrap(), BoxTrace::new(0));
}

/// Reading a file stops at the length its header implies: trailing bytes
/// are reported with the file's real length, without being read; a path
/// that is not a regular file is refused before any read.
#[test]
fn reading_stops_at_the_header_length() {
    let mut bytes = bytes_of(&sample_trace(3, 2));
    bytes.resize(bytes.len() + (1 << 20), 0);
    let path = std::env::temp_dir().join(format!("bvol-trailing-{}.bphf", std::process::id()));
    std::fs::write(&path, &bytes).unwrap();
    let e = BoxTrace::read(&path).unwrap_err();
    let actual = bytes.len() as u64;
    assert!(matches!(e, TraceError::TrailingBytes { expected: 160, actual: a } if a == actual));
    std::fs::remove_file(path).unwrap();
    assert!(matches!(BoxTrace::read("/dev/zero").unwrap_err(), TraceError::NotAFile));
    assert!(matches!(BoxTrace::read(std::env::temp_dir()).unwrap_err(), TraceError::NotAFile));
}
