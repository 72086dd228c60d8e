//! The mission file (DESIGN.md §15.4): the thermostat missions load, and every bad
//! mission in `tests/bad_missions/` (its first comment says what is wrong) is refused with a
//! located error (file:line:col, the text, what was expected; DESIGN.md §13), snapshot-tested as
//! `kairos check` prints it.

#[path = "support/bad_files.rs"]
#[macro_use]
mod bad_files;

use std::path::Path;

use kairos::goalnet::{GoalKind, Response, TimePointId, Window, mission};

fn root() {
    // Relative to the crate root, so that messages name files as a user at the root sees them.
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
}

macro_rules! bad_mission {
    ($($case:tt)+) => { bad_file!(mission::load, "tests/bad_missions", $($case)+); };
}

bad_mission!(syntax_error, "syntax_error.ron:4:5");
bad_mission!(missing_plant, "missing_plant.ron:3:13", "cannot read");
bad_mission!(
    unknown_point,
    "unknown_point.ron:6:53",
    "`TP_E`",
    "did you mean `TP_End`",
    "unknown_point.ron:7:126"
);
bad_mission!(unknown_sv, "unknown_sv.ron:6:43", "did you mean `switch1`");
bad_mission!(unknown_value, "unknown_value.ron:6:", "shut");
bad_mission!(
    other_variable,
    "other_variable.ron:6:",
    "may only constrain `switch1`"
);
bad_mission!(
    missing_constraint,
    "missing_constraint.ron:6:",
    "needs a constraint"
);
bad_mission!(knowledge_shape, "knowledge_shape.ron:6:", "least beliefs");
bad_mission!(bad_bounds, "bad_bounds.ron:6:", "[300, 200]");
bad_mission!(
    inconsistent,
    "inconsistent.ron:",
    "negative cycle",
    "TP_A → TP_S ∈ [60, 150]"
);
bad_mission!(
    unknown_parent,
    "unknown_parent.ron:7:",
    "unknown parent goal `heater`"
);
bad_mission!(duplicate_names, "declared twice", "knowledge threshold 1.5");
bad_mission!(unknown_field, "unknown_field.ron:6:", "begin");
bad_mission!(
    recursive_type,
    "recursive_type.ron:15:56",
    "goal type `Warm` elaborates into itself: Warm → Heat → Warm"
);
bad_mission!(
    multiplying_types,
    "multiplying_types.ron:11:25",
    "a goal of type `T0` elaborates into 38228 goals"
);

/// System test 4's mission (mds-goal-networks.md §3.2): the windows of its points follow from
/// the constraints alone (TP_S in [70, 165] before anything fires), and the goals are tied to the
/// components and macros they name.
#[test]
fn the_stay_warm_mission_loads_with_its_windows() {
    root();
    let mission = mission::load(Path::new("missions/thermostat_stay_warm.ron")).expect("loads");
    let network = &mission.network;
    let window = |name: &str| {
        let point = network.point_named(name).expect("declared");
        network.stn().window(point).expect("propagated")
    };
    assert_eq!(window("TP_H"), Window { lb: 10.0, ub: 10.0 });
    assert_eq!(window("TP_A"), Window { lb: 10.0, ub: 15.0 });
    assert_eq!(
        window("TP_S"),
        Window {
            lb: 70.0,
            ub: 165.0
        }
    );
    assert_eq!(
        window("TP_E"),
        Window {
            lb: 370.0,
            ub: 465.0
        }
    );
    assert_eq!(
        network.stn().window(TimePointId::ORIGIN),
        Some(Window { lb: 0.0, ub: 0.0 })
    );
    let heater = network.goal(network.goal_named("heater1").expect("declared"));
    assert_eq!(heater.kind, GoalKind::Maintain);
    let switch1 = mission.plant.component_named("switch1");
    assert_eq!(heater.sv, switch1);
    let parent = network.goal(heater.parent.expect("a parent"));
    assert!(parent.is_macro() && parent.name == "StayWarm");
    let closed: Vec<_> = heater
        .constraint
        .admitted()
        .map(|v| {
            mission
                .plant
                .table()
                .variable(mission.plant.component(switch1.unwrap()).mode_var())
                .value_name(v)
                .to_string()
        })
        .collect();
    assert_eq!(closed, ["closed", "stuck-closed"]);
    assert_eq!(mission.knowledge_threshold, 0.9);
}

/// System test 1's mission: knowledge goals only, every one requiring "known".
#[test]
fn the_know_all_mission_is_knowledge_only() {
    root();
    let mission = mission::load(Path::new("missions/thermostat_know_all.ron")).expect("loads");
    let goals: Vec<_> = mission
        .network
        .goals()
        .iter()
        .filter(|g| !g.is_macro())
        .collect();
    assert_eq!(goals.len(), 8);
    assert!(
        goals
            .iter()
            .all(|g| g.kind == GoalKind::Knowledge && g.constraint.requires_known())
    );
    assert!(mission.safe.goals().is_empty());
}

/// `kairos check` validates missions beside models and programs: the shipped
/// missions pass, a bad one exits 2 with its located error.
#[test]
fn kairos_check_validates_missions() {
    root();
    let kairos = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_kairos"))
            .args(args)
            .output()
            .expect("runs")
    };
    let good = kairos(&[
        "check",
        "missions/thermostat_stay_warm.ron",
        "missions/thermostat_know_all.ron",
    ]);
    assert_eq!(good.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&good.stdout);
    assert!(stdout.contains("ok: missions/thermostat_stay_warm.ron: mission on models/thermostat.ron (6 time points, 13 goals)"), "{stdout}");
    let bad = kairos(&["check", "tests/bad_missions/unknown_sv.ron"]);
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(stderr.contains("unknown_sv.ron:6:43"), "{stderr}");
}

// Goal types, tactics and children (`missions/thermostat.ron`'s format).
bad_mission!(
    unknown_goal_type,
    "unknown_goal_type.ron:6:",
    "unknown goal type `StayWrm`",
    "did you mean `StayWarm`"
);
bad_mission!(
    tactic_unknown_point,
    "tactic_unknown_point.ron:7:",
    "unknown time point `TP_G`",
    "did you mean `TP_H`"
);
bad_mission!(
    tactic_reserved_point,
    "tactic_reserved_point.ron:6:",
    "`start` cannot name a tactic's point",
    "time point `TP_H` is declared twice",
    "goal type `Heater` is declared twice"
);
bad_mission!(tactic_bad_bounds, "tactic_bad_bounds.ron:7:", "[5, 1]");
bad_mission!(
    child_constraint_without_sv,
    "child_constraint_without_sv.ron:8:",
    "takes its parent's constraint"
);
bad_mission!(
    child_errors,
    "child_errors.ron:9:",
    "unknown state variable `switch3`",
    "child_errors.ron:10:",
    "shut",
    "unknown goal type `Heatr`",
    "unknown time point `TP_B`"
);
bad_mission!(
    typed_safe_goal,
    "typed_safe_goal.ron:7:",
    "the safe network is not elaborated"
);
bad_mission!(unknown_response, "unknown_response.ron:5:", "Retry");

/// The complete thermostat (mds-goal-networks.md §3.1): the seed's five goal types with their
/// responses and tactic counts, and the initial goals' types.
#[test]
fn the_thermostat_mission_declares_the_seeds_goal_types() {
    root();
    let mission = mission::load(Path::new("missions/thermostat.ron")).expect("loads");
    let elaborators = &mission.elaborators;
    let shape: Vec<(&str, Response, usize)> = elaborators
        .types
        .iter()
        .map(|t| (t.name.as_str(), t.response, t.tactics.len()))
        .collect();
    assert_eq!(
        shape,
        [
            ("KnowAll", Response::FailUp, 1),
            ("StayWarm", Response::ReElaborate, 2),
            ("GetWarm", Response::ReElaborate, 2),
            ("Sensor", Response::FailUp, 0),
            ("Heater", Response::FailUp, 1),
        ]
    );
    let typed = |goal: &str| {
        let id = mission.network.goal_named(goal).expect("a goal");
        elaborators.of(id).map(|t| elaborators.get(t).name.as_str())
    };
    assert_eq!(typed("know-all"), Some("KnowAll"));
    assert_eq!(typed("stay-warm"), Some("StayWarm"));
    assert_eq!(
        elaborators
            .get(elaborators.named("StayWarm").unwrap())
            .budget,
        3
    );
}

// Controllers of state variables that are not components, and the goals delegated to them
// (`missions/rover_traverse.ron`'s format).
bad_mission!(
    bad_controller,
    "bad_controller.ron:6:29",
    "`motors` is a component of the plant",
    "a grid of 0 cells a side",
    "state variable `pose` has a controller already",
    "(5, 1) is off the grid",
    "(1, 1) holds an obstacle"
);
bad_mission!(
    bad_delegated_goal,
    "bad_delegated_goal.ron:10:50",
    "a Maintain goal on `pose`",
    "y = 7 is not on the grid",
    "`up` is not a heading",
    "`x` is constrained twice",
    "`speed = 2` is not a constraint on a pose",
    "a goal on `pose` needs a constraint"
);

/// The rover missions load: one controller of `pose` (seed 001's course-of-action controller,
/// its device on the 5×5 grid of mds-goal-networks.md §4.2) and a Transition goal delegated to
/// it, beside the goals on the motors, a component.
#[test]
fn the_rover_missions_delegate_the_traverse_to_the_pose_controller() {
    root();
    for (file, obstacles) in [
        ("missions/rover_traverse.ron", vec![]),
        ("missions/rover_traverse_blocked.ron", vec![(2, 0)]),
    ] {
        let loaded = mission::load(Path::new(file)).expect("the rover mission loads");
        assert_eq!(loaded.controllers.len(), 1);
        let controller = &loaded.controllers[0];
        assert_eq!(controller.sv, "pose");
        assert_eq!(controller.grid.size, 5);
        assert_eq!(
            controller
                .grid
                .obstacles
                .iter()
                .copied()
                .collect::<Vec<_>>(),
            obstacles
        );
        let network = &loaded.network;
        let goal = network.goal(network.goal_named("to-the-rock").expect("the traverse"));
        assert_eq!(goal.sv, None);
        assert_eq!(goal.kind, GoalKind::Transition);
        let delegate = goal.delegate.expect("delegated");
        assert_eq!(delegate.controller, 0);
        assert_eq!(delegate.constraint.to_string(), "(x=3, y=2)");
        assert!(!goal.is_macro());
    }
}
