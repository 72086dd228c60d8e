//! `kairos explore` (DESIGN.md §16, thesis §8.1 "model checking of timed
//! model-based programs"): every path a scenario's `Optional` rules allow, every expectation
//! checked on each, the shortest counterexample kept and replayable; the executive's `Clone`
//! and fingerprint that the search rests on.

#[path = "support/cli.rs"]
mod cli;

use std::collections::hash_map::DefaultHasher;
use std::hash::Hasher;
use std::path::Path;

use kairos::executive::adapters::{ControlAdapter, MonitorAdapter};
use kairos::executive::{Executive, NamedValue};
use kairos::exploration::{
    Budget, Choice, ExploreOptions, Finding, explore, replay_scenario, replay_text,
};
use kairos::simulation::{self, RunOptions, Scenario, ScriptedPlant};

fn scenario(path: &str) -> Scenario {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    simulation::load(&root.join(path)).unwrap_or_else(|e| panic!("{e}"))
}

fn flameout() -> Scenario {
    scenario("tests/scenarios/explore_flameout.ron")
}

fn options(faults: usize, jobs: usize) -> ExploreOptions {
    ExploreOptions {
        faults,
        jobs,
        ..ExploreOptions::default()
    }
}

/// Item 1: the flame-out may strike at any whole second from 40 s to 70 s while the engine
/// fires; every such path completes or reports the plan failure (the property holds), and the
/// shortest path showing a diagnosis is the earliest flame-out, at 41 s (the engine fires from
/// 40.1 s; 40 s itself finds the thrust still zero, so the rule's condition fails there).
#[test]
fn the_shortest_counterexample_is_the_earliest_flame_out() {
    let scenario = flameout();
    let explored = explore(&scenario, &options(1, 1), &|_| {}).expect("explores");
    assert_eq!(explored.cut_at, None, "every path covered");
    assert_eq!(
        explored.failing_paths[0], 0,
        "completes or reports, on every path"
    );
    assert_eq!(
        explored.counterexamples.len(),
        1,
        "{:?}",
        explored.counterexamples
    );
    let counterexample = &explored.counterexamples[0];
    assert!(matches!(
        &counterexample.finding,
        Finding::Violated { expectation: 1, reason, .. } if reason.starts_with("reported at 41.000 s")
    ));
    let flame_out = scenario.script.rule_named("flame-out").expect("declared");
    assert_eq!(
        counterexample.choices,
        [Choice {
            cycle: 410,
            rule: flame_out
        }]
    );
    // One path per flame-out second (41..=70 s) and the path without one.
    assert_eq!(explored.paths.complete(), 31);
    assert_eq!(explored.failing_paths[1], 30);
}

/// Deterministic and parallel: two workers find the same paths and counterexamples as one.
#[test]
fn workers_change_nothing_but_the_time() {
    let scenario = flameout();
    let one = explore(&scenario, &options(2, 1), &|_| {}).expect("explores");
    let two = explore(&scenario, &options(2, 2), &|_| {}).expect("explores");
    assert_eq!(one.counterexamples, two.counterexamples);
    assert_eq!(one.paths, two.paths);
    assert_eq!(one.states, two.states);
    assert_eq!(one.failing_paths, two.failing_paths);
}

/// With no fault allowed the search is the scripted run: one path, which holds.
#[test]
fn no_fault_is_the_nominal_run() {
    let explored = explore(&flameout(), &options(0, 1), &|_| {}).expect("explores");
    assert_eq!(explored.paths.complete(), 1);
    assert!(explored.holds());
}

/// A budget stops the search cleanly and says from which cycle on it did not cover.
#[test]
fn a_state_budget_says_what_was_covered() {
    let budget = ExploreOptions {
        budget: Budget::States(450),
        ..options(1, 1)
    };
    let explored = explore(&flameout(), &budget, &|_| {}).expect("explores");
    let cut = explored.cut_at.expect("the budget ran out");
    assert!(cut <= 450, "the fault-free path is cut at cycle {cut}");
    assert!(!explored.holds());
}

/// The counterexample replays: the scenario with its firings pinned fails the same
/// expectation in a plain run, and so does the replay file's text, loaded as a scenario.
#[test]
fn the_counterexample_replays_in_a_run_and_as_a_file() {
    let scenario = flameout();
    let explored = explore(&scenario, &options(1, 1), &|_| {}).expect("explores");
    let counterexample = &explored.counterexamples[0];
    let run = |replay: &Scenario| {
        simulation::run(replay, RunOptions::default(), &mut |_| {}).expect("runs")
    };
    let outcome = run(&replay_scenario(&scenario, counterexample));
    assert!(outcome.verdicts[0].holds());
    assert!(!outcome.verdicts[1].holds());

    let text = replay_text(&scenario, counterexample).expect("a Scenario( line");
    assert!(text.contains(r#"choose: { "flame-out": 41.0 }"#), "{text}");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenarios");
    let source = kairos::diagnostic::Source::new("replay.ron", text);
    let replay = simulation::load_source(&source, &dir).unwrap_or_else(|e| panic!("{e}"));
    assert!(!run(&replay).verdicts[1].holds());
    // The nominal run of the explored scenario fires no optional rule: it passes.
    assert!(run(&scenario).passed());
}

fn fingerprint(executive: &Executive) -> u64 {
    let mut hasher = DefaultHasher::new();
    executive.fingerprint(&mut hasher);
    hasher.finish()
}

/// The search rests on `Executive: Clone` (the SAT solver rebuilt from its clauses): a clone
/// taken mid-run has the original's fingerprint and, fed the same observations, issues the same
/// commands and reaches the same states as the original, cycle by cycle, through the burn.
#[test]
fn a_cloned_executive_runs_as_the_original() {
    let scenario = flameout();
    let mut original = Executive::builder(scenario.plant.clone(), scenario.program.clone())
        .kappa(scenario.kappa)
        .build()
        .expect("builds");
    let mut plant = ScriptedPlant::new(&scenario.script);
    let mut clone: Option<Executive> = None;
    for cycle in 0..500u32 {
        let time = f64::from(cycle) * scenario.cycle;
        if cycle == 200 {
            let copy = original.clone();
            assert_eq!(fingerprint(&copy), fingerprint(&original));
            clone = Some(copy);
        }
        let observation = plant.observe(time);
        let step = original.step(time, &observation).expect("steps");
        if let Some(copy) = clone.as_mut() {
            let twin = copy.step(time, &observation).expect("steps");
            assert_eq!(twin.command, step.command, "cycle {cycle}");
            assert_eq!(twin.most_likely, step.most_likely, "cycle {cycle}");
            assert_eq!(twin.marking, step.marking, "cycle {cycle}");
            assert_eq!(fingerprint(copy), fingerprint(&original), "cycle {cycle}");
        }
        let command: Vec<NamedValue> = (step.command.iter())
            .map(|&(x, v)| NamedValue::of(original.plant(), x, v))
            .collect();
        plant.send(time, &command).expect("a control");
        plant.estimated(&step.most_likely);
    }
    assert!(original.is_complete(), "the burn was run through");
}

/// Item 4 in small (the full search is scenarios/mars_edl/explore_faults.ron, BENCHMARKS.md):
/// the nominal EDL at 1 s with the engine's and the radar's power loss optional in the descent,
/// up to both on one path. No path is silent: each lands or reports the failure.
#[test]
fn no_edl_path_fails_silently() {
    let scenario = scenario("tests/scenarios/explore_edl_small.ron");
    let explored = explore(&scenario, &options(2, 2), &|_| {}).expect("explores");
    assert_eq!(explored.cut_at, None);
    assert_eq!(explored.failing_paths[0], 0, "a silent path");
    assert!(explored.paths.complete() > 1);
    // The engine's power loss leaves no way down: landing fails, and is reported.
    assert!(explored.failing_paths[1] > 0);
}

/// The command: exit 1 with the counterexample's path and its mission log; exit 0 when no
/// fault is allowed (the nominal path holds); exit 2 on a budget that is no budget.
#[test]
fn kairos_explore_exits_by_what_it_found() {
    let file = "tests/scenarios/explore_flameout.ron";
    let (code, stdout, stderr) = cli::kairos(&["explore", file, "--no-replay", "--jobs", "1"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("covered: every path"), "{stdout}");
    assert!(
        stdout.contains("path: `flame-out` at 41 s (cycle 410)"),
        "{stdout}"
    );
    assert!(stdout.contains("DIAGNOSIS    engine = failed"), "{stdout}");
    let (code, stdout, _) = cli::kairos(&["explore", file, "--faults", "0", "--quiet"]);
    assert_eq!(code, 0, "{stdout}");
    let (code, _, stderr) = cli::kairos(&["explore", file, "--budget", "soon"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("a number of states"), "{stderr}");
}

/// DESIGN.md §15.2 and the thermostat's exploration scenario: switch 1 may stick open or closed
/// at any cycle of the run (one fault a path), the device played faithfully at any cycle
/// (`scenarios/thermostat/physics.ron`). On every path: no safing while a working heater could
/// keep the device warm, no warmth lost without a goal failure reported, none lost at all once
/// the device has been warm while StayWarm holds, and StayWarm's end fires — shown by the
/// scenario's `Always` invariants.
/// (The last path to fail it: switch 1 sticking open at 360 s is diagnosed at 366 s, the cycle
/// StayWarm's end is due — its heater goal's failure is answered by "the interval ends", not by
/// safing; `scenarios/thermostat/switch1_sticks_open_as_stay_warm_ends.ron`.)
#[test]
fn no_thermostat_path_safes_or_loses_warmth_with_one_stuck_switch() {
    let scenario = scenario("scenarios/thermostat/explore_a_stuck_switch.ron");
    let explored = explore(&scenario, &options(1, 2), &|_| {}).expect("explores");
    assert_eq!(explored.cut_at, None, "every path covered");
    // Each rule at each of the 521 cycles (its condition holds until the switch sticks), and
    // the path with no fault.
    assert_eq!(explored.paths.complete(), 2 * 521 + 1);
    assert!(
        explored.counterexamples.is_empty(),
        "{:?}",
        explored.counterexamples
    );
}

/// The invariant is judged, not vacuous: on a mission that safes at 61 s with both heaters
/// able to work, `Always(that: Implies(Reported(Safing), Not(Plant(…a heater works…))))` fails
/// at that cycle; and `Once` remembers — a device never warm keeps `Not(Once(…warm))` true, and
/// `Once(Reported(Safing))` holds from 70 s though the safing came before its window opened.
#[test]
fn an_invariant_on_the_plant_s_true_state_catches_safing_with_a_working_heater() {
    let scenario = scenario("tests/scenarios/invariant_safes_with_a_working_heater.ron");
    let outcome = simulation::run(&scenario, RunOptions::default(), &mut |_| {}).expect("runs");
    let reasons: Vec<String> = (outcome.verdicts.iter())
        .map(|v| match &v.outcome {
            simulation::Outcome::Failed { reason } => reason.clone(),
            simulation::Outcome::Met { .. } => "met".to_string(),
        })
        .collect();
    // The scenario's three expectations, then the invariants every scenario checks (no command
    // against an active goal, no chatter).
    assert_eq!(reasons, ["not at 61.000 s", "met", "met", "met", "met"]);
}
