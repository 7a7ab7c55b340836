//! `bvol bench pairs`: update + all pairs per frame on a generated scene or a
//! recorded box trace, printed in the line format of ../shared/SCENE_FORMAT.md.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use bvol::tree::{CacheUpdate, PairCache, PairSet, Tree};
use bvol::volumes::Aabb;
use bvol_cli::digest::PairDigest;
use bvol_cli::scenes::{Scene, SceneKind};
use bvol_cli::trace::{BoxTrace, TraceWriter};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use super::breakdown::Breakdown;

/// Where the frames come from.
#[derive(Args, Debug)]
pub struct PairsArgs {
    /// A generated scene: uniform, clustered, mixed, pile, teleport, flat,
    /// heap, ground or fast.
    #[arg(long, default_value = "uniform", conflicts_with = "load")]
    scene: SceneKind,
    /// Bodies in the generated scene.
    #[arg(long, default_value_t = 100_000)]
    n: usize,
    /// Frames to run (the first builds the tree and is reported apart).
    #[arg(long, default_value_t = 100)]
    frames: usize,
    /// Seed of the generated scene.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Threads for pair finding and builds, 1 to 1024 (the output is the
    /// same for any).
    #[arg(long, default_value_t = 1, value_parser = super::threads)]
    threads: usize,
    /// Read the frames from a box-trace file instead of generating them.
    #[arg(long)]
    load: Option<PathBuf>,
    /// Also write the generated frames to a box-trace file.
    #[arg(long, conflicts_with = "load")]
    dump: Option<PathBuf>,
    /// Keep a persistent pair set and time its began / ended events too.
    #[arg(long, conflicts_with = "search")]
    events: bool,
    /// Search every pair afresh each frame (`Tree::pairs_into`), instead of
    /// keeping them in a `PairCache` that searches only around the leaves
    /// that moved when few did.
    #[arg(long)]
    search: bool,
    /// Also print to standard error, for each kind of frame (what the
    /// tree's update did: moved leaves one by one, refit, install a staged
    /// rebuild, rebuild in one go), how many there were and their means:
    /// leaves moved, update time, time to bring the pairs up to date, how
    /// many frames searched every pair and the node pairs they visited, the
    /// changed leaves queried instead, and pairs found.
    #[arg(long)]
    verbose: bool,
}

/// A source of frames.
enum Frames {
    Scene(Scene),
    Trace(BoxTrace),
}

impl Frames {
    fn frame(&mut self, f: usize) -> &[Aabb] {
        match self {
            Frames::Scene(scene) => scene.step(),
            Frames::Trace(trace) => trace.frame(f),
        }
    }
}

/// The trace file `--dump` writes, and its path for the errors.
struct Dump {
    path: PathBuf,
    writer: TraceWriter<BufWriter<File>>,
}

impl Dump {
    fn create(path: &Path, n: usize, frames: usize) -> Result<Dump, String> {
        let file = File::create(path).map_err(|e| in_file(path, e))?;
        let writer = TraceWriter::new(BufWriter::new(file), n, frames);
        Ok(Dump { path: path.to_path_buf(), writer: writer.map_err(|e| in_file(path, e))? })
    }

    fn write_frame(&mut self, boxes: &[Aabb]) -> Result<(), String> {
        self.writer.write_frame(boxes).map_err(|e| in_file(&self.path, e))
    }

    /// Checks every frame was written and flushes the file: a write error
    /// (a full disk) is reported here, not lost when the buffer is dropped.
    fn finish(self) -> Result<(), String> {
        let mut out = self.writer.finish().map_err(|e| in_file(&self.path, e))?;
        out.flush().map_err(|e| in_file(&self.path, e))
    }
}

/// An error about a file, for the user: its path, then what is wrong.
fn in_file(path: &Path, e: impl std::fmt::Display) -> String {
    format!("{}: {e}", path.display())
}

/// What one run measured.
struct Run {
    n: usize,
    frames: usize,
    pairs: u64,
    build_ms: f64,
    frame_ms: Vec<f64>,
    /// The part of `frame_ms` that `Tree::update` took, summed over frames
    /// 1.. (the rest is the pair search, or the pair set's update).
    update_ms: f64,
    digest: PairDigest,
    bytes: usize,
    /// Began and ended events over all frames (with `--events`).
    began: u64,
    ended: u64,
    /// Frames 1.. by kind.
    breakdown: Breakdown,
}

pub fn run(args: PairsArgs) -> Result<(), String> {
    let (frames, n, count) = match &args.load {
        Some(path) => {
            let trace = BoxTrace::read(path).map_err(|e| in_file(path, e))?;
            let (n, count) = (trace.n(), trace.frames());
            (Frames::Trace(trace), n, count)
        }
        None => (Frames::Scene(Scene::new(args.scene, args.n, args.seed)), args.n, args.frames),
    };
    // Where the counts came from, for the errors: the trace file or the options.
    let (of_frames, of_boxes) = match &args.load {
        Some(path) => (path.display().to_string(), path.display().to_string()),
        None => ("--frames".to_string(), "--n".to_string()),
    };
    if count < 2 {
        return Err(format!(
            "{of_frames}: {count} frames: the benchmark needs at least 2 (the first builds the tree)"
        ));
    }
    if n == 0 {
        return Err(format!("{of_boxes}: no boxes to run"));
    }
    let mut dump = match &args.dump {
        Some(path) => Some(Dump::create(path, n, count)?),
        None => None,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .map_err(|e| e.to_string())?;
    let finder = match (args.events, args.search) {
        (true, _) => Finder::Set(PairSet::new()),
        (false, true) => Finder::Search(Vec::new()),
        (false, false) => Finder::Cache(PairCache::new()),
    };
    let run = pool.install(|| measure(frames, n, count, finder, &mut dump))?;
    if let Some(dump) = dump {
        dump.finish()?;
    }
    print(
        &run,
        args.threads,
        args.load.as_ref().map_or(args.scene.name(), |_| "trace"),
        args.events,
    );
    if args.verbose {
        eprint!("{}", run.breakdown.table());
    }
    Ok(())
}

/// How a frame's pairs are found once the tree is up to date.
enum Finder {
    /// Every pair searched afresh (`--search`).
    Search(Vec<(u32, u32)>),
    /// Kept from frame to frame, searched around what moved (the default).
    Cache(PairCache),
    /// Kept sorted with began and ended pairs (`--events`).
    Set(PairSet),
}

impl Finder {
    /// Brings the pairs up to date with `tree`: what was done, but for a
    /// pair set, which does not say.
    fn update(&mut self, tree: &mut Tree<Aabb>) -> Option<CacheUpdate> {
        match self {
            Finder::Search(pairs) => {
                let search = Some(tree.pairs_into(pairs));
                Some(CacheUpdate { search, kept: 0, queried: 0 })
            }
            Finder::Cache(cache) => Some(cache.update(tree)),
            Finder::Set(set) => {
                set.update(tree);
                None
            }
        }
    }

    fn pairs(&self) -> &[(u32, u32)] {
        match self {
            Finder::Search(pairs) => pairs,
            Finder::Cache(cache) => cache.pairs(),
            Finder::Set(set) => set.pairs(),
        }
    }
}

fn measure(
    mut frames: Frames,
    n: usize,
    count: usize,
    mut finder: Finder,
    dump: &mut Option<Dump>,
) -> Result<Run, String> {
    let progress = ProgressBar::new(count as u64).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {eta} left").expect("template"),
    );
    let mut tree = Tree::<Aabb>::new();
    let mut run = Run {
        n,
        frames: count,
        pairs: 0,
        build_ms: 0.0,
        // Grown frame by frame, not reserved from `count`: what a run may
        // allocate is bounded by the frames it actually runs.
        frame_ms: Vec::new(),
        update_ms: 0.0,
        digest: PairDigest::default(),
        bytes: 0,
        began: 0,
        ended: 0,
        breakdown: Breakdown::default(),
    };
    for f in 0..count {
        let boxes = frames.frame(f);
        if let Some(dump) = dump {
            dump.write_frame(boxes)?;
        }
        let started = Instant::now();
        let mut update = None;
        if f == 0 {
            tree = Tree::from_bounds(boxes).map_err(|e| format!("frame 0: {e}"))?;
        } else {
            update = Some(tree.update(boxes).map_err(|e| format!("frame {f}: {e}"))?);
        }
        let update_ms = started.elapsed().as_secs_f64() * 1e3;
        let found = finder.update(&mut tree);
        let ms = started.elapsed().as_secs_f64() * 1e3;
        if let Finder::Set(set) = &finder {
            run.began += set.began().len() as u64;
            run.ended += set.ended().len() as u64;
        }
        let pairs = finder.pairs();
        if let Some(update) = update {
            run.update_ms += update_ms;
            run.frame_ms.push(ms);
            run.breakdown.add(&update, (update_ms, ms - update_ms), found, pairs.len());
        } else {
            run.build_ms = ms;
        }
        run.pairs += pairs.len() as u64;
        run.digest += PairDigest::of_pairs(pairs.iter().copied());
        progress.inc(1);
    }
    progress.finish_and_clear();
    run.bytes = tree.memory_bytes();
    Ok(run)
}

fn print(run: &Run, threads: usize, source: &str, events: bool) {
    let mut sorted = run.frame_ms.clone();
    sorted.sort_by(f64::total_cmp);
    // `run` refuses fewer than 2 frames: at least one frame after the build.
    let k = sorted.len();
    let median = if k % 2 == 1 { sorted[k / 2] } else { 0.5 * (sorted[k / 2 - 1] + sorted[k / 2]) };
    let mean = sorted.iter().sum::<f64>() / k as f64;
    // The worst frame: where a rebuild or a burst of reinsertions shows.
    let max = sorted[k - 1];
    let update_mean = run.update_ms / sorted.len() as f64;
    let avg_pairs = run.pairs as f64 / run.frames as f64;
    let per_body = run.bytes as f64 / run.n.max(1) as f64;
    let mut header = String::from(
        "n\tframes\tavg_pairs\tbuild_ms\tmedian_ms\tmean_ms\tthreads\tcount\th1\th2\tscene\ttree_bytes_per_body\tmax_ms\tupdate_mean_ms",
    );
    let mut row = format!(
        "{}\t{}\t{avg_pairs:.1}\t{:.3}\t{median:.3}\t{mean:.3}\t{threads}\t{}\t{source}\t{per_body:.1}\t{max:.3}\t{update_mean:.3}",
        run.n, run.frames, run.build_ms, run.digest
    );
    if events {
        let per_frame = |k: u64| k as f64 / run.frames as f64;
        header.push_str("\tavg_began\tavg_ended");
        row.push_str(&format!("\t{:.1}\t{:.1}", per_frame(run.began), per_frame(run.ended)));
    }
    println!("{header}\n{row}");
}
