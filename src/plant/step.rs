//! One step of a TCCA: Step_TCCA (Figure 6-6) and ConsistentState_TCCA (Figure 6-7), and their
//! common core — which transitions are enabled in a system state under a control action, and
//! each component's distribution over its next mode — which mode estimation shares.

use std::borrow::Cow;
use std::sync::Arc;

use super::{ComponentId, Plant, SystemState, mode_distribution};
use crate::logic::{Atom, Formula, ValueId, VarId};
use crate::opsat::{Literal, Ocsp, Theory, TheoryError};

/// Why a control action, an observation or a state does not fit the plant.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputError {
    /// Only control variables can be commanded.
    #[error("`{0}` is not a control of the plant")]
    NotAControl(String),
    /// Only observables can be observed.
    #[error("`{0}` is not an observable of the plant")]
    NotObservable(String),
    /// A variable was given two values in one cycle.
    #[error("`{0}` is given twice in one cycle")]
    Repeated(String),
    /// A value outside the variable's domain (or a variable not in the plant).
    #[error("value #{value} is outside the domain of `{name}`")]
    OutOfDomain {
        /// The variable.
        name: String,
        /// The value's number.
        value: u32,
    },
    /// A system state must give every component a mode and a clock start.
    #[error("a system state needs one mode and one clock start per component")]
    StateShape,
}

/// Why a step could not be taken.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StepError {
    /// The state, commands or observation do not fit the plant.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The theory refused a formula (it is not this plant's theory).
    #[error(transparent)]
    Theory(#[from] TheoryError),
}

/// Checks that every component has a mode of its own. (Inlined: a belief checks its states
/// with it every step, and a call per state cost as much as the check.)
#[inline]
pub(crate) fn check_modes(plant: &Plant, modes: &[ValueId]) -> Result<(), InputError> {
    let components = plant.components();
    if modes.len() != components.len() {
        return Err(InputError::StateShape);
    }
    // A pass without early exit over the mode counts first (estimation checks every state of a
    // belief twice a step, and nearly always they fit); the component at fault is looked for
    // only when one does not.
    let fits = (modes.iter().zip(plant.mode_counts()))
        .fold(true, |fits, (mode, &count)| fits & (mode.index() < count));
    if fits {
        return Ok(());
    }
    for (component, mode) in components.iter().zip(modes) {
        if mode.index() >= component.modes().len() {
            return Err(InputError::OutOfDomain {
                name: component.name().to_string(),
                value: mode.0,
            });
        }
    }
    Ok(())
}

/// Checks that the control action and observation name variables and values of the plant.
fn check_inputs(
    plant: &Plant,
    commands: &Commands,
    observation: &Observation,
) -> Result<(), InputError> {
    for &(var, value) in commands.values().iter().chain(observation.values()) {
        check_value(plant, var, value)?;
    }
    Ok(())
}

/// Checks that `(var, value)` names a variable of the plant and a value of its domain.
fn check_value(plant: &Plant, var: VarId, value: ValueId) -> Result<(), InputError> {
    if var.index() >= plant.table().len() {
        return Err(InputError::OutOfDomain {
            name: format!("#{}", var.0),
            value: value.0,
        });
    }
    let variable = plant.table().variable(var);
    if value.index() >= variable.domain_size() {
        return Err(InputError::OutOfDomain {
            name: variable.name().to_string(),
            value: value.0,
        });
    }
    Ok(())
}

/// A control action μ: a value for every control of the plant, commanded or idle, and which
/// commands flight software acknowledged as carried out ([`Commands::acknowledged`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Commands {
    /// One value per control, in the order of [`Plant::controls`].
    values: Vec<(VarId, ValueId)>,
    /// The commanded controls whose command is known to have reached the hardware, sorted
    /// (empty without acknowledgements, so that they cost nothing then).
    delivered: Vec<VarId>,
}

impl Commands {
    /// No command: every control holds its idle value.
    pub fn idle(plant: &Plant) -> Commands {
        Commands {
            values: plant.controls().iter().map(|c| (c.var, c.idle)).collect(),
            delivered: Vec::new(),
        }
    }

    /// The commands issued in a cycle; the other controls are idle.
    pub fn new(plant: &Plant, issued: &[(VarId, ValueId)]) -> Result<Commands, InputError> {
        let mut commands = Commands::idle(plant);
        let mut seen = Vec::new();
        for &(var, value) in issued {
            check_value(plant, var, value)?;
            let name = || plant.table().variable(var).name().to_string();
            let Some(slot) = commands.values.iter_mut().find(|(x, _)| *x == var) else {
                return Err(InputError::NotAControl(name()));
            };
            if seen.contains(&var) {
                return Err(InputError::Repeated(name()));
            }
            seen.push(var);
            slot.1 = value;
        }
        Ok(commands)
    }

    /// Every control's value.
    pub fn values(&self) -> &[(VarId, ValueId)] {
        &self.values
    }

    /// The controls whose command is known to have reached the hardware (sorted).
    pub fn delivered(&self) -> &[VarId] {
        &self.delivered
    }

    /// The control action as `observation`'s acknowledgements say it happened
    /// ([`acknowledgement`](super::acknowledgement)): a command answered `rejected` or `failed`
    /// is taken back (its control idle), one answered `accepted` or `completed` is marked
    /// delivered. An answer on a control not commanded, or `none`, changes nothing. Borrowed
    /// when no answer changes anything: flight software that holds its last answer reports it
    /// every cycle, and most cycles command nothing.
    pub fn acknowledged(&self, plant: &Plant, observation: &Observation) -> Cow<'_, Commands> {
        let mut answers = (observation.acknowledgements.iter())
            .filter_map(|&(var, value)| self.answered(plant, var, value))
            .peekable();
        if answers.peek().is_none() {
            return Cow::Borrowed(self);
        }
        let mut commands = self.clone();
        for (slot, control, carried_out) in answers {
            if carried_out {
                if let Err(at) = commands.delivered.binary_search(&control) {
                    commands.delivered.insert(at, control);
                }
            } else {
                commands.values[slot].1 = plant.controls()[slot].idle;
            }
        }
        Cow::Owned(commands)
    }

    /// What the acknowledgement `var = value` says of this action: the slot of the control it
    /// answers for, the control, and whether the command was carried out — `None` when it says
    /// nothing (not an acknowledgement, its control not commanded, the answer `none`).
    fn answered(&self, plant: &Plant, var: VarId, value: ValueId) -> Option<(usize, VarId, bool)> {
        let acknowledgement = plant.acknowledgement_of(var)?;
        let control = acknowledgement.control;
        let slot = plant.controls().iter().position(|c| c.var == control)?;
        if self.values[slot].1 == plant.controls()[slot].idle {
            return None;
        }
        let carried_out = acknowledgement.answer(value).carried_out()?;
        Some((slot, control, carried_out))
    }

    /// The same action with the delivered commands not sent: what is enabled without them.
    fn without_delivered(&self, plant: &Plant) -> Commands {
        let values = (self.values.iter().zip(plant.controls()))
            .map(|(&(var, value), control)| {
                let delivered = self.delivered.binary_search(&var).is_ok();
                (var, if delivered { control.idle } else { value })
            })
            .collect();
        Commands {
            values,
            delivered: Vec::new(),
        }
    }

    /// The controls that are not idle, for display.
    pub fn issued<'a>(&'a self, plant: &'a Plant) -> impl Iterator<Item = (VarId, ValueId)> + 'a {
        self.values
            .iter()
            .zip(plant.controls())
            .filter(|((_, v), control)| *v != control.idle)
            .map(|(&assignment, _)| assignment)
    }

    fn literals(&self) -> impl Iterator<Item = Literal> + '_ {
        self.values.iter().map(|&(x, v)| Literal::Is(x, v))
    }
}

/// An observation o: values of some observables; those absent are unknown this cycle. It
/// also carries the acknowledgements reported with it, which are evidence about the last
/// command rather than about the plant's modes ([`Commands::acknowledged`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct Observation {
    /// Observed values, sorted by variable.
    values: Vec<(VarId, ValueId)>,
    /// Reported acknowledgements, sorted by variable.
    acknowledgements: Vec<(VarId, ValueId)>,
}

impl Observation {
    /// Nothing observed.
    pub fn none() -> Observation {
        Observation::default()
    }

    /// The observables (and acknowledgement observables) read in a cycle.
    pub fn new(plant: &Plant, observed: &[(VarId, ValueId)]) -> Result<Observation, InputError> {
        let mut values = Vec::with_capacity(observed.len());
        let mut acknowledgements = Vec::new();
        for &(var, value) in observed {
            check_value(plant, var, value)?;
            let name = || plant.table().variable(var).name().to_string();
            let list = if plant.observables().contains(&var) {
                &mut values
            } else if plant.acknowledgement_of(var).is_some() {
                &mut acknowledgements
            } else {
                return Err(InputError::NotObservable(name()));
            };
            if list.iter().any(|(x, _)| *x == var) {
                return Err(InputError::Repeated(name()));
            }
            list.push((var, value));
        }
        values.sort_unstable();
        acknowledgements.sort_unstable();
        Ok(Observation {
            values,
            acknowledgements,
        })
    }

    /// The observed values, sorted by variable (acknowledgements not included).
    pub fn values(&self) -> &[(VarId, ValueId)] {
        &self.values
    }

    /// The reported acknowledgements, sorted by variable.
    pub fn acknowledgements(&self) -> &[(VarId, ValueId)] {
        &self.acknowledgements
    }

    /// The observation as assumptions.
    pub fn literals(&self) -> impl Iterator<Item = Literal> + '_ {
        self.values.iter().map(|&(x, v)| Literal::Is(x, v))
    }
}

/// `component = mode` for every component.
pub(crate) fn mode_literals(plant: &Plant, modes: &[ValueId]) -> Vec<Literal> {
    plant
        .components()
        .iter()
        .zip(modes)
        .map(|(c, &m)| Literal::Is(c.mode_var(), m))
        .collect()
}

/// A component's enabled transitions in a system state under a control action.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Enabled {
    /// The enabled transitions, by index into
    /// [`Component::transitions`](super::Component::transitions).
    pub transitions: Vec<usize>,
    /// Some of them are enabled only by a command acknowledged as carried out
    /// ([`Commands::delivered`]): the component does not stay in its mode for want of the
    /// command (`acknowledgement` has why).
    pub delivered: bool,
}

/// Figure 6-6, steps 3–4 (and Figure 6-10's "identify enabled transitions"): per component,
/// the transitions out of its mode whose guard the constraint store `C_M` (the modes' constraints
/// and the interconnections) and the control action μ entail. When the modes and μ contradict
/// each other nothing is entailed but by vacuity, so only unguarded transitions count as enabled.
/// With delivered commands, a component is marked [`Enabled::delivered`] when one of its
/// enabled transitions is not enabled without them (a second pass, only then).
pub fn enabled_transitions(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    commands: &Commands,
) -> Result<Vec<Enabled>, StepError> {
    check_modes(plant, modes)?;
    check_inputs(plant, commands, &Observation::none())?;
    let enabled = entailed_guards(plant, theory, modes, commands)?;
    let without = if commands.delivered.is_empty() {
        None
    } else {
        let idle = commands.without_delivered(plant);
        Some(entailed_guards(plant, theory, modes, &idle)?)
    };
    Ok(enabled
        .into_iter()
        .enumerate()
        .map(|(c, transitions)| {
            let delivered = without
                .as_ref()
                .is_some_and(|without| transitions.iter().any(|t| !without[c].contains(t)));
            Enabled {
                transitions,
                delivered,
            }
        })
        .collect())
}

/// Per component, the transitions whose guard the store of `modes` and μ entails.
fn entailed_guards(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    commands: &Commands,
) -> Result<Vec<Vec<usize>>, StepError> {
    let mut store = mode_literals(plant, modes);
    store.extend(commands.literals());
    let guarded = |t: &usize, c: &super::Component| c.transitions()[*t].guard != Formula::True;
    let any_guarded = plant
        .components()
        .iter()
        .zip(modes)
        .any(|(c, &m)| c.outgoing(m).iter().any(|t| guarded(t, c)));
    let store_consistent = !any_guarded || theory.is_consistent(&store);
    let mut assumed = StoreValues::default();
    let mut enabled = Vec::with_capacity(modes.len());
    for (component, &mode) in plant.components().iter().zip(modes) {
        let outgoing = component.outgoing(mode);
        // At most every outgoing transition: one allocation, never grown.
        let mut here = Vec::with_capacity(outgoing.len());
        for &t in outgoing {
            let guard = &component.transitions()[t].guard;
            let on = match guard {
                Formula::True => true,
                _ if !store_consistent => false,
                guard => match assumed.decides(&store, guard) {
                    Some(on) => on,
                    None => theory.entails(&store, guard)?,
                },
            };
            if on {
                here.push(t);
            }
        }
        enabled.push(here);
    }
    Ok(enabled)
}

/// The values a consistent store of mode and command literals assumes, for the guards it
/// decides alone. A guard `x = v` on a variable the store assumes equal to w is entailed
/// exactly when w = v: the store entails `x = w`, and a variable holds one value, so it entails
/// `x ≠ v` for every other v (and, being consistent, not `x = v` too). Most guards test a
/// command the store carries (a breaker switches on when commanded on): asking the theory each
/// of them cost a question over the whole store, two fifths of a 255-breaker replay.
///
/// The map is sized for the whole store before it is filled: grown as it filled, it rehashed
/// eight times per source state at 255 breakers (every component's mode goes in). Filled in
/// store order either way, so a variable assumed twice keeps its last value. With each
/// component's list of enabled transitions made at its outgoing count (one allocation, never
/// grown), measured on Livingstone 2's logs at κ = 10 (callgrind, whole process): 255 breakers
/// 26.35 G → 26.17 G instructions, CPU 0.990 (0.98–1.02, `farm-bench --vs`, 7 pairs); 15
/// breakers 6.710 G → 6.697 G, CPU 0.997 (9 pairs); the quiet EDL cycle unchanged (38,977 →
/// 38,986). A list indexed by variable instead of the map took 255 breakers to 26.00 G but
/// the quiet EDL cycle to 40,563 (clearing a list as long as the largest variable assumed,
/// per source state, on a plant with many attributes): rejected.
#[derive(Default)]
struct StoreValues {
    /// Filled on the first guard asked (a plant without atom guards never needs it).
    values: Option<rustc_hash::FxHashMap<VarId, ValueId>>,
}

impl StoreValues {
    /// Whether a consistent `store` entails `guard`, when the store alone decides it.
    fn decides(&mut self, store: &[Literal], guard: &Formula) -> Option<bool> {
        let Formula::Atom(Atom::Is(x, v)) = guard else {
            return None;
        };
        let values = self.values.get_or_insert_with(|| {
            let mut values =
                rustc_hash::FxHashMap::with_capacity_and_hasher(store.len(), Default::default());
            values.extend(store.iter().filter_map(|l| match *l {
                Literal::Is(x, w) => Some((x, w)),
                _ => None,
            }));
            values
        });
        values.get(x).map(|w| w == v)
    }
}

/// Each component's distribution over its next mode, given its enabled transitions
/// (`enabled[c]`, from [`enabled_transitions`]) and a step from `from` to `to` (absolute
/// seconds): §6.2.2's transition probability, stay included.
pub fn component_distributions(
    plant: &Plant,
    state: &SystemState,
    enabled: &[Enabled],
    from: f64,
    to: f64,
) -> Vec<Vec<(ValueId, f64)>> {
    plant
        .component_ids()
        .zip(state.modes.iter())
        .zip(enabled)
        .map(|(((id, component), &mode), enabled)| {
            component_distribution(component, mode, enabled, state.clock(id, from), to - from)
        })
        .collect()
}

/// One component's distribution over its next mode from `mode`, given its enabled transitions
/// ([`Enabled`]), its clock at the step's start and the step's length: a pure function of
/// these, which estimation relies on to share it between system states. When a delivered
/// command enables a transition, staying has likelihood 0 and is left out (not renormalised:
/// the evidence weighs the source state as a whole).
pub fn component_distribution(
    component: &super::Component,
    mode: ValueId,
    enabled: &Enabled,
    clock: Option<f64>,
    step: f64,
) -> Vec<(ValueId, f64)> {
    let laws = enabled.transitions.iter().filter_map(|&t| {
        let transition = component.transitions().get(t)?;
        Some((transition.target, transition.law))
    });
    let mut distribution = mode_distribution(mode, laws, clock, step);
    let moves = |d: &[(ValueId, f64)]| d.iter().any(|&(m, p)| m != mode && p > 0.0);
    if enabled.delivered && moves(&distribution) {
        distribution.retain(|&(m, _)| m != mode);
    }
    distribution
}

/// Whether [`component_distribution`] with these enabled transitions and a step of length
/// `step` is on a steady stretch at clock `clock`: the same distribution, bit for bit, at every
/// clock where this holds. It reads the clock only through its enabled transitions' laws
/// ([`TransitionLaw::steady_at`](super::TransitionLaw::steady_at)), each the same value
/// wherever it is steady; the rest of its arithmetic is the same.
pub fn distribution_steady_at(
    component: &super::Component,
    enabled: &Enabled,
    clock: Option<f64>,
    step: f64,
) -> bool {
    enabled.transitions.iter().all(|&t| {
        (component.transitions().get(t))
            .is_none_or(|transition| transition.law.steady_at(clock, step))
    })
}

/// The common core of Figures 6-6, 6-7, 6-10 and 6-11: in `state` at time `from`, under control
/// action μ, each component's distribution over its mode at `to`.
pub fn transition_choices(
    plant: &Plant,
    theory: &mut Theory,
    state: &SystemState,
    commands: &Commands,
    from: f64,
    to: f64,
) -> Result<Vec<Vec<(ValueId, f64)>>, StepError> {
    state.check(plant)?;
    let enabled = enabled_transitions(plant, theory, &state.modes, commands)?;
    Ok(component_distributions(plant, state, &enabled, from, to))
}

/// Figure 6-6 step 6 / Figure 6-11 step 5: the state reached when every component takes the
/// transition to `targets`, at time `to` — clocks of components that changed mode restart then.
/// When no component changed mode, that is `source` itself, shared.
pub fn successor(source: &SystemState, targets: Vec<ValueId>, to: f64) -> SystemState {
    if *source.modes == *targets {
        return source.clone();
    }
    let clock_starts = source
        .modes
        .iter()
        .zip(&targets)
        .zip(source.clock_starts.iter())
        .map(|((before, after), start)| if before == after { *start } else { Some(to) })
        .collect();
    SystemState {
        modes: targets.into(),
        clock_starts,
    }
}

/// [`successor`] with the clocks that cannot matter in the new modes forgotten
/// ([`SystemState::forget_idle_clocks`]), built in one pass: the state estimation keeps. Each
/// component's clock start is forgotten when its new mode ignores the clock, else kept when it
/// stayed and restarted at `to` when it moved — what the two steps give in turn.
pub fn successor_forgetting(
    plant: &Plant,
    source: &SystemState,
    targets: &[ValueId],
    to: f64,
) -> SystemState {
    if *source.modes == *targets {
        return source.clone().forget_idle_clocks(plant);
    }
    let starts = || {
        (plant.components().iter().zip(source.modes.iter()))
            .zip(targets.iter().zip(source.clock_starts.iter()))
            .map(|((component, before), (after, start))| {
                if !component.clock_matters(*after) {
                    None
                } else if before == after {
                    *start
                } else {
                    Some(to)
                }
            })
    };
    // The source's clock starts are shared when they are the successor's, bit for bit (always,
    // on a plant without clocks): one allocation less per successor estimation builds.
    let same = (starts().zip(source.clock_starts.iter()))
        .all(|(new, old)| new.map(f64::to_bits) == old.map(f64::to_bits));
    let clock_starts = if same {
        Arc::clone(&source.clock_starts)
    } else {
        starts().collect()
    };
    SystemState {
        modes: targets.into(),
        clock_starts,
    }
}

/// Step_TCCA (Figure 6-6): every component takes one enabled transition (staying is the
/// implicit one), chosen by `choose(component, distribution)`, which returns an index into the
/// distribution (a simulator samples; a test picks); out-of-range indices mean "stay".
pub fn step_tcca(
    plant: &Plant,
    theory: &mut Theory,
    state: &SystemState,
    commands: &Commands,
    from: f64,
    to: f64,
    choose: impl FnMut(ComponentId, &[(ValueId, f64)]) -> usize,
) -> Result<SystemState, StepError> {
    let choices = transition_choices(plant, theory, state, commands, from, to)?;
    Ok(chosen_successor(state, &choices, to, choose))
}

/// Figure 6-6 steps 5–6 given the distributions (`choices[c]`, from
/// [`transition_choices`]): every component takes the transition `choose(component,
/// distribution)` picks — an index into the distribution; out of range means "stay" — and the
/// state reached at `to` is returned. Components are asked in order.
pub fn chosen_successor(
    state: &SystemState,
    choices: &[Vec<(ValueId, f64)>],
    to: f64,
    mut choose: impl FnMut(ComponentId, &[(ValueId, f64)]) -> usize,
) -> SystemState {
    let targets = choices
        .iter()
        .zip(state.modes.iter())
        .enumerate()
        .map(|(c, (distribution, &current))| {
            let pick = choose(ComponentId(c as u32), distribution);
            distribution
                .get(pick)
                .map_or(current, |&(target, _)| target)
        })
        .collect();
    successor(state, targets, to)
}

/// An OCSP whose decisions are the components' next modes with the given costs (−ln p), subject
/// to the plant's theory and `observation`: its solutions are the next plant states consistent
/// with the observation, most probable first (Figure 6-11 step 3 for one source state).
pub(crate) fn target_ocsp<C, I>(plant: &Plant, costs: C, observation: &Observation) -> Ocsp
where
    C: IntoIterator<Item = I>,
    I: IntoIterator<Item = (ValueId, f64)>,
{
    let mut ocsp = Ocsp::with_capacity(plant.components().len());
    for (component, next) in plant.components().iter().zip(costs) {
        let options = next.into_iter().filter(|(_, cost)| cost.is_finite());
        if ocsp.decide(component.mode_var(), options).is_err() {
            unreachable!("each component decides once, with finite costs");
        }
    }
    for literal in observation.literals() {
        ocsp.assume(literal);
    }
    ocsp
}

/// ConsistentState_TCCA (Figure 6-7): a next state reachable by enabled transitions whose modes'
/// constraints are consistent with `observation`. Figure 6-7 chooses non-deterministically; this
/// returns the most probable such state (OPSAT), or `None` when no choice of transitions is
/// consistent with the observation.
pub fn consistent_state(
    plant: &Plant,
    theory: &mut Theory,
    state: &SystemState,
    commands: &Commands,
    observation: &Observation,
    from: f64,
    to: f64,
) -> Result<Option<SystemState>, StepError> {
    check_inputs(plant, commands, observation)?;
    let choices = transition_choices(plant, theory, state, commands, from, to)?;
    let costs = choices
        .iter()
        .map(|d| d.iter().map(|&(value, p)| (value, -p.ln())));
    let ocsp = target_ocsp(plant, costs, observation);
    let best = ocsp.best(theory, 1);
    Ok(best.solutions.into_iter().next().map(|solution| {
        let targets = solution.assignment.into_iter().map(|(_, v)| v).collect();
        successor(state, targets, to)
    }))
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;

    fn state(modes: &[u32], starts: &[Option<f64>]) -> SystemState {
        SystemState::new(modes.iter().map(|&m| ValueId(m)).collect(), starts.to_vec())
    }

    /// Figure 6-6 step 6: a component that changed mode restarts its clock at the step's end,
    /// the others keep theirs; a step that changed no mode is the source itself, shared.
    #[test]
    fn a_successor_restarts_changed_clocks_and_shares_an_unchanged_state() {
        let source = state(&[0, 1, 2], &[Some(1.0), None, Some(3.0)]);
        let stayed = successor(&source, vec![ValueId(0), ValueId(1), ValueId(2)], 5.0);
        assert!(Arc::ptr_eq(&stayed.modes, &source.modes));
        assert!(Arc::ptr_eq(&stayed.clock_starts, &source.clock_starts));
        let moved = successor(&source, vec![ValueId(0), ValueId(4), ValueId(2)], 5.0);
        assert_eq!(&*moved.modes, &[ValueId(0), ValueId(4), ValueId(2)]);
        assert_eq!(&*moved.clock_starts, &[Some(1.0), Some(5.0), Some(3.0)]);
        assert_eq!(
            &*source.clock_starts,
            &[Some(1.0), None, Some(3.0)],
            "source untouched"
        );
    }

    /// Figure 6-6 step 3: the transitions a store of modes and commands enables are those whose
    /// guard it entails — whether the store decides a guard alone ([`StoreValues`]) or the
    /// theory is asked. Checked against the theory asked for every guard, on the breaker tree
    /// of Livingstone 2's benchmark (guards on commands) and the power model (guards on other
    /// components' modes and attributes), over states that vary one or two components and
    /// every value of one command.
    #[test]
    fn the_store_decides_guards_as_the_theory_does() {
        for (name, text) in [
            (
                "l2_breakers_15.ron",
                include_str!("../../models/l2_breakers_15.ron"),
            ),
            ("power.ron", include_str!("../../models/power.ron")),
            (
                "driver_valve.ron",
                include_str!("../../models/driver_valve.ron"),
            ),
        ] {
            let plant = Plant::load(&crate::diagnostic::Source::new(name, text)).expect("loads");
            let mut theory = plant.theory().expect("theory");
            let initial = plant.most_likely_initial();
            let mut states = vec![initial.clone()];
            for (c, component) in plant.components().iter().enumerate() {
                for m in 0..component.modes().len() as u32 {
                    let mut modes = initial.clone();
                    modes[c] = ValueId(m);
                    modes[(c + 1) % initial.len()] = ValueId(m.min(1));
                    states.push(modes);
                }
            }
            let mut commands = vec![Commands::idle(&plant)];
            for control in plant.controls() {
                let size = plant.table().variable(control.var).domain_size() as u32;
                commands.extend((0..size).map(|v| {
                    Commands::new(&plant, &[(control.var, ValueId(v))]).expect("a command")
                }));
            }
            let mut checked = 0;
            for modes in &states {
                for commands in &commands {
                    let Ok(enabled) = enabled_transitions(&plant, &mut theory, modes, commands)
                    else {
                        continue;
                    };
                    let mut store = mode_literals(&plant, modes);
                    store.extend(commands.literals());
                    let consistent = theory.is_consistent(&store);
                    for ((component, &mode), enabled) in
                        plant.components().iter().zip(modes).zip(&enabled)
                    {
                        for &t in component.outgoing(mode) {
                            let guard = &component.transitions()[t].guard;
                            let entailed = *guard == Formula::True
                                || (consistent && theory.entails(&store, guard).expect("asks"));
                            let on = enabled.transitions.contains(&t);
                            assert_eq!(on, entailed, "{name}: {} {t}", component.name());
                            checked += 1;
                        }
                    }
                }
            }
            assert!(checked > 100, "{name}: {checked} guards checked");
        }
    }

    /// The one-pass successor is the successor with its idle clocks forgotten, bit for bit,
    /// and shares the source's clock starts exactly when they are equal: the Mars lander
    /// (timed modes) from states varying one component's mode, every target of every
    /// component, clock starts known, forgotten or at odd times, and the same sources with
    /// their idle clocks forgotten (where most successors share them).
    #[test]
    fn the_one_pass_successor_is_the_successor_with_idle_clocks_forgotten() {
        let text = include_str!("../../models/mars_lander.ron");
        let plant =
            Plant::load(&crate::diagnostic::Source::new("mars_lander.ron", text)).expect("loads");
        let initial = plant.most_likely_initial();
        let n = initial.len();
        let (mut checked, mut shares) = (0, 0);
        for (c, component) in plant.components().iter().enumerate() {
            for m in 0..component.modes().len() as u32 {
                let mut modes = initial.clone();
                modes[c] = ValueId(m);
                let starts = (0..n).map(|i| (i % 3 != 0).then_some(i as f64 * 0.7 - 3.0));
                let odd = SystemState::new(modes.clone(), starts.collect());
                for source in [odd.clone(), odd.forget_idle_clocks(&plant)] {
                    for (d, other) in plant.components().iter().enumerate() {
                        for t in 0..other.modes().len() as u32 {
                            let mut targets = modes.clone();
                            targets[d] = ValueId(t);
                            let fused = successor_forgetting(&plant, &source, &targets, 9.5);
                            let composed =
                                successor(&source, targets, 9.5).forget_idle_clocks(&plant);
                            assert_eq!(fused.modes, composed.modes);
                            let bits = |s: &SystemState| {
                                s.clock_starts
                                    .iter()
                                    .map(|t| t.map(f64::to_bits))
                                    .collect::<Vec<_>>()
                            };
                            assert_eq!(bits(&fused), bits(&composed), "component {c} → {d}");
                            let shared = Arc::ptr_eq(&fused.clock_starts, &source.clock_starts);
                            let changed = fused.modes != source.modes;
                            if changed {
                                assert_eq!(shared, bits(&fused) == bits(&source), "{c} → {d}");
                                shares += usize::from(shared);
                            }
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 1000, "{checked} successors checked");
        assert!(
            shares > 100,
            "{shares} successors share their source's clock starts"
        );
    }

    /// Equality compares modes and clock starts bit for bit whether or not the vectors are
    /// shared: the pointer comparison is only a shortcut.
    #[test]
    fn states_are_equal_by_value_shared_or_not() {
        let a = state(&[0, 1], &[Some(1.0), None]);
        assert_eq!(a, a.clone());
        assert_eq!(a, state(&[0, 1], &[Some(1.0), None]));
        assert_ne!(a, state(&[0, 2], &[Some(1.0), None]));
        assert_ne!(a, state(&[0, 1], &[Some(1.0), Some(0.0)]));
        assert_ne!(a, state(&[0, 1], &[Some(1.0 + f64::EPSILON), None]));
        assert_ne!(a, state(&[0], &[Some(1.0)]));
    }
}
