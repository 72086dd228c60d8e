//! The shipped plant models and the plant-level semantics: variables named as
//! agreed, Table 6.1's numbers, §6.2's per-step probabilities, Step_TCCA (Figure 6-6) and
//! ConsistentState (Figure 6-7), and `kairos graph`.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

use kairos::diagnostic::Source;
use kairos::logic::{ValueId, VarId};
use kairos::opsat::{Consistency, Literal, Theory};
use kairos::plant::{
    Commands, ComponentId, ModeKind, Observation, Plant, StepError, SystemState, TransitionLaw,
    TransitionSource, consistent_state, step_tcca, transition_choices,
};

fn model(name: &str) -> Plant {
    let path = format!("{}/models/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("model file");
    Plant::load(&Source::new(path, text)).unwrap_or_else(|e| panic!("{e}"))
}

fn var(plant: &Plant, name: &str) -> VarId {
    plant.table().variable_id(name).expect(name)
}

fn value(plant: &Plant, var_name: &str, value: &str) -> (VarId, ValueId) {
    let x = var(plant, var_name);
    (x, plant.table().variable(x).value(value).expect(value))
}

fn modes(plant: &Plant, names: &[&str]) -> Vec<ValueId> {
    plant
        .components()
        .iter()
        .zip(names)
        .map(|(c, n)| c.mode_named(n).expect(n))
        .collect()
}

fn probability_of(distribution: &[(ValueId, f64)], mode: ValueId) -> f64 {
    distribution
        .iter()
        .find(|(m, _)| *m == mode)
        .map_or(0.0, |(_, p)| *p)
}

#[test]
fn the_shipped_models_load_and_name_their_variables_as_agreed() {
    for name in ["driver_valve", "engine_camera", "propulsion"] {
        let plant = model(name);
        plant.theory().expect("the theory encodes");
        for (id, component) in plant.component_ids() {
            assert_eq!(var(&plant, component.name()), component.mode_var());
            assert_eq!(plant.component_of(component.mode_var()), Some(id));
            for &attribute in component.attributes() {
                let attribute_name = plant.table().variable(attribute).name();
                assert!(attribute_name.starts_with(&format!("{}.", component.name())));
                assert_eq!(plant.component_of(attribute), None);
            }
        }
    }
    let plant = model("propulsion");
    assert_eq!(plant.components().len(), 6);
    assert!(plant.table().variable_id("engine.temp").is_some());
    assert_eq!(plant.controls().len(), 1);
    assert_eq!(plant.observables().len(), 5);
}

/// Table 6.1 and §6.1.3, exactly.
#[test]
fn driver_valve_is_table_6_1() {
    let plant = model("driver_valve");
    let driver = plant.component(ComponentId(0));
    let mode = |name: &str| driver.mode_named(name).expect(name);
    assert_eq!(driver.initial()[mode("off").index()], 0.9);
    assert_eq!(driver.initial()[mode("on").index()], 0.1);
    assert_eq!(driver.mode(mode("resettable")).reward, -10.0);
    assert_eq!(driver.mode(mode("failed")).reward, -20.0);
    assert_eq!(driver.mode(mode("failed")).kind, ModeKind::Fault);
    // tau1..tau4 out of Off: commanded 0.989, resettable 0.01, failed 0.001.
    let out_of_off: Vec<(String, TransitionLaw)> = driver
        .outgoing(mode("off"))
        .iter()
        .map(|&t| {
            let t = &driver.transitions()[t];
            (driver.mode(t.target).name.clone(), t.law)
        })
        .collect();
    assert_eq!(
        out_of_off,
        vec![
            (
                "turning-on".into(),
                TransitionLaw::PerCycle { probability: 0.989 }
            ),
            (
                "resettable".into(),
                TransitionLaw::PerCycle { probability: 0.01 }
            ),
            (
                "failed".into(),
                TransitionLaw::PerCycle { probability: 0.001 }
            ),
        ]
    );
    // "*" is every nominal mode: not Resettable (tau20 is its own transition) nor Failed.
    let star = driver
        .transitions()
        .iter()
        .position(|t| t.source == TransitionSource::AnyNominal)
        .expect("a * transition");
    assert!(!driver.outgoing(mode("resettable")).contains(&star));
    assert!(driver.outgoing(mode("failed")).is_empty());
    let valve = plant.component(ComponentId(1));
    assert_eq!(
        valve.mode(valve.mode_named("open").expect("open")).reward,
        -5.0
    );
}

/// Table 6.1, tau6 at t_D = 0.1: a step that spans TurningOn's window takes it to On with
/// 0.989, and staying in TurningOn becomes impossible (§7.1.2: "the transition will be taken
/// after one cycle spent in TurningOn mode").
#[test]
fn table_6_1_tau_6_after_one_cycle_spanning_the_window() {
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    let state = SystemState::entered_at(&plant, modes(&plant, &["turning-on", "closed"]), 0.0);
    let choices = transition_choices(
        &plant,
        &mut theory,
        &state,
        &Commands::idle(&plant),
        0.0,
        0.1,
    )
    .expect("choices");
    let driver = plant.component(ComponentId(0));
    let on = driver.mode_named("on").expect("on");
    let turning_on = driver.mode_named("turning-on").expect("turning-on");
    assert!((probability_of(&choices[0], on) - 0.989).abs() < 1e-12);
    assert_eq!(probability_of(&choices[0], turning_on), 0.0);
    // Half the window: half of tau6, and tau5 keeps the rest.
    let half = transition_choices(
        &plant,
        &mut theory,
        &state,
        &Commands::idle(&plant),
        0.0,
        0.05,
    )
    .expect("choices");
    assert!((probability_of(&half[0], on) - 0.989 * 0.5).abs() < 1e-12);
    assert!((probability_of(&half[0], turning_on) - (1.0 - 0.011 - 0.4945)).abs() < 1e-12);
}

/// Figure 6-6: a commanded transition is enabled only when the store entails its guard, and the
/// clock of a component that changes mode restarts.
#[test]
fn step_tcca_follows_the_commands_and_restarts_clocks() {
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    let start = SystemState::entered_at(&plant, modes(&plant, &["off", "closed"]), 0.0);
    let most_likely = |_: ComponentId, d: &[(ValueId, f64)]| {
        (0..d.len())
            .max_by(|&a, &b| d[a].1.total_cmp(&d[b].1))
            .unwrap_or(0)
    };
    let on = Commands::new(&plant, &[value(&plant, "driver.dcmd_in", "on")]).expect("command");
    let next = step_tcca(&plant, &mut theory, &start, &on, 0.0, 1.0, most_likely).expect("step");
    assert_eq!(next.describe(&plant), "driver = turning-on, valve = closed");
    assert_eq!(next.clock_starts[0], Some(1.0));
    // Without the command the driver stays off.
    let idle = Commands::idle(&plant);
    let still = step_tcca(&plant, &mut theory, &start, &idle, 0.0, 1.0, most_likely).expect("step");
    assert_eq!(still.describe(&plant), "driver = off, valve = closed");
    // One more cycle spanning the window: on.
    let on_now = step_tcca(&plant, &mut theory, &next, &idle, 1.0, 2.0, most_likely).expect("step");
    assert_eq!(on_now.describe(&plant), "driver = on, valve = closed");
}

/// Figure 6-7: the next state must be consistent with the observation. A valve commanded open
/// (through an on driver) that shows no flow out while flow comes in is stuck closed.
#[test]
fn consistent_state_explains_the_observation() {
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    let state = SystemState::entered_at(&plant, modes(&plant, &["on", "closed"]), 0.0);
    let open = Commands::new(&plant, &[value(&plant, "driver.dcmd_in", "open")]).expect("command");
    let flows = |out: &str| {
        Observation::new(
            &plant,
            &[
                value(&plant, "valve.flow_in", "nominal"),
                value(&plant, "valve.flow_out", out),
            ],
        )
        .expect("observation")
    };
    let opened = consistent_state(
        &plant,
        &mut theory,
        &state,
        &open,
        &flows("nominal"),
        0.0,
        1.0,
    )
    .expect("theory")
    .expect("a consistent state");
    assert_eq!(opened.describe(&plant), "driver = on, valve = open");
    let stuck = consistent_state(&plant, &mut theory, &state, &open, &flows("zero"), 0.0, 1.0)
        .expect("theory")
        .expect("a consistent state");
    assert_eq!(stuck.describe(&plant), "driver = on, valve = stuck-closed");
}

/// §6.1.3's interconnection: an on driver relays its command to the valve.
#[test]
fn the_theory_holds_the_modes_and_the_interconnection() {
    let plant = model("driver_valve");
    let mut theory: Theory = plant.theory().expect("theory");
    let (driver, on) = value(&plant, "driver", "on");
    let (dcmd_in, open) = value(&plant, "driver.dcmd_in", "open");
    let (vcmd_in, vopen) = value(&plant, "valve.vcmd_in", "open");
    let relayed = kairos::logic::Formula::is(vcmd_in, vopen);
    let store = [Literal::Is(driver, on), Literal::Is(dcmd_in, open)];
    assert!(theory.entails(&store, &relayed).expect("entailment"));
    let (_, off) = value(&plant, "driver", "off");
    let refuted = [Literal::Is(driver, off), Literal::Is(vcmd_in, vopen)];
    assert!(matches!(
        theory.consistent(&refuted),
        Consistency::Conflict(_)
    ));
}

#[test]
fn commands_and_observations_are_checked_against_the_plant() {
    let plant = model("driver_valve");
    let flow = value(&plant, "valve.flow_in", "zero");
    let command = value(&plant, "driver.dcmd_in", "on");
    assert!(Commands::new(&plant, &[flow]).is_err());
    assert!(Commands::new(&plant, &[command, command]).is_err());
    assert!(Observation::new(&plant, &[command]).is_err());
    assert!(Observation::new(&plant, &[(flow.0, ValueId(7))]).is_err());
    let commands = Commands::new(&plant, &[command]).expect("command");
    assert_eq!(commands.issued(&plant).collect::<Vec<_>>(), vec![command]);
}

/// `kairos graph MODEL --dot`: one cluster per component automaton, timed edges labelled with
/// their windows.
#[test]
fn graph_draws_one_cluster_per_component_with_timed_windows() {
    let (code, dot, _) = kairos(&["graph", "models/engine_camera.ron", "--dot"]);
    assert_eq!(code, 0);
    assert!(dot.contains("subgraph \"cluster_engine\""), "{dot}");
    assert!(dot.contains("subgraph \"cluster_camera\""), "{dot}");
    assert!(
        dot.contains("\"engine/heating\" -> \"engine/standby\" [label=\"not engine.cmd = off\\lafter Uniform(30, 60) s\\l\"];"),
        "{dot}"
    );
    insta::assert_snapshot!(dot);
    let (code, listing, _) = kairos(&["graph", "models/driver_valve.ron"]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(listing);
}

/// A state that does not fit the plant is reported by `check`, and the step functions do not
/// panic on it (DESIGN.md §13: no panics on any input).
#[test]
fn a_state_of_the_wrong_shape_is_reported_not_a_panic() {
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    let idle = Commands::idle(&plant);
    for state in [
        SystemState::new(vec![ValueId(0)], vec![Some(0.0)]),
        SystemState::new(vec![ValueId(0), ValueId(42)], vec![None]),
    ] {
        assert!(state.check(&plant).is_err());
        let stepped = step_tcca(&plant, &mut theory, &state, &idle, 0.0, 1.0, |_, _| 0);
        assert!(matches!(stepped, Err(StepError::Input(_))));
        let choices = transition_choices(&plant, &mut theory, &state, &idle, 0.0, 1.0);
        assert!(matches!(choices, Err(StepError::Input(_))));
        let none = Observation::none();
        let next = consistent_state(&plant, &mut theory, &state, &idle, &none, 0.0, 1.0);
        assert!(matches!(next, Err(StepError::Input(_))));
        let _ = state.describe(&plant);
    }
    let good = SystemState::entered_at(&plant, modes(&plant, &["off", "closed"]), 0.0);
    assert_eq!(good.check(&plant), Ok(()));
}
