//! A diagnosis's evidence (issue 19 item 2): the observations the previous most likely state
//! cannot explain — Livingstone's "discrepant observations" (Williams & Nayak 1996), here
//! against ŝ(i−1) stepped by the last command μ(i−1) along its most likely transitions (thesis
//! §6.2.2's transition probabilities; Figure 6-6's Step_TCCA with the most probable choice per
//! component). The commanded transition is the likely one, so `open2` moves valve 2 to `open`
//! and its outlet staying low is evidence; a fault or a timed transition is not, so an
//! observation only a fault (or an early timed transition) explains is evidence too.
//!
//! Each observation is checked on its own against the stepped state's modes with the plant's
//! [`Theory`]: an observation that is discrepant only together with another is not named. It
//! is computed only in a cycle that reports a diagnosis, never in a quiet one.

use crate::estimation::Belief;
use crate::logic::ValueId;
use crate::opsat::{Literal, Theory};
use crate::plant::{
    Commands, Observation, Plant, StepError, SystemState, chosen_successor, mode_literals,
    transition_choices,
};

/// The observations of `observation` that `previous`'s most probable system state with the
/// modes `modes` (ŝ(i−1)), stepped by `commands` to `now`, cannot explain, as
/// `variable = value`. Empty before the first belief.
pub(super) fn discrepant(
    plant: &Plant,
    theory: &mut Theory,
    previous: Option<&Belief>,
    modes: &[ValueId],
    commands: &Commands,
    observation: &Observation,
    now: f64,
) -> Result<Vec<String>, StepError> {
    let Some(belief) = previous else {
        return Ok(Vec::new());
    };
    // The belief's states are most probable first: the first with ŝ's modes is its best clock.
    let Some(state) = (belief.states().iter()).find(|s| s.state.modes == modes) else {
        return Ok(Vec::new());
    };
    let stepped = stepped(plant, theory, &state.state, commands, belief.time(), now)?;
    let mut store = mode_literals(plant, &stepped.modes);
    let table = plant.table();
    let mut evidence = Vec::new();
    for &(var, value) in observation.values() {
        store.push(Literal::Is(var, value));
        if !theory.is_consistent(&store) {
            evidence.push(table.assignment(var, value).to_string());
        }
        store.pop();
    }
    Ok(evidence)
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
