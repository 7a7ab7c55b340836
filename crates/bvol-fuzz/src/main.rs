//! `bvol-fuzz`: replays each target's corpus, then runs mutants of it from a
//! seeded generator, and reports every input that breaks an invariant:
//! a panic, an abort from an allocation past the input's cap, or a run past
//! its time limit. Such inputs are saved under `fuzz/found/<target>/`.
//!
//! ```text
//! cargo run -p bvol-fuzz -- --inputs 2000            # every target
//! cargo run -p bvol-fuzz -- obj fit --seconds 600    # two, ten minutes each
//! cargo run -p bvol-fuzz -- --replay obj fuzz/found/obj/1f2e...
//! ```

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::time::{Duration, Instant};

use bvol_fuzz::cap::{self, CappedAlloc};
use bvol_fuzz::mutate::Mutator;
use bvol_fuzz::{TARGETS, Target};
use clap::Parser;

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc;

/// Memory any input may take, plus [`BYTES_PER_INPUT_BYTE`] for each of its
/// bytes: the fitters, hulls and trees hold a few hundred bytes a point.
const BASE_MEMORY: usize = 256 << 20;
const BYTES_PER_INPUT_BYTE: usize = 4096;
/// Time an input may take: its target's, plus this for each byte.
const TIME_PER_INPUT_BYTE: Duration = Duration::from_micros(200);
/// A target stops after this many failing inputs.
const MAX_FAILURES: usize = 10;

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

/// The input running now, for the watchdog and the allocation hook.
static CURRENT: Mutex<Option<(&'static str, Vec<u8>)>> = Mutex::new(None);
static FOUND: Mutex<Option<PathBuf>> = Mutex::new(None);
/// When the input running now must end, in milliseconds since `EPOCH`; 0: none.
static DEADLINE_MS: AtomicU64 = AtomicU64::new(0);
static EPOCH: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
/// The last panic's message and place.
static PANIC: Mutex<String> = Mutex::new(String::new());

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    let targets: Vec<&Target> = if args.targets.is_empty() {
        TARGETS.iter().collect()
    } else {
        match args.targets.iter().map(|n| bvol_fuzz::target(n).ok_or(n)).collect() {
            Ok(t) => t,
            Err(name) => {
                let names: Vec<_> = TARGETS.iter().map(|t| t.name).collect();
                eprintln!("bvol-fuzz: no target {name:?}; the targets are {names:?}");
                return std::process::ExitCode::from(2);
            }
        }
    };
    if let Some(path) = args.bvol.clone() {
        bvol_fuzz::set_binary(path);
    }
    *FOUND.lock().unwrap() = Some(args.found.clone());
    install_guards();
    let mut failed = 0;
    if !args.replay.is_empty() {
        let [target] = targets[..] else {
            eprintln!("bvol-fuzz: --replay needs exactly one target");
            return std::process::ExitCode::from(2);
        };
        for path in &args.replay {
            let input = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            failed += usize::from(!run_one(target, &input, false));
        }
    } else {
        for target in targets {
            failed += fuzz(target, &args);
        }
    }
    bvol_fuzz::remove_scratch();
    if failed == 0 { std::process::ExitCode::SUCCESS } else { std::process::ExitCode::FAILURE }
}

/// Runs a target's corpus and `args.inputs` mutants; returns the failures.
fn fuzz(target: &'static Target, args: &Args) -> usize {
    let corpus = read_corpus(&args.corpus.join(target.name));
    let started = Instant::now();
    let mut failures = corpus.iter().filter(|input| !run_one(target, input, true)).count();
    let replayed = started.elapsed();
    let seed = args.seed ^ fnv1a(target.name.as_bytes());
    let mut mutator = Mutator::new(seed);
    let pool: Vec<&[u8]> =
        if corpus.is_empty() { vec![&[]] } else { corpus.iter().map(Vec::as_slice).collect() };
    let deadline = args.seconds.map(|s| Instant::now() + Duration::from_secs_f64(s));
    let mut count = 0u64;
    let fresh = Instant::now();
    while count < args.inputs && failures < MAX_FAILURES {
        if deadline.is_some_and(|d| Instant::now() > d) {
            break;
        }
        let base = pool[mutator.below(pool.len())];
        let other = pool[mutator.below(pool.len())];
        let input = mutator.mutate(base, other, target.dictionary, target.max_len);
        failures += usize::from(!run_one(target, &input, true));
        count += 1;
    }
    let secs = fresh.elapsed().as_secs_f64();
    println!(
        "{}: {} corpus inputs in {:.1} s, {count} new in {secs:.1} s ({:.0}/s): {}",
        target.name,
        corpus.len(),
        replayed.as_secs_f64(),
        count as f64 / secs.max(1e-9),
        if failures == 0 { "nothing found".to_owned() } else { format!("{failures} failing") },
    );
    failures
}

/// Runs one input under the guards; false (and the input saved) if it fails.
fn run_one(target: &'static Target, input: &[u8], save: bool) -> bool {
    *CURRENT.lock().unwrap() = save.then(|| (target.name, input.to_vec()));
    let limit = target.time + TIME_PER_INPUT_BYTE * input.len() as u32;
    let now = EPOCH.get().expect("guards installed").elapsed();
    DEADLINE_MS.store((now + limit).as_millis() as u64, Relaxed);
    cap::allow(BASE_MEMORY + BYTES_PER_INPUT_BYTE * input.len());
    let result = std::panic::catch_unwind(|| target.run(input));
    cap::lift();
    DEADLINE_MS.store(0, Relaxed);
    *CURRENT.lock().unwrap() = None;
    if result.is_ok() {
        return true;
    }
    let message = std::mem::take(&mut *PANIC.lock().unwrap());
    let saved = if save { save_input(target.name, input) } else { "not saved".into() };
    eprintln!("{}: {} ({saved})", target.name, message.replace('\n', " | "));
    false
}

/// The panic hook (records the message instead of printing it), the
/// watchdog thread, and the allocation hook.
fn install_guards() {
    EPOCH.get_or_init(Instant::now);
    std::panic::set_hook(Box::new(|info| {
        if let Ok(mut last) = PANIC.lock() {
            *last = info.to_string();
        }
    }));
    cap::on_refusal(|size, live| {
        let saved = current_saved();
        eprintln!("allocation of {size} bytes with {live} live: past the input's cap ({saved})");
    });
    std::thread::spawn(|| {
        let epoch = *EPOCH.get().expect("set above");
        loop {
            std::thread::sleep(Duration::from_millis(100));
            let deadline = DEADLINE_MS.load(Relaxed);
            if deadline != 0 && epoch.elapsed().as_millis() as u64 > deadline {
                eprintln!("an input ran past its time limit ({})", current_saved());
                std::process::exit(1);
            }
        }
    });
}

/// Saves the input running now, if any; says where.
fn current_saved() -> String {
    match CURRENT.try_lock().ok().and_then(|c| c.clone()) {
        Some((name, input)) => save_input(name, &input),
        None => "the input was not saved".into(),
    }
}

fn save_input(target: &str, input: &[u8]) -> String {
    let folder = FOUND.lock().unwrap().clone().expect("set in main").join(target);
    let path = folder.join(format!("{:016x}", fnv1a(input)));
    match std::fs::create_dir_all(&folder).and_then(|()| std::fs::write(&path, input)) {
        Ok(()) => format!("saved to {}", path.display()),
        Err(e) => format!("not saved: {}: {e}", path.display()),
    }
}

fn read_corpus(folder: &Path) -> Vec<Vec<u8>> {
    let Ok(entries) = std::fs::read_dir(folder) else { return Vec::new() };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| Some(e.ok()?.path())).collect();
    paths.sort();
    paths
        .iter()
        .filter(|p| p.is_file())
        .map(|p| std::fs::read(p).expect("read the corpus"))
        .collect()
}

/// FNV-1a, 64-bit: names a saved input by its bytes.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}
