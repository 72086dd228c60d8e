//! Irreversible actions (thesis §6.3.3, "Addressing the issue of irreversible actions") and the
//! lander's backup pyro (§3.3) on `models/lander_separation.ron`: separation is irreversible, so
//! mode reconfiguration separates only when the goal names `lander = separated`; a primary pyro
//! misfire (`unsuccessful-attempt`) is recovered by firing the backup.

#[path = "support/reconfiguration.rs"]
mod support;

use kairos::reconfiguration::{Action, GoalState, PlanOutcome};
use support::Setup;

fn lander() -> Setup {
    Setup::model("lander_separation")
}

/// §6.3.3: "when the control sequencer issues the configuration goal Lander = Separated, MR
/// overlooks the fact that the Separated mode is not reversibly reachable from the Connected
/// mode ... and determines from the model that this goal can be achieved by issuing the
/// fire-primary pyro command." The pyro bus is armed first (a reversible sub-goal) and disarmed
/// last (an upstream helper restored to its goal mode).
#[test]
fn lander_separated_fires_the_primary_pyro() {
    let mut setup = lander();
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "lander = separated")
        .expect("a goal state");
    assert_eq!(
        setup.describe(goal.modes()),
        "pyro_bus = disarmed, lander = separated"
    );
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&run),
        [
            "command pyro_bus.cmd = arm (pyro_bus: disarmed -> armed)",
            "command pyro_bus.cmd = fire-primary (lander: connected -> separated)",
            "command pyro_bus.cmd = disarm (pyro_bus: armed -> disarmed)",
        ]
    );
}

/// §3.3: "failure of the primary latches to fire open would result in the deductive controller
/// reasoning through the lander model to deduce that it should fire the backup latch". After
/// the fire-primary command, mode estimation reports `unsuccessful-attempt`; goal interpretation
/// is re-run on the new estimate and the planner fires the backup, a repair.
#[test]
fn a_primary_misfire_is_recovered_with_the_backup_pyro() {
    let mut setup = lander();
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "lander = separated")
        .expect("a goal state");
    let run = setup.run(&start, &goal);
    // The state after the arm command, where the planner fires the primary pyro ...
    let armed = run.steps[0].state.clone();
    assert_eq!(
        setup.next(&armed, &goal),
        "command pyro_bus.cmd = fire-primary (lander: connected -> separated)"
    );
    // ... which misfires. Goal interpretation runs again on the new estimate, keeping the
    // configuration intended before the goal (the bus disarmed: it was armed only as a helper).
    let misfired = setup.state(&[("pyro_bus", "armed"), ("lander", "unsuccessful-attempt")]);
    let goal = setup
        .interpret_keeping(&misfired, "lander = separated", &start)
        .expect("separation is still reachable, by the backup pyro");
    let Action::Command(backup) = setup.next_action(&misfired, &goal) else {
        panic!("a command");
    };
    assert!(backup.repair);
    let recovery = setup.run(&misfired, &goal);
    assert_eq!(recovery.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&recovery),
        [
            "command pyro_bus.cmd = fire-backup (repair) (lander: unsuccessful-attempt -> separated)",
            "command pyro_bus.cmd = disarm (pyro_bus: armed -> disarmed)",
        ]
    );
}

/// §6.3.3: "MR will not achieve irreversible goals as side effects of other goals". The model
/// rewards `separated` above `connected`, so only the reachability rule keeps GI from proposing
/// it: from `connected`, and from `unsuccessful-attempt` (where the backup pyro would be a
/// repair, but into an irreversible mode), goals that do not name separation leave the lander
/// where it is — and a goal that needs it without naming it fails, saying why.
#[test]
fn goal_interpretation_never_proposes_separation_unless_the_goal_names_it() {
    let mut setup = lander();
    let lander = setup.plant.component_named("lander").expect("lander");
    for state in [
        setup.state(&[]),
        setup.state(&[("lander", "unsuccessful-attempt")]),
    ] {
        for goal in ["true", "pyro_bus = armed", "not lander = failed"] {
            let chosen = setup.interpret(&state, goal).expect("a goal state");
            assert_eq!(chosen.mode(lander), state[lander.index()], "goal `{goal}`");
        }
    }
    let failed = setup
        .interpret(&setup.state(&[]), "lander.latches = open")
        .expect_err("separation is not named");
    assert_eq!(
        failed.reason,
        "lander.latches = open is unreachable: lander can reach only connected from connected; \
         lander = separated would be irreversible and the goal does not name it"
    );
    // A negated mention is not a request.
    let failed = setup
        .interpret(
            &setup.state(&[]),
            "lander.latches = open and not lander = separated or lander = failed",
        )
        .expect_err("separation is not requested");
    assert!(
        failed.reason.contains("does not name it"),
        "{}",
        failed.reason
    );
}

/// The planner itself refuses an irreversible step toward a goal mode nobody named, even when
/// handed such a goal state directly.
#[test]
fn the_planner_refuses_an_irreversible_step_the_goal_did_not_name() {
    let setup = lander();
    let start = setup.state(&[]);
    let separated = vec![
        setup.mode("pyro_bus", "armed"),
        setup.mode("lander", "separated"),
    ];
    let unnamed = GoalState::new(&setup.plant, separated.clone(), &[]);
    let armed = setup.state(&[("pyro_bus", "armed")]);
    let Action::Failure(failure) = setup.next_action(&armed, &unnamed) else {
        panic!("no action toward an unnamed irreversible goal");
    };
    assert_eq!(
        failure.reason,
        "lander cannot be moved from connected to separated: the step would be irreversible and \
         the goal does not name the target"
    );
    let lander = setup.plant.component_named("lander").expect("lander");
    let named = GoalState::new(&setup.plant, separated, &[lander]);
    assert!(matches!(
        setup.next_action(&start, &named),
        Action::Command(_)
    ));
}

/// The lander's policy as a table: separation is marked irreversible, the backup a repair.
#[test]
fn the_lander_policy_marks_irreversible_steps_and_repairs() {
    let setup = lander();
    let lander = setup.plant.component_named("lander").expect("lander");
    let policy = setup.reconfiguration.policy(lander);
    let cell = |from: &str, to: &str| {
        policy.cell(
            &setup.plant,
            setup.mode("lander", from),
            setup.mode("lander", to),
        )
    };
    assert_eq!(
        cell("connected", "separated"),
        "lander.fire = primary (irreversible)"
    );
    assert_eq!(
        cell("unsuccessful-attempt", "separated"),
        "lander.fire = backup (repair) (irreversible)"
    );
    assert_eq!(cell("separated", "connected"), "Failure");
    let reachability = policy.reachability();
    assert!(reachability.is_committing(setup.mode("lander", "separated")));
    assert!(reachability.is_irreversible(
        setup.mode("lander", "connected"),
        setup.mode("lander", "separated")
    ));
}

/// §7.2.3, Figure B-4: once the engine fires, the program asserts the landing attitude and the
/// gravity turn together ("the propulsion control system concurrently initiates a gravity turn
/// maneuver"). The attitude slew is a timed transition of up to 300 s; the planner must not hold
/// the propulsion controller's mode switch, which does not depend on the attitude, until the slew
/// ends. On the propulsion path the wait still holds: the PDE, which relays the heating engine's
/// command, is switched off only once the engine is in standby (§6.3.3).
#[test]
fn independent_goals_go_on_while_a_timed_transition_is_awaited() {
    let mut setup = Setup::model("mars_lander");
    let start = setup.state(&[
        ("engine", "firing"),
        ("valve1", "open"),
        ("valve2", "open"),
        ("att", "vel-vector-orient"),
    ]);
    let goal = setup
        .interpret(&start, "att = landing-orient and prop = gravity-turn")
        .expect("a goal state");
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&run)[..3],
        [
            "command att.cmd = to-landing (att: vel-vector-orient -> slew-to-landing)",
            "command prop.cmd = gravity-turn (prop: idle -> gravity-turn)",
            "wait, after Uniform(0, 300) s (att: slew-to-landing -> landing-orient)",
        ]
    );

    let cold = setup.state(&[]);
    let goal = setup
        .interpret(&cold, "engine = standby")
        .expect("a goal state");
    let run = setup.run(&cold, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&run),
        [
            "command PDE.cmd = on (PDE: off -> on)",
            "command PDE.cmd = engine-standby (engine: off -> heating)",
            "wait, after Uniform(30, 60) s (engine: heating -> standby)",
            "command PDE.cmd = off (PDE: on -> off)",
        ]
    );
}
