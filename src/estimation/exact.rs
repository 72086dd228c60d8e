//! BeliefUpdate_TCCA (thesis Figure 6-10): the exact belief update over system states, the
//! reference TimedME is measured against. For small models only: it enumerates every
//! combination of every component's enabled transitions from every tracked state.
//!
//! 1. (step 2) For each system state: clocks advance; enabled transitions (guards entailed by the
//!    state's constraint store and μ(i)) give each component its next modes with §6.2.2's
//!    probabilities; every combination is a target, with probability
//!    `p(source) · Π p_j`; clocks restart where a mode changed.
//! 2. (step 3) Equal targets are consolidated by summing. Clocks that cannot matter any more are
//!    forgotten first, which is exact and keeps the state count down (DESIGN.md §8).
//! 3. (step 4) Each target is weighed by P_O(o(i+1) | s): 1 per observed value entailed, 1/m per
//!    value left open, 0 if the observation is inconsistent with it.
//! 4. (step 5) Unlike the figure, the posterior is normalised, so the probabilities are exact
//!    posteriors rather than a likelihood ordering.
//!
//! When no target survives the observation, the same fallbacks as TimedME apply (DESIGN.md §8),
//! with an unbounded number of states.

use std::collections::HashMap;

use super::expand::{Choices, Expander, Limits, SourceChoices};
use super::timed_me::{Outcome, fallen_from, initial_belief, with_fault_jumps};
use super::{Belief, EstimationError, ModeEstimator, Update, WeightedState, check_step};
use crate::logic::ValueId;
use crate::opsat::{SearchOptions, Theory};
use crate::plant::{Commands, Observation, Plant, SystemState, successor};

/// The exact update refuses to enumerate more targets than this from one source state.
const MAX_TARGETS_PER_STATE: u128 = 1 << 20;

/// The exact belief update (Figure 6-10), with the caches its observation factors and enabled
/// transitions share with TimedME.
#[derive(Default)]
pub struct BeliefUpdate {
    expander: Expander,
}

impl BeliefUpdate {
    /// An exact updater.
    pub fn new() -> Self {
        BeliefUpdate::default()
    }
}

fn unbounded() -> Limits {
    Limits {
        kappa: usize::MAX,
        max_candidates: usize::MAX,
        search: SearchOptions::default(),
        share_conflicts: true,
    }
}

impl ModeEstimator for BeliefUpdate {
    fn initial(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        time: f64,
        observation: &Observation,
    ) -> Result<Update, EstimationError> {
        initial_belief(
            &mut self.expander,
            plant,
            theory,
            time,
            observation,
            unbounded(),
        )
    }

    fn update(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        belief: &Belief,
        commands: &Commands,
        observation: &Observation,
        time: f64,
    ) -> Result<Update, EstimationError> {
        check_step(plant, belief, commands, observation, time)?;
        // The step as the acknowledgements say it happened (`plant::acknowledgement`).
        let commands = &*commands.acknowledged(plant, observation);
        let sat_before = theory.stats().sat_calls;
        let mut sources = Vec::with_capacity(belief.states().len());
        let mut targets = Targets::default();
        for weighted in belief.states() {
            let choices = self.expander.choices(
                plant,
                theory,
                &weighted.state,
                commands,
                belief.time(),
                time,
            )?;
            let count: u128 = choices.iter().map(|c| c.len() as u128).product();
            if count > MAX_TARGETS_PER_STATE {
                return Err(EstimationError::TooLarge(count));
            }
            for_each_combination(&choices, |modes, p| {
                let next =
                    successor(&weighted.state, modes.to_vec(), time).forget_idle_clocks(plant);
                targets.add(next, weighted.probability * p);
            });
            sources.push(SourceChoices {
                probability: weighted.probability,
                choices,
            });
        }
        let candidates = targets.states.len() as u64;
        let mut posterior = Vec::with_capacity(targets.states.len());
        for (state, prior) in targets.states {
            let factor = self
                .expander
                .observe
                .factor(plant, theory, &state.modes, observation)?;
            if factor > 0.0 {
                posterior.push(WeightedState {
                    state,
                    probability: prior * factor,
                });
            }
        }
        let mut outcome = Outcome::from_states(posterior, candidates);
        if outcome.is_empty() {
            with_fault_jumps(plant, &mut sources);
            let next = |k: usize, modes: &[ValueId]| {
                successor(&belief.states()[k].state, modes.to_vec(), time).forget_idle_clocks(plant)
            };
            let jumps =
                self.expander
                    .expand(plant, theory, &sources, observation, unbounded(), next)?;
            outcome.fall_back(jumps, belief.states(), fallen_from(belief));
        }
        Ok(outcome.into_update(plant, time, theory.stats().sat_calls - sat_before))
    }
}

/// Targets with summed prior probabilities, in order of first appearance (deterministic).
#[derive(Default)]
struct Targets {
    index: HashMap<SystemState, usize>,
    states: Vec<(SystemState, f64)>,
}

impl Targets {
    fn add(&mut self, state: SystemState, p: f64) {
        match self.index.get(&state) {
            Some(&i) => self.states[i].1 += p,
            None => {
                self.index.insert(state.clone(), self.states.len());
                self.states.push((state, p));
            }
        }
    }
}

/// Calls `visit(modes, probability)` for every combination of one choice per component.
fn for_each_combination(choices: &Choices, mut visit: impl FnMut(&[ValueId], f64)) {
    if choices.iter().any(|c| c.is_empty()) {
        return;
    }
    let mut position = vec![0usize; choices.len()];
    let mut modes: Vec<ValueId> = choices.iter().map(|c| c[0].mode).collect();
    loop {
        let p: f64 = choices
            .iter()
            .zip(&position)
            .map(|(c, &i)| c[i].probability)
            .product();
        visit(&modes, p);
        // Odometer: advance the last component, carrying leftwards.
        let mut j = choices.len();
        loop {
            if j == 0 {
                return;
            }
            j -= 1;
            position[j] += 1;
            if position[j] < choices[j].len() {
                modes[j] = choices[j][position[j]].mode;
                break;
            }
            position[j] = 0;
            modes[j] = choices[j][0].mode;
        }
    }
}
