//! Tallies of checked pairs: counts of each outcome, the worst errors, an
//! example of each kind, and the failures; and seeded chunks of checks run
//! on every core, their tallies merged in chunk order.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rand::SeedableRng;
use rand::rngs::SmallRng;

/// Counts of each outcome, the worst errors seen, and the failures.
#[derive(Default)]
pub struct Tally {
    /// How many pairs were checked.
    pub pairs: usize,
    /// How many pairs fell under each outcome.
    counts: BTreeMap<String, usize>,
    /// The first pair of each outcome, described.
    examples: BTreeMap<String, String>,
    /// The greatest relative error of each kind.
    worst: BTreeMap<&'static str, f64>,
    /// How many pairs failed.
    pub failures: usize,
}

impl Tally {
    /// Counts one pair under `what`.
    pub fn note(&mut self, what: impl Into<String>) {
        *self.counts.entry(what.into()).or_default() += 1;
    }

    /// Keeps the greatest `value` of `what`.
    pub fn worst(&mut self, what: &'static str, value: f64) {
        let w = self.worst.entry(what).or_insert(0.0);
        *w = w.max(value);
    }

    /// Counts one pair under `what`, and keeps the first example of it.
    pub fn example(&mut self, what: String, example: impl FnOnce() -> String) {
        self.examples.entry(what.clone()).or_insert_with(example);
        self.note(what);
    }

    /// A failure of the kinds `tags`: counted under each, the first of each
    /// kind kept as an example.
    pub fn fail(&mut self, tags: Vec<&'static str>, report: String) {
        self.failures += 1;
        for tag in tags {
            self.note(tag);
            self.examples.entry(tag.to_string()).or_insert_with(|| report.clone());
        }
    }

    /// Adds another tally's counts (its examples only where this has none).
    pub fn merge(&mut self, other: Tally) {
        self.pairs += other.pairs;
        for (k, v) in other.counts {
            *self.counts.entry(k).or_default() += v;
        }
        for (k, v) in other.examples {
            self.examples.entry(k).or_insert(v);
        }
        for (k, v) in other.worst {
            self.worst(k, v);
        }
        self.failures += other.failures;
    }

    /// Prints everything and fails on any failure.
    pub fn finish(self, title: &str, started: Instant) {
        println!("{title}: {} pairs in {:.1?}", self.pairs, started.elapsed());
        for (k, v) in &self.counts {
            println!("  {v:>9}  {k}");
        }
        for (k, v) in &self.worst {
            println!("  worst {k}: {v:.3e}");
        }
        for (k, v) in &self.examples {
            println!("  example of {k}: {v}");
        }
        assert_eq!(
            self.failures, 0,
            "{title}: {} failures (an example of each kind above)",
            self.failures
        );
    }
}

/// Runs `chunks` seeded chunks of a generator on every core; each chunk has its
/// own generator and tally, merged in chunk order, so that nothing printed
/// depends on the thread count.
pub fn run_chunks(
    chunks: usize,
    seed: u64,
    work: impl Fn(&mut SmallRng, &mut Tally) + Sync,
) -> Tally {
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut done: Vec<(usize, Tally)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        if chunk >= chunks {
                            return mine;
                        }
                        let mut rng =
                            SmallRng::seed_from_u64(seed.wrapping_mul(1_000_003) + chunk as u64);
                        let mut tally = Tally::default();
                        work(&mut rng, &mut tally);
                        mine.push((chunk, tally));
                    }
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().expect("worker")).collect()
    });
    done.sort_by_key(|d| d.0);
    let mut all = Tally::default();
    done.into_iter().for_each(|(_, t)| all.merge(t));
    all
}
