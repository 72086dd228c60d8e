//! Repairs that take several transitions (thesis §6.3.3, "repairs out of fault modes") on
//! `models/driver_valve.ron`, Table 6.1: a `resettable` driver is reset through the transient
//! `resetting-on` (or turned off through `resetting-off`), modes the plant enters only through
//! that repair. They are steps of the repair, not commitments: the driver's `on` and `off`,
//! which it could be in before the fault, stay reversibly reachable from `resettable`, so goal
//! interpretation offers them without the goal naming them, and the planner repairs the driver
//! and then proceeds. (Before, `on` and `off` counted as entered irreversibly from the repair
//! modes and every goal failed with the driver resettable, even `valve = closed`.)

#[path = "support/reconfiguration.rs"]
mod support;

#[path = "support/cli.rs"]
mod cli;

use kairos::reconfiguration::{PlanOutcome, PolicyEntry};
use support::Setup;

fn driver_valve() -> Setup {
    Setup::model("driver_valve")
}

/// The reset command of Table 6.1's repair transition (tau18), then the timed tau22.
const RESET: [&str; 2] = [
    "command driver.dcmd_in = reset (repair) (driver: resettable -> resetting-on)",
    "wait, after Uniform(0, 0.2) s, p 0.989 (driver: resetting-on -> on)",
];

/// §6.3.3: `resetting-on` and `resetting-off` are repair modes; the driver's nominal modes
/// commit nothing, and a repair's region runs through the repair modes to them.
#[test]
fn section_6_3_3_repair_modes_lead_to_the_nominal_modes_reversibly() {
    let setup = driver_valve();
    let driver = setup.plant.component_named("driver").expect("driver");
    let policy = setup.reconfiguration.policy(driver);
    let reach = policy.reachability();
    let m = |name| setup.mode("driver", name);
    for mode in ["resetting-on", "resetting-off"] {
        assert!(reach.is_repair_mode(m(mode)), "{mode}");
    }
    for mode in ["off", "turning-on", "on", "turning-off"] {
        assert!(!reach.is_repair_mode(m(mode)), "{mode}");
        assert!(!reach.is_committing(m(mode)), "{mode}");
        assert!(reach.is_reversible(m("resettable"), m(mode)), "{mode}");
        assert!(reach.is_reversible(m("resetting-on"), m(mode)), "{mode}");
    }
    assert_eq!(reach.irreversible(m("resettable")).count(), 0);
    // The repair modes cannot be returned to.
    assert_eq!(
        policy.entry(m("on"), m("resetting-on")),
        PolicyEntry::Failure
    );
}

/// §6.3.3: from `driver = resettable`, `driver = on` resets the driver.
#[test]
fn section_6_3_3_a_resettable_driver_is_reset_to_on() {
    let mut setup = driver_valve();
    let start = setup.state(&[("driver", "resettable"), ("valve", "closed")]);
    let goal = setup
        .interpret(&start, "driver = on")
        .expect("on is reachable through the repair");
    assert_eq!(setup.describe(goal.modes()), "driver = on, valve = closed");
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(setup.actions(&run), RESET);
}

/// §6.3.3: from `driver = resettable`, `valve = open` resets the driver (a sub-goal: the driver
/// relays the valve's command), opens the valve, and turns the driver back off, its goal mode.
#[test]
fn section_6_3_3_a_resettable_driver_is_reset_then_opens_the_valve() {
    let mut setup = driver_valve();
    let start = setup.state(&[("driver", "resettable"), ("valve", "closed")]);
    let goal = setup
        .interpret(&start, "valve = open")
        .expect("the valve is reachable once the driver is repaired");
    assert_eq!(setup.describe(goal.modes()), "driver = off, valve = open");
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    let mut expected = RESET.to_vec();
    expected.extend([
        "command driver.dcmd_in = open (valve: closed -> open)",
        "command driver.dcmd_in = off (driver: on -> turning-off)",
        "wait, after Uniform(0, 0.1) s, p 0.989 (driver: turning-off -> off)",
    ]);
    assert_eq!(setup.actions(&run), expected);
}

/// Even a goal the plant already satisfies repairs the driver (a repairable fault must be
/// repaired), here by the cheaper way into `off`; and a driver caught in the middle of the
/// repair (`resetting-on`) waits for it to end, then proceeds.
#[test]
fn section_6_3_3_a_repair_under_way_is_completed() {
    let mut setup = driver_valve();
    let start = setup.state(&[("driver", "resettable"), ("valve", "closed")]);
    let goal = setup
        .interpret(&start, "valve = closed")
        .expect("a goal state");
    assert_eq!(setup.run(&start, &goal).outcome, PlanOutcome::Achieved);

    let resetting = setup.state(&[("driver", "resetting-on"), ("valve", "closed")]);
    let goal = setup
        .interpret(&resetting, "valve = open")
        .expect("a goal state");
    let run = setup.run(&resetting, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&run)[..2],
        [
            RESET[1],
            "command driver.dcmd_in = open (valve: closed -> open)"
        ]
    );
}

/// The same through `kairos plan`.
#[test]
fn section_6_3_3_kairos_plan_resets_the_driver() {
    let (code, stdout, stderr) = cli::kairos(&[
        "plan",
        "--plant",
        "models/driver_valve.ron",
        "--state",
        "driver = resettable, valve = closed",
        "--goal",
        "valve = open",
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.contains("goal state:  driver = off, valve = open"),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "1. command driver.dcmd_in = reset (repair)  driver: resettable -> resetting-on"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("goal state reached after 5 cycles"),
        "{stdout}"
    );
}
