//! The `kairos` command line. Argument parsing lives here; each subcommand's work is in a module
//! of `src/cli/`, which calls the library. Exit codes: 0 success, 1 an expectation or a run
//! failed, 2 bad input (DESIGN.md §12).

mod cli;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kairos::report::log::LogFilter;

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
    /// Validate plant models (`.ron`) and parse and link RMPL programs (`.rmpl`), reporting
    /// every error, each located at file:line:col. Programs are linked against the models given
    /// on the same command line (against the names they use when none is given).
    Check {
        /// The files to check (plant models, OCSP files, missions, RMPL programs).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Check each program against each plant model given (thesis §8.1): goals the program
        /// can assert in the same cycle that the model makes inconsistent, and modes no
        /// transition reaches; exit 1 when there is a finding.
        #[arg(long)]
        deep: bool,
    },
    /// Schedule a mission's goal network (the format is documented in
    /// `src/goalnet/mission.rs`) from the plant's most likely initial modes and print every time
    /// point's window and each state variable's XGoals, or why it cannot be scheduled.
    Schedule {
        /// The mission file.
        mission: PathBuf,
        /// Project the schedule to this time (seconds): every point fired as early as the
        /// network lets it, the windows left, and the XGoal each state variable is under.
        #[arg(long, value_name = "SECONDS")]
        at: Option<f64>,
        /// Print a Graphviz drawing (time points, temporal constraints, XGoals) instead.
        #[arg(long)]
        dot: bool,
    },
    /// Compile an RMPL program to its timed hierarchical constraint automaton (THCA) and print
    /// its locations, or a Graphviz drawing.
    Compile {
        /// The RMPL file.
        program: PathBuf,
        /// The program to compile (default: the file's first).
        #[arg(long)]
        entry: Option<String>,
        /// Link against this plant model's variables (default: the names the program uses).
        #[arg(long)]
        plant: Option<PathBuf>,
        /// Print Graphviz DOT: composites as clusters, guards on edges.
        #[arg(long)]
        dot: bool,
    },
    /// Replay a command/observation log (JSON lines; the format is documented in
    /// `src/estimation/log.rs`) through mode estimation and print, per cycle, the most likely
    /// plant states with their probabilities.
    Estimate {
        /// The plant model file.
        #[arg(long)]
        plant: PathBuf,
        /// The log: one JSON object per cycle with `time`, `observations` and `commands`.
        #[arg(long)]
        log: PathBuf,
        /// How many system states TimedME tracks (at least 1).
        #[arg(long, default_value_t = 10, value_parser = cli::limits::parse_kappa)]
        kappa: usize,
        /// TimedME's history window.
        #[command(flatten)]
        window: cli::window_args::WindowArgs,
        /// Use the exact belief update (Figure 6-10; small models only) instead of TimedME.
        #[arg(long)]
        exact: bool,
        /// How many plant states to print per cycle.
        #[arg(long, default_value_t = 3)]
        top: usize,
        /// Print one JSON object per cycle instead of text.
        #[arg(long)]
        json: bool,
        /// Print every cycle (default: only those where something changed).
        #[arg(long)]
        full: bool,
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
    /// Run a scenario (RON; the format is documented in `src/simulation/mod.rs`): the program
    /// against a scripted plant, printing the mission log; exit 0 when every expectation holds,
    /// 1 when one fails, 2 on bad input.
    Run {
        /// The scenario file.
        scenario: PathBuf,
        /// Write every cycle as a line of JSON to this file (format: `src/report/trace.rs`); a
        /// line holds only what changed since the previous lines, unless `--trace-full`.
        #[arg(long)]
        trace: Option<PathBuf>,
        /// Write every field of the trace on every line.
        #[arg(long, requires = "trace")]
        trace_full: bool,
        /// Draw the run as an SVG picture in this file: a swimlane per state variable, goals,
        /// commands and diagnoses, long idle stretches compressed (`src/report/timeline.rs`).
        #[arg(long, value_name = "FILE.svg")]
        timeline: Option<PathBuf>,
        /// Write an interactive report of the run to this HTML file (self-contained): the
        /// timeline, and cycle by cycle the belief, goals, command and why, events and a plant
        /// schematic coloured by estimated mode (`src/report/html.rs`).
        #[arg(long, value_name = "FILE.html")]
        report: Option<PathBuf>,
        /// Print only the summary and the expectations' verdicts, and no progress bar (the bar
        /// shows on standard error only when it is a terminal).
        #[arg(long)]
        quiet: bool,
        /// The model-driven plant's seed, in place of the scenario's: replays a campaign's run
        /// (with the campaign's `--fault` and `--noise`, if it had any).
        #[arg(long)]
        seed: Option<u64>,
        /// Leave the scripted plant's rule lines out of the log.
        #[arg(long)]
        hide_plant: bool,
        /// Log only what concerns these components (repeat the option or separate by commas):
        /// their mode changes and diagnoses, and the lines that name them.
        #[arg(long, value_delimiter = ',', value_name = "COMPONENT")]
        only: Vec<String>,
        /// Log only the cycles at or after this time (seconds).
        #[arg(long, value_name = "SECONDS")]
        from: Option<f64>,
        /// Log only the cycles at or before this time (seconds).
        #[arg(long, value_name = "SECONDS")]
        to: Option<f64>,
        /// The model-driven plant's forced faults and noise.
        #[command(flatten)]
        model: cli::model_args::ModelArgs,
        /// Mode estimation's history window, in place of the scenario's.
        #[command(flatten)]
        window: cli::window_args::WindowArgs,
    },
    /// Explore every path a scenario's `Optional` rules allow (each may fire at any cycle of its
    /// window, or not, at most `--faults` per path), checking every expectation on each; print
    /// the shortest counterexample of each violated one, its mission log and a replay file.
    /// Exit 0 when none is violated, 1 when one is, 2 on bad input.
    Explore(cli::explore::ExploreArgs),
    /// A Monte Carlo campaign: many seeded runs of a scenario with a model-driven plant, in
    /// parallel, tabulated (pass rate, failures with the seeds that replay them, diagnosis
    /// latencies, cycle times); or `campaign merge DIR...` to join shards.
    Campaign(cli::campaign::CampaignArgs),
    /// Measure cycle times per phase (estimation, sequencer, reconfiguration, submissions, whole cycle):
    /// min / median / p99 / max of quiet and busy cycles separately, for sizing a flight
    /// computer. Either run a scenario, or replay an estimation log with `--plant` and `--log`
    /// (estimation alone, once per `--kappa`).
    Bench {
        /// The scenario to run (omit it with `--plant` and `--log`).
        #[arg(required_unless_present = "log", conflicts_with_all = ["plant", "log"])]
        scenario: Option<PathBuf>,
        /// The plant model of the replay log.
        #[arg(long, requires = "log")]
        plant: Option<PathBuf>,
        /// A replay log (the format of `kairos estimate`).
        #[arg(long, requires = "plant")]
        log: Option<PathBuf>,
        /// κ values to measure at (repeat the option or separate by commas; default: the
        /// scenario's κ, or 10 for a log).
        #[arg(long, value_delimiter = ',', value_parser = cli::limits::parse_kappa)]
        kappa: Vec<usize>,
        /// Mode estimation's history window (in place of the scenario's).
        #[command(flatten)]
        window: cli::window_args::WindowArgs,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Bind a plant model to an F´ deployment's JSON dictionary (what `fpp-to-dict` writes):
    /// with `--binding`, check the binding file (every observable reported by a channel, every
    /// control value sent as a command, types matching; errors located); without, print a
    /// starting binding matched by name similarity. The format is documented in
    /// `src/executive/fprime/binding.rs` and docs/embedding.md.
    Bind {
        /// The F´ JSON dictionary.
        #[arg(long, value_name = "DICT")]
        fprime_dict: PathBuf,
        /// The plant model.
        #[arg(long)]
        plant: PathBuf,
        /// The binding file to check.
        #[arg(long)]
        binding: Option<PathBuf>,
    },
}

/// Bad arguments that clap's rules let through: the message and exit code 2.
fn usage_error(message: &str) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(cli::BAD_INPUT)
}

fn main() -> ExitCode {
    let outcome = match Cli::parse().command {
        Command::Solve { file, k, json } => cli::solve::run(&file, k, json),
        Command::Check { files, deep: false } => cli::check::run(&files),
        Command::Bind {
            fprime_dict,
            plant,
            binding,
        } => cli::bind::run(&fprime_dict, &plant, binding.as_deref()),
        Command::Check { files, deep: true } => cli::check::run_deep(&files),
        Command::Schedule { mission, at, dot } => cli::schedule::run(&mission, at, dot),
        Command::Compile {
            program,
            entry,
            plant,
            dot,
        } => cli::compile::run(&program, entry.as_deref(), plant.as_deref(), dot),
        Command::Graph { model, dot } => cli::graph::run(&model, dot),
        Command::Estimate {
            plant,
            log,
            kappa,
            window,
            exact,
            top,
            json,
            full,
        } => cli::estimate::run(&cli::estimate::EstimateArgs {
            plant: &plant,
            log: &log,
            kappa,
            window,
            exact,
            top,
            json,
            full,
        }),
        Command::Plan(args) => cli::plan::run(&args),
        Command::Run {
            scenario,
            trace,
            trace_full,
            timeline,
            report,
            quiet,
            seed,
            hide_plant,
            only,
            from,
            to,
            model,
            window,
        } => cli::run::run(&cli::run::RunArgs {
            scenario: &scenario,
            trace: trace.as_deref(),
            trace_full,
            timeline: timeline.as_deref(),
            report: report.as_deref(),
            quiet,
            seed,
            filter: LogFilter {
                hide_plant,
                only,
                from: from.unwrap_or(f64::NEG_INFINITY),
                to: to.unwrap_or(f64::INFINITY),
            },
            model: &model,
            window,
        }),
        Command::Campaign(args) => cli::campaign::run(&args),
        Command::Explore(args) => cli::explore::run(&args),
        Command::Bench {
            scenario,
            plant,
            log,
            kappa,
            window,
            json,
        } => {
            let target = match (&scenario, &plant, &log) {
                (Some(scenario), _, _) => cli::bench::BenchTarget::Scenario(scenario, &kappa),
                (None, Some(plant), Some(log)) => cli::bench::BenchTarget::Log {
                    plant,
                    log,
                    kappas: if kappa.is_empty() { &[10] } else { &kappa },
                },
                _ => {
                    return usage_error("kairos bench needs a SCENARIO, or --plant and --log");
                }
            };
            cli::bench::run(&target, window, json)
        }
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("{}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}
