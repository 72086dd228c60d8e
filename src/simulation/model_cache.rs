//! What the model-driven plant asks its theory, asked once per (modes, command) and kept
//! (BENCHMARKS.md "Campaigns"): a cycle in which neither the modes nor the command
//! change — most of a 17,000 s cruise — then costs lookups and the generator's draws, not the
//! 25–70 SAT calls of the observation and the entailment checks of the step.
//!
//! The answers are the theory's own, so the cache changes no draw: the plant consumes the
//! generator exactly as without it (its shuffles depend on the lengths of what is shuffled, not
//! on the answers) and takes the same decisions from the same answers. `tests/model_plant.rs`
//! pins this against records made before the cache existed.
//!
//! Observations: a partial assignment of the observables is consistent with the modes and the
//! command (the plant's theory) exactly when some consistent *complete* assignment of the
//! observables extends it — the projection of one of its models. So, per key, the plant keeps
//! the set of consistent complete assignments and answers "consistent?" by looking for one
//! that agrees. The set is built from each observable's allowed values (a value allowed alone):
//! an observable with one allowed value has it in every model, so only the others — those a
//! fault mode leaves open, typically — are enumerated, depth first, each partial assignment
//! checked. When their product exceeds [`MAX_ASSIGNMENTS`] the key is marked too open and the
//! plant asks the theory each cycle, as without a cache.

use rustc_hash::FxHashMap;

use crate::logic::{ValueId, VarId};
use crate::opsat::{Consistency, Literal, Theory};
use crate::plant::{Commands, Enabled, Plant, enabled_transitions, mode_literals};

/// The most complete observation assignments kept for one key: beyond, enumerating them once
/// would cost more SAT calls than the cycles that reuse them save.
pub(super) const MAX_ASSIGNMENTS: usize = 256;

/// The modes of every component and the control action of the previous cycle.
type Key = (Vec<ValueId>, Commands);

/// The theory's answers the model-driven plant needs, by what they depend on.
#[derive(Default)]
pub(super) struct ModelCache {
    /// Are these modes consistent together (the rejection test of a step's draw)?
    modes: FxHashMap<Vec<ValueId>, bool>,
    /// The enabled transitions of each component ([`enabled_transitions`]).
    enabled: FxHashMap<Key, Vec<Enabled>>,
    /// The observation's assumptions and consistent assignments.
    observations: FxHashMap<Key, Observations>,
}

/// What an observation is drawn from, for one key.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Observations {
    /// The literals every observation assumes: the modes, and the command when it fits them.
    pub(super) assumed: Vec<Literal>,
    /// Every consistent complete assignment of the observables, a value per observable in the
    /// order of [`Plant::observables`]; `None` when there are more than [`MAX_ASSIGNMENTS`].
    pub(super) assignments: Option<Vec<Vec<ValueId>>>,
}

impl ModelCache {
    /// Whether `modes` are consistent together with the plant's constraints.
    pub(super) fn modes_consistent(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
    ) -> bool {
        if let Some(&known) = self.modes.get(modes) {
            return known;
        }
        let consistent = is_consistent(theory, &mode_literals(plant, modes));
        self.modes.insert(modes.to_vec(), consistent);
        consistent
    }

    /// [`enabled_transitions`] in `modes` under `commands`; errors are not kept.
    pub(super) fn enabled(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
        commands: &Commands,
    ) -> Result<&[Enabled], String> {
        let key = (modes.to_vec(), commands.clone());
        if !self.enabled.contains_key(&key) {
            let enabled =
                enabled_transitions(plant, theory, modes, commands).map_err(|e| e.to_string())?;
            self.enabled.insert(key.clone(), enabled);
        }
        Ok(self.enabled.get(&key).map_or(&[], Vec::as_slice))
    }

    /// What an observation in `modes` after `commands` is drawn from.
    pub(super) fn observations(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
        commands: &Commands,
    ) -> &Observations {
        self.observations
            .entry((modes.to_vec(), commands.clone()))
            .or_insert_with(|| observations(plant, theory, modes, commands))
    }
}

fn is_consistent(theory: &mut Theory, literals: &[Literal]) -> bool {
    theory.consistent(literals) == Consistency::Consistent
}

/// The assumptions of an observation in `modes` after `commands` — the command is assumed when
/// it fits the modes (a mode may say nothing about it, or contradict it, as a stuck valve does)
/// — and the consistent assignments of the observables under them.
fn observations(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    commands: &Commands,
) -> Observations {
    let mut assumed = mode_literals(plant, modes);
    let with_commands: Vec<Literal> = assumed
        .iter()
        .copied()
        .chain(commands.values().iter().map(|&(x, v)| Literal::Is(x, v)))
        .collect();
    if is_consistent(theory, &with_commands) {
        assumed = with_commands;
    }
    let assignments = assignments(plant, theory, &assumed);
    Observations {
        assumed,
        assignments,
    }
}

/// Every assignment of the observables consistent with `assumed`, or `None` when the open
/// observables allow more than [`MAX_ASSIGNMENTS`] combinations.
fn assignments(
    plant: &Plant,
    theory: &mut Theory,
    assumed: &[Literal],
) -> Option<Vec<Vec<ValueId>>> {
    let allowed: Vec<Vec<ValueId>> = plant
        .observables()
        .iter()
        .map(|&var| allowed_values(plant, theory, assumed, var))
        .collect();
    if allowed.iter().any(Vec::is_empty) {
        // Inconsistent assumptions: nothing is consistent, as the theory would answer.
        return Some(Vec::new());
    }
    let combinations = allowed
        .iter()
        .try_fold(1usize, |n, values| n.checked_mul(values.len()));
    if combinations.is_none_or(|n| n > MAX_ASSIGNMENTS) {
        return None;
    }
    let mut found = Vec::new();
    let mut partial: Vec<ValueId> = Vec::with_capacity(allowed.len());
    let mut literals = assumed.to_vec();
    extend(
        plant,
        theory,
        &allowed,
        &mut partial,
        &mut literals,
        &mut found,
    );
    Some(found)
}

/// The values of `var` consistent with `assumed`, alone.
fn allowed_values(
    plant: &Plant,
    theory: &mut Theory,
    assumed: &[Literal],
    var: VarId,
) -> Vec<ValueId> {
    let size = plant.table().variable(var).domain_size() as u32;
    let mut literals = assumed.to_vec();
    (0..size)
        .map(ValueId)
        .filter(|&value| {
            literals.push(Literal::Is(var, value));
            let consistent = is_consistent(theory, &literals);
            literals.pop();
            consistent
        })
        .collect()
}

/// Depth first over the observables from `partial.len()`: every consistent completion of
/// `partial` (whose literals `literals` holds after the assumptions) goes to `found`. An
/// observable with a single allowed value takes it unchecked: it has it in every model.
fn extend(
    plant: &Plant,
    theory: &mut Theory,
    allowed: &[Vec<ValueId>],
    partial: &mut Vec<ValueId>,
    literals: &mut Vec<Literal>,
    found: &mut Vec<Vec<ValueId>>,
) {
    let Some(values) = allowed.get(partial.len()) else {
        found.push(partial.clone());
        return;
    };
    let var = plant.observables()[partial.len()];
    for &value in values {
        literals.push(Literal::Is(var, value));
        if values.len() == 1 || is_consistent(theory, literals) {
            partial.push(value);
            extend(plant, theory, allowed, partial, literals, found);
            partial.pop();
        }
        literals.pop();
    }
}

#[cfg(test)]
mod tests {
    //! The consistent assignments of the observables, against what the theory says of each
    //! complete assignment, and the fall-back of a mode that leaves too many open.

    use super::*;
    use crate::diagnostic::Source;
    use crate::executive::adapters::{ControlAdapter, MonitorAdapter};
    use crate::simulation::{ModelPlant, ModelPlantConfig};

    /// Nine two-valued observables: `ok` fixes them all, `either` wants `a` or `b` high (three
    /// assignments), `broken` says nothing (2⁹ = 512 > [`MAX_ASSIGNMENTS`]).
    fn nine_sensors(initial: &str) -> Plant {
        let names = ["a", "b", "c", "d", "e", "f", "g", "h", "i"];
        let attributes: Vec<String> = names
            .iter()
            .map(|n| format!("\"{n}\": [\"low\", \"high\"]"))
            .collect();
        let observables: Vec<String> = names.iter().map(|n| format!("\"s.{n}\"")).collect();
        let low = |from: usize| -> String {
            names[from..]
                .iter()
                .map(|n| format!("s.{n} = low"))
                .collect::<Vec<_>>()
                .join(" and ")
        };
        let text = format!(
            r#"Plant(name: "sensors", components: [Component(
                name: "s",
                attributes: {{ {} }},
                modes: [
                    Mode(name: "ok", constraint: "{}"),
                    Mode(name: "either", constraint: "(s.a = high or s.b = high) and {}"),
                    Mode(name: "broken", kind: Fault, reward: -10),
                ],
                initial: {{ "{initial}": 1.0 }},
                transitions: [],
            )], observables: [{}])"#,
            attributes.join(", "),
            low(0),
            low(2),
            observables.join(", ")
        );
        Plant::load(&Source::new("sensors.ron", text)).unwrap_or_else(|e| panic!("{e}"))
    }

    fn assignments_in(plant: &Plant, mode: &str) -> Option<Vec<Vec<ValueId>>> {
        let mut theory = plant.theory().expect("encodes");
        let component = plant.component(plant.component_named("s").expect("s"));
        let modes = [component.mode_named(mode).expect("a mode")];
        observations(plant, &mut theory, &modes, &Commands::idle(plant)).assignments
    }

    /// The module doc's equivalence: the kept assignments are exactly the complete assignments
    /// the theory finds consistent with the mode (checked on all 512), and a mode that leaves
    /// more than [`MAX_ASSIGNMENTS`] open keeps none.
    #[test]
    fn the_kept_assignments_are_the_consistent_ones() {
        let plant = nine_sensors("ok");
        let mut theory = plant.theory().expect("encodes");
        let component = plant.component(plant.component_named("s").expect("s"));
        for mode in ["ok", "either"] {
            let mut kept = assignments_in(&plant, mode).expect("few enough");
            kept.sort();
            let mode_literal = Literal::Is(
                component.mode_var(),
                component.mode_named(mode).expect("a mode"),
            );
            let consistent: Vec<Vec<ValueId>> = (0u32..512)
                .map(|bits| {
                    (0..9)
                        .map(|i| ValueId((bits >> (8 - i)) & 1))
                        .collect::<Vec<_>>()
                })
                .filter(|values: &Vec<ValueId>| {
                    let mut literals = vec![mode_literal];
                    literals.extend(
                        plant
                            .observables()
                            .iter()
                            .zip(values)
                            .map(|(&x, &v)| Literal::Is(x, v)),
                    );
                    is_consistent(&mut theory, &literals)
                })
                .collect();
            assert_eq!(kept, consistent, "{mode}");
        }
        assert_eq!(assignments_in(&plant, "ok").map(|a| a.len()), Some(1));
        assert_eq!(assignments_in(&plant, "either").map(|a| a.len()), Some(3));
        assert_eq!(assignments_in(&plant, "broken"), None);
    }

    /// The fall-back path: in `broken` the plant asks the theory each cycle, and still reports
    /// a value for every observable, not always the same ones.
    #[test]
    fn a_mode_too_open_to_keep_is_drawn_with_the_theory() {
        let plant = nine_sensors("broken");
        let mut model = ModelPlant::new(&plant, &ModelPlantConfig::seeded(3)).expect("encodes");
        let mut seen = std::collections::BTreeSet::new();
        for i in 0..50 {
            let observation = model.observe(f64::from(i));
            assert_eq!(observation.len(), 9);
            seen.insert(
                observation
                    .iter()
                    .map(|o| o.to_string())
                    .collect::<Vec<_>>(),
            );
            model.send(f64::from(i), &[]).expect("idle");
        }
        assert!(seen.len() > 40, "{} distinct observations", seen.len());
    }
}
