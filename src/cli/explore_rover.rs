//! `kairos explore ROVER_SCENARIO`: the controller protocol of seed 001 on every interleaving
//! of its messages (`kairos::protocol`; mds-goal-networks.md §4.2). `kairos explore` hands a
//! file here when it is a `RoverScenario(...)`.
//!
//! Prints what was explored (configurations, steps, terminal configurations, interleavings,
//! time, coverage), whether each property holds, and for each violated one the shortest
//! counterexample as a message trace. `--budget`, `--memory` and `--quiet` apply; `--faults`,
//! `--depth`, `--jobs` and `--shard` concern a script's optional rules and are refused here
//! (the protocol's spaces are searched by one thread, in one process). Exit 0 when every property holds on every interleaving,
//! 1 when one does not or the budget cut the search, 2 on bad input.

use std::path::Path;

use kairos::diagnostic::Source;
use kairos::exploration::protocol::{Property, ProtocolExploration, explore};
use kairos::exploration::{Budget, Limit};
use kairos::protocol::CoaController;
use kairos::protocol::scenario::{self, RoverScenario};

use super::Failure;
use super::explore::ExploreArgs;
use super::output::emit;

/// Whether the file at `path` is a rover scenario (unreadable files are left to the scripted
/// scenarios' loader, which reports them).
pub fn is_rover(path: &Path) -> bool {
    Source::read(path).is_ok_and(|source| scenario::is_rover_scenario(&source.text))
}

/// Loads and explores the rover scenario at `path` within `memory` bytes; the outcome is the
/// exit code.
pub fn run(path: &Path, args: &ExploreArgs, memory: u64) -> Result<(), Failure> {
    if args.shard.is_some() || args.out.is_some() {
        return Err(Failure::bad_input(format!(
            "error: {}: a rover scenario's protocol is explored in one process: --shard and \
             --out apply to scripted scenarios",
            path.display()
        )));
    }
    let scenario = scenario::load(path).map_err(Failure::bad_input)?;
    let controller = CoaController::new(scenario.initial_value());
    let explored = explore(
        &scenario,
        controller,
        args.budget.unwrap_or(Budget::Unbounded),
        memory,
    );
    emit(&report(&scenario, &explored, args.quiet))?;
    if explored.holds() {
        return Ok(());
    }
    Err(Failure::failed(match explored.counterexamples.len() {
        0 => format!(
            "error: scenario `{}`: the budget ran out before every interleaving was explored",
            scenario.name
        ),
        n => format!(
            "error: scenario `{}`: {n} propert{} violated",
            scenario.name,
            if n == 1 { "y" } else { "ies" }
        ),
    }))
}

/// The summary, the properties and the counterexamples (their traces unless `quiet`).
pub fn report(scenario: &RoverScenario, explored: &ProtocolExploration, quiet: bool) -> String {
    let paths = explored
        .paths
        .map_or_else(|| "not counted".to_string(), |n| n.to_string());
    let mut text = format!(
        "explore `{}`: the controller protocol on every interleaving of its messages\n\
         {} states, {} steps; {} terminal configuration{}, {paths} interleaving{} to them; {} \
         stopped at a violation, {} outside the scenario's arrival windows; deepest {} steps; \
         {}\n",
        scenario.name,
        explored.states,
        explored.transitions,
        explored.terminals,
        plural(explored.terminals),
        if explored.paths == Some(1) { "" } else { "s" },
        explored.stopped,
        explored.excluded,
        explored.depth,
        wall(explored.wall),
    );
    text.push_str(match explored.limit {
        None => "covered: every interleaving\n",
        Some(Limit::Memory) => {
            "covered: partly — the memory budget ran out before every configuration was explored\n"
        }
        Some(_) => "covered: partly — the budget ran out before every configuration was explored\n",
    });
    let failed = |p: Property| explored.counterexamples.iter().any(|c| c.property == p);
    let held = Property::ALL.iter().filter(|&&p| !failed(p)).count();
    text.push_str(&format!(
        "properties: {held} of {} hold on every interleaving{}\n",
        Property::ALL.len(),
        if explored.cut { " explored" } else { "" }
    ));
    for property in Property::ALL {
        let verdict = if failed(property) { "FAILS" } else { "holds" };
        text.push_str(&format!(
            "  {property}: {} — {verdict}\n",
            property.statement()
        ));
    }
    for (k, counterexample) in explored.counterexamples.iter().enumerate() {
        text.push_str(&format!(
            "\ncounterexample {}: {} fails: {}\n  trace ({} step{}):\n",
            k + 1,
            counterexample.property,
            counterexample.reason,
            counterexample.trace.len(),
            plural(counterexample.trace.len() as u64),
        ));
        if !quiet {
            for line in &counterexample.trace {
                text.push_str(&format!("  {line}\n"));
            }
        }
    }
    text
}

/// Wall time: these searches take milliseconds, so below a second they are shown in them.
fn wall(time: std::time::Duration) -> String {
    match time.as_secs_f64() {
        s if s < 1.0 => format!("{:.2} ms", s * 1e3),
        s => format!("{s:.2} s"),
    }
}

fn plural(n: u64) -> &'static str {
    if n == 1 { "" } else { "s" }
}
