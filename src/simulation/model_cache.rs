//! What the model-driven plant asks its theory, asked once per (modes, command) and kept
//! (issue 18; BENCHMARKS.md "Campaigns"): a cycle in which neither the modes nor the command
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
use crate::plant::{Commands, Plant, enabled_transitions, mode_literals};

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
    enabled: FxHashMap<Key, Vec<Vec<usize>>>,
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
    ) -> Result<&[Vec<usize>], String> {
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
