//! The update's tuning constants, each with the reason for its value: the
//! policy's thresholds first, then how far ahead the kernels ask for memory
//! and how finely they split work between threads. The defaults a user can
//! change are in [`Config`](crate::Config).

/// More than one leaf in this many jumping clear of its old bound is many.
/// In one frame (mass motion: bodies falling faster than their size, and
/// their neighbours with them) they are refit in place and left to the
/// staged rebuilds: reinserting them all, or rebuilding the tree in each
/// such frame, costs more than the pair search loses to their stretched
/// ancestors. Over a staged rebuild's frames (a trickle of teleports),
/// reinserting that many at its install would cost about as much as
/// rebuilding the tree in one go, so the rebuild then takes fewer frames.
pub(crate) const MANY_JUMPS: usize = 16;

/// In a frame of mass motion whose refit finds the SAH cost this many
/// times [`Config::drift`](crate::Config::drift) above its cost after the
/// last build, the tree is rebuilt in one go at once. Bodies that keep
/// moving several times their size a frame (debris from an explosion, a
/// fast swarm) outrun a staged build: its topology places them where they
/// were frames before, and the tree's cost, and the pair search's with it,
/// grows without end (the `fast` scene's frames rose past a second). Bodies
/// falling onto a pile stretch it far less, and stay with the staged builds.
pub(crate) const DRIFT_AT_ONCE: f64 = 4.0;

/// A staged rebuild starts when the SAH cost has drifted this fraction of
/// [`Config::drift`](crate::Config::drift) above its cost after the last
/// build: the tree drifts on while the build runs, and its topology places
/// the leaves where they were when it began, so starting early installs it
/// about when a rebuild in one go at the full drift would have been made,
/// and the pair searches cost what they cost with those rebuilds.
pub(crate) const DRIFT_STAGED: f64 = 0.35;

/// Steps a frame of a rebuild staged among a trickle of teleports: built in
/// three frames, its install included, it finds a third as many of them
/// placed where they were as a build taking one step a frame would.
pub(crate) const TRICKLE_PACE: usize = 3;

/// How many nodes ahead of the one being refit the refit asks for the
/// user's leaf bounds, and how many leaves ahead a listed update or an
/// install asks for a leaf's parent node. Leaf ids follow the user's order,
/// not the tree's, so those reads are scattered: past the caches, waiting
/// for each in turn would take about half the refit.
pub(crate) const PREFETCH_AHEAD: usize = 16;

/// Leaves from which the scan for moved leaves asks for their bounds
/// [`PREFETCH_AHEAD`] nodes early. Past the caches (a million leaves) it
/// waits on each bound read otherwise. Below, where bounds and nodes fit
/// them, the requests save about as much where ids fall in a random order
/// as they cost where ids follow the tree's (a flat layer laid out row by
/// row), which the processor's own read-ahead already serves.
pub(crate) const FAR_LEAVES: usize = 1 << 18;

/// How many leaves ahead the reinsertion asks for the parent node of the
/// leaf it will take out: jumps land anywhere in the tree, and a few
/// removals' time is enough for the node to arrive.
pub(crate) const REMOVE_AHEAD: usize = 4;

/// Reinserted leaves a rayon task looks up the slots of, at least: a lookup
/// is one descent from the root, under a microsecond (the teleport scene's
/// thousand a frame take about 0.7 ms), and a task costs about as much as a
/// few.
pub(crate) const SIBLINGS_A_TASK: usize = 32;

/// How many nodes ahead the refit asks for the node it will refit: the
/// nodes are walked backwards, and past the caches (a million leaves) the
/// refit would otherwise wait on each; within them the request costs
/// nothing.
pub(crate) const NODES_AHEAD: usize = 64;

/// How many pairs ahead a pass over a kept pair list asks for them. The
/// pass looks up each pair's two ids in the change log's bits, and past the
/// caches (a million leaves' pairs) the processor's own read-ahead does not
/// keep up with it.
pub(crate) const PAIRS_AHEAD: usize = 256;

/// A tree out of preorder whose last refit found more than one node in
/// this many late (see `Tree::refit_blocks`) is laid out in preorder
/// again, when they piled up over frames, or else refit along a preorder
/// walk: refit in memory order, so many nodes would be refit again, with
/// their ancestors, that the walk costs less.
pub(crate) const WALK_LATE: usize = 64;

/// A tree out of preorder whose shape held through this many refits in a
/// row is laid out in preorder again. A layout costs about a refit, and
/// saves each refit after it a few percent: a shape that held this long
/// is taken to hold long enough to pay for it. A pile whose landings
/// reshape it every few frames never would (laid out at every frame its
/// shape held, its update took 2.25 ms a frame on average against 1.90).
pub(crate) const SETTLED: u32 = 8;

/// Bounds checked by one task of an update's input check: a task a bound
/// would cost more than the check, and a chunk this long is checked in a
/// fraction of a frame.
pub(crate) const CHECK_CHUNK: usize = 16384;

/// Subtrees with at least this many nodes are refit on two rayon tasks;
/// smaller ones cost less to refit than to hand to another thread.
pub(crate) const PARALLEL_REFIT: usize = 8192;

/// Nodes a rayon task sums in the SAH cost's pass over the node array:
/// enough that a task's overhead is lost in its work, few enough to
/// balance two threads or more on 100 000 nodes. Fixed, so that the sum
/// comes out the same on any number of threads.
pub(crate) const PASS_RUN: usize = 4096;

/// Jumped leaves a rayon task lists with their bounds after a refit.
pub(crate) const JUMPS_A_TASK: usize = 4096;
