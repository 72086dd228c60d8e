//! Mode reconfiguration on the propulsion subsystem of thesis §6.3.3 (Figures 6-14 and 6-15,
//! Table 6.2, Figure 6-16) as `models/propulsion.ron` models it: the PDE relays every valve and
//! engine command (its `PDE.cmd` is the only control), so a command to the engine or a valve
//! needs the PDE on.

#[path = "support/reconfiguration.rs"]
mod support;

use kairos::logic::Formula;
use kairos::plant::TransitionLaw;
use kairos::reconfiguration::{
    Action, Condition, FailureCause, PlanOutcome, PolicyEntry, Reconfiguration,
};
use support::Setup;

fn propulsion() -> Setup {
    Setup::model("propulsion")
}

/// Table 6.2, cell by cell, in our names: the thesis's `ecmd` is the engine's command input
/// `engine.cmd` (connected to the PDE's `engine_cmd` output). Rows are current modes, columns
/// target modes (the nominal ones: `failed` is never a target).
#[test]
fn the_compiled_engine_policy_is_table_6_2() {
    let setup = propulsion();
    let plant = &setup.plant;
    let engine = plant.component_named("engine").expect("engine");
    let policy = setup.reconfiguration.policy(engine);
    let targets = ["off", "heating", "standby", "firing"];
    let table_6_2: [(&str, [&str; 4]); 5] = [
        (
            "off",
            [
                "Idle",
                "engine.cmd = standby",
                "engine.cmd = standby",
                "engine.cmd = standby",
            ],
        ),
        ("heating", ["engine.cmd = off", "Idle", "Idle", "Idle"]),
        (
            "standby",
            [
                "engine.cmd = off",
                "engine.cmd = off",
                "Idle",
                "valve1 = open, valve2 = open, engine.cmd = fire",
            ],
        ),
        (
            "firing",
            [
                "engine.cmd = standby",
                "engine.cmd = standby",
                "engine.cmd = standby",
                "Idle",
            ],
        ),
        ("failed", ["Failure", "Failure", "Failure", "Failure"]),
    ];
    for (current, row) in table_6_2 {
        for (target, expected) in targets.iter().zip(row) {
            let cell = policy.cell(
                plant,
                setup.mode("engine", current),
                setup.mode("engine", target),
            );
            assert_eq!(cell, expected, "Table 6.2, row {current}, column {target}");
        }
    }
}

/// Behind the cells of Table 6.2: what the planner does for them. §6.3.3: "time constraints map
/// to the Idle control action" (heating → standby, heating → firing); the standby → firing
/// entry needs both valves open (sub-goals) and then the fire command, which only a PDE that is
/// on relays, so the PDE being on is a sub-goal too (Figure 6-12's interconnection).
#[test]
fn table_6_2s_entries_compile_to_sub_goals_and_pde_commands() {
    let setup = propulsion();
    let plant = &setup.plant;
    let table = plant.table();
    let engine = plant.component_named("engine").expect("engine");
    let policy = setup.reconfiguration.policy(engine);
    let step = |from: &str, to: &str| {
        let PolicyEntry::Next { step, irreversible } =
            policy.entry(setup.mode("engine", from), setup.mode("engine", to))
        else {
            panic!("{from} -> {to} has a step");
        };
        assert!(
            !irreversible,
            "the engine's nominal transitions are reversible"
        );
        policy.steps()[step].clone()
    };
    let name = |(x, v)| table.assignment(x, v).to_string();
    let mode_name = |(c, m): (kairos::plant::ComponentId, kairos::logic::ValueId)| {
        format!(
            "{} = {}",
            plant.component(c).name(),
            plant.component(c).mode(m).name
        )
    };

    let fire = step("standby", "firing");
    let fire_needs = fire.requirement.expect("plannable");
    let sub_goals: Vec<String> = fire_needs.modes.iter().copied().map(mode_name).collect();
    // Sub-goals in the planner's order: downstream first, so the PDE comes last.
    assert_eq!(sub_goals, ["valve1 = open", "valve2 = open", "PDE = on"]);
    let controls: Vec<String> = fire_needs.controls.iter().copied().map(name).collect();
    assert_eq!(controls, ["PDE.cmd = engine-fire"]);
    assert!(matches!(
        fire_needs.conditions.last(),
        Some(Condition::Input(Formula::Atom(_)))
    ));

    let start = step("off", "firing").requirement.expect("plannable");
    let controls: Vec<String> = start.controls.iter().copied().map(name).collect();
    assert_eq!(controls, ["PDE.cmd = engine-standby"]);

    for target in ["standby", "firing"] {
        let wait = step("heating", target);
        assert!(wait.requirement.as_ref().is_ok_and(|r| r.is_idle()));
        let law = plant.component(engine).transitions()[wait.transition].law;
        assert!(matches!(law, TransitionLaw::Timed { .. }), "{law}");
        assert_eq!(law.to_string(), "after Uniform(30, 60) s");
    }
}

/// Figure 6-16: from all off, GI's goal state for `engine = firing` is {PDE = off, valve1 =
/// open, valve2 = open, engine = firing} — the PDE is needed on the way, not in the goal state.
#[test]
fn goal_interpretation_for_engine_firing_is_figure_6_16s_state() {
    let mut setup = propulsion();
    let off = setup.state(&[]);
    let goal = setup
        .interpret(&off, "engine = firing")
        .expect("a goal state");
    assert_eq!(
        setup.describe(goal.modes()),
        "PDE = off, tank1 = full, tank2 = full, valve1 = open, valve2 = open, engine = firing"
    );
    assert_eq!(goal.reward(), -13.0);
    let engine = setup.plant.component_named("engine").expect("engine");
    assert!(goal.is_named(engine));
}

/// §6.3.3's sequence, one action per cycle, each confirmed nominally (as mode estimation would),
/// with goal interpretation re-run on every new estimate as the executive does. Our model
/// routes every command through the PDE, so the sequence differs from the thesis's list in one
/// place, for one reason: the thesis's step 1 commands the engine directly (`Engine.ecmd =
/// standby`), while here the standby command is a PDE command and needs the PDE on first. The
/// PDE then stays on through the wait — the planner serialises and does not fill idle time
/// (§6.3.3's second limitation) — so the thesis's step 3, "turn on the driver", has nothing
/// left to do.
#[test]
fn the_section_6_3_3_sequence_from_all_off_to_engine_firing() {
    let mut setup = propulsion();
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "engine = firing")
        .expect("a goal state");
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    let expected = [
        // The engine is furthest downstream, so its goal is worked on first. Its off → heating
        // step needs `engine.cmd = standby`, which the PDE relays only when on: sub-goal
        // PDE = on, whose own policy says `PDE.cmd = on`.
        "command PDE.cmd = on (PDE: off -> on)",
        // Thesis step 1: the standby command, through the PDE.
        "command PDE.cmd = engine-standby (engine: off -> heating)",
        // Thesis step 2: heating → standby is timed (Uniform(30, 60) s): Idle.
        "wait, after Uniform(30, 60) s (engine: heating -> standby)",
        // Thesis steps 4 and 5: standby → firing needs both valves open (sub-goals, worked on
        // before the command that needs them); each open command goes through the PDE, on.
        "command PDE.cmd = open1 (valve1: closed -> open)",
        "command PDE.cmd = open2 (valve2: closed -> open)",
        // Thesis step 6: the fire command.
        "command PDE.cmd = engine-fire (engine: standby -> firing)",
        // Thesis step 7: the engine and the valves are in their goal modes; the PDE, upstream
        // helper, is returned to its goal mode last.
        "command PDE.cmd = off (PDE: on -> off)",
    ];
    assert_eq!(setup.actions(&run), expected);
    // One component moves per cycle, as intended; GI, re-run on each confirmed state with the
    // configuration kept from before the goal (as the executive does), keeps the same goal
    // state — the PDE, on only as a helper, is still meant to be off.
    for step in &run.steps {
        assert_eq!(step.moves.len(), 1, "{:?}", step.moves);
        let again = setup
            .interpret_keeping(&step.state, "engine = firing", &start)
            .expect("still a goal state");
        assert_eq!(again.modes(), goal.modes());
    }
}

/// §6.3's introductory example: `engine = standby` from all off. The goal state keeps the PDE
/// off (its power is not free), and the planner's sequence is the thesis's exactly: power on
/// the PDE, issue the engine standby command, wait, power off the PDE.
#[test]
fn engine_standby_powers_the_pde_on_then_off_as_in_section_6_3() {
    let mut setup = propulsion();
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "engine = standby")
        .expect("a goal state");
    assert_eq!(
        setup.describe(goal.modes()),
        "PDE = off, tank1 = full, tank2 = full, valve1 = closed, valve2 = closed, engine = standby"
    );
    let run = setup.run(&start, &goal);
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

/// §6.3: "should the PDE suddenly be determined to have transitioned into its resettable fault
/// mode, RP then issues the appropriate recovery command". Mid-sequence, with valve 2 still to
/// open, the PDE is needed on: the repair is `reset` (resettable → on), then the sequence goes
/// on where it was.
#[test]
fn a_pde_found_resettable_mid_sequence_is_reset_and_the_sequence_continues() {
    let mut setup = propulsion();
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "engine = firing")
        .expect("a goal state");
    let run = setup.run(&start, &goal);
    // After valve 1 opened (cycle 4), mode estimation reports the PDE resettable.
    let mut state = run.steps[3].state.clone();
    assert!(setup.describe(&state).contains("valve1 = open"));
    let pde = setup.plant.component_named("PDE").expect("PDE");
    state[pde.index()] = setup.mode("PDE", "resettable");
    let goal = setup
        .interpret(&state, "engine = firing")
        .expect("still a goal state");
    assert_eq!(goal.mode(pde), setup.mode("PDE", "off"));
    let Action::Command(repair) = setup.next_action(&state, &goal) else {
        panic!("a repair command");
    };
    assert!(repair.repair);
    let recovery = setup.run(&state, &goal);
    assert_eq!(recovery.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&recovery),
        [
            "command PDE.cmd = reset (repair) (PDE: resettable -> on)",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "command PDE.cmd = engine-fire (engine: standby -> firing)",
            "command PDE.cmd = off (PDE: on -> off)",
        ]
    );
}

/// §6.3: "assuming no further engine commands need to be issued, the appropriate recovery
/// command is (dcmd_in = off)": once the engine fires, a resettable PDE is repaired by `off`.
#[test]
fn a_pde_found_resettable_after_the_fire_command_is_repaired_by_off() {
    let mut setup = propulsion();
    let state = setup.state(&[
        ("PDE", "resettable"),
        ("valve1", "open"),
        ("valve2", "open"),
        ("engine", "firing"),
    ]);
    let goal = setup
        .interpret(&state, "engine = firing")
        .expect("a goal state");
    let run = setup.run(&state, &goal);
    assert_eq!(
        setup.actions(&run),
        ["command PDE.cmd = off (repair) (PDE: resettable -> off)"]
    );
}

/// DESIGN.md §9: "No solution → goal failed event with a reason naming the components that
/// make it unreachable (e.g. 'engine is failed')".
#[test]
fn a_goal_on_a_failed_engine_fails_naming_the_engine() {
    let mut setup = propulsion();
    let state = setup.state(&[("engine", "failed")]);
    let failed = setup
        .interpret(&state, "engine = standby")
        .expect_err("a failed engine has no repair");
    assert_eq!(
        failed.reason,
        "engine = standby is unreachable: engine is failed"
    );
    let engine = setup.plant.component_named("engine").expect("engine");
    assert!(matches!(
        failed.cause,
        FailureCause::Unreachable { ref components, .. } if components == &[engine]
    ));
}

#[test]
fn two_goals_on_one_component_fail_naming_both() {
    let mut setup = propulsion();
    let state = setup.state(&[]);
    let failed = setup
        .interpret(&state, "engine = standby and engine = firing")
        .expect_err("contradictory");
    assert_eq!(
        failed.reason,
        "conflicting goals: engine = standby and engine = firing cannot hold together"
    );
    assert!(matches!(
        failed.cause,
        FailureCause::Contradictory { ref goals } if goals.len() == 2
    ));
}

/// The conflict names what is really responsible: an empty tank (no propellant, so no firing)
/// and a failed PDE (the valves can no longer be commanded).
#[test]
fn unreachable_goals_name_the_upstream_cause() {
    let mut setup = propulsion();
    let empty = setup.state(&[("tank1", "empty")]);
    let failed = setup
        .interpret(&empty, "engine = firing")
        .expect_err("no fuel");
    assert_eq!(
        failed.reason,
        "engine = firing is unreachable: tank1 is empty"
    );
    let dead_pde = setup.state(&[("PDE", "failed")]);
    let failed = setup
        .interpret(&dead_pde, "engine = firing")
        .expect_err("nothing can be commanded");
    assert!(
        failed
            .reason
            .starts_with("engine = firing is unreachable: "),
        "{}",
        failed.reason
    );
    assert!(failed.reason.contains("PDE is failed"), "{}", failed.reason);
}

/// A goal over attributes is interpreted by entailment (§6.3.1): thrust is nominal only when
/// firing, so the goal state is Figure 6-16's again.
#[test]
fn an_attribute_goal_is_achieved_by_the_modes_that_entail_it() {
    let mut setup = propulsion();
    let state = setup.state(&[]);
    let goal = setup
        .interpret(&state, "engine.thrust = nominal")
        .expect("a goal state");
    let engine = setup.plant.component_named("engine").expect("engine");
    assert_eq!(goal.mode(engine), setup.mode("engine", "firing"));
    assert!(!goal.is_named(engine), "the goal names no mode");
    let power = setup
        .interpret(&state, "engine.power = nominal or engine = failed")
        .expect("a goal state");
    // Heating and standby tie on reward, but the engine leaves heating by itself (a timed
    // transition): GI proposes the mode it stays in.
    assert_eq!(power.mode(engine), setup.mode("engine", "standby"));
    let named = setup
        .interpret(&state, "engine = heating")
        .expect("a goal state");
    assert_eq!(named.mode(engine), setup.mode("engine", "heating"));
}

#[test]
fn bad_input_is_a_goal_failure_not_a_panic() {
    let mut setup = propulsion();
    let goal = setup.formula("engine = firing");
    let short = setup.state(&[])[..2].to_vec();
    let failed = setup
        .reconfiguration
        .interpret(&mut setup.theory, &short, &goal)
        .expect_err("too few modes");
    assert_eq!(failed.cause, FailureCause::BadInput);
    let other = support::model("lander_separation")
        .theory()
        .expect("theory");
    let mut other = other;
    let failed = setup
        .reconfiguration
        .interpret(&mut other, &setup.state(&[]), &goal)
        .expect_err("another plant's theory");
    assert_eq!(failed.cause, FailureCause::BadInput);
    let start = setup.state(&[]);
    let goal_state = setup.interpret(&start, "engine = firing").expect("goal");
    assert!(matches!(
        setup.next_action(&short, &goal_state),
        Action::Failure(_)
    ));
}

/// The planner's goal order and the causal graph it comes from.
#[test]
fn the_causal_graph_puts_the_engine_downstream_of_the_pde_valves_and_tanks() {
    let setup = propulsion();
    let graph = setup.reconfiguration.causal_graph();
    let name = |c: kairos::plant::ComponentId| setup.plant.component(c).name().to_string();
    let engine = setup.plant.component_named("engine").expect("engine");
    let upstream: Vec<String> = graph.upstream(engine).into_iter().map(name).collect();
    assert_eq!(upstream, ["PDE", "tank1", "tank2", "valve1", "valve2"]);
    assert!(graph.is_acyclic());
    let order: Vec<String> = graph.downstream_first().iter().map(|&c| name(c)).collect();
    assert_eq!(
        order,
        ["engine", "valve1", "valve2", "PDE", "tank1", "tank2"]
    );
    // Compiling twice gives the same policies.
    let again = Reconfiguration::compile(&setup.plant).expect("compiles");
    assert_eq!(again.policies(), setup.reconfiguration.policies());
}
