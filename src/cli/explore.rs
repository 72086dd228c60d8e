//! `kairos explore SCENARIO [--faults N] [--depth D] [--budget STATES|SECONDSs] [--jobs J]`:
//! every path of a scenario its `Optional` rules, `Between` delays and simultaneous deliveries
//! allow, every expectation checked on each
//! (`kairos::exploration`; DESIGN.md §16, thesis §8.1).
//!
//! Prints what was explored (states, paths, time, what the budget left out) and, for each
//! violated expectation, the shortest counterexample: the firings on its path, its mission log
//! (a run of the replay), and the replay itself, written beside the scenario as
//! `<scenario>.counterexample-<k>.ron` (its paths are relative to the scenario's directory) —
//! `kairos run` of it shows the failure again. Exit 0 when no path violates an expectation
//! (within the budget: the output says what was covered), 1 when one does, 2 on bad input.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kairos::exploration::{
    self, Budget, Counterexample, Exploration, ExploreOptions, Finding, replay_scenario,
    replay_text,
};
use kairos::report::log::MissionLog;
use kairos::simulation::{self, RunOptions, Scenario};

use super::Failure;
use super::output::emit;

/// `kairos explore`'s arguments (for a rover scenario, `super::explore_rover`, only `--budget`
/// and `--quiet` apply).
#[derive(clap::Args)]
pub struct ExploreArgs {
    /// The scenario (its `Optional` rules, `Between` delays and contending simultaneous
    /// deliveries are what is explored), or a rover scenario (the interleavings of its
    /// controller protocol).
    pub scenario: PathBuf,
    /// At most this many optional rules fire on a path.
    #[arg(long, default_value_t = 1)]
    pub faults: usize,
    /// Cut paths after this many cycles (their eventual expectations are then not judged).
    #[arg(long, value_name = "CYCLES")]
    pub depth: Option<u64>,
    /// Stop after this many states (`100000`) or this much wall time (`90s`); the output says
    /// what was covered.
    #[arg(long, value_name = "STATES|SECONDSs", value_parser = parse_budget)]
    pub budget: Option<Budget>,
    /// Threads (default: one per core).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Print the summary and the counterexamples' paths, not their mission logs, and no
    /// progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Do not write the counterexamples' replay files.
    #[arg(long)]
    pub no_replay: bool,
}

/// `100000` (states) or `90s` (seconds).
fn parse_budget(text: &str) -> Result<Budget, String> {
    let expected = "a number of states (`100000`) or of seconds (`90s`)";
    if let Some(seconds) = text.strip_suffix('s') {
        return match seconds.parse::<f64>() {
            Ok(s) if s.is_finite() && s > 0.0 => Ok(Budget::Time(Duration::from_secs_f64(s))),
            _ => Err(format!("`{text}` is not {expected}")),
        };
    }
    match text.parse::<u64>() {
        Ok(n) if n > 0 => Ok(Budget::States(n)),
        _ => Err(format!("`{text}` is not {expected}")),
    }
}

/// Loads and explores the scenario; the outcome is the exit code.
pub fn run(args: &ExploreArgs) -> Result<(), Failure> {
    if super::explore_rover::is_rover(&args.scenario) {
        return super::explore_rover::run(args);
    }
    let scenario = simulation::load(&args.scenario).map_err(Failure::bad_input)?;
    let jobs = match args.jobs {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    let options = ExploreOptions {
        faults: args.faults,
        depth: args.depth,
        budget: args.budget.unwrap_or(Budget::Unbounded),
        jobs,
    };
    let bar = progress_bar(args.quiet);
    let explored = exploration::explore(&scenario, &options, &|states| bar.inc(states));
    bar.finish_and_clear();
    let explored = explored.map_err(|e| Failure::bad_input(format!("error: {e}")))?;
    emit(&summary(&scenario, &options, &explored))?;
    for (k, counterexample) in explored.counterexamples.iter().enumerate() {
        let replay = (!args.no_replay)
            .then(|| write_replay(&args.scenario, &scenario, counterexample, k + 1))
            .transpose()?;
        emit(&describe(
            &scenario,
            counterexample,
            k + 1,
            replay.as_deref(),
        ))?;
        if !args.quiet {
            emit(&mission_log(&scenario, counterexample))?;
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
    text.push_str(&match explored.cut_at {
        None => "covered: every path\n".to_string(),
        Some(cycle) => format!(
            "covered: partly — the budget ran out; every path whose first choice (an optional \
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
        .map_err(|e| Failure::failed(format!("error: cannot write {}: {e}", replay.display())))?;
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
