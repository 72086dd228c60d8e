//! DESIGN.md §9, goal-faithful commands: every scenario fails on a `GoalContradicted` or a
//! `Chatter` event unless it says it expects one. Two planted scenarios, each with no
//! expectation of its own, fail on exactly that invariant; the same scenario that says it
//! expects the event is judged by what it says. `kairos explore` finds the invariant's
//! violation as it finds any expectation's, a campaign counts it as a run's failure (reported,
//! not silent), and the chatter window is the scenario's.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

/// A goal the plant leaves by itself makes the executive switch a heater on and off by turns:
/// the scenario fails on `Chatter`, and on nothing else.
#[test]
fn a_chattering_goal_fails_its_scenario() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/planted_chatter.ron"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("CHATTER      switch2 commanded back into closed"),
        "{stdout}"
    );
    assert!(
        stdout.contains("FAILED never reported Chatter (checked in every scenario)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok     never reported GoalContradicted (checked in every scenario)"),
        "{stdout}"
    );
}

/// A scenario that names the event in an expectation of its own is judged by it: the invariant
/// is not added, and the chattering run passes.
#[test]
fn a_scenario_that_expects_chatter_is_judged_by_its_expectation() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/planted_chatter_expected.ron"]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(stdout.contains("CHATTER"), "{stdout}");
    assert!(!stdout.contains("never reported Chatter"), "{stdout}");
    assert!(
        stdout.contains("ok     never reported GoalContradicted (checked in every scenario)"),
        "{stdout}"
    );
}

/// The chatter window is the scenario's `chatter_cycles`: with one cycle, the same run's
/// returns (two cycles after each move out) are not chatter, and the scenario passes.
#[test]
fn the_chatter_window_is_configurable() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/planted_chatter_window.ron"]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(!stdout.contains("CHATTER"), "{stdout}");
    assert!(
        stdout.contains("ok     never reported Chatter (checked in every scenario)"),
        "{stdout}"
    );
}

/// `kairos explore` treats the invariants as the scenario's expectations: chatter is a
/// violation with a counterexample.
#[test]
fn explore_reports_chatter_as_a_violation() {
    let (code, stdout, stderr) = kairos(&[
        "explore",
        "tests/scenarios/planted_chatter.ron",
        "--no-replay",
        "--jobs",
        "1",
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains(
            "counterexample 1: `never reported Chatter (checked in every scenario)` fails: \
             reported at 4.000 s (Chatter)"
        ),
        "{stdout}"
    );
}

/// A campaign counts the invariant as each run's failure, and a chattering run as reported by
/// the executive, not silent.
#[test]
fn a_campaign_counts_chatter_as_a_failure() {
    let (code, stdout, stderr) = kairos(&[
        "campaign",
        "tests/scenarios/planted_chatter_campaign.ron",
        "--runs",
        "4",
        "--seed",
        "1",
        "--jobs",
        "1",
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("runs: 4   passed: 0"), "{stdout}");
    assert!(
        stdout.contains("silent (no failure reported by the executive): 0"),
        "{stdout}"
    );
    assert!(
        stdout.contains("4 × never reported Chatter (checked in every scenario)"),
        "{stdout}"
    );
}

/// A command that would switch on a driver a holding goal keeps off is withheld and reported;
/// the scenario fails on `GoalContradicted`.
#[test]
fn a_contradicting_command_is_withheld_and_fails_its_scenario() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/planted_contradiction.ron"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains(
            "CONTRADICTED withheld driver.dcmd_in = on: it would move driver out of off, which \
             driver = off requires"
        ),
        "{stdout}"
    );
    assert!(
        !stdout.contains("command      driver.dcmd_in = on"),
        "{stdout}"
    );
    assert!(
        stdout.contains("FAILED never reported GoalContradicted (checked in every scenario)"),
        "{stdout}"
    );
}

/// `kairos check --deep` says up front that a goal holds only in states the plant leaves by
/// itself, located at the goal.
#[test]
fn check_deep_reports_a_goal_the_plant_leaves_by_itself() {
    let (code, stdout, stderr) = kairos(&[
        "check",
        "--deep",
        "tests/scenarios/planted_chatter.rmpl",
        "models/thermostat.ron",
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("1 goal the plant leaves by itself"),
        "{stdout}"
    );
    assert!(
        stderr.contains(
            "goal `temperature = warming` holds only in states the plant leaves by itself: \
             `temperature` leaves it by itself by its transition to cold"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("planted_chatter.rmpl:6:11"), "{stderr}");
}
