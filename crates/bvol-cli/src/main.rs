//! The `bvol` command line: fit bounds to a mesh; benchmark the broadphase
//! (`bench pairs`) and the whole frame of a world (`bench world`).

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = cli::Args::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("bvol: {message}");
            ExitCode::from(2)
        }
    }
}
