//! Running inputs under guards: a panic fails the input; so does a run past
//! its time limit (a watchdog thread ends the process) and an allocation
//! past the input's cap (with [`CappedAlloc`](crate::cap::CappedAlloc)
//! installed). A failing input is saved, named by its hash.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use crate::Target;
use crate::cap;
use crate::mutate::Mutator;

/// Memory any input may take, plus [`BYTES_PER_INPUT_BYTE`] for each of its
/// bytes: the fitters, hulls and trees hold a few hundred bytes a point.
pub const BASE_MEMORY: usize = 256 << 20;
/// See [`BASE_MEMORY`].
pub const BYTES_PER_INPUT_BYTE: usize = 4096;
/// Time an input may take: its target's, plus this for each byte.
pub const TIME_PER_INPUT_BYTE: Duration = Duration::from_micros(200);
/// A target stops after this many failing inputs.
const MAX_FAILURES: usize = 10;

/// The input running now, for the watchdog and the allocation hook.
static CURRENT: Mutex<Option<(&'static str, Vec<u8>)>> = Mutex::new(None);
static FOUND: OnceLock<PathBuf> = OnceLock::new();
/// When the input running now must end, in milliseconds since `EPOCH`; 0: none.
static DEADLINE_MS: AtomicU64 = AtomicU64::new(0);
static EPOCH: OnceLock<Instant> = OnceLock::new();
/// The last panic's message and place.
static PANIC: Mutex<String> = Mutex::new(String::new());

/// How many new inputs to run after the corpus, and from what seed.
pub struct Budget {
    /// New inputs at most.
    pub inputs: u64,
    /// Stop the new inputs after this long.
    pub time: Option<Duration>,
    /// The mutations' seed (mixed with the target's name).
    pub seed: u64,
}

/// Sets the guards up, once per process: failing inputs go under `found`
/// (a folder per target); panics are recorded, not printed; the watchdog
/// starts; a refused allocation saves the input running.
pub fn install_guards(found: PathBuf) {
    if FOUND.set(found).is_err() {
        return;
    }
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
            std::thread::sleep(Duration::from_millis(50));
            let deadline = DEADLINE_MS.load(Relaxed);
            if deadline != 0 && epoch.elapsed().as_millis() as u64 > deadline {
                eprintln!("an input ran past its time limit ({})", current_saved());
                std::process::exit(1);
            }
        }
    });
}

/// Runs a target's corpus (the files in `corpus`) and then new inputs
/// mutated from it; prints a line of counts and rates, and returns the
/// number of failing inputs.
pub fn fuzz(target: &'static Target, corpus: &Path, budget: &Budget) -> usize {
    let corpus = read_corpus(corpus);
    let started = Instant::now();
    let mut failures = corpus.iter().filter(|input| !run_one(target, input, true)).count();
    let replayed = started.elapsed();
    let mut mutator = Mutator::new(budget.seed ^ fnv1a(target.name.as_bytes()));
    let pool: Vec<&[u8]> =
        if corpus.is_empty() { vec![&[]] } else { corpus.iter().map(Vec::as_slice).collect() };
    let fresh = Instant::now();
    let mut count = 0u64;
    while count < budget.inputs && failures < MAX_FAILURES {
        if budget.time.is_some_and(|t| fresh.elapsed() > t) {
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

/// Runs one input under the guards ([`install_guards`] first); false, with
/// the panic printed and the input saved (when `save`), if it fails.
pub fn run_one(target: &'static Target, input: &[u8], save: bool) -> bool {
    *CURRENT.lock().unwrap() = save.then(|| (target.name, input.to_vec()));
    let limit = target.time + TIME_PER_INPUT_BYTE * input.len() as u32;
    let now = EPOCH.get().expect("install_guards first").elapsed();
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

/// Where a failing input of `target` is saved.
pub fn saved_path(target: &str, input: &[u8]) -> PathBuf {
    let found = FOUND.get().expect("install_guards first");
    found.join(target).join(format!("{:016x}", fnv1a(input)))
}

/// Saves the input running now, if any; says where.
fn current_saved() -> String {
    match CURRENT.try_lock().ok().and_then(|c| c.clone()) {
        Some((name, input)) => save_input(name, &input),
        None => "the input was not saved".into(),
    }
}

fn save_input(target: &str, input: &[u8]) -> String {
    let path = saved_path(target, input);
    let written = path.parent().map_or(Ok(()), std::fs::create_dir_all);
    match written.and_then(|()| std::fs::write(&path, input)) {
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
