//! The embedding API with a mission as the control program (DESIGN.md §15.3,
//! §15.4): `Executive::builder(plant, scheduled_mission)` runs the goal network in the cycle, and
//! `Executive::submit` adds goals to the running network — rescheduled with the fired points
//! held at their times — or refuses them and leaves the network unchanged.

use std::path::Path;

use kairos::executive::{
    EventKind, Executive, NamedValue, ScheduledMission, Submission, SubmitError,
    SubmittedConstraint, SubmittedGoal,
};
use kairos::goalnet::{ConstraintSet, GoalKind, ScheduleError, mission};
use kairos::reconfiguration::Reconfiguration;

/// System test 1's mission (missions/thermostat_know_all.ron) in an executive: nothing is
/// commanded until a goal is submitted.
fn know_all() -> Executive {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("missions/thermostat_know_all.ron");
    let mission = mission::load(&path).expect("the mission loads");
    let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
    let plant = mission.plant.clone();
    let scheduled = ScheduledMission::schedule(mission, &reconfiguration).expect("schedules");
    Executive::builder(plant, scheduled)
        .build()
        .expect("builds")
}

/// Steps 1 s cycles from `from` to `to` with the device reading cold; returns the events.
fn run(executive: &mut Executive, from: u32, to: u32) -> Vec<(f64, EventKind)> {
    let cold = [NamedValue::new("sensor.reading", "cold")];
    let mut events = Vec::new();
    for t in from..=to {
        let step = executive.step(f64::from(t), &cold).expect("a cycle");
        events.extend(step.events.into_iter().map(|e| (e.time, e.kind)));
    }
    events
}

/// `switch1` to reach `target` between two new points, `TP_H` at `at` s and `TP_A` up to 5 s
/// later, and to hold it until `TP_E`, 10 s after `TP_A` (system test 4's switch goals,
/// submitted as the seed submits StayWarm). The maintain goal makes `TP_A` wait until the switch
/// is there: a point fires once the XGoals starting at it are ready.
fn close_switch1(executive: &Executive, at: f64, target: &str) -> Submission {
    let plant = executive.plant();
    let sv = plant.component_named("switch1").expect("switch1");
    let component = plant.component(sv);
    let target = component.mode_named(target).expect("a mode");
    let set = ConstraintSet::control(component.modes().len(), |v| v == target);
    Submission {
        points: vec!["TP_H".into(), "TP_A".into(), "TP_E".into()],
        constraints: vec![
            SubmittedConstraint {
                from: "origin".into(),
                to: "TP_H".into(),
                min: at,
                max: at,
            },
            SubmittedConstraint {
                from: "TP_H".into(),
                to: "TP_A".into(),
                min: 0.0,
                max: 5.0,
            },
            SubmittedConstraint {
                from: "TP_A".into(),
                to: "TP_E".into(),
                min: 10.0,
                max: 10.0,
            },
        ],
        goals: vec![
            SubmittedGoal {
                name: "close-switch1".into(),
                sv: Some(sv),
                kind: GoalKind::Transition,
                constraint: set.clone(),
                text: String::new(),
                start: "TP_H".into(),
                end: "TP_A".into(),
                parent: None,
                priority: 0,
                goal_type: None,
            },
            SubmittedGoal {
                name: "heater1".into(),
                sv: Some(sv),
                kind: GoalKind::Maintain,
                constraint: set,
                text: String::new(),
                start: "TP_A".into(),
                end: "TP_E".into(),
                parent: None,
                priority: 0,
                goal_type: None,
            },
        ],
    }
}

fn fired(events: &[(f64, EventKind)]) -> Vec<(f64, String)> {
    events
        .iter()
        .filter_map(|(t, e)| match e {
            EventKind::TimePointFired { point, .. } => Some((*t, point.clone())),
            _ => None,
        })
        .collect()
}

/// Goals submitted at 20 s, after TP_k1 fired at 10 s: they are scheduled with TP_k1 held at 10 s
/// (it does not fire again); TP_H fires at 30 s and the transition it dispatches is the
/// configuration goal — switch 1 is commanded closed at 30 s — and TP_A fires at 31 s, once the
/// switch is believed closed.
#[test]
fn a_submitted_goal_is_scheduled_around_the_fired_points_and_commanded() {
    let mut executive = know_all();
    let before = run(&mut executive, 0, 20);
    assert_eq!(fired(&before), [(10.0, "TP_k1".to_string())]);
    let submission = close_switch1(&executive, 30.0, "closed");
    executive.submit(&submission, 21.0).expect("accepted");
    // Up to 31 s: from 32 s the device, cold in the reading, may be warming, and goal
    // interpretation keeps it in its intended `cold` (no goal names the temperature here).
    let after = run(&mut executive, 21, 31);
    assert_eq!(
        fired(&after),
        [(30.0, "TP_H".to_string()), (31.0, "TP_A".to_string())]
    );
    let commands: Vec<(f64, String)> = after
        .iter()
        .filter_map(|(t, e)| match e {
            EventKind::CommandIssued { assignments, .. } => Some((*t, assignments.join(", "))),
            _ => None,
        })
        .collect();
    assert_eq!(commands, [(30.0, "switch1.cmd = close".to_string())]);
    let network = &executive.control().executable().expect("a mission").network;
    assert!(network.point_named("TP_E").is_some());
}

/// A goal no reconfiguration can achieve (switch 1 into its stuck-open fault) is refused with
/// the scheduler's reason; the running network is unchanged and runs on.
#[test]
fn an_unachievable_submission_is_refused_and_the_network_is_unchanged() {
    let mut executive = know_all();
    run(&mut executive, 0, 20);
    let points = |e: &Executive| {
        e.control()
            .executable()
            .expect("a mission")
            .network
            .points()
            .len()
    };
    let before = points(&executive);
    let submission = close_switch1(&executive, 30.0, "stuck-open");
    match executive.submit(&submission, 21.0) {
        Err(SubmitError::Refused {
            error: ScheduleError::Unachievable { .. },
            explanation,
            ..
        }) => assert!(explanation.contains("close-switch1"), "{explanation}"),
        other => panic!("not refused as unachievable: {other:?}"),
    }
    assert_eq!(points(&executive), before);
    let after = run(&mut executive, 21, 70);
    assert_eq!(fired(&after), [(70.0, "TP_k2".to_string())]);
}

/// A point cannot be submitted into the past: at 21 s, a start point at 15 s makes the network
/// inconsistent, and the submission is refused.
#[test]
fn a_submission_into_the_past_is_inconsistent() {
    let mut executive = know_all();
    run(&mut executive, 0, 20);
    let submission = close_switch1(&executive, 15.0, "closed");
    assert!(matches!(
        executive.submit(&submission, 21.0),
        Err(SubmitError::Refused {
            error: ScheduleError::Inconsistent(_),
            ..
        })
    ));
}

/// Names must resolve: a goal on an unknown point is refused before scheduling.
#[test]
fn a_submission_naming_an_unknown_point_is_refused() {
    let mut executive = know_all();
    let mut submission = close_switch1(&executive, 30.0, "closed");
    submission.goals[0].end = "TP_Z".into();
    assert_eq!(
        executive.submit(&submission, 0.0),
        Err(SubmitError::Unknown {
            what: "time point",
            name: "TP_Z".into()
        })
    );
}
