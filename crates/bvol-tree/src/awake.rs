//! The pool's other threads kept awake through one update of the tree's,
//! so that its parallel passes do not wait for them to wake.
//!
//! An update that scans or refits the whole tree runs several parallel
//! passes with serial stretches between them (the policy's choices,
//! reinserting leaves, the rebuild's steps). A rayon worker that finds no
//! work spins a few dozen rounds and then sleeps; the next pass hands it
//! work and waits while the system wakes it, which on a virtual machine (a
//! halted virtual processor woken by the hypervisor) takes tens of
//! microseconds at every pass. Box2D v3's solver keeps its workers spinning between its stages
//! for this reason (`b2SolverTask`); here a keeper task on each other
//! thread spins while the call runs, running any of the pool's work it
//! finds, and ends with the call.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::Yield;

/// Pause hints between two looks for work while a keeper finds none: each
/// look reads the other threads' queues, whose lines the calling thread is
/// writing.
const PAUSES: usize = 16;

/// Runs `work` with every other thread of the current rayon pool kept awake
/// until it returns: on the calling thread, or on one of the global pool's
/// when called from outside any pool (as rayon's own calls run). A keeper
/// that the thread running `work` takes itself (while it waits for a task
/// of its own, or when nobody else was free) returns at once: `work`'s
/// result and the work done are the same either way.
pub(crate) fn awake<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    let others = rayon::current_num_threads() - 1;
    if others == 0 {
        return work();
    }
    let done = AtomicBool::new(false);
    rayon::scope(|scope| {
        // Asked here, not before: called from outside the pool, the scope
        // runs on one of its threads.
        let home = rayon::current_thread_index();
        for _ in 0..others {
            let done = &done;
            scope.spawn(move |_| keep(home, done));
        }
        let result = work();
        done.store(true, Ordering::Release);
        result
    })
}

/// A keeper: until `done`, runs the pool's pending work or pauses; at once
/// if it runs on thread `home`, the one whose call it keeps others awake for
/// (which takes it while waiting, and must not spin there).
fn keep(home: Option<usize>, done: &AtomicBool) {
    if rayon::current_thread_index() == home {
        return;
    }
    while !done.load(Ordering::Acquire) {
        if rayon::yield_now() != Some(Yield::Executed) {
            for _ in 0..PAUSES {
                std::hint::spin_loop();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    #[test]
    fn work_runs_once_and_its_result_returns_on_any_pool() {
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let runs = AtomicUsize::new(0);
            let result = pool.install(|| {
                awake(|| {
                    runs.fetch_add(1, Ordering::Relaxed);
                    // Parallel work inside is done whole, whoever runs it.
                    rayon::join(|| 20, || 22)
                })
            });
            assert_eq!(result, (20, 22));
            assert_eq!(runs.into_inner(), 1);
        }
    }

    #[test]
    fn a_call_from_outside_the_pools_returns_its_work() {
        /// Counts to `n` by halves on tasks, which the other threads may
        /// steal while their keepers look for work.
        fn sum(n: u64) -> u64 {
            match n {
                0 | 1 => n,
                _ => {
                    let (a, b) = rayon::join(|| sum(n / 2), || sum(n - n / 2));
                    a + b
                }
            }
        }
        let total = std::thread::spawn(|| awake(|| sum(10_000))).join().unwrap();
        assert_eq!(total, 10_000);
    }

    #[test]
    fn nested_calls_end_with_their_work() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let sum = pool.install(|| awake(|| (0..8).map(|k| awake(|| k)).sum::<i32>()));
        assert_eq!(sum, 28);
    }
}
