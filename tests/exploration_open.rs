//! `kairos explore` over the two kinds of nondeterminism DESIGN.md §16 names besides optional
//! faults: "timed plant responses may land anywhere in a declared interval (discretised to the
//! cycle); simultaneous deliveries in any order" (DESIGN.md §16). Each search's counts are
//! pinned, its counterexample replays in `kairos run`, and the nominal run stays the path that
//! takes the interval's lower bound and the order the rules fired in.

#[path = "support/cli.rs"]
mod cli;

use std::path::Path;

use kairos::exploration::{
    Delivery, Exploration, ExploreOptions, Landing, explore, replay_scenario, replay_text,
};
use kairos::simulation::{self, RunOptions, RunOutcome, Scenario};

fn scenario(path: &str) -> Scenario {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    simulation::load(&root.join(path)).unwrap_or_else(|e| panic!("{e}"))
}

fn explored(scenario: &Scenario, jobs: usize) -> Exploration {
    let options = ExploreOptions {
        jobs,
        ..ExploreOptions::default()
    };
    explore(scenario, &options, &|_| {}).expect("explores")
}

fn run(scenario: &Scenario) -> RunOutcome {
    simulation::run(scenario, RunOptions::default(), &mut |_| {}).expect("runs")
}

/// The replay file's text, loaded as a scenario beside the explored one.
fn replay_file(text: String) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenarios");
    let source = kairos::diagnostic::Source::new("replay.ron", text);
    simulation::load_source(&source, &dir).unwrap_or_else(|e| panic!("{e}"))
}

const HEAT: &str = "tests/scenarios/explore_heat_window.ron";
const RACE: &str = "tests/scenarios/explore_power_on_race.ron";

/// A timed response in an interval: the heat-up, fired with the standby command at 1 s, lands
/// at any whole second from 32 s to 62 s — 31 paths. The engine fires and the program
/// completes on every one; firing by 60 s fails on the five latest (landing at 58–62 s: the
/// engine fires 3 s after it is hot), and the shortest counterexample is the earliest of them.
#[test]
fn the_heat_up_lands_anywhere_in_its_window() {
    let scenario = scenario(HEAT);
    let explored = explored(&scenario, 1);
    assert_eq!(explored.cut_at, None, "every path covered");
    assert_eq!(explored.paths.complete(), 31);
    assert_eq!(explored.paths.merged, 0);
    assert_eq!(explored.states, 1982);
    // The last two: the invariants every scenario checks (DESIGN.md §9), never violated.
    assert_eq!(explored.failing_paths, [0, 0, 0, 5, 0, 0]);
    assert_eq!(explored.counterexamples.len(), 1);
    let counterexample = &explored.counterexamples[0];
    let heat = scenario
        .script
        .rule_named("engine heats up")
        .expect("declared");
    assert_eq!(
        counterexample.landings,
        [Landing {
            rule: heat,
            fired: 1,
            lands: 58
        }]
    );
    assert!(counterexample.choices.is_empty() && counterexample.deliveries.is_empty());
    // The same answer with two workers.
    let two = self::explored(&scenario, 2);
    assert_eq!(two.counterexamples, explored.counterexamples);
    assert_eq!(two.failing_paths, explored.failing_paths);
    assert_eq!(two.paths, explored.paths);
}

/// `kairos run` lands the response at the lower bound (the nominal run passes); the
/// counterexample pins its delay with `choose` and fails the deadline in a run, as a scenario
/// and as the replay file's text.
#[test]
fn the_late_heat_up_replays() {
    let scenario = scenario(HEAT);
    assert!(run(&scenario).passed(), "the lower bound: hot at 32 s");
    let counterexample = explored(&scenario, 1).counterexamples.remove(0);
    let replayed = run(&replay_scenario(&scenario, &counterexample));
    let holds: Vec<bool> = replayed.verdicts.iter().map(|v| v.holds()).collect();
    assert_eq!(holds, [true, true, true, false, true, true]);
    let text = replay_text(&scenario, &counterexample).expect("a Scenario( line");
    assert!(
        text.contains(r#"choose: { "engine heats up": 57.0 },"#),
        "{text}"
    );
    let from_file = run(&replay_file(text));
    assert!(!from_file.verdicts[3].holds());
}

/// Simultaneous deliveries: the latch-up transient and the power-up both reach the PDE at
/// 1 s and set it differently, so the search tries both orders (2 paths); the fired order (a
/// run's) leaves the PDE on, the other leaves it latched and the executive resets it — the
/// engine fires and the program completes either way.
#[test]
fn the_power_on_race_is_tried_in_both_orders() {
    let scenario = scenario(RACE);
    let explored = explored(&scenario, 1);
    assert_eq!(explored.cut_at, None);
    assert_eq!(explored.paths.complete(), 2);
    assert_eq!(explored.states, 93);
    assert_eq!(explored.failing_paths, [0, 0, 1, 0, 0]);
    let counterexample = &explored.counterexamples[0];
    let rule = |name| scenario.script.rule_named(name).expect("declared");
    assert_eq!(
        counterexample.deliveries,
        [Delivery {
            cycle: 1,
            order: vec![rule("PDE powers up"), rule("latch-up transient")]
        }]
    );
    assert_eq!(counterexample.cycle, 2, "the reset is commanded at 2 s");
}

/// The order found replays through `deliver`; the nominal run keeps the fired order and passes.
#[test]
fn the_race_replays_with_its_order() {
    let scenario = scenario(RACE);
    assert!(run(&scenario).passed());
    let counterexample = explored(&scenario, 1).counterexamples.remove(0);
    assert!(!run(&replay_scenario(&scenario, &counterexample)).verdicts[2].holds());
    let text = replay_text(&scenario, &counterexample).expect("a Scenario( line");
    let pinned = r#"deliver: [(at: 1.0, order: ["PDE powers up", "latch-up transient"])],"#;
    assert!(text.contains(pinned), "{text}");
    assert!(!text.contains("choose:"), "nothing to choose: {text}");
    let from_file = run(&replay_file(text));
    assert!(!from_file.verdicts[2].holds());
    assert!(from_file.verdicts[1].holds(), "the reset repairs the PDE");
}

/// Effects that cannot change each other's outcome do not branch: the nominal propulsion
/// scenario, where the engine's power-up and its heat-up fire together but land apart and
/// every simultaneous pair writes different names, is one path.
#[test]
fn no_contention_no_branching() {
    let explored = explored(&scenario("scenarios/propulsion/nominal.ron"), 1);
    assert_eq!(explored.paths.complete(), 1);
    assert!(explored.holds());
}

/// The command prints where the response landed and the order the deliveries took.
#[test]
fn kairos_explore_shows_landings_and_orders() {
    let (code, stdout, stderr) = cli::kairos(&["explore", HEAT, "--no-replay", "--jobs", "1"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    let landed = "`engine heats up` fired at 1 s lands at 58 s (cycle 58)";
    assert!(stdout.contains(landed), "{stdout}");
    let (code, stdout, stderr) = cli::kairos(&["explore", RACE, "--no-replay", "--jobs", "1"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    let order = "at 1 s (cycle 1) applied `PDE powers up` then `latch-up transient`";
    assert!(stdout.contains(order), "{stdout}");
}
