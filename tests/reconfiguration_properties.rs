//! Properties of mode reconfiguration on random small plants with acyclic causal graphs (issue
//! 5): whenever goal interpretation finds a goal state, that state entails the goal, and the
//! reactive planner, run against nominal transitions, reaches it in a bounded number of cycles
//! without ever taking an irreversible transition into a mode the goal did not name (§6.3.3),
//! making progress by the planner's own measure every cycle it acts for its focus.
//! `KAIROS_CASES=N` raises the number of cases.

#[path = "support/reconfiguration_plants.rs"]
mod plants;
#[path = "support/reconfiguration.rs"]
mod support;

#[path = "support/seeded.rs"]
mod seeded;
use kairos::logic::ValueId;
use kairos::opsat::Literal;
use kairos::reconfiguration::PlanOutcome;
use plants::{RandomComponent, RandomPlant, synthetic_plant_ron};
use proptest::prelude::*;
use support::{Setup, plant_from};

fn component() -> impl Strategy<Value = RandomComponent> {
    (
        2usize..=4,
        prop::collection::vec(-5i32..=0, 4),
        prop::collection::vec(
            (
                0usize..4,
                0usize..4,
                prop::bool::weighted(0.2),
                prop::option::weighted(0.5, (0usize..4, 0usize..4)),
                prop::bool::weighted(0.6),
            ),
            1..9,
        ),
        0usize..3,
        prop::collection::vec(prop::bool::weighted(0.5), 4),
    )
        .prop_map(|(modes, rewards, edges, fault, links)| RandomComponent {
            modes,
            rewards,
            edges,
            fault,
            links,
        })
}

/// A goal atom: (component pick, mode pick, on the status attribute rather than the mode).
type GoalAtom = (usize, usize, bool);

fn case() -> impl Strategy<Value = (RandomPlant, Vec<usize>, Vec<GoalAtom>)> {
    (
        prop::collection::vec(component(), 1..=4),
        prop::collection::vec(0usize..7, 4),
        prop::collection::vec((0usize..4, 0usize..4, prop::bool::weighted(0.25)), 1..=3),
    )
        .prop_map(|(components, start, goal)| (RandomPlant { components }, start, goal))
}

/// The goal as text: `ci = mX` or `ci.status = mX`, joined by `and`, at most one per component
/// (contradictory goals are tested on their own, in `reconfiguration_propulsion.rs`).
fn goal_text(plant: &RandomPlant, atoms: &[GoalAtom]) -> String {
    let mut seen = Vec::new();
    atoms
        .iter()
        .filter(|&&(c, _, _)| {
            let c = c % plant.components.len();
            !seen.contains(&c) && {
                seen.push(c);
                true
            }
        })
        .map(|&(c, m, on_status)| {
            let c = c % plant.components.len();
            let m = m % plant.components[c].modes;
            if on_status {
                format!("c{c}.status = m{m}")
            } else {
                format!("c{c} = m{m}")
            }
        })
        .collect::<Vec<_>>()
        .join(" and ")
}

/// A start state: a mode per component; pick 6 is the fault mode, when there is one.
fn start_state(plant: &RandomPlant, picks: &[usize]) -> Vec<ValueId> {
    plant
        .components
        .iter()
        .zip(picks)
        .map(|(c, &pick)| {
            let fault = c.mode_names().len() - 1;
            let mode = if pick == 6 && fault == c.modes {
                fault
            } else {
                pick % c.modes
            };
            ValueId(mode as u32)
        })
        .collect()
}

/// More cycles than any serial plan on these plants can need: every component's walk to its
/// goal, each step preceded by the walks of its upstream sub-goals.
const STEP_BOUND: usize = 400;

fn check(plant: &RandomPlant, picks: &[usize], atoms: &[GoalAtom]) -> Result<(), TestCaseError> {
    let text = plant.to_ron();
    let mut setup = Setup::new(plant_from("random.ron", &text));
    prop_assert!(setup.reconfiguration.causal_graph().is_acyclic());
    let start = start_state(plant, picks);
    let goal_text = goal_text(plant, atoms);
    let Ok(goal) = setup.interpret(&start, &goal_text) else {
        return Ok(());
    };
    let literals: Vec<Literal> = setup
        .plant
        .components()
        .iter()
        .zip(goal.modes())
        .map(|(c, &m)| Literal::Is(c.mode_var(), m))
        .collect();
    let formula = setup.formula(&goal_text);
    prop_assert!(
        setup.theory.entails(&literals, &formula).expect("entails"),
        "the goal state entails the goal"
    );
    let run = setup
        .reconfiguration
        .simulate_nominal(&mut setup.theory, &start, &goal, STEP_BOUND)
        .expect("simulates");
    // The planner's measure of progress strictly decreases every cycle, so no state
    // comes back.
    let mut before = setup.reconfiguration.progress(&start, &goal);
    let mut visited = vec![start.clone()];
    for step in &run.steps {
        let after = setup.reconfiguration.progress(&step.state, &goal);
        prop_assert!(
            after < before,
            "no progress: {:?} then {:?} after {}\n{}",
            before,
            after,
            step.action.describe(&setup.plant),
            text
        );
        prop_assert!(
            !visited.contains(&step.state),
            "the planner came back to {}\n{}",
            setup.describe(&step.state),
            text
        );
        visited.push(step.state.clone());
        before = after;
    }
    prop_assert_eq!(
        &run.outcome,
        &PlanOutcome::Achieved,
        "from {} to {} ({}):\n{}\n{}",
        setup.describe(&start),
        setup.describe(goal.modes()),
        goal_text,
        setup.actions(&run).join("\n"),
        text
    );
    let last = run.steps.last().map_or(start.clone(), |s| s.state.clone());
    prop_assert_eq!(last.as_slice(), goal.modes());
    for step in &run.steps {
        for m in &step.moves {
            let reachability = setup.reconfiguration.policy(m.component).reachability();
            if !reachability.is_reversible(m.from, m.to) {
                prop_assert!(
                    goal.is_named(m.component) && goal.mode(m.component) == m.to,
                    "an irreversible move the goal did not name: {:?} in\n{}",
                    m,
                    text
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(seeded::config(256))]

    #[test]
    fn rp_reaches_the_gi_goal_state_and_never_takes_an_unnamed_irreversible_step(
        (plant, start, goal) in case()
    ) {
        check(&plant, &start, &goal)?;
    }
}

/// The synthetic plant of the benchmarks plans too: opening one device needs the bus on, then
/// its driver on; both are switched off again last.
#[test]
fn the_synthetic_plant_opens_a_device_through_bus_and_driver() {
    let mut setup = Setup::new(plant_from("synthetic.ron", &synthetic_plant_ron(3, 3)));
    let start = setup.state(&[]);
    let goal = setup
        .interpret(&start, "d1v2 = open")
        .expect("a goal state");
    let run = setup.run(&start, &goal);
    assert_eq!(run.outcome, PlanOutcome::Achieved);
    assert_eq!(
        setup.actions(&run),
        [
            "command bus.cmd = on (bus: off -> on)",
            "command d1.cmd = on (d1: off -> on)",
            "command d1.cmd = open2 (d1v2: closed -> open)",
            "command d1.cmd = off (d1: on -> off)",
            "command bus.cmd = off (bus: on -> off)",
        ]
    );
}
