//! Box traces: N moving axis-aligned boxes over F frames, in the file layout of
//! ../shared/SCENE_FORMAT.md, so that any broadphase can be run on the same
//! frames and compared.

use std::fmt;
use std::io::{self, Read, Write};
use std::path::Path;

use bvol::volumes::Aabb;
use glam::Vec3;

const MAGIC: &[u8; 4] = b"BPHF";
const VERSION: u32 = 1;
const HEADER: usize = 16;
const BOX_BYTES: usize = 24;

/// A recording of `n` boxes over `frames` frames; box `i` is the same object in
/// every frame.
///
/// ```
/// use bvol_cli::trace::BoxTrace;
/// use bvol::volumes::Aabb;
/// use glam::Vec3;
/// let mut trace = BoxTrace::new(2);
/// trace.push_frame(&[Aabb::new(Vec3::ZERO, Vec3::ONE), Aabb::new(Vec3::ONE, Vec3::splat(2.0))]).unwrap();
/// let mut bytes = Vec::new();
/// trace.write_to(&mut bytes).unwrap();
/// assert_eq!(BoxTrace::from_bytes(&bytes).unwrap(), trace);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BoxTrace {
    n: usize,
    /// Counted apart from the boxes: a trace of no boxes still has frames.
    frames: usize,
    boxes: Vec<Aabb>,
}

/// What is wrong with a box-trace file.
#[derive(Debug)]
pub enum TraceError {
    /// The file could not be read or written.
    Io(io::Error),
    /// The first four bytes are not `BPHF`.
    BadMagic,
    /// A version other than 1.
    UnknownVersion(u32),
    /// Shorter than its header says.
    Truncated {
        /// Bytes the header implies.
        expected: u64,
        /// Bytes there are.
        actual: u64,
    },
    /// Longer than its header says.
    TrailingBytes {
        /// Bytes the header implies.
        expected: u64,
        /// Bytes there are.
        actual: u64,
    },
    /// A box with `min > max` on some axis.
    MinAboveMax {
        /// Frame of the box.
        frame: usize,
        /// Index of the box.
        index: usize,
    },
    /// A box with a NaN or infinite coordinate.
    NonFinite {
        /// Frame of the box.
        frame: usize,
        /// Index of the box.
        index: usize,
    },
    /// More or fewer frames written than the header announced.
    FrameCount {
        /// Frames the header announced.
        announced: usize,
        /// Frames written.
        written: usize,
    },
    /// A frame with another number of boxes than the trace's.
    WrongCount {
        /// The trace's box count.
        expected: usize,
        /// The frame's.
        actual: usize,
    },
    /// Frames of no boxes: nothing to replay, however many frames are
    /// announced (a 16-byte file could otherwise ask for 2^32 - 1 of them).
    NoBoxes {
        /// Frames the header announced.
        frames: usize,
    },
    /// The path is not a regular file (a directory, a FIFO, a device such
    /// as `/dev/zero`): such a file may block or never end.
    NotAFile,
    /// More boxes or frames than the format's 32-bit counts hold.
    TooMany {
        /// Boxes a frame.
        boxes: usize,
        /// Frames.
        frames: usize,
    },
}

impl fmt::Display for TraceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TraceError::Io(e) => write!(f, "{e}"),
            TraceError::BadMagic => write!(f, "bad magic: not a box trace (expected BPHF)"),
            TraceError::UnknownVersion(v) => write!(f, "unknown version {v} (expected 1)"),
            TraceError::Truncated { expected, actual } => {
                write!(f, "truncated: {actual} bytes, the header implies {expected}")
            }
            TraceError::TrailingBytes { expected, actual } => {
                write!(f, "trailing bytes: {actual} bytes, the header implies {expected}")
            }
            TraceError::MinAboveMax { frame, index } => {
                write!(f, "frame {frame}, box {index}: min > max")
            }
            TraceError::NonFinite { frame, index } => {
                write!(f, "frame {frame}, box {index}: NaN or infinite coordinate")
            }
            TraceError::FrameCount { announced, written } => {
                write!(f, "{written} frames written, the header announced {announced}")
            }
            TraceError::WrongCount { expected, actual } => {
                write!(f, "a frame of {actual} boxes in a trace of {expected}")
            }
            TraceError::NoBoxes { frames } => {
                write!(f, "{frames} frames of no boxes: a trace needs at least one box")
            }
            TraceError::NotAFile => write!(f, "not a regular file"),
            TraceError::TooMany { boxes, frames } => {
                write!(f, "{boxes} boxes over {frames} frames: the format counts each in 32 bits")
            }
        }
    }
}

impl std::error::Error for TraceError {}

impl From<io::Error> for TraceError {
    fn from(e: io::Error) -> Self {
        TraceError::Io(e)
    }
}

/// Checks one box: finite, `min <= max`.
fn check_box(b: &Aabb, frame: usize, index: usize) -> Result<(), TraceError> {
    if !(b.min.is_finite() && b.max.is_finite()) {
        return Err(TraceError::NonFinite { frame, index });
    }
    if b.min.cmpgt(b.max).any() {
        return Err(TraceError::MinAboveMax { frame, index });
    }
    Ok(())
}

/// The header's box and frame counts, once its magic, length and version
/// are checked.
fn header(bytes: &[u8]) -> Result<(u64, u64), TraceError> {
    if bytes.len() < 4 || &bytes[..4] != MAGIC {
        return Err(TraceError::BadMagic);
    }
    if bytes.len() < HEADER {
        return Err(TraceError::Truncated { expected: HEADER as u64, actual: bytes.len() as u64 });
    }
    let word = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().expect("4 bytes"));
    if word(4) != VERSION {
        return Err(TraceError::UnknownVersion(word(4)));
    }
    Ok((word(8).into(), word(12).into()))
}

impl BoxTrace {
    /// An empty trace of `n` boxes (no frames yet).
    pub fn new(n: usize) -> Self {
        BoxTrace { n, frames: 0, boxes: Vec::new() }
    }

    /// The number of boxes.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// The boxes of frame `f`.
    ///
    /// # Panics
    ///
    /// If `f` is not below [`frames`](BoxTrace::frames), as slice indexing
    /// does.
    pub fn frame(&self, f: usize) -> &[Aabb] {
        assert!(f < self.frames, "frame {f} of a trace of {} frames", self.frames);
        &self.boxes[f * self.n..(f + 1) * self.n]
    }

    /// Appends a frame; it must hold `n` finite boxes with `min <= max`.
    pub fn push_frame(&mut self, boxes: &[Aabb]) -> Result<(), TraceError> {
        if boxes.len() != self.n {
            return Err(TraceError::WrongCount { expected: self.n, actual: boxes.len() });
        }
        let frame = self.frames();
        for (index, b) in boxes.iter().enumerate() {
            check_box(b, frame, index)?;
        }
        self.boxes.extend_from_slice(boxes);
        self.frames += 1;
        Ok(())
    }

    /// Reads a trace file: a regular file, read no further than the length
    /// its header implies, so that a file with a forged header or endless
    /// trailing bytes costs no more memory than a well-formed one.
    pub fn read(path: impl AsRef<Path>) -> Result<BoxTrace, TraceError> {
        let metadata = std::fs::metadata(path.as_ref())?;
        if !metadata.is_file() {
            return Err(TraceError::NotAFile);
        }
        let mut file = std::fs::File::open(path)?;
        let mut bytes = Vec::new();
        Read::by_ref(&mut file).take(HEADER as u64).read_to_end(&mut bytes)?;
        let (n, frames) = header(&bytes)?;
        let implied = (BOX_BYTES as u64).saturating_mul(n * frames).saturating_add(HEADER as u64);
        if metadata.len() > implied {
            return Err(TraceError::TrailingBytes { expected: implied, actual: metadata.len() });
        }
        file.take(implied - HEADER as u64).read_to_end(&mut bytes)?;
        BoxTrace::from_bytes(&bytes)
    }

    /// Parses a trace from its bytes, checking the layout and every box.
    pub fn from_bytes(bytes: &[u8]) -> Result<BoxTrace, TraceError> {
        let (n, frames) = header(bytes)?;
        if n == 0 && frames > 0 {
            return Err(TraceError::NoBoxes { frames: frames as usize });
        }
        // In 128 bits: 24 n frames can pass 2^64, and wrapped it could match a
        // short file's length (then the boxes' vector, sized from the
        // header, could not be allocated).
        let expected = HEADER as u128 + BOX_BYTES as u128 * (n * frames) as u128;
        let actual = bytes.len() as u64;
        if (actual as u128) < expected {
            let expected = u64::try_from(expected).unwrap_or(u64::MAX);
            return Err(TraceError::Truncated { expected, actual });
        }
        let expected = expected as u64;
        if actual > expected {
            return Err(TraceError::TrailingBytes { expected, actual });
        }
        let float = |i: usize| f32::from_le_bytes(bytes[i..i + 4].try_into().expect("4 bytes"));
        let boxes = Vec::with_capacity((n * frames) as usize);
        let mut trace = BoxTrace { n: n as usize, frames: frames as usize, boxes };
        for k in 0..(n * frames) as usize {
            let at = HEADER + k * BOX_BYTES;
            let b = Aabb::new(
                Vec3::new(float(at), float(at + 4), float(at + 8)),
                Vec3::new(float(at + 12), float(at + 16), float(at + 20)),
            );
            check_box(&b, k / n as usize, k % n as usize)?;
            trace.boxes.push(b);
        }
        Ok(trace)
    }

    /// Writes the trace in the file layout.
    pub fn write_to(&self, out: &mut impl Write) -> Result<(), TraceError> {
        let mut writer = TraceWriter::new(out, self.n, self.frames())?;
        for f in 0..self.frames() {
            writer.write_frame(self.frame(f))?;
        }
        writer.finish().map(|_| ())
    }

    /// Writes the trace to a file.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), TraceError> {
        let mut out = io::BufWriter::new(std::fs::File::create(path)?);
        self.write_to(&mut out)?;
        out.flush()?;
        Ok(())
    }
}

/// Writes a trace frame by frame, without holding it in memory: the header
/// first, then each frame as it comes.
pub struct TraceWriter<W: Write> {
    out: W,
    n: usize,
    frames: usize,
    written: usize,
}

impl<W: Write> TraceWriter<W> {
    /// Starts a trace of `n` boxes over `frames` frames. The format counts
    /// each in 32 bits: more is [`TraceError::TooMany`], and nothing is
    /// written.
    pub fn new(mut out: W, n: usize, frames: usize) -> Result<Self, TraceError> {
        let (Ok(n32), Ok(frames32)) = (u32::try_from(n), u32::try_from(frames)) else {
            return Err(TraceError::TooMany { boxes: n, frames });
        };
        out.write_all(MAGIC)?;
        for word in [VERSION, n32, frames32] {
            out.write_all(&word.to_le_bytes())?;
        }
        Ok(TraceWriter { out, n, frames, written: 0 })
    }

    /// Writes the next frame: `n` boxes, checked as [`BoxTrace::push_frame`] does.
    pub fn write_frame(&mut self, boxes: &[Aabb]) -> Result<(), TraceError> {
        if boxes.len() != self.n {
            return Err(TraceError::WrongCount { expected: self.n, actual: boxes.len() });
        }
        if self.written == self.frames {
            return Err(TraceError::FrameCount {
                announced: self.frames,
                written: self.written + 1,
            });
        }
        let mut bytes = Vec::with_capacity(boxes.len() * BOX_BYTES);
        for b in boxes {
            for v in [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        self.out.write_all(&bytes)?;
        self.written += 1;
        Ok(())
    }

    /// The underlying writer, once every frame announced has been written.
    pub fn finish(self) -> Result<W, TraceError> {
        if self.written != self.frames {
            return Err(TraceError::FrameCount { announced: self.frames, written: self.written });
        }
        Ok(self.out)
    }
}
