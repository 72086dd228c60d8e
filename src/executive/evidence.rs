//! A diagnosis's evidence: the observations the previous most likely state
//! cannot explain — Livingstone's "discrepant observations" (Williams & Nayak 1996), here
//! against ŝ(i−1) stepped by the last command μ(i−1) along its most likely transitions (thesis
//! §6.2.2's transition probabilities; Figure 6-6's Step_TCCA with the most probable choice per
//! component). The commanded transition is the likely one, so `open2` moves valve 2 to `open`
//! and its outlet staying low is evidence; a fault or a timed transition is not, so an
//! observation only a fault (or an early timed transition) explains is evidence too. In cycle 0
//! there is no previous belief: the state the executive starts from — each component's most
//! likely initial mode (§6.2.2's P_Θ), which no command and no time has moved yet — stands for
//! it.
//!
//! Each observation is checked on its own against the expected state's modes with the plant's
//! [`Theory`]. When none is discrepant on its own but they are together (a sensor pair that must
//! agree reads `a = low`, `b = high`), a minimal jointly inconsistent set is named instead, as
//! one piece of evidence `pair.a = low & pair.b = high`: the theory's conflict core (the SAT
//! solver's failed assumptions) narrows the observations, and deleting each remaining one in turn
//! with the modes held fixed leaves a set none of whose members can go. It is computed only in a
//! cycle that reports a diagnosis, never in a quiet one.

use crate::estimation::Belief;
use crate::logic::ValueId;
use crate::opsat::{Consistency, Literal, Theory};
use crate::plant::{
    Commands, Observation, Plant, StepError, SystemState, chosen_successor, mode_literals,
    transition_choices,
};

/// The observations of `observation` that `previous`'s most probable system state with the
/// modes `modes` (ŝ(i−1)), stepped by `commands` to `now`, cannot explain, as `variable =
/// value`; or, when each is explained on its own, a minimal set that is not explained together,
/// as one entry `a = x & b = y`. Without a previous belief (cycle 0) the plant's most likely
/// initial state is expected instead.
pub(super) fn discrepant(
    plant: &Plant,
    theory: &mut Theory,
    previous: Option<&Belief>,
    modes: &[ValueId],
    commands: &Commands,
    observation: &Observation,
    now: f64,
) -> Result<Vec<String>, StepError> {
    let expected = match previous {
        None => plant.most_likely_initial(),
        Some(belief) => {
            // The belief's states are most probable first: the first with ŝ's modes is its
            // best clock.
            let Some(state) = (belief.states().iter()).find(|s| *s.state.modes == *modes) else {
                return Ok(Vec::new());
            };
            let commands = commands.acknowledged(plant, observation);
            stepped(plant, theory, &state.state, &commands, belief.time(), now)?
                .modes
                .to_vec()
        }
    };
    Ok(unexplained(plant, theory, &expected, observation))
}

/// The observations the modes `expected` cannot explain, each on its own; when there is none,
/// a minimal jointly unexplained set, joined by ` & ` (nothing when all are explained).
fn unexplained(
    plant: &Plant,
    theory: &mut Theory,
    expected: &[ValueId],
    observation: &Observation,
) -> Vec<String> {
    let modes = mode_literals(plant, expected);
    let observed: Vec<Literal> = (observation.values().iter())
        .map(|&(var, value)| Literal::Is(var, value))
        .collect();
    let table = plant.table();
    let text = |literals: &[Literal]| {
        let assignments = literals.iter().filter_map(|&literal| match literal {
            Literal::Is(var, value) => Some(table.assignment(var, value).to_string()),
            _ => None,
        });
        assignments.collect::<Vec<_>>().join(" & ")
    };
    let mut store = modes.clone();
    let single: Vec<String> = (observed.iter())
        .filter(|&&literal| {
            store.push(literal);
            let explained = theory.is_consistent(&store);
            store.pop();
            !explained
        })
        .map(|&literal| text(&[literal]))
        .collect();
    if !single.is_empty() {
        return single;
    }
    match jointly_unexplained(theory, &modes, &observed) {
        Some(set) => vec![text(&set)],
        None => Vec::new(),
    }
}

/// A minimal subset of `observed` inconsistent with `modes`, if there is one: the theory's
/// conflict core keeps the observations it names, then each is dropped in turn if the rest,
/// with every mode, is still inconsistent (deletion-based minimisation; a diagnosis has a few
/// observations, so a check each).
fn jointly_unexplained(
    theory: &mut Theory,
    modes: &[Literal],
    observed: &[Literal],
) -> Option<Vec<Literal>> {
    let with_modes = |set: &[Literal]| [modes, set].concat();
    let Consistency::Conflict(core) = theory.consistent(&with_modes(observed)) else {
        return None;
    };
    let mut set: Vec<Literal> = (observed.iter())
        .filter(|literal| core.contains(literal))
        .copied()
        .collect();
    let mut k = 0;
    while k < set.len() {
        let without: Vec<Literal> = [&set[..k], &set[k + 1..]].concat();
        if theory.is_consistent(&with_modes(&without)) {
            k += 1;
        } else {
            set = without;
        }
    }
    // Modes inconsistent on their own (no observation to blame) leave nothing to name.
    (!set.is_empty()).then_some(set)
}

/// `state` stepped from `from` to `to` under `commands`, every component taking its most
/// probable transition (staying included).
fn stepped(
    plant: &Plant,
    theory: &mut Theory,
    state: &SystemState,
    commands: &Commands,
    from: f64,
    to: f64,
) -> Result<SystemState, StepError> {
    let choices = transition_choices(plant, theory, state, commands, from, to)?;
    Ok(chosen_successor(state, &choices, to, |_, distribution| {
        (0..distribution.len())
            .max_by(|&a, &b| distribution[a].1.total_cmp(&distribution[b].1))
            .unwrap_or(usize::MAX)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;

    /// A chain that must read the same at a, b and c while `level`; `d` has no part in it.
    const CHAIN: &str = r#"Plant(
        name: "chain",
        components: [
            Component(
                name: "x",
                attributes: {
                    "a": ["low", "high"], "b": ["low", "high"],
                    "c": ["low", "high"], "d": ["low", "high"],
                },
                modes: [
                    Mode(name: "level", constraint: "x.a = x.b and x.b = x.c", reward: 0),
                    Mode(name: "broken", kind: Fault, constraint: "true", reward: -1),
                ],
                initial: { "level": 1.0 },
                transitions: [],
            ),
        ],
        controls: {},
        observables: ["x.a", "x.b", "x.c", "x.d"],
    )"#;

    /// With `a = low`, `b = low`, `c = high`, `d = low` none is discrepant
    /// alone; both {a, c} and {b, c} are minimal jointly inconsistent sets, {a, b, c} is not
    /// minimal. The set named is one of the two: inconsistent with `level`, consistent when any
    /// member is dropped, and without `d`.
    #[test]
    fn the_jointly_unexplained_set_is_minimal() {
        let plant = Plant::load(&Source::new("chain.ron", CHAIN)).expect("a valid model");
        let mut theory = plant.theory().expect("a theory");
        let table = plant.table();
        let observed: Vec<(crate::logic::VarId, ValueId)> = [
            ("x.a", "low"),
            ("x.b", "low"),
            ("x.c", "high"),
            ("x.d", "low"),
        ]
        .iter()
        .map(|&(name, value)| {
            let var = table.variable_id(name).expect("a variable");
            (var, table.variable(var).value(value).expect("a value"))
        })
        .collect();
        let observation = Observation::new(&plant, &observed).expect("an observation");
        let level = plant.most_likely_initial();
        let evidence = unexplained(&plant, &mut theory, &level, &observation);
        assert!(
            evidence == ["x.a = low & x.c = high"] || evidence == ["x.b = low & x.c = high"],
            "{evidence:?}"
        );

        let modes = mode_literals(&plant, &level);
        let all: Vec<Literal> = (observed.iter())
            .map(|&(var, value)| Literal::Is(var, value))
            .collect();
        let named = jointly_unexplained(&mut theory, &modes, &all).expect("a set");
        assert_eq!(named.len(), 2, "{named:?}");
        assert!(!named.contains(&all[3]), "d has no part in it");
        assert!(!theory.is_consistent(&[modes.clone(), named.clone()].concat()));
        for k in 0..named.len() {
            let mut fewer = named.clone();
            fewer.remove(k);
            assert!(theory.is_consistent(&[modes.clone(), fewer].concat()));
        }
    }
}
