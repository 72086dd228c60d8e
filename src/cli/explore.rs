//! `kairos explore SCENARIO [--faults N] [--depth D] [--budget STATES|SECONDSs] [--jobs J]
//! [--memory BYTES] [--shard i/n --out DIR]`:
//! every path of a scenario its `Optional` rules, `Between` delays and simultaneous deliveries
//! allow, every expectation checked on each
//! (`kairos::exploration`; DESIGN.md §16, thesis §8.1); and `kairos explore merge DIR...`, which
//! joins the shards of one search (`exploration::merge`) and reports as one process would.
//!
//! Prints what was explored (states, paths, time, what the budget left out) and, for each
//! violated expectation, the shortest counterexample: the firings on its path, its mission log
//! (a run of the replay), and the replay itself, written beside the scenario as
//! `<scenario>.counterexample-<k>.ron` (its paths are relative to the scenario's directory) —
//! `kairos run` of it shows the failure again. Exit 0 when no path violates an expectation
//! (within the budget: the output says what was covered), 1 when one does, 2 on bad input or a
//! file that cannot be written.
//!
//! A shard (`--shard i/n`) explores its part of the search and, with `--out`, writes it as
//! `exploration.json` beside the shard's manifest (`super::shards`); it writes no replay file
//! (the shards of one search would write the same names), the merge does.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kairos::exploration::{
    self, Budget, Counterexample, Exploration, ExploreOptions, Finding, Limit, Shard, memory,
    replay_scenario, replay_text,
};
use kairos::report::log::MissionLog;
use kairos::simulation::{self, RunOptions, Scenario};

use super::Failure;
use super::limits::{self, parse_memory, parse_shard};
use super::output::emit;
use super::shards::{self, Manifest};

/// A shard's exploration, in its output directory.
const EXPLORATION: &str = "exploration.json";

/// `kairos explore`'s arguments (for a rover scenario, `super::explore_rover`, only `--budget`,
/// `--memory` and `--quiet` apply).
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct ExploreArgs {
    /// Join shards instead of exploring.
    #[command(subcommand)]
    pub merge: Option<MergeCommand>,
    /// The scenario (its `Optional` rules, `Between` delays and contending simultaneous
    /// deliveries are what is explored), or a rover scenario (the interleavings of its
    /// controller protocol).
    #[arg(required = true)]
    pub scenario: Option<PathBuf>,
    /// At most this many optional rules fire on a path.
    #[arg(long, default_value_t = 1)]
    pub faults: usize,
    /// Cut paths after this many cycles, at least 1 (their eventual expectations are then not
    /// judged).
    #[arg(long, value_name = "CYCLES", value_parser = clap::value_parser!(u64).range(1..))]
    pub depth: Option<u64>,
    /// Stop after this many states (`100000`) or this much wall time (`90s`); the output says
    /// what was covered.
    #[arg(long, value_name = "STATES|SECONDSs", value_parser = parse_budget)]
    pub budget: Option<Budget>,
    /// Threads, at most the machine's cores (default, 0: one per core).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Stop, as a budget does, once the process holds this much memory (`4G`, `512M`).
    #[arg(long, value_name = "BYTES", value_parser = parse_memory, default_value = "4G")]
    pub memory: u64,
    /// Explore only shard i of n of the search (`exploration::Shard`), such as `--shard 3/8`;
    /// `kairos explore merge` joins the shards' `--out` directories.
    #[arg(long, value_name = "i/n", value_parser = parse_shard)]
    pub shard: Option<(u64, u64)>,
    /// Write the shard's manifest and its exploration (`exploration.json`) in this directory.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print the summary and the counterexamples' paths, not their mission logs, and no
    /// progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Do not write the counterexamples' replay files.
    #[arg(long)]
    pub no_replay: bool,
}

/// `kairos explore merge`.
#[derive(clap::Subcommand)]
pub enum MergeCommand {
    /// Join the shards of one search (their `--out` directories) and report it whole.
    Merge {
        /// The shards' output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Print the summary and the counterexamples' paths, not their mission logs.
        #[arg(long)]
        quiet: bool,
        /// Do not write the counterexamples' replay files.
        #[arg(long)]
        no_replay: bool,
    },
}

/// `100000` (states) or `90s` (seconds).
fn parse_budget(text: &str) -> Result<Budget, String> {
    let expected = "a number of states (`100000`) or of seconds (`90s`)";
    if let Some(seconds) = text.strip_suffix('s') {
        let seconds: f64 = seconds
            .parse()
            .map_err(|_| format!("`{text}` is not {expected}"))?;
        return limits::duration(seconds)
            .map(Budget::Time)
            .map_err(|why| format!("`{text}`: {why}; expected {expected}"));
    }
    match text.parse::<u64>() {
        Ok(n) if n > 0 => Ok(Budget::States(n)),
        _ => Err(format!("`{text}` is not {expected}")),
    }
}

/// Loads and explores the scenario (or merges shards); the outcome is the exit code.
pub fn run(args: &ExploreArgs) -> Result<(), Failure> {
    if let Some(MergeCommand::Merge {
        dirs,
        quiet,
        no_replay,
    }) = &args.merge
    {
        return merge(dirs, *quiet, *no_replay);
    }
    let Some(path) = &args.scenario else {
        return Err(Failure::bad_input("error: kairos explore needs SCENARIO"));
    };
    let memory = limits::memory_budget(args.memory)?;
    if super::explore_rover::is_rover(path) {
        return super::explore_rover::run(path, args, memory);
    }
    let scenario = simulation::load(path).map_err(Failure::bad_input)?;
    let (index, count) = args.shard.unwrap_or((0, 1));
    let options = ExploreOptions {
        faults: args.faults,
        depth: args.depth,
        budget: args.budget.unwrap_or(Budget::Unbounded),
        jobs: limits::threads(args.jobs)?,
        memory,
        shard: Shard { index, count },
    };
    let manifest = match &args.out {
        Some(out) => Some((out, manifest(path, &scenario, args, (index, count))?)),
        None => None,
    };
    let bar = progress_bar(args.quiet);
    let explored = exploration::explore(&scenario, &options, &|states| bar.inc(states));
    bar.finish_and_clear();
    let explored = explored.map_err(|e| Failure::bad_input(format!("error: {e}")))?;
    if let Some((out, manifest)) = manifest {
        write_shard(out, &manifest, &explored)?;
    }
    let sharded = count > 1;
    let heading = summary(&scenario, &options, &explored);
    let heading = if sharded {
        format!("shard {index}/{count} of the search (merge the shards for the whole)\n{heading}")
    } else {
        heading
    };
    report(
        path,
        &scenario,
        &heading,
        &explored,
        args.quiet,
        args.no_replay || sharded,
    )
}

/// The manifest of a shard: the options every shard of the search shares.
fn manifest(
    path: &Path,
    scenario: &Scenario,
    args: &ExploreArgs,
    shard: (u64, u64),
) -> Result<Manifest, Failure> {
    let budget = match args.budget {
        None | Some(Budget::Unbounded) => serde_json::Value::Null,
        Some(Budget::States(n)) => serde_json::json!({ "states": n }),
        Some(Budget::Time(t)) => serde_json::json!({ "seconds": t.as_secs_f64() }),
    };
    let options = [
        ("faults", serde_json::json!(args.faults)),
        ("depth", serde_json::json!(args.depth)),
        ("budget", budget),
    ];
    let options = options.map(|(k, v)| (k.to_string(), v)).into();
    Manifest::new("explore", path, &scenario.name, options, shard)
}

/// Writes the shard's manifest and exploration into `out`.
fn write_shard(out: &Path, manifest: &Manifest, explored: &Exploration) -> Result<(), Failure> {
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::io(format!("error: cannot create {}: {e}", out.display())))?;
    manifest.write(out)?;
    let path = out.join(EXPLORATION);
    let text = serde_json::to_string(explored)
        .map_err(|e| Failure::failed(format!("error: cannot encode the exploration: {e}")))?;
    std::fs::write(&path, text + "\n")
        .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))
}

/// `kairos explore merge`: the shards of one search, joined and reported whole.
fn merge(dirs: &[PathBuf], quiet: bool, no_replay: bool) -> Result<(), Failure> {
    let manifests = shards::read_all("explore", dirs)?;
    let first = &manifests[0];
    let path = &first.path;
    let scenario = simulation::load(path).map_err(|e| {
        Failure::bad_input(format!(
            "{e}\n  (the shards' scenario, read again to word the merged report)"
        ))
    })?;
    let mut parts = Vec::new();
    for dir in dirs {
        let file = dir.join(EXPLORATION);
        let text = std::fs::read_to_string(&file).map_err(|e| {
            Failure::bad_input(format!("error: cannot read {}: {e}", file.display()))
        })?;
        let part: Exploration = serde_json::from_str(&text).map_err(|e| {
            Failure::bad_input(format!(
                "error: {}:{}:{}: not an exploration: {e}",
                file.display(),
                e.line(),
                e.column()
            ))
        })?;
        if part.failing_paths.len() != scenario.expectations.len() {
            return Err(Failure::bad_input(format!(
                "error: {}: {} expectations, the scenario has {}",
                file.display(),
                part.failing_paths.len(),
                scenario.expectations.len()
            )));
        }
        parts.push(part);
    }
    let explored = exploration::merge(parts);
    let faults = first
        .options
        .get("faults")
        .and_then(serde_json::Value::as_u64);
    let heading = format!(
        "merged from {} shards\n{}",
        dirs.len(),
        summary(
            &scenario,
            &ExploreOptions {
                faults: faults.map_or(0, |f| usize::try_from(f).unwrap_or(usize::MAX)),
                jobs: dirs.len(),
                ..ExploreOptions::default()
            },
            &explored
        )
    );
    report(path, &scenario, &heading, &explored, quiet, no_replay)
}

/// Prints the summary and each counterexample (with its replay file and mission log); the exit
/// code says whether one was found.
fn report(
    path: &Path,
    scenario: &Scenario,
    heading: &str,
    explored: &Exploration,
    quiet: bool,
    no_replay: bool,
) -> Result<(), Failure> {
    emit(heading)?;
    for (k, counterexample) in explored.counterexamples.iter().enumerate() {
        let replay = (!no_replay)
            .then(|| write_replay(path, scenario, counterexample, k + 1))
            .transpose()?;
        emit(&describe(
            scenario,
            counterexample,
            k + 1,
            replay.as_deref(),
        ))?;
        if !quiet {
            emit(&mission_log(scenario, counterexample))?;
        }
    }
    match explored.counterexamples.len() {
        0 => Ok(()),
        n => Err(Failure::failed(format!(
            "error: scenario `{}`: {n} counterexample{} found",
            scenario.name,
            if n == 1 { "" } else { "s" }
        ))),
    }
}

/// States, paths, time and coverage.
fn summary(scenario: &Scenario, options: &ExploreOptions, explored: &Exploration) -> String {
    let paths = &explored.paths;
    let mut text = format!(
        "explore `{}`: at most {} optional rule{} per path, {} worker{}\n\
         {} states; {} paths to their end ({} at the end time, {} settled, {} cut at the depth \
         bound, {} stopped by an error), {} merged into others; longest {} cycles; {:.2} s\n",
        scenario.name,
        options.faults,
        if options.faults == 1 { "" } else { "s" },
        options.jobs,
        if options.jobs == 1 { "" } else { "s" },
        explored.states,
        paths.complete(),
        paths.ended,
        paths.settled,
        paths.truncated,
        paths.errors,
        paths.merged,
        explored.longest,
        explored.wall.as_secs_f64(),
    );
    let budget = match explored.limit {
        Some(Limit::Memory) => format!(
            "the memory budget ({}) ran out",
            memory::format_bytes(options.memory)
        ),
        Some(Limit::Time) => "the time budget ran out".to_string(),
        Some(Limit::States) | None => "the budget ran out".to_string(),
    };
    text.push_str(&match explored.cut_at {
        None => "covered: every path\n".to_string(),
        Some(cycle) => format!(
            "covered: partly — {budget}; every path whose first choice (an optional \
             rule, a later landing, another order) falls \
             before cycle {cycle} ({} s) was explored, the rest not\n",
            cycle as f64 * scenario.cycle
        ),
    });
    let violated = explored
        .counterexamples
        .iter()
        .filter(|c| matches!(c.finding, Finding::Violated { .. }))
        .count();
    text.push_str(&format!(
        "expectations: {} of {} hold on every path explored\n",
        scenario.expectations.len() - violated,
        scenario.expectations.len()
    ));
    for (expectation, failing) in scenario.expectations.iter().zip(&explored.failing_paths) {
        if *failing > 0 {
            text.push_str(&format!(
                "  `{}` fails on {failing} path{} to the end\n",
                expectation.label,
                if *failing == 1 { "" } else { "s" }
            ));
        }
    }
    text
}

/// The counterexample's finding, path and replay file.
fn describe(
    scenario: &Scenario,
    counterexample: &Counterexample,
    k: usize,
    replay: Option<&Path>,
) -> String {
    let what = match &counterexample.finding {
        Finding::Violated { label, reason, .. } => format!("`{label}` fails: {reason}"),
        Finding::Error(message) => format!("the run stops: {message}"),
    };
    let rules = scenario.script.rules();
    let time = |cycle: u64| cycle as f64 * scenario.cycle;
    let path: Vec<String> = (counterexample.choices.iter())
        .map(|c| {
            let at = time(c.cycle);
            format!("`{}` at {at} s (cycle {})", rules[c.rule].name, c.cycle)
        })
        .collect();
    let path = if path.is_empty() {
        "no optional rule fires".to_string()
    } else {
        path.join(", then ")
    };
    let landed = (counterexample.landings.iter()).map(|l| {
        let (fired, lands) = (time(l.fired), time(l.lands));
        format!(
            "`{}` fired at {fired} s lands at {lands} s (cycle {})",
            rules[l.rule].name, l.lands
        )
    });
    let delivered = (counterexample.deliveries.iter()).map(|d| {
        let names: Vec<String> = (d.order.iter())
            .map(|&r| format!("`{}`", rules[r].name))
            .collect();
        let at = time(d.cycle);
        format!(
            "at {at} s (cycle {}) applied {}",
            d.cycle,
            names.join(" then ")
        )
    });
    let path: String = std::iter::once(path)
        .chain(landed)
        .chain(delivered)
        .collect::<Vec<String>>()
        .join("; ");
    let mut text = format!(
        "\ncounterexample {k}: {what}\n  at cycle {} ({} s); path: {path}\n",
        counterexample.cycle,
        counterexample.cycle as f64 * scenario.cycle
    );
    if let Some(replay) = replay {
        text.push_str(&format!("  replay: kairos run {}\n", replay.display()));
    }
    text
}

/// Writes the replay beside the scenario.
fn write_replay(
    path: &Path,
    scenario: &Scenario,
    counterexample: &Counterexample,
    k: usize,
) -> Result<PathBuf, Failure> {
    let text = replay_text(scenario, counterexample).ok_or_else(|| {
        Failure::failed(format!(
            "error: {}: no line starts with `Scenario(`; the replay cannot be written",
            path.display()
        ))
    })?;
    let stem = path.file_stem().map_or_else(
        || "scenario".to_string(),
        |s| s.to_string_lossy().to_string(),
    );
    let replay = path.with_file_name(format!("{stem}.counterexample-{k}.ron"));
    std::fs::write(&replay, text)
        .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", replay.display())))?;
    Ok(replay)
}

/// The mission log of the counterexample's path: a run of the replay.
fn mission_log(scenario: &Scenario, counterexample: &Counterexample) -> String {
    let replay = replay_scenario(scenario, counterexample);
    let mut log = MissionLog::new(&replay);
    let mut text = log.header();
    let outcome = simulation::run(&replay, RunOptions::default(), &mut |record| {
        if let Some(block) = log.cycle(record) {
            text.push_str(&block);
        }
    });
    match outcome {
        Ok(outcome) => text.push_str(&log.summary(&outcome)),
        Err(e) => text.push_str(&format!("the run stops: {e}\n")),
    }
    text
}

/// The number of states explored, on standard error when it is a terminal.
fn progress_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    // The template is a constant; were it refused, the default style still shows the count.
    if let Ok(style) =
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {human_pos} states ({per_sec})")
    {
        bar.set_style(style);
    }
    bar
}
