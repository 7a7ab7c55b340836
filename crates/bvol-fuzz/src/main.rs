//! `bvol-fuzz`: replays each target's corpus, then runs mutants of it from a
//! seeded generator, and reports every input that breaks an invariant:
//! a panic, an abort from an allocation past the input's cap, or a run past
//! its time limit. Such inputs are saved under `fuzz/found/<target>/`.
//!
//! ```text
//! cargo run -p bvol-fuzz -- --inputs 2000            # every target
//! cargo run -p bvol-fuzz -- obj fit --seconds 600    # two, ten minutes each
//! cargo run -p bvol-fuzz -- obj --replay fuzz/found/obj/1f2e...
//! ```

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use bvol_fuzz::cap::CappedAlloc;
use bvol_fuzz::runner::{self, Budget};
use bvol_fuzz::{TARGETS, Target};
use clap::Parser;

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc;

/// Fuzz bvol's inputs: replay the corpus, then run seeded mutants of it.
#[derive(Parser)]
struct Args {
    /// Targets to run (default: all): obj, trace, world, fit, contact, cli.
    targets: Vec<String>,
    /// New inputs per target, after the corpus.
    #[arg(long, default_value_t = 1000)]
    inputs: u64,
    /// Also stop each target's new inputs after this many seconds.
    #[arg(long)]
    seconds: Option<f64>,
    /// Seed of the mutations: the same seed gives the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The corpus: a folder per target.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/corpus"))]
    corpus: PathBuf,
    /// Where failing inputs are saved: a folder per target.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/found"))]
    found: PathBuf,
    /// The `bvol` binary the cli target runs (default: the one beside this).
    #[arg(long)]
    bvol: Option<PathBuf>,
    /// Run only these files, as inputs of the one target named.
    #[arg(long, num_args = 1..)]
    replay: Vec<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let targets: Vec<&'static Target> = if args.targets.is_empty() {
        TARGETS.iter().collect()
    } else {
        match args.targets.iter().map(|n| bvol_fuzz::target(n).ok_or(n)).collect() {
            Ok(t) => t,
            Err(name) => {
                let names: Vec<_> = TARGETS.iter().map(|t| t.name).collect();
                eprintln!("bvol-fuzz: no target {name:?}; the targets are {names:?}");
                return ExitCode::from(2);
            }
        }
    };
    if let Some(path) = args.bvol.clone() {
        bvol_fuzz::set_binary(path);
    }
    runner::install_guards(args.found.clone());
    let mut failed = 0;
    if !args.replay.is_empty() {
        let [target] = targets[..] else {
            eprintln!("bvol-fuzz: --replay needs exactly one target");
            return ExitCode::from(2);
        };
        for path in &args.replay {
            match std::fs::read(path) {
                Ok(input) => failed += usize::from(!runner::run_one(target, &input, false)),
                Err(e) => {
                    eprintln!("bvol-fuzz: {}: {e}", path.display());
                    return ExitCode::from(2);
                }
            }
        }
    } else {
        let time = match args.seconds.map(Duration::try_from_secs_f64).transpose() {
            Ok(time) => time,
            Err(_) => {
                eprintln!("bvol-fuzz: --seconds: expected a number of seconds, at least 0");
                return ExitCode::from(2);
            }
        };
        let budget = Budget { inputs: args.inputs, time, seed: args.seed };
        for target in targets {
            failed += runner::fuzz(target, &args.corpus.join(target.name), &budget);
        }
    }
    bvol_fuzz::remove_scratch();
    if failed == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
