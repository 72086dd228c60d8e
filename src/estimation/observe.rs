//! The observation probability P_O(o | s) of Figure 6-10 (thesis §6.2.2, "Observation
//! Probability"): each observed value counts 1 when the state's modes and the model entail it,
//! 0 when they refute it, 1/m (m the observable's domain size) when they leave it open; the
//! product over the observation. A state whose modes are inconsistent with the observation as a
//! whole gets 0 even if no single value is refuted (Figure 6-7, step 7) — and so does a state
//! whose modes are inconsistent with the model itself (its connections), observed or not: such a
//! combination of modes is no plant state at all (DESIGN.md §8, "the targets must be consistent
//! with o(i+1) and the model", where an unobserved step once kept up to 0.73
//! of the exact belief on mode combinations the connections forbid).
//!
//! The factor depends on the modes only, never on clocks, so it is cached per (modes,
//! observation): in a quiet cycle the same few states meet the same observation again.
//!
//! TimedME's candidates are OPSAT solutions of an OCSP that assumes the observation over the
//! plant's theory ([`ObservationModel::factor_of_solution`]): each was found consistent with the
//! model and the observation as a whole (OPSAT returns only consistent assignments, and the
//! independent sub-problems it splits into share no variable, so their solutions are consistent
//! together). The whole-observation check is then answered before it is asked — yes — and the
//! factor is the product over the observed values alone; with nothing observed it is 1 without
//! any question to the theory. The answer is the one [`ObservationModel::factor`] gives: only
//! the satisfiability question whose answer is known is left out. (Leaving it out when nothing
//! was observed is what a partially observed plant, one reading every few steps, spends most of
//! its questions on otherwise: one per distinct combination of modes.) A solution's factor
//! with nothing observed is not cached either: it is 1 whatever the modes, and the cache's key
//! (a copy of the modes), hash, comparison and, for each new combination of modes, allocation
//! cost Livingstone 2's 15-breaker log, observed every few steps, 13 % of its CPU time at κ = 10
//! (1.3 % of its instructions: the time was cache misses). The cache can hold no other answer
//! for that key: [`ObservationModel::factor`] of modes consistent with the theory, unobserved,
//! is 1 as well. A replay (`replay.rs`) serves that 1 too rather than giving up on a solution
//! whose factor its full step never computed, so more unobserved steps replay: the same beliefs
//! with fewer theory questions (κ = 50 on that log).

use rustc_hash::FxHashMap;

use crate::logic::{Formula, ValueId, VarId};
use crate::opsat::{Literal, Theory, TheoryError};
use crate::plant::{Observation, Plant, mode_literals};

/// Past this many entries the cache starts afresh (it only holds what recent cycles met).
const CACHE_LIMIT: usize = 50_000;

/// P_O with a cache.
#[derive(Debug, Default)]
pub(crate) struct ObservationModel {
    cache: FxHashMap<Vec<u32>, f64>,
    key: Vec<u32>,
}

impl ObservationModel {
    /// P_O(o | modes).
    pub(crate) fn factor(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
        observation: &Observation,
    ) -> Result<f64, TheoryError> {
        self.factor_given(plant, theory, modes, observation, false)
    }

    /// [`ObservationModel::factor`] of `modes` that OPSAT found consistent with the theory and
    /// `observation` (a solution of an OCSP assuming the observation; see the module
    /// documentation): the same answer, without asking whether they are consistent.
    pub(crate) fn factor_of_solution(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
        observation: &Observation,
    ) -> Result<f64, TheoryError> {
        self.factor_given(plant, theory, modes, observation, true)
    }

    fn factor_given(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        modes: &[ValueId],
        observation: &Observation,
        consistent: bool,
    ) -> Result<f64, TheoryError> {
        if consistent && observation.values().is_empty() {
            return Ok(1.0);
        }
        if let Some(factor) = self.cached(modes, observation) {
            return Ok(factor);
        }
        let factor = compute(plant, theory, modes, observation, consistent)?;
        if self.cache.len() >= CACHE_LIMIT {
            self.cache.clear();
        }
        self.cache.insert(self.key.clone(), factor);
        Ok(factor)
    }

    /// [`ObservationModel::factor_of_solution`] of `modes` if it answers without asking the
    /// theory: nothing observed, or the factor cached.
    pub(crate) fn known_of_solution(
        &mut self,
        modes: &[ValueId],
        observation: &Observation,
    ) -> Option<f64> {
        if observation.values().is_empty() {
            return Some(1.0);
        }
        self.cached(modes, observation)
    }

    /// P_O(o | modes) if it is cached (then [`ObservationModel::factor`] would answer it without
    /// asking the theory); leaves the key of `modes` and `observation` in `self.key`.
    fn cached(&mut self, modes: &[ValueId], observation: &Observation) -> Option<f64> {
        self.key.clear();
        self.key.extend(modes.iter().map(|m| m.0));
        for &(x, v) in observation.values() {
            self.key.extend([x.0, v.0]);
        }
        self.cache.get(self.key.as_slice()).copied()
    }
}

/// P_O(o | modes); `consistent` when the modes are known to be consistent with the theory and
/// the observation (then that is not asked).
fn compute(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    observation: &Observation,
    consistent: bool,
) -> Result<f64, TheoryError> {
    if consistent && observation.values().is_empty() {
        return Ok(1.0);
    }
    let store = mode_literals(plant, modes);
    let mut everything = store.clone();
    everything.extend(observation.literals());
    if consistent {
        theory.known_consistent(&everything);
    } else if !theory.is_consistent(&everything) {
        return Ok(0.0);
    }
    // Consistent as a whole, so no value is refuted: each is entailed (1) or left open (1/m).
    let mut factor = 1.0;
    for &(x, v) in observation.values() {
        if !theory.entails(&store, &Formula::is(x, v))? {
            factor *= unpredicted(plant, x);
        }
    }
    Ok(factor)
}

/// The a-priori probability of a value nothing predicts: uniform over the domain.
fn unpredicted(plant: &Plant, x: VarId) -> f64 {
    1.0 / plant.table().variable(x).domain_size() as f64
}

/// How much a state with these modes predicts `x = v`: 1, 0 or 1/m (see the module docs).
pub(crate) fn prediction(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    x: VarId,
    v: ValueId,
) -> Result<f64, TheoryError> {
    let store: Vec<Literal> = mode_literals(plant, modes);
    let value = Formula::is(x, v);
    if theory.entails(&store, &value)? {
        Ok(1.0)
    } else if theory.entails(&store, &value.negate())? {
        Ok(0.0)
    } else {
        Ok(unpredicted(plant, x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;
    use crate::estimation::{ModeEstimator, TimedMe, TimedMeOptions};

    /// Thesis §6.2.2 (P_O), for a solution's factor: unobserved it is 1 and the same as
    /// `factor`'s, answered without the cache (which stays empty); observed, it is known only
    /// once computed, and then equal to what was computed — for every value of the plant's
    /// first observable (an LED), on the Livingstone 2 breakers' initial belief.
    #[test]
    fn a_solutions_factor_is_known_unobserved_and_cached_observed() {
        let text = include_str!("../../models/l2_breakers_15.ron");
        let plant = Plant::load(&Source::new("l2_breakers_15.ron", text)).expect("the model");
        let mut theory = plant.theory().expect("theory");
        let belief = TimedMe::new(TimedMeOptions::kappa(5))
            .initial(&plant, &mut theory, 0.0, &Observation::none())
            .expect("initial belief")
            .belief;
        let modes = &belief.states()[0].state.modes;
        let mut observe = ObservationModel::default();
        let none = Observation::none();
        assert_eq!(observe.known_of_solution(modes, &none), Some(1.0));
        let factor = observe.factor_of_solution(&plant, &mut theory, modes, &none);
        assert_eq!(factor.expect("factor"), 1.0);
        assert!(observe.cache.is_empty());
        let unobserved = ObservationModel::default().factor(&plant, &mut theory, modes, &none);
        assert_eq!(unobserved.expect("factor"), 1.0);
        let x = plant.observables()[0];
        for v in 0..plant.table().variable(x).domain_size() {
            let observed = Observation::new(&plant, &[(x, ValueId(v as u32))]).expect("obs");
            assert_eq!(observe.known_of_solution(modes, &observed), None);
            let fresh = ObservationModel::default().factor(&plant, &mut theory, modes, &observed);
            let computed = observe.factor(&plant, &mut theory, modes, &observed);
            assert_eq!(computed.as_ref().ok(), fresh.as_ref().ok());
            assert_eq!(observe.known_of_solution(modes, &observed), computed.ok());
        }
    }
}
