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
    /// Load and validate a plant model (TCCA, RON; the format is documented in
    /// `src/plant/file.rs`). Temporary: becomes part of `kairos check FILES…`.
    CheckModel {
        /// The plant model file.
        model: PathBuf,
    },
    /// Show a plant model's component automata: a text listing, or a Graphviz drawing with one
    /// cluster per component.
    Graph {
        /// The plant model file.
        model: PathBuf,
        /// Print Graphviz DOT instead of text.
        #[arg(long)]
        dot: bool,
    },
    /// Mode reconfiguration: the goal state goal interpretation picks and the command sequence
    /// the reactive planner produces when every command succeeds nominally; or, with
    /// `--policies`, the causal graph and every component's concurrent policy.
    Plan(cli::plan::PlanArgs),
}

fn main() -> ExitCode {
    let outcome = match Cli::parse().command {
        Command::Solve { file, k, json } => cli::solve::run(&file, k, json),
        Command::CheckModel { model } => cli::check_model::check_model(&model),
        Command::Graph { model, dot } => cli::graph::run(&model, dot),
        Command::Plan(args) => cli::plan::run(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("{}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}
