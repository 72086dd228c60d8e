//! A mission goal delegated to the course-of-action controller (seed 001,
//! mds-goal-networks.md §1.7, §2.9, §4), run by the executive through `kairos run`: the goal on
//! the rover's pose — a state variable that is not a plant component — is sent to its
//! controller when its start point fires, the controller's commands go to the device one a
//! cycle, `endcstr success` lets the end point fire, and `endcstr coanosuccess` fails the goal
//! so that its type's failure response (safing) runs.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/scenario_run.rs"]
mod scenario_run;
#[path = "support/seeded.rs"]
mod seeded;

use kairos::protocol::messages::Outcome;
use kairos::protocol::posandhead::{Command, Constraint, Heading, Pose, StateValue, coa, satisfy};
use kairos::protocol::rover::Grid;
use kairos::protocol::{CoaDeclaration, Delegation, Delivered};
use proptest::prelude::*;

use scenario_run::{assert_every_file_is_tested, assert_in_order, run_passing};

/// Every file of `scenarios/rover/` is a mission scenario tested here, one of the protocol
/// scenarios R1–R7 that `tests/rover_protocol.rs` explores, or the script of the motors.
#[test]
fn every_rover_scenario_is_tested() {
    assert_every_file_is_tested(
        "scenarios/rover",
        &[
            "mission_traverse.ron",
            "mission_blocked.ron",
            "mission_motors_fail.ron",
        ],
        &[
            "r1.ron",
            "r2.ron",
            "r3.ron",
            "r4.ron",
            "r5.ron",
            "r6.ron",
            "r7.ron",
            "plant.ron",
        ],
        "tests/rover_missions.rs and tests/rover_protocol.rs",
    );
}

/// §4.2 R1's course of action from (0, 0) heading N to x = 3, y = 2 (turn E, drive ×3, turn N,
/// drive ×2), one command a cycle from the cycle TP_S fires (§2.9: a command's report is the
/// next cycle's measurement); `endcstr success` in the cycle after the last, and TP_E fires in
/// that cycle (it waited for the `endcstr`).
#[test]
fn the_delegated_traverse_reaches_the_rock_and_its_end_point_fires() {
    let log = run_passing("scenarios/rover/mission_traverse.ron");
    assert_in_order(
        &log,
        &[
            "command motors.cmd = on (motors: off -> on) for goal power",
            "[ 2.000 s",
            "fired TP_S",
            "delegated to-the-rock: constraint (x=3, y=2) sent to the controller of pose",
            "controller pose: turn(E) (for goal to-the-rock)",
            "[ 3.000 s",
            "controller pose: drive",
            "[ 4.000 s",
            "controller pose: drive",
            "[ 5.000 s",
            "controller pose: drive",
            "[ 6.000 s",
            "controller pose: turn(N)",
            "[ 7.000 s",
            "controller pose: drive",
            "[ 8.000 s",
            "controller pose: drive",
            "[ 9.000 s",
            "endcstr to-the-rock: the controller of pose ended it success; pose = (3, 2, N)",
            "fired TP_E",
            "completed",
        ],
    );
    assert!(!log.contains("GOAL FAILED"), "{log}");
}

/// §4.2 R3 inside a mission: the obstacle at (2, 0) blocks two drives, the fixed course of
/// action runs out at (1, 2) and the controller answers `coanosuccess`; the goal fails with the
/// controller named as the evidence, its type Traverse responds by safing, the safe network
/// switches the motors off, and TP_E never fires.
#[test]
fn an_obstacle_fails_the_delegated_goal_and_its_response_safes_the_mission() {
    let log = run_passing("scenarios/rover/mission_blocked.ron");
    assert_in_order(
        &log,
        &[
            "delegated to-the-rock: constraint (x=3, y=2) sent to the controller of pose",
            "[ 8.000 s",
            "controller pose: drive",
            "[ 9.000 s",
            "ENDCSTR to-the-rock: the controller of pose ended it coanosuccess; pose = (1, 2, N)",
            "GOAL FAILED to-the-rock: the controller of pose ended its constraint coanosuccess",
            "RESPONSE to-the-rock failed: pose = (1, 2, N) (p 1.00) → safing",
            "SAFING",
            "command motors.cmd = off (motors: on -> off) for goal motors-off",
        ],
    );
    assert!(!log.contains("fired TP_E"), "{log}");
}

/// A delegated goal retired while its controller works on it (beyond the seed, whose
/// constraints end only by `endcstr`): the motors fail two drives into the traverse, safing
/// retires every goal, and the traverse's constraint is withdrawn in that cycle — the drive
/// already under way reports, but the controller issues nothing more and never ends it.
#[test]
fn safing_withdraws_a_delegated_goal_from_its_controller() {
    let log = run_passing("scenarios/rover/mission_motors_fail.ron");
    assert_in_order(
        &log,
        &[
            "delegated to-the-rock: constraint (x=3, y=2) sent to the controller of pose",
            "[ 5.000 s",
            "DIAGNOSIS motors = failed",
            "SAFING motors-on failed",
            "withdrawn to-the-rock: retired while the controller of pose worked on it; its \
             constraint is withdrawn, no further command; pose = (2, 0, E)",
            "fired assessed",
        ],
    );
    let after = log
        .split("withdrawn to-the-rock")
        .nth(1)
        .unwrap_or_default();
    assert!(!after.contains("controller pose:"), "{after}");
    assert!(
        !log.contains("endcstr") && !log.contains("ENDCSTR"),
        "{log}"
    );
}

/// The cycles of both runs as the mission log prints them (snapshot), and the same on a second
/// run: the protocol is delivered first in, first out, so a run is deterministic.
#[test]
fn the_delegated_goal_in_the_mission_log() {
    let cycles = |scenario: &str| -> String {
        let log = run_passing(scenario);
        let lines: Vec<&str> = log
            .lines()
            .skip_while(|l| !l.starts_with('['))
            .take_while(|l| !l.starts_with("run ended"))
            .collect();
        format!("# {scenario}\n{}", lines.join("\n"))
    };
    let runs = [
        "scenarios/rover/mission_traverse.ron",
        "scenarios/rover/mission_blocked.ron",
    ]
    .map(cycles)
    .join("\n");
    let again = [
        "scenarios/rover/mission_traverse.ron",
        "scenarios/rover/mission_blocked.ron",
    ]
    .map(cycles)
    .join("\n");
    assert_eq!(runs, again, "two runs print the same log");
    insta::assert_snapshot!(runs);
}

/// Achievability of a delegated goal is its controller's (mds-goal-networks.md §1.7
/// `is_achievable`): from `uk` the course-of-action controller has nothing to plan from (§4.2,
/// §5 C12), so a mission whose estimator starts unknowing is refused when it is scheduled, with
/// the goal, the state variable and its value as the evidence; the same goal from a known pose
/// is achievable even with an obstacle in the way, which the controller does not know of (R3).
#[test]
fn a_goal_its_controller_cannot_reach_from_uk_is_unachievable_at_scheduling() {
    use kairos::executive::ScheduledMission;
    use kairos::goalnet::{ScheduleError, display, mission};
    use kairos::reconfiguration::Reconfiguration;
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    let schedule = |path: &str| {
        let loaded = mission::load(std::path::Path::new(path)).expect("loads");
        let reconfiguration = Reconfiguration::compile(&loaded.plant).expect("compiles");
        let network = loaded.network.clone();
        let plant = loaded.plant.clone();
        ScheduledMission::schedule(loaded, &reconfiguration)
            .map_err(|e| (display::explain(&e, &network, &plant), e))
    };
    let (text, error) = schedule("tests/missions/delegated_from_uk.ron").expect_err("refused");
    assert!(
        matches!(&error, ScheduleError::DelegatedUnachievable { sv, value, .. } if sv == "pose" && value == "uk"),
        "{error:?}"
    );
    assert_eq!(
        text,
        "unachievable: goal `to-the-rock` (x = 3 and y = 2) on pose — from pose = uk its \
         controller has no course of action that reaches it"
    );
    assert!(schedule("missions/rover_traverse_blocked.ron").is_ok());
}

/// `kairos schedule` lists a delegated goal apart from the component timelines: it is on none,
/// its controller judges and achieves it.
#[test]
fn kairos_schedule_lists_the_delegated_goal() {
    let (code, stdout, stderr) = cli::kairos(&["schedule", "missions/rover_traverse.ron"]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stdout.ends_with(
            "delegated to the controllers of their state variables:\n  [TP_S, TP_E] Transition x = 3 and y = 2: to-the-rock\n"
        ),
        "{stdout}"
    );
}

/// The executive of a mission file (relative to the crate root) through the embedding API.
fn executive_of(file: &str) -> kairos::executive::Executive {
    use kairos::executive::{Executive, ScheduledMission};
    use kairos::goalnet::mission;
    use kairos::reconfiguration::Reconfiguration;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let loaded = mission::load(&path).expect("loads");
    let reconfiguration = Reconfiguration::compile(&loaded.plant).expect("compiles");
    let plant = loaded.plant.clone();
    let scheduled = ScheduledMission::schedule(loaded, &reconfiguration).expect("schedules");
    Executive::builder(plant, scheduled)
        .build()
        .expect("builds")
}

/// The end point of a delegated goal waits for its controller's `endcstr`; at its latest time
/// it is forced, and the goal fails with the controller's silence as the reason (the embedding
/// API, 1 s cycles). The controller carries on; its later `endcstr` fails nothing twice.
#[test]
fn a_delegated_goal_not_ended_by_its_end_points_latest_time_fails_when_it_is_forced() {
    use kairos::executive::{EventKind, NamedValue};
    let mut executive = executive_of("tests/missions/delegated_too_slow.ron");
    let off = [NamedValue::new("motors.current", "zero")];
    let mut events = Vec::new();
    for t in 0..=10 {
        let step = executive.step(f64::from(t), &off).expect("a cycle");
        events.extend(step.events.into_iter().map(|e| (e.time, e.kind)));
    }
    let forced = events
        .iter()
        .find(|(_, e)| matches!(e, EventKind::TimePointForced { point, .. } if point == "TP_E"));
    assert_eq!(forced.map(|(t, _)| *t), Some(3.0), "{events:#?}");
    let failed: Vec<(f64, &str)> = events
        .iter()
        .filter_map(|(t, e)| match e {
            EventKind::MissionGoalFailed { goal, reason, .. } if goal == "to-the-rock" => {
                Some((*t, reason.as_str()))
            }
            _ => None,
        })
        .collect();
    assert_eq!(
        failed,
        [(
            3.0,
            "its end point was forced before its controller ended the constraint"
        )]
    );
    let ended = events.iter().find(
        |(_, e)| matches!(e, EventKind::ConstraintEnded { outcome, .. } if outcome == "success"),
    );
    assert_eq!(
        ended.map(|(t, _)| *t),
        Some(7.0),
        "the controller carries on: {events:#?}"
    );
}

/// A delegation run as the executive runs it: the constraint sent, then one cycle at a time
/// until its `endcstr`; the commands issued per cycle and the outcome.
fn delegate(declaration: &CoaDeclaration, constraint: Constraint) -> (Vec<Vec<Command>>, Outcome) {
    let mut delegation = Delegation::new(declaration);
    let mut delivered = delegation.send(0, constraint);
    let mut cycles = Vec::new();
    loop {
        let commands = (delivered.iter())
            .filter_map(|d| match d {
                Delivered::Command { command, .. } => Some(*command),
                Delivered::Ended { .. } => None,
            })
            .collect();
        cycles.push(commands);
        let ended = delivered.iter().find_map(|d| match d {
            Delivered::Ended { outcome, .. } => Some(*outcome),
            Delivered::Command { .. } => None,
        });
        if let Some(outcome) = ended {
            let value = delegation.value();
            assert_eq!(
                outcome == Outcome::Success,
                satisfy(&value, &constraint),
                "{value}"
            );
            return (cycles, outcome);
        }
        assert!(cycles.len() <= 20, "no endcstr after {cycles:?}");
        delivered = delegation.cycle();
    }
}

fn heading() -> impl Strategy<Value = Heading> {
    prop::sample::select(vec![
        Heading::N,
        Heading::NE,
        Heading::E,
        Heading::SE,
        Heading::S,
        Heading::SW,
        Heading::W,
        Heading::NW,
    ])
}

proptest! {
    #![proptest_config(seeded::config(256))]

    /// The executive's run of the protocol (§2.9, one step a cycle) keeps the seed's
    /// properties on any 5×5 grid (mds-goal-networks.md §4.2): exactly one `endcstr`, success
    /// exactly when the estimate satisfies the constraint (P-succ/P-fail), at most one command
    /// a cycle, the commands a prefix of `coa(v0, c)` (P-cmds) — all of it without obstacles.
    #[test]
    fn a_delegated_constraint_ends_once_after_a_prefix_of_its_course_of_action(
        (x0, y0, h0) in (0..5i32, 0..5i32, heading()),
        (x, y, h) in (prop::option::of(0..5i32), prop::option::of(0..5i32), prop::option::of(heading())),
        obstacles in prop::collection::btree_set((0..5i32, 0..5i32), 0..6),
    ) {
        let rover = Pose { x: x0, y: y0, heading: h0 };
        let obstacles = obstacles.into_iter().filter(|&c| c != (x0, y0)).collect();
        let constraint = Constraint::PosHead { x, y, heading: h };
        let declaration = |obstacles| CoaDeclaration {
            sv: "pose".into(),
            grid: Grid { size: 5, obstacles },
            rover,
            known: true,
        };
        let plan = coa(&StateValue::Known(rover), &constraint);
        // `delegate` checks the outcome against the estimate (P-succ/P-fail).
        let (cycles, _) = delegate(&declaration(obstacles), constraint);
        prop_assert!(cycles.iter().all(|c| c.len() <= 1), "{cycles:?}");
        let issued: Vec<Command> = cycles.into_iter().flatten().collect();
        prop_assert!(plan.starts_with(&issued), "{issued:?} is not a prefix of {plan:?}");
        let (free, free_outcome) = delegate(&declaration(Default::default()), constraint);
        prop_assert_eq!(free_outcome, Outcome::Success);
        prop_assert_eq!(free.into_iter().flatten().collect::<Vec<_>>(), plan);
    }
}

/// A delegated goal is a goal of the network like any other: its type's tactic elaborates it
/// (mds-goal-networks.md §2.1) into a Maintain goal on the motors over its interval, which the
/// goal controller dispatches at TP_S beside the constraint sent to the controller of `pose`.
#[test]
fn a_delegated_goal_is_elaborated_by_its_types_tactic() {
    use kairos::executive::{EventKind, NamedValue};
    let mut executive = executive_of("tests/missions/delegated_elaborated.ron");
    let mut events = Vec::new();
    for t in 0..=6 {
        let current = if t == 0 { "zero" } else { "nominal" };
        let observed = [NamedValue::new("motors.current", current)];
        let step = executive.step(f64::from(t), &observed).expect("a cycle");
        events.extend(step.events.into_iter().map(|e| (e.time, e.kind)));
    }
    let at = |wanted: &dyn Fn(&EventKind) -> bool| {
        events.iter().find(|(_, e)| wanted(e)).map(|(t, _)| *t)
    };
    let tactic =
        at(&|e| matches!(e, EventKind::TacticChosen { goal, tactic: 1 } if goal == "to-the-rock"));
    assert_eq!(tactic, Some(0.0), "{events:#?}");
    let child = at(
        &|e| matches!(e, EventKind::XGoalDispatched { goals, .. } if goals == &["to-the-rock.motors"]),
    );
    assert_eq!(child, Some(2.0), "{events:#?}");
    let sent =
        at(&|e| matches!(e, EventKind::ConstraintSent { goal, .. } if goal == "to-the-rock"));
    assert_eq!(sent, Some(2.0));
    // turn(E) at 2 s, drive at 3 s, success at 4 s; TP_E fires then.
    let ended =
        at(&|e| matches!(e, EventKind::ConstraintEnded { outcome, .. } if outcome == "success"));
    assert_eq!(ended, Some(4.0), "{events:#?}");
    let end = at(&|e| matches!(e, EventKind::TimePointFired { point, .. } if point == "TP_E"));
    assert_eq!(end, Some(4.0));
    assert!(at(&|e| matches!(e, EventKind::MissionGoalFailed { .. })).is_none());
}
