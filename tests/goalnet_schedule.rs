//! Merging and scheduling (mds-goal-networks.md §2.2 and §3.3's negative
//! scheduling tests): XGoals per state variable, serialisation, the four outcomes with their
//! evidence, and `kairos schedule` on the thermostat mission (snapshot).

use std::path::Path;
use std::process::Command;

use kairos::goalnet::{GoalKind, Provenance, ScheduleError, display, mission, schedule};
use kairos::logic::ValueId;
use kairos::reconfiguration::Reconfiguration;

fn root() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
}

/// Schedules a mission from the thermostat's initial state (every mode's first value: cold,
/// open, open, healthy — the model's most likely initial modes).
fn scheduled(
    path: &str,
) -> (
    mission::Mission,
    Result<kairos::goalnet::ExecutableNetwork, ScheduleError>,
) {
    root();
    let mission = mission::load(Path::new(path)).expect("loads");
    let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
    let current = vec![ValueId(0); mission.plant.components().len()];
    let result = schedule(&mission.network, &reconfiguration, &current);
    (mission, result)
}

fn explained(path: &str) -> (ScheduleError, String) {
    let (mission, result) = scheduled(path);
    let error = result.expect_err("scheduling fails");
    let text = display::explain(&error, &mission.network, &mission.plant);
    (error, text)
}

/// System test 4's network: switch 1's timeline is Known, then the transition to CLOSED merged
/// with Known, then CLOSED maintained, then Known again (§2.2 step 2c).
#[test]
fn the_stay_warm_network_has_an_xgoal_per_interval() {
    let (mission, result) = scheduled("missions/thermostat_stay_warm.ron");
    let executable = result.expect("schedules");
    let switch1 = mission.plant.component_named("switch1").unwrap();
    let timeline = executable.timeline(switch1).expect("switch1 has goals");
    let kinds: Vec<GoalKind> = timeline.xgoals.iter().map(|x| x.kind).collect();
    use GoalKind::*;
    assert_eq!(kinds, [Knowledge, Transition, Maintain, Knowledge]);
    assert_eq!(timeline.xgoals[1].constituents.len(), 2);
    assert!(
        timeline
            .xgoals
            .iter()
            .all(|x| x.constraint.requires_known())
    );
    // Upstream first: the switches before the temperature they heat.
    let names: Vec<&str> = executable
        .timelines
        .iter()
        .map(|t| mission.plant.component(t.sv).name())
        .collect();
    let temperature = names.iter().position(|n| *n == "temperature").unwrap();
    assert!(names.iter().position(|n| *n == "switch1").unwrap() < temperature);
}

/// System test 1: the second knowledge activity merges with KnowAll on [TP_k1, TP_k2] on every
/// state variable (mds-goal-networks.md §3.3: "2 constituents merged").
#[test]
fn the_knowledge_activity_merges_with_know_all() {
    let (mission, result) = scheduled("missions/thermostat_know_all.ron");
    let executable = result.expect("schedules");
    assert_eq!(executable.timelines.len(), 4);
    let network = &executable.network;
    for timeline in &executable.timelines {
        let spans: Vec<(&str, &str, usize)> = timeline
            .xgoals
            .iter()
            .map(|x| {
                (
                    network.point(x.start).name.as_str(),
                    network.point(x.end).name.as_str(),
                    x.constituents.len(),
                )
            })
            .collect();
        assert_eq!(
            spans,
            [
                ("origin", "TP_k1", 1),
                ("TP_k1", "TP_k2", 2),
                ("TP_k2", "TP_bgE", 1)
            ],
            "{}",
            mission.plant.component(timeline.sv).name()
        );
    }
}

/// Goals that do not merge are serialised when the network allows it (§2.2 step 2d).
#[test]
fn incompatible_goals_are_serialised() {
    let (_, result) = scheduled("tests/missions/serialised.ron");
    let executable = result.expect("schedules");
    let network = &executable.network;
    let reasons: Vec<String> = network
        .stn()
        .constraints()
        .iter()
        .filter_map(|c| match &c.provenance {
            Provenance::Scheduled { reason } if reason.starts_with("end(") => Some(reason.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(
        reasons,
        ["end(close) ≤ start(open)", "end(closed) ≤ start(open)"]
    );
    let point = |n: &str| network.point_named(n).unwrap();
    let window = network.stn().window(point("c")).unwrap();
    assert_eq!(
        window.lb, 10.0,
        "c no earlier than b, which is 10 s after a ≥ 0"
    );
}

#[test]
fn unmergeable_goals_are_named() {
    let (error, text) = explained("tests/missions/unmergeable.ron");
    assert!(
        matches!(error, ScheduleError::Unmergeable { .. }),
        "{error:?}"
    );
    insta::assert_snapshot!(text);
}

#[test]
fn a_transition_into_a_fault_is_unachievable() {
    let (error, text) = explained("tests/missions/unachievable.ron");
    assert!(
        matches!(error, ScheduleError::Unachievable { .. }),
        "{error:?}"
    );
    insta::assert_snapshot!(text);
}

#[test]
fn a_maintain_goal_without_its_transition_is_transition_unachievable() {
    let (error, text) = explained("tests/missions/no_transition_goal.ron");
    assert!(
        matches!(error, ScheduleError::TransitionUnachievable { .. }),
        "{error:?}"
    );
    insta::assert_snapshot!(text);
}

/// `kairos schedule` prints the windows and the XGoals of system test 4's mission.
#[test]
fn kairos_schedule_prints_windows_and_xgoals() {
    root();
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .args(["schedule", "missions/thermostat_stay_warm.ron"])
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("TP_S    [70, 165]"), "{stdout}");
    insta::assert_snapshot!(stdout);
}

/// `kairos schedule` on a network that cannot be scheduled says why and exits 1.
#[test]
fn kairos_schedule_explains_a_failure() {
    root();
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .args(["schedule", "tests/missions/unmergeable.ron"])
        .output()
        .expect("runs");
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("unmergeable: on switch1"), "{stderr}");
}

fn schedule_cli(args: &[&str]) -> (Option<i32>, String, String) {
    root();
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .arg("schedule")
        .args(args)
        .output()
        .expect("runs");
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    (
        output.status.code(),
        text(&output.stdout),
        text(&output.stderr),
    )
}

/// `kairos schedule --at T` projects the network to T (mds-goal-networks.md
/// §2.4): the points that fire by T at their earliest times, the windows left to the others,
/// the XGoal each SV is under at T.
#[test]
fn kairos_schedule_at_projects_firings_and_active_xgoals() {
    let (code, stdout, stderr) =
        schedule_cli(&["missions/thermostat_stay_warm.ron", "--at", "100"]);
    assert_eq!(code, Some(0), "{stderr}");
    // TP_H at 10 s, TP_A at once (min 0), TP_S 60 s later; TP_E then fixed by [300, 300].
    assert!(stdout.contains("TP_S    fired at 70"), "{stdout}");
    assert!(stdout.contains("TP_E    [370, 370]"), "{stdout}");
    assert!(
        stdout.contains("[TP_S, TP_E] Maintain temperature ∈ {warm-low, warm, warm-high}, known: know-temperature, stay-warm  ← active"),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

/// `kairos schedule --dot` draws points, written constraints and XGoals.
#[test]
fn kairos_schedule_dot_draws_points_constraints_and_xgoals() {
    let (code, stdout, stderr) =
        schedule_cli(&["missions/thermostat_stay_warm.ron", "--at", "100", "--dot"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.starts_with("digraph "), "{stdout}");
    assert!(stdout.contains("rankdir=LR"), "{stdout}");
    // A fired point has a double border, a written constraint its bounds, the active XGoal is
    // highlighted in the cluster of its SV.
    assert!(
        stdout.contains(
            "\"point/3\" [label=\"TP_A\\lfired at 10 s\\l\", shape=ellipse, peripheries=2];"
        ),
        "{stdout}"
    );
    assert!(stdout.contains("[label=\"[60, 150] s\"]"), "{stdout}");
    assert!(
        stdout.contains("subgraph \"cluster_sv/temperature\""),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

/// A time that is not finite is refused with a message, not a panic.
#[test]
fn kairos_schedule_at_refuses_a_non_finite_time() {
    let (code, _, stderr) = schedule_cli(&["missions/thermostat_stay_warm.ron", "--at", "NaN"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("expected a finite time"), "{stderr}");
}

/// A Maintain goal on a set the plant enters by itself (a trigger no command sets) is a
/// condition its start point waits for, not an unachievable goal (docs/design/goal-networks.md,
/// "Scheduling"; mds-goal-networks.md §2.4's firing rule): the EDL descent mission schedules, its
/// TP_bs held back by `alt-vel-triggered`. A set only a command reaches still needs its
/// Transition goal (`a_maintain_goal_without_its_transition_is_transition_unachievable`).
#[test]
fn a_maintain_goal_on_a_spontaneous_trigger_schedules_as_a_wait() {
    let (mission, result) = scheduled("missions/mars_edl_descent.ron");
    let executable = result.expect("the descent mission schedules");
    let trigger = mission
        .plant
        .component_named("alt_vel_trigger")
        .expect("the lander has the trigger");
    let timeline = executable.timeline(trigger).expect("the trigger has goals");
    let xgoal = &timeline.xgoals[0];
    assert_eq!(xgoal.kind, GoalKind::Maintain);
    assert_eq!(mission.network.point(xgoal.start).name, "TP_bs");
}

/// `kairos schedule --dot` on a mission with goal types: the network as the
/// goal controller elaborates it at 0 s from the initial modes, and the elaboration tree beside
/// it — each goal with its type and tactic in use, parent to child.
#[test]
fn kairos_schedule_dot_draws_the_elaboration_tree() {
    let (code, stdout, stderr) = schedule_cli(&["missions/thermostat.ron", "--dot"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.contains("subgraph \"cluster_elaboration\""),
        "{stdout}"
    );
    assert!(
        stdout.contains("stay-warm\\ltype StayWarm\\ltactic 1: heater 1\\l"),
        "{stdout}"
    );
    // StayWarm's child, elaborated: an edge from the parent goal, and its tactic's point drawn.
    assert!(
        stdout.contains("stay-warm.get-warm\\ltype GetWarm\\ltactic 1"),
        "{stdout}"
    );
    assert!(stdout.contains("stay-warm.TP_A"), "{stdout}");
    insta::assert_snapshot!(stdout);
}

/// A goal holds from its start to its end (docs/design/goal-networks.md, "Scheduling"): one word
/// changed in a shipped mission's constraint let close-switch1's end come before its start, and
/// `schedule` and `run` left the goal out with exit 0. The scheduler now refuses the network,
/// naming the goal and the written constraint, each located.
#[test]
fn a_goal_whose_end_must_come_before_its_start_is_refused() {
    let (code, stdout, stderr) = schedule_cli(&["tests/missions/reversed_goal.ron"]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stderr.contains("reversed goal: `close-switch1`")
            && stderr.contains("tests/missions/reversed_goal.ron:36:25: goal `close-switch1`")
            && stderr.contains("tests/missions/reversed_goal.ron:13:13: TP_A → TP_H"),
        "{stderr}"
    );
}

/// A goal whose start and end are forced to one instant covered no interval and vanished from
/// its timeline; it is refused by name.
#[test]
fn a_goal_over_no_time_is_refused() {
    let (code, stdout, stderr) = schedule_cli(&["tests/missions/empty_goal.ron"]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stderr.contains("empty goal: `close-switch1`")
            && stderr.contains("tests/missions/empty_goal.ron:35:25"),
        "{stderr}"
    );
}

/// Constraints that merely allow the reverse order are fine: `start ≤ end` is part of every
/// goal, so the network schedules with TP_A at or after TP_H, as the shipped mission does.
#[test]
fn constraints_that_allow_the_reverse_order_schedule_in_the_goals_order() {
    let (_, result) = scheduled("tests/missions/reverse_allowed.ron");
    let executable = result.expect("schedules");
    let network = &executable.network;
    let (h, a) = (
        network.point_named("TP_H").expect("TP_H"),
        network.point_named("TP_A").expect("TP_A"),
    );
    let window = |p| network.stn().window(p).expect("a window");
    assert_eq!((window(h).lb, window(a).lb), (10.0, 10.0));
    let close = network.goal_named("close-switch1").expect("declared");
    let covering = (executable.timelines.iter())
        .flat_map(|t| &t.xgoals)
        .find(|x| x.constituents.contains(&close))
        .expect("close-switch1 is on its timeline");
    assert_eq!((covering.start, covering.end), (h, a));
}
