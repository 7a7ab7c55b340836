//! Fuzz targets for every input a user of bvol controls, and the parts of
//! the runner (`bvol-fuzz`, src/main.rs) that drives them on stable Rust.
//!
//! A target takes any bytes and panics when an invariant fails:
//!
//! - no panic, abort or hang anywhere below it (the runner enforces a time
//!   limit per input and caps allocation by the input's size, see [`cap`]);
//! - every accepted bound contains every accepted point;
//! - no NaN or infinity in any output;
//! - every error names what is wrong (and the file or argument, where there
//!   is one) in one line.
//!
//! | target | input |
//! | --- | --- |
//! | `obj` | an OBJ file, through `bvol::load_obj` and `Shape::from_meshes` |
//! | `trace` | a box-trace file, parsed and replayed against brute force |
//! | `world` | a sequence of World edits, applied to a tree world and a brute-force one |
//! | `fit` | a point set, through every fitter and the convex hull |
//! | `contact` | two parts and their poses, through the pair table |
//! | `cli` | the `bvol` binary's arguments and the files they name |
//!
//! Corpora live in `fuzz/corpus/<target>/` at the workspace root; the
//! README's test command replays them and runs a fixed number of mutated
//! inputs from a fixed seed.
//!
//! ```
//! // Any bytes are an input; this one is an OBJ triangle.
//! bvol_fuzz::target("obj").unwrap().run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
//! ```

#![warn(missing_docs)]

pub mod cap;
pub mod mutate;
pub mod runner;

mod checks;
mod cli;
mod contact;
mod fit;
mod floats;
mod obj;
mod scratch;
mod trace;
mod world;

use std::time::Duration;

pub use cli::set_binary;
pub use scratch::remove_scratch;

/// One fuzz target.
pub struct Target {
    /// Its name: the corpus folder and the runner's argument.
    pub name: &'static str,
    /// Runs one input; panics when an invariant fails.
    pub run: fn(&[u8]),
    /// Mutants are cut to this many bytes.
    pub max_len: usize,
    /// Tokens worth inserting (keywords, numbers at the edges of ranges).
    pub dictionary: &'static [&'static [u8]],
    /// How long any input may run, before the allowance for its size.
    pub time: Duration,
}

impl Target {
    /// Runs one input.
    pub fn run(&self, input: &[u8]) {
        (self.run)(input)
    }
}

/// Every target, in the order the runner runs them.
pub const TARGETS: &[Target] = &[
    Target {
        name: "obj",
        run: obj::run,
        max_len: 1 << 16,
        dictionary: obj::DICTIONARY,
        time: LIMIT,
    },
    Target {
        name: "trace",
        run: trace::run,
        max_len: 1 << 14,
        dictionary: trace::DICTIONARY,
        time: LIMIT,
    },
    Target { name: "world", run: world::run, max_len: 1 << 14, dictionary: &[], time: LIMIT },
    Target { name: "fit", run: fit::run, max_len: 1 << 12, dictionary: &[], time: LIMIT },
    Target { name: "contact", run: contact::run, max_len: 1 << 10, dictionary: &[], time: LIMIT },
    Target {
        name: "cli",
        run: cli::run,
        max_len: 1 << 13,
        dictionary: cli::DICTIONARY,
        // The target's own limit on the binary, and then some: its report
        // (naming the command) is the one to see.
        time: cli::TIME_LIMIT.saturating_add(LIMIT),
    },
];

/// How long an input of the in-process targets may run, before the
/// allowance for its size: each takes milliseconds.
const LIMIT: Duration = Duration::from_secs(5);

/// The target called `name`.
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}
