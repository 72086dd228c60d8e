//! Mode estimation (thesis §6.2, DESIGN.md §8): from a belief over system states, the control
//! action μ(i), the observation o(i+1) and the time t(i+1), the next belief.
//!
//! - A [`Belief`] is a set of weighted [`SystemState`]s (modes + clock starts), most probable
//!   first, summing to 1, at a time. Its most likely *plant* state sums the system states with
//!   equal modes ([`Belief::most_likely_plant_state`], §4.3.2); [`Belief::marginal`] is the
//!   belief in one assignment (the executive's `P(x = v) >= p`).
//! - [`TimedMe`] is TimedME (Figure 6-11) on OPSAT: the κ most likely next system states.
//! - [`BeliefUpdate`] is the exact BeliefUpdate_TCCA (Figure 6-10), the reference for small
//!   models.
//!
//! Both take the plant's one [`Theory`] by `&mut` (DESIGN.md: one theory per plant, owned by the
//! caller), share the plant module's enabled-transition core, and apply the observation factor
//! of Figure 6-10 (1 entailed, 0 refuted, 1/m otherwise) before renormalising. System states
//! whose clocks no longer matter merge exactly (DESIGN.md §8). When nothing explains an
//! observation, an [`EstimationEvent::InconsistentObservation`] says so and the estimator falls
//! back as DESIGN.md §8 prescribes, never panicking.

mod exact;
mod expand;
mod history;
pub mod log;
mod merge;
mod observe;
mod recents;
mod replay;
mod streams;
mod timed_me;

use std::fmt;
use std::sync::Arc;

pub use exact::BeliefUpdate;
pub use timed_me::{DEFAULT_HISTORY, MAX_HISTORY, Rerun, TimedMe, TimedMeOptions};

use crate::logic::{ValueId, VarId};
use crate::opsat::{Cut, Theory, TheoryError};
use crate::plant::{Commands, InputError, Observation, Plant, StepError, SystemState};

/// Plant-state probabilities this close (relatively) count as tied.
const TIE: f64 = 1e-9;

/// A system state and its probability.
#[derive(Debug, Clone, PartialEq)]
pub struct WeightedState {
    /// Modes and clock starts.
    pub state: SystemState,
    /// Its probability in the belief.
    pub probability: f64,
}

/// A plant state (modes only) and its probability: the sum over the system states with these
/// modes.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantEstimate {
    /// Mode per component, by [`ComponentId`](crate::plant::ComponentId): its first system
    /// state's, shared.
    pub modes: Arc<[ValueId]>,
    /// Summed probability.
    pub probability: f64,
}

/// A belief state: system states with probabilities, most probable first, at a time.
#[derive(Clone)]
pub struct Belief {
    time: f64,
    states: Vec<WeightedState>,
    /// The plant's mode variables, by component, to answer [`Belief::marginal`]. Made by
    /// [`Belief::new`], it is the plant's own allocation (`Plant::mode_vars`, shared by the
    /// plant's clones, whose components are the same), and `Belief::new` checked every state
    /// against that plant: a belief whose `mode_vars` is a plant's allocation fits that plant,
    /// and an update from it need not check its states again (`check_step`).
    mode_vars: Arc<[VarId]>,
    /// The serial number TimedME returned this belief under, if it did (`history.rs`: an
    /// update from it continues that estimator's history). Where a belief came from is not
    /// part of its value: equality and `Debug` leave it out.
    issued: Option<u64>,
    /// An upper bound on the probability mass the exact update, run from the same start,
    /// holds outside these states, over theirs (0 for a belief made by [`Belief::new`]; see
    /// [`Belief::distance_bound`]). A record of how it was made, not part of its value:
    /// equality and `Debug` leave it out.
    outside: f64,
}

impl PartialEq for Belief {
    fn eq(&self, other: &Self) -> bool {
        self.time == other.time && self.states == other.states && self.mode_vars == other.mode_vars
    }
}

impl fmt::Debug for Belief {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Belief")
            .field("time", &self.time)
            .field("states", &self.states)
            .field("mode_vars", &self.mode_vars)
            .finish()
    }
}

impl Belief {
    /// A belief from weighted states (normalised here, most probable first). `None` when the
    /// states have no positive total probability or do not fit the plant.
    pub fn new(plant: &Plant, time: f64, states: Vec<WeightedState>) -> Option<Belief> {
        if !states.iter().all(|w| w.state.check(plant).is_ok()) {
            return None;
        }
        Belief::made_for(plant, time, states)
    }

    /// [`Belief::new`] of states known to fit `plant`: estimation's successors of a belief
    /// checked on entry to the update ([`check_step`]), which keep its shape and take their
    /// modes from the plant's own distributions. A quiet cycle makes one; checking its states
    /// again was a fortieth of the Mars lander's quiet cycle.
    pub(crate) fn made_for(plant: &Plant, time: f64, states: Vec<WeightedState>) -> Option<Belief> {
        let total: f64 = states.iter().map(|w| w.probability).sum();
        if !(total > 0.0 && total.is_finite() && time.is_finite()) {
            return None;
        }
        let mut states: Vec<WeightedState> = states
            .into_iter()
            .filter(|w| w.probability > 0.0)
            .map(|w| WeightedState {
                probability: w.probability / total,
                state: w.state,
            })
            .collect();
        states.sort_by(|a, b| b.probability.total_cmp(&a.probability));
        Some(Belief {
            time,
            states,
            mode_vars: Arc::clone(plant.mode_vars()),
            issued: None,
            outside: 0.0,
        })
    }

    /// An upper bound on the total-variation distance, over system states (and so over plant
    /// states), between this belief and the one the exact update (Figure 6-10, [`BeliefUpdate`])
    /// would hold after the same steps from the same start: 0 for a belief made by
    /// [`Belief::new`] and for the exact update's; for TimedME's, what its truncations can
    /// have cost so far (`timed_me.rs`, "How far from exact"); 1 when nothing is known (after
    /// a budget cut or a fallback).
    pub fn distance_bound(&self) -> f64 {
        if self.outside.is_finite() {
            self.outside / (1.0 + self.outside)
        } else {
            1.0
        }
    }

    /// Sets the bound behind [`Belief::distance_bound`] (`outside / (1 + outside)`).
    pub(crate) fn set_outside(&mut self, outside: f64) {
        self.outside = outside;
    }

    /// The bound behind [`Belief::distance_bound`].
    pub(crate) fn outside(&self) -> f64 {
        self.outside
    }

    /// The time of the last observation folded in, t(i).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The tracked system states, most probable first.
    pub fn states(&self) -> &[WeightedState] {
        &self.states
    }

    /// The plant states (system states with equal modes summed), most probable first; ties keep
    /// the order of their most probable system state.
    pub fn plant_states(&self) -> Vec<PlantEstimate> {
        summed(&self.states, |out, _, weighted| {
            out.iter().position(|e| e.modes == weighted.state.modes)
        })
    }

    /// ŝ: the most likely plant state, the marginal over system states with equal modes
    /// (§4.3.2, DESIGN.md §3 step 4). Plant states within a relative 1e-9 of the best count as
    /// tied, and a tie goes to the later-declared modes (compared component by component): at
    /// the exact middle of a uniform window — §7.1.2's engine at 45 s of heating — the state the
    /// timed transition leads to wins, as models list modes along their nominal progression.
    pub fn most_likely_plant_state(&self) -> PlantEstimate {
        Belief::most_likely_among(&self.plant_states())
            .cloned()
            .unwrap_or(PlantEstimate {
                modes: Arc::from([]),
                probability: 0.0,
            })
    }

    /// ŝ among `states`, the belief's [`Belief::plant_states`] (most probable first), with the
    /// ties of [`Belief::most_likely_plant_state`]; `None` when there are none. For callers that
    /// need both the plant states and ŝ without grouping the belief twice.
    pub fn most_likely_among(states: &[PlantEstimate]) -> Option<&PlantEstimate> {
        let best = states.first().map_or(0.0, |e| e.probability);
        states
            .iter()
            .take_while(|e| e.probability >= best * (1.0 - TIE))
            .max_by(|a, b| a.modes.cmp(&b.modes))
    }

    /// The belief that mode variable `var` has value `value`: the probability of the tracked
    /// system states that say so. `None` when `var` is not a mode variable (attributes are not
    /// tracked; see [`Belief::predicted_marginal`]).
    pub fn marginal(&self, var: VarId, value: ValueId) -> Option<f64> {
        let component = self.mode_vars.iter().position(|&x| x == var)?;
        self.component_marginal(component, value)
    }

    /// [`Belief::marginal`] of the mode variable of the component with this index (`None`
    /// past the last component): for callers that go through the components in order, without
    /// looking the variable up.
    pub fn component_marginal(&self, component: usize, value: ValueId) -> Option<f64> {
        (component < self.mode_vars.len()).then(|| {
            self.states
                .iter()
                .filter(|w| w.state.modes[component] == value)
                .map(|w| w.probability)
                .sum()
        })
    }

    /// [`Belief::component_marginal`] of each component's mode in `modes`, into `out` (0 past
    /// the last component), in one pass over the states: each component's sum still runs over
    /// the states in order, so the numbers are the same bit for bit. The executive records
    /// every component's each cycle; a pass over the states per component was a fiftieth of
    /// the Mars lander's quiet cycle.
    pub fn component_marginals(&self, modes: &[ValueId], out: &mut Vec<f64>) {
        let none: f64 = std::iter::empty::<f64>().sum();
        let known = modes.len().min(self.mode_vars.len());
        out.clear();
        out.resize(known, none);
        for weighted in &self.states {
            let here = weighted.state.modes.iter().zip(modes);
            let p = weighted.probability;
            // A state that says otherwise adds −0.0, which leaves every sum as it is, bit for
            // bit (x + −0.0 = x for every x, −0.0 and +0.0 included): the same sums as adding
            // only where it agrees, without a branch per component.
            for (sum, (mode, wanted)) in out.iter_mut().zip(here) {
                *sum += if mode == wanted { p } else { -0.0 };
            }
        }
        out.resize(modes.len(), 0.0);
    }

    /// The belief that any variable (an attribute too) has `value`, as the states predict it:
    /// each system state counts fully when its modes and the model entail `var = value`, not at
    /// all when they refute it, and 1/m of itself when they leave it open (the observation
    /// model of Figure 6-10).
    pub fn predicted_marginal(
        &self,
        plant: &Plant,
        theory: &mut Theory,
        var: VarId,
        value: ValueId,
    ) -> Result<f64, EstimationError> {
        if var.index() >= plant.table().len()
            || value.index() >= plant.table().variable(var).domain_size()
        {
            return Err(EstimationError::Input(InputError::OutOfDomain {
                name: format!("#{}", var.0),
                value: value.0,
            }));
        }
        let mut total = 0.0;
        for weighted in &self.states {
            let factor = observe::prediction(plant, theory, &weighted.state.modes, var, value)?;
            total += weighted.probability * factor;
        }
        Ok(total)
    }
}

/// Per state of `states`, into `groups`, the index of its plant state among the distinct mode
/// vectors in order of first appearance (each state compared with the first state of every
/// plant state before it); returns how many there are.
fn group_by_modes(states: &[WeightedState], groups: &mut Vec<usize>) -> usize {
    // The first state of each plant state, by index.
    let mut firsts: Vec<usize> = Vec::with_capacity(states.len());
    groups.clear();
    for weighted in states {
        let modes = &weighted.state.modes;
        match firsts.iter().position(|&f| states[f].state.modes == *modes) {
            Some(g) => groups.push(g),
            None => {
                groups.push(firsts.len());
                firsts.push(groups.len() - 1);
            }
        }
    }
    firsts.len()
}

/// The plant states of `states` grouped as `groups` says ([`group_by_modes`]): each one's modes
/// its first state's, its probability the sum of its states' in order; most probable first, ties
/// in order of first appearance ([`Belief::plant_states`]).
fn summed_by_group(states: &[WeightedState], groups: &[usize]) -> Vec<PlantEstimate> {
    summed(states, |out, i, _| {
        groups.get(i).copied().filter(|&g| g < out.len())
    })
}

/// The plant states of `states`, each state's probability added, in order, to the plant state
/// `group` names (given the plant states so far, the state's index and the state), or opening a
/// new one with its modes; most probable first, ties in order of first appearance. The two
/// callers differ only in how they find a state's group: by comparing modes
/// ([`Belief::plant_states`], the reference) or by the remembered grouping.
fn summed(
    states: &[WeightedState],
    mut group: impl FnMut(&[PlantEstimate], usize, &WeightedState) -> Option<usize>,
) -> Vec<PlantEstimate> {
    // At most one plant state per system state: sized once rather than grown step by step.
    let mut out: Vec<PlantEstimate> = Vec::with_capacity(states.len());
    for (i, weighted) in states.iter().enumerate() {
        match group(&out, i, weighted) {
            Some(g) => out[g].probability += weighted.probability,
            None => out.push(PlantEstimate {
                modes: Arc::clone(&weighted.state.modes),
                probability: weighted.probability,
            }),
        }
    }
    out.sort_by(|a, b| b.probability.total_cmp(&a.probability));
    out
}

/// [`Belief::plant_states`] for a caller that asks it of one belief after another (the executive,
/// every cycle), remembering how the last belief's states grouped by modes.
///
/// Exact: the grouping is a function of which states' mode vectors are equal. When the new
/// belief's states hold the very mode vectors of the last one's, in the same order (the same
/// `Arc`s, held here so that their addresses name them; a mode vector never changes once
/// made), every equality among them is what it was, so the grouping is too; a state's group is
/// the plant state [`Belief::plant_states`] adds it to (the first whose modes equal its own), and
/// the sums run over the states in order and are sorted with the same comparator: the same
/// numbers in the same order (a property test compares the two). A quiet estimation step keeps
/// its states' allocations (`replay.rs`, "Shared successors"), so what this spares — comparing
/// each state's modes with every plant state's before it — is most of the grouping's cost on
/// the Mars lander's quiet cycle (41,157 → 39,673 instructions a quiet cruise cycle).
///
/// It also gives the marginals of one mode vector ([`PlantGrouping::marginals`]) from the
/// grouping: a state's modes differ from ŝ's in a few components (a fault or two), which are the
/// same for every state of its plant state, so each state adds its probability to the runs of
/// components between them — contiguous additions the compiler vectorises — instead of comparing
/// every component's mode.
#[derive(Debug, Clone, Default)]
pub(crate) struct PlantGrouping {
    /// The last belief's states' mode vectors, in order.
    modes: Vec<Arc<[ValueId]>>,
    /// Per state, its plant state's index in order of first appearance.
    groups: Vec<usize>,
    /// The mode vector `differing` was computed against, if any.
    against: Option<Arc<[ValueId]>>,
    /// Per plant state, the components whose mode differs from `against`'s, ascending.
    differing: Vec<Vec<usize>>,
}

impl PlantGrouping {
    /// `belief.plant_states()`, the same bit for bit.
    pub(crate) fn plant_states(&mut self, belief: &Belief) -> Vec<PlantEstimate> {
        let states = belief.states();
        if !self.holds(states) {
            let groups = group_by_modes(states, &mut self.groups);
            self.modes.clear();
            (self.modes).extend(states.iter().map(|w| Arc::clone(&w.state.modes)));
            self.against = None;
            self.differing.resize_with(groups, Vec::new);
        }
        summed_by_group(states, &self.groups)
    }

    /// Whether the grouping is `states`': they hold the mode vectors it was made from, in order.
    fn holds(&self, states: &[WeightedState]) -> bool {
        self.modes.len() == states.len()
            && (self.modes.iter().zip(states)).all(|(m, w)| Arc::ptr_eq(m, &w.state.modes))
    }

    /// `belief.component_marginals(modes, out)`, the same bit for bit: each component's sum
    /// still receives the probability of every state that agrees with `modes` there, in the
    /// states' order, and nothing else. From the grouping when it is `belief`'s
    /// ([`PlantGrouping::plant_states`] was asked of it) and every mode vector has one mode per
    /// component of the belief; otherwise by [`Belief::component_marginals`].
    pub(crate) fn marginals(
        &mut self,
        belief: &Belief,
        modes: &Arc<[ValueId]>,
        out: &mut Vec<f64>,
    ) {
        let states = belief.states();
        let components = belief.mode_vars.len();
        if !self.holds(states)
            || modes.len() != components
            || self.modes.iter().any(|m| m.len() != components)
        {
            return belief.component_marginals(modes, out);
        }
        if !self.against.as_ref().is_some_and(|a| Arc::ptr_eq(a, modes)) {
            for (g, differing) in self.differing.iter_mut().enumerate() {
                let first = self.groups.iter().position(|&h| h == g);
                let group = first.map_or(&[][..], |f| &states[f].state.modes[..]);
                differing.clear();
                (differing).extend((0..components).filter(|&c| group[c] != modes[c]));
            }
            self.against = Some(Arc::clone(modes));
        }
        let none: f64 = std::iter::empty::<f64>().sum();
        out.clear();
        out.resize(components, none);
        for (weighted, &g) in states.iter().zip(&self.groups) {
            let p = weighted.probability;
            let mut from = 0;
            for &c in &self.differing[g] {
                out[from..c].iter_mut().for_each(|sum| *sum += p);
                from = c + 1;
            }
            out[from..].iter_mut().for_each(|sum| *sum += p);
        }
    }
}

/// Which fallback the estimator took when no tracked state explained an observation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// The last `steps` steps were estimated again tracking more states, and that explained it
    /// (a state truncated away earlier was found again; `history.rs`).
    Reestimated {
        /// How many steps were estimated again, this one included.
        steps: usize,
    },
    /// Components were allowed to jump into their unconstrained fault modes (`failed`,
    /// `unknown`), which explain any observation of theirs.
    UnconstrainedFaults,
    /// Even that did not explain it: the previous belief is kept (clocks running on) and the
    /// observation is set aside for this cycle.
    PreviousBelief,
}

/// Something the caller should know about one update.
#[derive(Debug, Clone, PartialEq)]
pub enum EstimationEvent {
    /// No state reachable from the tracked ones is consistent with the observation
    /// (DESIGN.md §8): the estimator fell back as said.
    InconsistentObservation {
        /// What the belief was built from instead.
        fallback: Fallback,
    },
    /// An OPSAT budget ran out; the belief holds the best states found so far.
    SearchCut(Cut),
}

/// Work done by one update, for reports and benchmarks.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UpdateStats {
    /// Candidate trajectories (source state × next plant state) examined.
    pub candidates: u64,
    /// SAT solver calls made (entailment, consistency, conflict minimisation).
    pub sat_calls: u64,
    /// System states in the new belief.
    pub states: u64,
    /// The belief was found by replaying the previous step's streams with the new
    /// probabilities (a quiet step, certified to give the full expansion's answer; see
    /// [`TimedMeOptions::replay`]).
    pub replayed: bool,
    /// Steps TimedME estimated again from its history window, wider, to give this belief (0
    /// but when an observation contradicted every tracked state or truncation could have
    /// decided ŝ; see [`TimedMeOptions::history`]).
    pub rerun: u32,
    /// The fraction of this step's merged weight (the next states found, observation weighed in)
    /// that truncation to κ states discarded: 0 for the exact update, and whenever every next
    /// state found was kept. Per step; [`Belief::distance_bound`] is what the steps so far,
    /// and the states the search did not enumerate, can add up to.
    pub discarded: f64,
}

/// The result of one estimation step.
#[derive(Debug, Clone, PartialEq)]
pub struct Update {
    /// The new belief, at the new time.
    pub belief: Belief,
    /// Events (inconsistent observations, budget cuts).
    pub events: Vec<EstimationEvent>,
    /// Work done.
    pub stats: UpdateStats,
}

/// Why an update could not be made at all (the caller's inputs do not fit; data problems are
/// events, not errors).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EstimationError {
    /// A command, observation or state does not fit the plant.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Time must not go backwards, and must be a number.
    #[error("time {to} s is not after the belief's time {from} s")]
    TimeWentBackwards {
        /// The belief's time.
        from: f64,
        /// The time asked for.
        to: f64,
    },
    /// The exact update would enumerate more target states than it is meant for.
    #[error(
        "the exact update would enumerate {0} target states from one state: use TimedME for a model this size"
    )]
    TooLarge(u128),
    /// The theory refused a formula (it is not this plant's theory).
    #[error(transparent)]
    Theory(#[from] TheoryError),
}

impl From<StepError> for EstimationError {
    fn from(error: StepError) -> Self {
        match error {
            StepError::Input(e) => EstimationError::Input(e),
            StepError::Theory(e) => EstimationError::Theory(e),
        }
    }
}

/// The shape of every mode estimator: TimedME and the exact update.
pub trait ModeEstimator {
    /// The belief at `time` before any transition: the initial distribution P_Θ over plant
    /// states consistent with the model and `observation`, every clock starting at `time`
    /// (§6.2.2, "P_Θ(s) if the clock interpretation assigns zero to each plant clock").
    fn initial(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        time: f64,
        observation: &Observation,
    ) -> Result<Update, EstimationError>;

    /// One step: from `belief` (at t(i)), with the control action μ(i), the observation
    /// o(i+1) and the time t(i+1), the next belief.
    fn update(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        belief: &Belief,
        commands: &Commands,
        observation: &Observation,
        time: f64,
    ) -> Result<Update, EstimationError>;
}

/// Checks what an update is given: values in their domains, a belief for this plant, a time
/// that does not go backwards.
fn check_step(
    plant: &Plant,
    belief: &Belief,
    commands: &Commands,
    observation: &Observation,
    time: f64,
) -> Result<(), EstimationError> {
    check_values(plant, commands.values())?;
    check_values(plant, observation.values())?;
    // Checked when made, if made for this plant (see `Belief::mode_vars`).
    if !Arc::ptr_eq(&belief.mode_vars, plant.mode_vars()) {
        for weighted in &belief.states {
            weighted.state.check(plant)?;
        }
    }
    if !time.is_finite() || time < belief.time {
        return Err(EstimationError::TimeWentBackwards {
            from: belief.time,
            to: time,
        });
    }
    Ok(())
}

fn check_values(plant: &Plant, values: &[(VarId, ValueId)]) -> Result<(), InputError> {
    let table = plant.table();
    for &(var, value) in values {
        if var.index() >= table.len() || value.index() >= table.variable(var).domain_size() {
            return Err(InputError::OutOfDomain {
                name: format!("#{}", var.0),
                value: value.0,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;
    use crate::seeded;
    use proptest::prelude::*;

    /// A belief of `states` as (mode vector, probability), taken as given (no plant).
    fn belief_of(states: &[(Arc<[ValueId]>, f64)]) -> Belief {
        let states = states
            .iter()
            .map(|(modes, probability)| WeightedState {
                state: SystemState {
                    modes: Arc::clone(modes),
                    clock_starts: vec![None; modes.len()].into(),
                },
                probability: *probability,
            })
            .collect();
        Belief {
            time: 0.0,
            states,
            mode_vars: Arc::from([VarId(0), VarId(1), VarId(2)]),
            issued: None,
            outside: 0.0,
        }
    }

    proptest! {
        #![proptest_config(seeded::config(256))]

        /// `PlantGrouping` (the executive's plant states, DESIGN.md §3 step 4) gives what
        /// `Belief::plant_states` gives, bit for bit and sharing the same mode vectors, over a
        /// run of beliefs that keep their states' mode vectors (reweighed: the remembered
        /// grouping is used), reorder them, or bring equal ones in other allocations.
        #[test]
        fn the_remembered_grouping_gives_the_plant_states(
            steps in proptest::collection::vec(
                (any::<bool>(), proptest::collection::vec((0usize..8, 1u32..64), 1..9)),
                1..12,
            ),
            marginals in 0usize..8,
        ) {
            // Four mode vectors, each in two allocations: 0–3 and 4–7 are equal in turn.
            let pool: Vec<Arc<[ValueId]>> = (0..8u32)
                .map(|i| Arc::from([ValueId(i % 4), ValueId(i % 2), ValueId(0)]))
                .collect();
            let mut grouping = PlantGrouping::default();
            let mut last: Vec<(Arc<[ValueId]>, f64)> = Vec::new();
            for (reweigh, states) in steps {
                let these: Vec<(Arc<[ValueId]>, f64)> = if reweigh && !last.is_empty() {
                    (last.iter().zip(states.iter().cycle()))
                        .map(|((modes, _), &(_, w))| (Arc::clone(modes), f64::from(w) / 7.0))
                        .collect()
                } else {
                    (states.iter())
                        .map(|&(i, w)| (Arc::clone(&pool[i]), f64::from(w) / 7.0))
                        .collect()
                };
                let belief = belief_of(&these);
                let expected = belief.plant_states();
                let remembered = grouping.plant_states(&belief);
                prop_assert_eq!(remembered.len(), expected.len());
                for (a, b) in remembered.iter().zip(&expected) {
                    prop_assert!(Arc::ptr_eq(&a.modes, &b.modes));
                    prop_assert_eq!(a.probability.to_bits(), b.probability.to_bits());
                }
                // The marginals of ŝ's modes (as the executive asks), of another state's, and
                // of a vector no state has, twice each (the second from what the first kept).
                let best = Belief::most_likely_among(&expected).map(|e| Arc::clone(&e.modes));
                let others = [Arc::clone(&pool[marginals % 8]), Arc::from([ValueId(3); 3])];
                for modes in best.into_iter().chain(others) {
                    for _ in 0..2 {
                        let (mut fast, mut plain) = (Vec::new(), Vec::new());
                        grouping.marginals(&belief, &modes, &mut fast);
                        belief.component_marginals(&modes, &mut plain);
                        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                        prop_assert_eq!(bits(&fast), bits(&plain));
                    }
                }
                last = these;
            }
        }
    }

    fn load(name: &str, text: &str) -> Plant {
        Plant::load(&Source::new(name, text)).expect("the model loads")
    }

    /// `plant`'s theory, a TimedME tracking `kappa` states, and its initial belief, unobserved.
    fn started(plant: &Plant, kappa: usize) -> (Theory, TimedMe, Belief) {
        let mut theory = plant.theory().expect("theory");
        let mut me = TimedMe::new(TimedMeOptions::kappa(kappa));
        let first = me
            .initial(plant, &mut theory, 0.0, &Observation::none())
            .expect("initial belief");
        (theory, me, first.belief)
    }

    /// The marginals in one pass are each component's marginal asked alone, bit for bit (the
    /// executive records them as §7.2's mode timelines): the Mars lander's belief after a
    /// step, for ŝ's modes and for modes no state has (0, whatever zero the sum gives).
    #[test]
    fn the_marginals_in_one_pass_are_the_marginals_asked_alone() {
        const LANDER: &str = include_str!("../../models/mars_lander.ron");
        let plant = load("mars_lander.ron", LANDER);
        let (mut theory, mut me, first) = started(&plant, 10);
        let idle = Commands::idle(&plant);
        let next = me
            .update(
                &plant,
                &mut theory,
                &first,
                &idle,
                &Observation::none(),
                0.1,
            )
            .expect("a step");
        let belief = &next.belief;
        assert!(belief.states().len() > 1, "a belief worth summing");
        let best = belief.most_likely_plant_state().modes.to_vec();
        let absent: Vec<ValueId> = best.iter().map(|_| ValueId(u32::MAX)).collect();
        for modes in [best, absent] {
            let mut marginals = Vec::new();
            belief.component_marginals(&modes, &mut marginals);
            assert_eq!(marginals.len(), modes.len());
            for (c, &mode) in modes.iter().enumerate() {
                let alone = belief.component_marginal(c, mode).expect("a component");
                assert_eq!(marginals[c].to_bits(), alone.to_bits(), "component {c}");
            }
        }
    }

    /// `check_step` leaves out the states of a belief made for the plant it is given (its
    /// mode variables are that plant's allocation) and checks any other's: a belief of the
    /// same model loaded again fits and is accepted, one of another model is refused.
    #[test]
    fn a_belief_made_for_another_plant_is_checked() {
        const VALVE: &str = include_str!("../../models/driver_valve.ron");
        let valve = load("driver_valve.ron", VALVE);
        let (_, _, first) = started(&valve, 3);
        assert!(Arc::ptr_eq(&first.mode_vars, valve.mode_vars()));
        let step = |plant: &Plant, belief: &Belief| {
            let mut theory = plant.theory().expect("theory");
            let commands = Commands::idle(plant);
            TimedMe::new(TimedMeOptions::kappa(3)).update(
                plant,
                &mut theory,
                belief,
                &commands,
                &Observation::none(),
                1.0,
            )
        };
        assert!(step(&valve, &first).is_ok());
        let again = load("driver_valve.ron", VALVE);
        assert!(!Arc::ptr_eq(&first.mode_vars, again.mode_vars()));
        assert!(step(&again, &first).is_ok());
        let thermostat = load(
            "thermostat.ron",
            include_str!("../../models/thermostat.ron"),
        );
        assert!(matches!(
            step(&thermostat, &first),
            Err(EstimationError::Input(_))
        ));
    }
}
