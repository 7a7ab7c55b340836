//! `bvol bench pairs --verbose`: the frames grouped by what the tree's
//! update did, and where each group's time went, so that a regression shows
//! in the stage and the kind of frame where it is.

use bvol::tree::{CacheUpdate, UpdateStats};

/// What a frame's update did, from its [`UpdateStats`]; its value indexes
/// [`Breakdown`]'s totals, in the order of [`FrameKind::ALL`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FrameKind {
    /// Moved leaves updated one by one (few moved).
    Moves,
    /// Every node refit, no rebuild installed.
    Refit,
    /// A refit that installed a rebuild staged over the frames before.
    Install,
    /// A refit followed by a rebuild in one go (mass motion outran the
    /// staged builds).
    Rebuild,
}

impl FrameKind {
    const ALL: [FrameKind; 4] =
        [FrameKind::Moves, FrameKind::Refit, FrameKind::Install, FrameKind::Rebuild];

    fn of(update: &UpdateStats) -> FrameKind {
        match (update.refit, update.installed, update.rebuilt > 0) {
            (false, ..) => FrameKind::Moves,
            (true, true, _) => FrameKind::Install,
            (true, false, true) => FrameKind::Rebuild,
            (true, false, false) => FrameKind::Refit,
        }
    }

    fn name(self) -> &'static str {
        match self {
            FrameKind::Moves => "moves",
            FrameKind::Refit => "refit",
            FrameKind::Install => "install",
            FrameKind::Rebuild => "rebuild",
        }
    }
}

/// The sums over one kind of frame.
#[derive(Clone, Copy, Debug, Default)]
struct Totals {
    frames: u64,
    moved: u64,
    update_ms: f64,
    pairs_ms: f64,
    /// Frames whose pairs were all searched afresh, and their node pairs.
    searched: u64,
    node_pairs: u64,
    /// Changed leaves that queried the tree instead.
    queried: u64,
    pairs: u64,
    /// Frames whose pair finder said what it did (not a pair set's).
    told: u64,
}

/// The frames after the first, summed by kind.
#[derive(Debug, Default)]
pub struct Breakdown {
    totals: [Totals; 4],
}

impl Breakdown {
    /// Adds one frame: what its update did, the time `(update, pairs)` in
    /// milliseconds that the update and bringing the pairs up to date took,
    /// what the latter did (`None` for a [`bvol::tree::PairSet`], which does
    /// not say), and the pairs found.
    pub fn add(
        &mut self,
        update: &UpdateStats,
        (update_ms, pairs_ms): (f64, f64),
        found: Option<CacheUpdate>,
        pairs: usize,
    ) {
        let t = &mut self.totals[FrameKind::of(update) as usize];
        t.frames += 1;
        t.moved += update.moved as u64;
        t.update_ms += update_ms;
        t.pairs_ms += pairs_ms;
        t.pairs += pairs as u64;
        if let Some(found) = found {
            t.told += 1;
            t.queried += found.queried as u64;
            if let Some(search) = found.search {
                t.searched += 1;
                t.node_pairs += search.node_pairs;
            }
        }
    }

    /// The table, one row per kind of frame that occurred: counts, and means
    /// per frame (node pairs: per frame that searched them).
    pub fn table(&self) -> String {
        let mut out = String::from(
            "frame_kind\tframes\tmoved\tupdate_ms\tpairs_ms\tsearched\tnode_pairs\tqueried\tpairs\n",
        );
        for (kind, t) in FrameKind::ALL.iter().zip(&self.totals) {
            if t.frames == 0 {
                continue;
            }
            let mean = |x: f64, of: u64| x / of.max(1) as f64;
            let told = |text: String| if t.told > 0 { text } else { "-".to_string() };
            out.push_str(&format!(
                "{}\t{}\t{:.0}\t{:.3}\t{:.3}\t{}\t{}\t{}\t{:.0}\n",
                kind.name(),
                t.frames,
                mean(t.moved as f64, t.frames),
                mean(t.update_ms, t.frames),
                mean(t.pairs_ms, t.frames),
                told(t.searched.to_string()),
                told(format!("{:.0}", mean(t.node_pairs as f64, t.searched))),
                told(format!("{:.0}", mean(t.queried as f64, t.frames))),
                mean(t.pairs as f64, t.frames),
            ));
        }
        out
    }
}
