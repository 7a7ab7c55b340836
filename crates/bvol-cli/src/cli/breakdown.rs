//! `bvol bench pairs --verbose`: the frames grouped by what the tree's
//! update did, and where each group's time went, so that a regression shows
//! in the stage and the kind of frame where it is.

use bvol::tree::{SearchStats, UpdateStats};

/// What a frame's update did, from its [`UpdateStats`].
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
    search_ms: f64,
    node_pairs: u64,
    pairs: u64,
}

/// The frames after the first, summed by kind.
#[derive(Debug, Default)]
pub struct Breakdown {
    totals: [Totals; 4],
}

impl Breakdown {
    /// Adds one frame: what its update did and took, and what its pair
    /// search took (`search` is `None` where the pairs came from a
    /// [`bvol::tree::PairSet`], which does not count its work).
    pub fn add(
        &mut self,
        update: &UpdateStats,
        update_ms: f64,
        search_ms: f64,
        search: Option<SearchStats>,
        pairs: usize,
    ) {
        let kind = FrameKind::of(update);
        let t = &mut self.totals[FrameKind::ALL.iter().position(|&k| k == kind).unwrap_or(0)];
        t.frames += 1;
        t.moved += update.moved as u64;
        t.update_ms += update_ms;
        t.search_ms += search_ms;
        t.node_pairs += search.map_or(0, |s| s.node_pairs);
        t.pairs += pairs as u64;
    }

    /// The table, one row per kind of frame that occurred: means per frame.
    pub fn table(&self, counted: bool) -> String {
        let mut out = String::from(
            "frame_kind\tframes\tmoved\tupdate_ms\tsearch_ms\tnode_pairs\tpairs\tnode_pairs_per_pair\n",
        );
        for (kind, t) in FrameKind::ALL.iter().zip(&self.totals) {
            if t.frames == 0 {
                continue;
            }
            let mean = |x: f64| x / t.frames as f64;
            let (visits, per_pair) = match counted {
                true => (
                    format!("{:.0}", mean(t.node_pairs as f64)),
                    format!("{:.2}", t.node_pairs as f64 / t.pairs.max(1) as f64),
                ),
                false => ("-".to_string(), "-".to_string()),
            };
            out.push_str(&format!(
                "{}\t{}\t{:.0}\t{:.3}\t{:.3}\t{visits}\t{:.0}\t{per_pair}\n",
                kind.name(),
                t.frames,
                mean(t.moved as f64),
                mean(t.update_ms),
                mean(t.search_ms),
                mean(t.pairs as f64),
            ));
        }
        out
    }
}
