//! DESIGN.md §9, goal-faithful commands: every scenario fails on a `GoalContradicted` or a
//! `Chatter` event unless it says it expects one. Two planted scenarios, each with no
//! expectation of its own, fail on exactly that invariant; the same scenario that says it
//! expects the event is judged by what it says.

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
        stdout.contains("CHATTER      switch1 commanded back into closed"),
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
    assert!(stdout.contains("1 goal the plant leaves by itself"), "{stdout}");
    assert!(
        stderr.contains(
            "goal `temperature = warming` holds only in states the plant leaves by itself: \
             `temperature` leaves it by itself by its transition to cold"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("planted_chatter.rmpl:6:11"), "{stderr}");
}
