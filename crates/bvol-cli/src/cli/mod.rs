//! Command-line arguments and dispatch.

mod bench;
mod bench_world;
mod breakdown;
mod fit;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// bvol: bounding volumes, broadphase and narrow phase for rigid bodies.
#[derive(Parser, Debug)]
#[command(name = "bvol", version)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Fit every kind of bound by every method to a mesh's vertices and compare
    /// them: size, ratio to the best of its kind, and time.
    Fit {
        /// The mesh, a Wavefront OBJ file (every object's vertices are used).
        mesh: PathBuf,
        /// Print a JSON array, one object per result, bound included.
        #[arg(long)]
        json: bool,
    },
    /// Benchmarks.
    #[command(subcommand)]
    Bench(Bench),
}

#[derive(Subcommand, Debug)]
enum Bench {
    /// Broadphase: tree update + every overlapping pair, per frame, on a
    /// generated scene or a box trace; one line in the box-trace bench format.
    Pairs(bench::PairsArgs),
    /// The whole frame of a world of mesh-shaped bodies: pairs and time of
    /// each stage (tree candidates, after spheres, after OBBs, touching).
    World(bench_world::WorldArgs),
}

/// The most threads `--threads` takes: rayon starts one OS thread each, and
/// past a few thousand the OS refuses them or the pool takes minutes to start;
/// no machine this tool runs on has anywhere near this many cores.
const MAX_THREADS: usize = 1024;

/// Parses `--threads`: a whole number in `1..=MAX_THREADS`.
fn threads(arg: &str) -> Result<usize, String> {
    match arg.parse::<usize>() {
        Ok(k) if (1..=MAX_THREADS).contains(&k) => Ok(k),
        _ => Err(format!("expected a whole number from 1 to {MAX_THREADS}")),
    }
}

/// Runs a command; the error is one line for the user.
pub fn run(args: Args) -> Result<(), String> {
    match args.command {
        Command::Fit { mesh, json } => fit::run(&mesh, json),
        Command::Bench(Bench::Pairs(args)) => bench::run(args),
        Command::Bench(Bench::World(args)) => bench_world::run(args),
    }
}
