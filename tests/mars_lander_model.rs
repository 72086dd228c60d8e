//! The Mars lander plant model (items 1 and 2): `models/mars_lander.ron` holds the 22
//! state variables of thesis Table 7.1 with the kinds of modes §7.2.4 and DESIGN.md §6.3
//! describe, `programs/mars_edl.rmpl` (Appendix B) links against it, and every goal the program
//! asserts can be reached from any consistent nominal state of the components it depends on by
//! commands and waits alone — the reachability the reactive planner of §6.3.3 needs.

mod support;

use std::collections::{HashMap, HashSet, VecDeque};
use std::process::Command;

use kairos::diagnostic::Source;
use kairos::logic::{Formula, ValueId, VarId};
use kairos::opsat::{Consistency, Literal, Theory};
use kairos::plant::{
    Commands, ComponentId, ModeKind, Plant, TransitionLaw, TransitionSource, enabled_transitions,
};
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::Thca;
use support::plants::model;

const EDL: &str = "programs/mars_edl.rmpl";

fn lander() -> Plant {
    model("mars_lander")
}

fn edl_against(plant: &Plant) -> Thca {
    let path = format!("{}/{EDL}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the EDL program");
    let options = LinkOptions {
        plant: Some(plant.table()),
        ..LinkOptions::default()
    };
    rmpl::load(&Source::new(EDL, text), &options).unwrap_or_else(|e| panic!("{e}"))
}

fn mode_names(plant: &Plant, component: &str) -> Vec<(String, ModeKind)> {
    let id = plant.component_named(component).expect(component);
    plant
        .component(id)
        .modes()
        .iter()
        .map(|m| (m.name.clone(), m.kind))
        .collect()
}

fn names_of(modes: &[(String, ModeKind)], kind: ModeKind) -> Vec<&str> {
    modes
        .iter()
        .filter(|(_, k)| *k == kind)
        .map(|(n, _)| n.as_str())
        .collect()
}

#[test]
fn table_7_1s_22_state_variables_are_the_components_in_order() {
    // Table 7.1, in the table's order.
    let plant = lander();
    let names: Vec<&str> = plant.components().iter().map(|c| c.name()).collect();
    assert_eq!(
        names,
        [
            "engine",
            "PDE",
            "valve1",
            "valve2",
            "tank1",
            "tank2",
            "nav",
            "entry",
            "att",
            "lander",
            "Mach_trigger",
            "chute",
            "heatshield",
            "alt_vel_trigger",
            "legs",
            "radar_altim",
            "backshield",
            "prop",
            "alt_40m_trigger",
            "alt_12m_trigger",
            "touchdown_sensor",
            "landing",
        ]
    );
}

#[test]
fn each_component_has_the_modes_its_kind_calls_for() {
    // DESIGN.md §6.3's guide to §7.2.4: nominal and fault modes per component.
    let plant = lander();
    let expect = |component: &str, nominal: &[&str], faults: &[&str]| {
        let modes = mode_names(&plant, component);
        assert_eq!(names_of(&modes, ModeKind::Nominal), nominal, "{component}");
        assert_eq!(names_of(&modes, ModeKind::Fault), faults, "{component}");
    };
    // Hardware components (§7.2.4, Figures 7-8, 7-9, 6-15; §3.2).
    expect(
        "engine",
        &["off", "heating", "standby", "firing"],
        &["failed"],
    );
    expect("PDE", &["off", "on"], &["resettable", "failed"]);
    for valve in ["valve1", "valve2"] {
        expect(valve, &["closed", "open"], &["stuck-open", "stuck-closed"]);
    }
    for tank in ["tank1", "tank2"] {
        expect(tank, &["full"], &["empty"]);
    }
    expect(
        "lander",
        &["connected", "separated"],
        &["unsuccessful-attempt", "failed"],
    );
    expect("chute", &["stowed", "deployed"], &["failed"]);
    expect("heatshield", &["attached", "jettison"], &["failed"]);
    expect("legs", &["stowed", "deployed"], &["failed"]);
    expect("backshield", &["attached", "jettisoned"], &["failed"]);
    expect("radar_altim", &["off", "on"], &["failed"]);
    expect(
        "touchdown_sensor",
        &["not-triggered", "triggered"],
        &["failed"],
    );
    // The continuous-state abstraction (Figure 7-10): four set-points, a slew toward each.
    expect(
        "att",
        &[
            "cruise-orient",
            "slew-to-entry",
            "entry-orient",
            "slew-to-vel-vector",
            "vel-vector-orient",
            "slew-to-landing",
            "landing-orient",
            "slew-to-cruise",
        ],
        &["failed"],
    );
    // Controller/estimator modes (Figure 7-11; §7.2.4).
    expect("nav", &["earth-relative", "inertial"], &["unknown"]);
    expect(
        "prop",
        &["idle", "gravity-turn", "const-vel-descent"],
        &["unknown"],
    );
    // Event triggers (Figure 7-12): software flags, no fault modes.
    expect("entry", &["not-initiated", "initiated"], &[]);
    for trigger in [
        "Mach_trigger",
        "alt_vel_trigger",
        "alt_40m_trigger",
        "alt_12m_trigger",
    ] {
        expect(trigger, &["not-triggered", "triggered"], &[]);
    }
    expect("landing", &["in-progress", "success"], &[]);
}

#[test]
fn the_unknown_and_failed_modes_are_unconstrained() {
    // §3.2 "constraint suspension", §7.2.5 "unconstrained fault modes ... 'unknown' modes".
    let plant = lander();
    for component in plant.components() {
        for mode in component.modes() {
            if mode.name == "failed" || mode.name == "unknown" {
                assert!(
                    mode.is_unconstrained_fault(),
                    "{}.{}",
                    component.name(),
                    mode.name
                );
            } else {
                assert!(
                    !mode.is_unconstrained_fault(),
                    "{}.{}",
                    component.name(),
                    mode.name
                );
            }
        }
    }
}

fn law_of(plant: &Plant, component: &str, from: &str, to: &str) -> TransitionLaw {
    let id = plant.component_named(component).expect(component);
    let c = plant.component(id);
    let (from, to) = (c.mode_named(from).expect(from), c.mode_named(to).expect(to));
    let found: Vec<&kairos::plant::Transition> = c
        .transitions()
        .iter()
        .filter(|t| t.target == to && t.source == TransitionSource::Mode(from))
        .collect();
    assert_eq!(
        found.len(),
        1,
        "{component}: one transition {from:?} -> {to:?}"
    );
    found[0].law
}

#[test]
fn the_timed_transitions_are_the_theses() {
    use kairos::plant::Timing;
    let plant = lander();
    let timing = |component, from, to| {
        *law_of(&plant, component, from, to)
            .timing()
            .unwrap_or_else(|| panic!("{component}: {from} -> {to} is timed"))
    };
    // Engine heating, 30 to 60 s (§3.2, §7.2.4).
    assert_eq!(
        timing("engine", "heating", "standby"),
        Timing::Uniform {
            lower: 30.0,
            upper: 60.0
        }
    );
    // Slews, 0 to 300 s (§7.2.4).
    for (slew, set_point) in [
        ("slew-to-entry", "entry-orient"),
        ("slew-to-vel-vector", "vel-vector-orient"),
        ("slew-to-landing", "landing-orient"),
        ("slew-to-cruise", "cruise-orient"),
    ] {
        assert_eq!(
            timing("att", slew, set_point),
            Timing::Uniform {
                lower: 0.0,
                upper: 300.0
            }
        );
    }
    // Entry: a Gaussian around the predicted entry time (§7.2.4), after the nominal timeline's
    // separation (about 43 + 16,200 + 240 + a slew of up to 300 s).
    let Timing::Gaussian { mean, sd } = timing("entry", "not-initiated", "initiated") else {
        panic!("entry is Gaussian");
    };
    assert!(mean > 43.0 + 16200.0 + 240.0 + 300.0, "{mean}");
    assert!((10.0..=100.0).contains(&sd), "{sd}");
}

#[test]
fn faults_are_hazards_and_pyro_misfires_are_outcomes_of_firing() {
    // DESIGN.md §6.2: fault transitions are `rate:` hazards, so estimation does not depend on
    // the cycle period; a pyro firing either separates or misfires (§3.3).
    let plant = lander();
    for component in plant.components() {
        for transition in component.transitions() {
            let target = component.mode(transition.target);
            if target.kind == ModeKind::Fault && transition.guard == Formula::True {
                assert!(
                    matches!(transition.law, TransitionLaw::Rate { .. }),
                    "{} -> {}",
                    component.name(),
                    target.name
                );
            }
        }
    }
    let per_cycle = |law| match law {
        TransitionLaw::PerCycle { probability } => probability,
        other => panic!("{other:?}"),
    };
    let separate = per_cycle(law_of(&plant, "lander", "connected", "separated"));
    let misfire = per_cycle(law_of(
        &plant,
        "lander",
        "connected",
        "unsuccessful-attempt",
    ));
    assert!((separate + misfire - 1.0).abs() < 1e-12 && misfire > 0.0);
    let backup = per_cycle(law_of(
        &plant,
        "lander",
        "unsuccessful-attempt",
        "separated",
    ));
    assert!(backup > 0.99);
}

#[test]
fn nominal_rewards_are_flat_so_achieved_goals_stay_achieved() {
    // Goal interpretation picks the maximum-reward state that entails the goal (§6.3.1), and
    // Appendix B asserts most goals once and moves on: were the engine's standby or an open
    // valve to cost reward (as §6.1.3's valve does), a later goal would turn the engine off in
    // cruise or close the valves — and so stop the engine — in powered descent. Only the PDE,
    // which holds no other component's mode, is biased off (§6.3.3: "turn off the driver to
    // conserve power"); faults keep §6.1.3's scale.
    let plant = lander();
    for component in plant.components() {
        let rewards: Vec<(&str, f64)> = component
            .modes()
            .iter()
            .filter(|m| m.kind == ModeKind::Nominal)
            .map(|m| (m.name.as_str(), m.reward))
            .collect();
        if component.name() == "PDE" {
            assert_eq!(rewards, [("off", 0.0), ("on", -2.0)]);
        } else {
            assert!(
                rewards.iter().all(|&(_, r)| r == 0.0),
                "{}: {rewards:?}",
                component.name()
            );
        }
        for mode in component
            .modes()
            .iter()
            .filter(|m| m.kind == ModeKind::Fault)
        {
            assert!(
                [-10.0, -20.0].contains(&mode.reward),
                "{}.{}",
                component.name(),
                mode.name
            );
        }
    }
}

#[test]
fn every_observable_is_determined_by_each_nominal_mode_of_its_component() {
    // The model's observation design (header of the model): every nominal mode entails a value
    // of each of its component's observables, so an unconstrained fault mode pays the
    // observation factor 1/m (DESIGN.md §8) every cycle they are reported. The exceptions are
    // the transitional slewing modes (the attitude is anywhere but at the target) and the
    // PDE-relayed, tank-fed valve outlets (determined given the tank).
    let plant = lander();
    let mut theory = plant.theory().expect("theory");
    let owner = |x: VarId| {
        plant
            .components()
            .iter()
            .position(|c| c.attributes().contains(&x))
            .expect("an attribute")
    };
    for &x in plant.observables() {
        let c = owner(x);
        let component = &plant.components()[c];
        let name = plant.table().variable(x).name().to_string();
        for (m, mode) in component.modes().iter().enumerate() {
            if mode.kind == ModeKind::Fault
                || name == "att.att_obs" && mode.name.starts_with("slew")
            {
                continue;
            }
            let mut assumptions = vec![Literal::Is(component.mode_var(), ValueId(m as u32))];
            if name.starts_with("valve") {
                let tank = plant.component_named(&format!("tank{}", &name[5..6]));
                let tank = plant.component(tank.expect("a tank"));
                assumptions.push(Literal::Is(tank.mode_var(), ValueId(0)));
            }
            let determined = plant.table().variable(x).value_ids().any(|v| {
                theory
                    .entails(&assumptions, &Formula::is(x, v))
                    .expect("ok")
            });
            assert!(
                determined,
                "{} = {} leaves {name} open",
                component.name(),
                mode.name
            );
        }
    }
}

#[test]
fn the_edl_program_links_against_the_model() {
    // Appendix B's program names only variables and values of the model.
    let plant = lander();
    let thca = edl_against(&plant);
    assert_eq!(thca.name(), "MarsEDL");
    assert_eq!(thca.locations().len(), 52);
    assert_eq!(thca.table().clocks().len(), 6);
    // The linked table is the plant's, with the program's clocks added.
    assert_eq!(thca.table().len(), plant.table().len());
}

#[test]
fn kairos_check_accepts_the_model_and_links_the_programs() {
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .args([
            "check",
            "models/mars_lander.ron",
            "programs/mars_edl.rmpl",
            "programs/mars_entry.rmpl",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the kairos binary runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    insta::assert_snapshot!(stdout);
}

/// The goals the program asserts, as (component, mode), each once.
fn program_goals(plant: &Plant, thca: &Thca) -> Vec<(ComponentId, ValueId)> {
    let mut goals = Vec::new();
    for location in thca.locations() {
        let Some(goal) = location.goal() else {
            continue;
        };
        let assignments = thca
            .formula(goal.formula)
            .as_assignments()
            .expect("the EDL's goals are conjunctions of assignments");
        for (x, v) in assignments {
            let c = plant.component_of(x).expect("goals name modes");
            if !goals.contains(&(c, v)) {
                goals.push((c, v));
            }
        }
    }
    goals
}

/// The components coupled to `c` by interconnections (the propulsion path), `c` included.
fn cluster(plant: &Plant, c: ComponentId) -> Vec<ComponentId> {
    let owner = |x: VarId| {
        plant
            .components()
            .iter()
            .position(|k| k.attributes().contains(&x))
            .map(|i| ComponentId(i as u32))
    };
    let mut members = vec![c];
    loop {
        let before = members.len();
        for connection in plant.connections() {
            let touched: Vec<ComponentId> = connection
                .variables()
                .into_iter()
                .filter_map(owner)
                .collect();
            if touched.iter().any(|k| members.contains(k)) {
                for k in touched {
                    if !members.contains(&k) {
                        members.push(k);
                    }
                }
            }
        }
        if members.len() == before {
            members.sort();
            return members;
        }
    }
}

/// Every mode assignment of `members` over `allowed` modes, as full states (the others initial),
/// that is consistent with the model.
fn consistent_starts(
    plant: &Plant,
    theory: &mut Theory,
    members: &[ComponentId],
    allowed: impl Fn(ComponentId, ValueId) -> bool,
) -> Vec<Vec<ValueId>> {
    let initial: Vec<ValueId> = plant
        .components()
        .iter()
        .map(|c| {
            let best = c
                .initial()
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map_or(0, |(i, _)| i);
            ValueId(best as u32)
        })
        .collect();
    let mut states = vec![initial];
    for &k in members {
        let modes = plant.component(k).modes().len() as u32;
        states = states
            .into_iter()
            .flat_map(|s| {
                (0..modes)
                    .map(ValueId)
                    .filter(|&m| allowed(k, m))
                    .map(move |m| {
                        let mut s = s.clone();
                        s[k.index()] = m;
                        s
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
    }
    states
        .into_iter()
        .filter(|s| {
            let literals: Vec<Literal> = plant
                .components()
                .iter()
                .zip(s)
                .map(|(c, &m)| Literal::Is(c.mode_var(), m))
                .collect();
            theory.consistent(&literals) == Consistency::Consistent
        })
        .collect()
}

/// One cycle of the plant under `commands`, nominally: each member of `cluster` takes its
/// enabled transition to a nominal mode that a command or a wait causes (a guarded per-cycle
/// transition, or a timed one: the wait is taken as long enough). Hazards never strike. Panics
/// if a component has two such transitions enabled at once (the model would be ambiguous).
fn nominal_step(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    commands: &Commands,
    cluster: &[ComponentId],
) -> Vec<ValueId> {
    let enabled = enabled_transitions(plant, theory, modes, commands).expect("enabled");
    let mut next = modes.to_vec();
    for &k in cluster {
        let component = plant.component(k);
        let moves: Vec<ValueId> = enabled[k.index()]
            .transitions
            .iter()
            .map(|&t| &component.transitions()[t])
            .filter(|t| component.mode(t.target).kind == ModeKind::Nominal)
            .filter(|t| !matches!(t.law, TransitionLaw::Rate { .. }))
            .map(|t| t.target)
            .collect();
        assert!(
            moves.len() <= 1,
            "{}: {} nominal moves at once",
            component.name(),
            moves.len()
        );
        if let Some(&target) = moves.first() {
            next[k.index()] = target;
        }
    }
    next
}

/// One cycle's action in a plan: a command, or `None` for a wait.
type Action = Option<(VarId, ValueId)>;

/// [`nominal_step`]s already computed, by state and action.
type Steps = HashMap<(Vec<ValueId>, Action), Vec<ValueId>>;

/// The shortest sequence of cycles (each one command or a wait) that brings `c` to `goal`
/// from `start`, moving only `c`'s cluster: each cycle's action and the state it leads to.
fn plan(
    plant: &Plant,
    theory: &mut Theory,
    steps: &mut Steps,
    start: Vec<ValueId>,
    (c, goal): (ComponentId, ValueId),
) -> Option<Vec<(Action, Vec<ValueId>)>> {
    let members = cluster(plant, c);
    let mut actions: Vec<Action> = vec![None];
    for control in plant.controls() {
        let owner = members
            .iter()
            .any(|&k| plant.component(k).attributes().contains(&control.var));
        if owner {
            for v in plant.table().variable(control.var).value_ids() {
                if v != control.idle {
                    actions.push(Some((control.var, v)));
                }
            }
        }
    }
    let mut seen = HashSet::from([start.clone()]);
    let mut queue = VecDeque::from([(start, Vec::new())]);
    while let Some((modes, path)) = queue.pop_front() {
        if modes[c.index()] == goal {
            return Some(path);
        }
        if path.len() >= 10 {
            continue;
        }
        for &action in &actions {
            let next = steps
                .entry((modes.clone(), action))
                .or_insert_with(|| {
                    let issued: Vec<(VarId, ValueId)> = action.into_iter().collect();
                    let commands = Commands::new(plant, &issued).expect("a control");
                    nominal_step(plant, theory, &modes, &commands, &members)
                })
                .clone();
            if seen.insert(next.clone()) {
                let mut longer = path.clone();
                longer.push((action, next.clone()));
                queue.push_back((next, longer));
            }
        }
    }
    None
}

#[test]
fn every_goal_of_the_edl_is_reached_by_commands_and_waits() {
    // §6.3.3: the reactive planner reaches a goal by commands through the right path (the PDE
    // for the engine and valves) and by waiting for timed transitions; faults are left to
    // estimation. For every goal Appendix B asserts, from every consistent state of the
    // components it depends on — over their nominal modes and the fault modes a command repairs
    // (the PDE's resettable, the lander's unsuccessful attempt) — a sequence of single commands
    // and waits reaches it, with the rest of the lander in its initial state.
    let plant = lander();
    let thca = edl_against(&plant);
    let mut theory = plant.theory().expect("theory");
    let goals = program_goals(&plant, &thca);
    assert_eq!(goals.len(), 18, "the EDL asserts 18 distinct goals");
    let mut steps = Steps::new();
    let repairable = |k: ComponentId, m: ValueId| {
        let component = plant.component(k);
        component.mode(m).kind == ModeKind::Nominal
            || component.transitions().iter().any(|t| {
                t.source == TransitionSource::Mode(m)
                    && t.guard != Formula::True
                    && component.mode(t.target).kind == ModeKind::Nominal
            })
    };
    for goal in goals {
        let members = cluster(&plant, goal.0);
        let starts = consistent_starts(&plant, &mut theory, &members, repairable);
        assert!(!starts.is_empty());
        for start in starts {
            let path = plan(&plant, &mut theory, &mut steps, start.clone(), goal);
            let describe = |modes: &[ValueId]| kairos::plant::describe_modes(&plant, modes);
            let (name, target) = (
                plant.component(goal.0).name(),
                &plant.component(goal.0).mode(goal.1).name,
            );
            let Some(path) = path else {
                panic!("{name} = {target} is unreachable from {}", describe(&start));
            };
            // Every step but the last is reversible: the planner may leave a mode's reversible
            // region only by a final transition into a target the goal names (§6.3.3).
            let back = (goal.0, start[goal.0.index()]);
            for (_, on_the_way) in path.iter().rev().skip(1) {
                assert!(
                    plan(&plant, &mut theory, &mut steps, on_the_way.clone(), back).is_some(),
                    "on the way to {name} = {target}, {} cannot return to {}",
                    describe(on_the_way),
                    describe(&start)
                );
            }
        }
    }
}

fn commands_to(plant: &Plant, from: &[(&str, &str)], goal: (&str, &str)) -> Vec<String> {
    let mut theory = plant.theory().expect("theory");
    let mut start = consistent_starts(plant, &mut theory, &[], |_, _| true)
        .pop()
        .expect("the initial state");
    for (component, mode) in from {
        let k = plant.component_named(component).expect(component);
        start[k.index()] = plant.component(k).mode_named(mode).expect(mode);
    }
    let c = plant.component_named(goal.0).expect(goal.0);
    let v = plant.component(c).mode_named(goal.1).expect(goal.1);
    let path = plan(plant, &mut theory, &mut Steps::new(), start, (c, v)).expect("reachable");
    path.into_iter()
        .map(|(action, _)| match action {
            Some((x, v)) => plant.table().assignment(x, v).to_string(),
            None => "wait".to_string(),
        })
        .collect()
}

#[test]
fn the_engine_fires_through_the_pde_and_both_valves() {
    // §6.3.3's sequence for `engine = firing` from all off: standby via the PDE, open both
    // valves, fire, every command through `PDE.cmd` (the engine and the valves have no control
    // of their own, §3.2, §7.2.4). The heating may end while the valves are opened, so five or
    // six cycles.
    let plant = lander();
    let path = commands_to(&plant, &[], ("engine", "firing"));
    assert!((5..=6).contains(&path.len()), "{path:?}");
    assert!(
        path.iter()
            .all(|c| c == "wait" || c.starts_with("PDE.cmd = ")),
        "{path:?}"
    );
    assert_eq!(
        path.last().map(String::as_str),
        Some("PDE.cmd = engine-fire")
    );
    for needed in [
        "PDE.cmd = on",
        "PDE.cmd = engine-standby",
        "PDE.cmd = open1",
        "PDE.cmd = open2",
    ] {
        assert!(path.iter().any(|c| c == needed), "{needed}: {path:?}");
    }
    // A resettable PDE is reset first (§7.2.5's recovery by repair).
    let path = commands_to(&plant, &[("PDE", "resettable")], ("engine", "standby"));
    assert_eq!(
        path,
        ["PDE.cmd = reset", "PDE.cmd = engine-standby", "wait"]
    );
}

#[test]
fn pyro_goals_are_reached_by_their_named_pyro_commands() {
    // §6.3.3: irreversible events by explicit pyro commands; §3.3: the backup pyro after a
    // misfire of the primary.
    let plant = lander();
    let one = |from: &[(&str, &str)], goal| commands_to(&plant, from, goal);
    assert_eq!(
        one(&[], ("lander", "separated")),
        ["lander.cmd = fire-primary"]
    );
    assert_eq!(
        one(
            &[("lander", "unsuccessful-attempt")],
            ("lander", "separated")
        ),
        ["lander.cmd = fire-backup"]
    );
    assert_eq!(one(&[], ("chute", "deployed")), ["chute.cmd = fire"]);
    assert_eq!(
        one(&[], ("heatshield", "jettison")),
        ["heatshield.cmd = fire"]
    );
    assert_eq!(one(&[], ("legs", "deployed")), ["legs.cmd = fire"]);
    assert_eq!(
        one(&[], ("backshield", "jettisoned")),
        ["backshield.cmd = fire"]
    );
    // The touchdown latch is reset by command, the landing flag set by command.
    assert_eq!(
        one(
            &[("touchdown_sensor", "triggered")],
            ("touchdown_sensor", "not-triggered")
        ),
        ["touchdown_sensor.cmd = reset"]
    );
    assert_eq!(
        one(&[], ("landing", "success")),
        ["landing.cmd = set-success"]
    );
    // A slew: the command, then the wait for the timed transition (§7.2.4).
    assert_eq!(
        one(&[], ("att", "entry-orient")),
        ["att.cmd = to-entry", "wait"]
    );
}
