//! The `kairos` command line. Argument parsing lives here; each subcommand's work is in a module
//! of `src/cli/`, which calls the library. Exit codes: 0 success, 1 an expectation or a run
//! failed, 2 bad input (DESIGN.md §12).

mod cli;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// kairos: a timed model-based executive.
#[derive(Parser)]
#[command(name = "kairos", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve an optimal constraint satisfaction problem (OCSP) file with OPSAT and print the k
    /// best solutions, cheapest (most probable) first.
    Solve {
        /// The OCSP file (RON; the format is documented in `src/opsat/file.rs`).
        file: PathBuf,
        /// How many solutions to print.
        #[arg(short, default_value_t = 1)]
        k: usize,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Parse and link RMPL programs and report every error, each located at file:line:col.
    Check {
        /// The files to check (`.rmpl`).
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Compile an RMPL program to its timed hierarchical constraint automaton (THCA) and print
    /// its locations, or a Graphviz drawing.
    Compile {
        /// The RMPL file.
        program: PathBuf,
        /// The program to compile (default: the file's first).
        #[arg(long)]
        entry: Option<String>,
        /// Print Graphviz DOT: composites as clusters, guards on edges.
        #[arg(long)]
        dot: bool,
    },
}

fn main() -> ExitCode {
    let outcome = match Cli::parse().command {
        Command::Solve { file, k, json } => cli::solve::run(&file, k, json),
        Command::Check { files } => cli::check::run(&files),
        Command::Compile {
            program,
            entry,
            dot,
        } => cli::compile::run(&program, entry.as_deref(), dot),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("{}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}
