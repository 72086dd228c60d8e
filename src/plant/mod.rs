//! Plant models: timed concurrent constraint automata (TCCA; thesis §6.1, DESIGN.md §6).
//!
//! A [`Plant`] is a set of [`Component`]s, each a timed constraint automaton: a mode variable
//! named by the component (`engine`) whose values are the component's [`Mode`]s (nominal or
//! fault, each with a behaviour constraint and a reward), attribute variables
//! `component.attribute`, an initial distribution, and probabilistic [`Transition`]s guarded by
//! constraints and possibly timed on the component's clock. Components are coupled by
//! interconnection constraints; some attributes are **controls** (commanded) and some are
//! **observables** (sensed).
//!
//! - [`Plant::load`] reads and validates the RON format (documented in [`file`](mod@self::file)),
//!   with located errors.
//! - [`Plant::theory`] encodes the plant once into the [`Theory`] that estimation, the sequencer
//!   and goal interpretation all query: `component = mode => constraint` for every mode, plus the
//!   interconnections.
//! - A control may declare an acknowledgement observable ([`acknowledgement`]): flight
//!   software's answer to its last command, which estimation takes as evidence that the command
//!   was or was not carried out ([`Commands::acknowledged`], [`Enabled::delivered`]).
//! - [`timing`](TransitionLaw) turns a transition's law into a per-step probability (§6.2).
//! - [`step_tcca`] and [`consistent_state`] are Figures 6-6 and 6-7; [`transition_choices`] is
//!   their common core (enabled transitions and each component's distribution over next modes),
//!   shared with mode estimation.

pub mod acknowledgement;
pub mod file;
pub mod monitor;
mod step;
mod timing;
mod validate;

use std::hash::{Hash, Hasher};
use std::sync::Arc;

pub use acknowledgement::{Acknowledgement, Answer};
pub use step::{
    Commands, Enabled, InputError, Observation, StepError, chosen_successor,
    component_distribution, component_distributions, consistent_state, distribution_steady_at,
    enabled_transitions, step_tcca, successor, successor_forgetting, transition_choices,
};
pub(crate) use step::{mode_literals, target_ocsp};
pub use timing::{BOUND_TOLERANCE, Timing, TransitionLaw, mode_distribution};

use crate::diagnostic::{Source, SourceErrors};
use crate::logic::{Formula, ValueId, VarId, VarTable};
use crate::opsat::{Theory, TheoryError, TheoryOptions};
use monitor::Monitor;

/// A component, by position in [`Plant::components`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ComponentId(pub u32);

impl ComponentId {
    /// Position in the plant's component list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Whether a mode is part of nominal behaviour or a fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModeKind {
    /// Nominal behaviour; transitions into it are nominal transitions.
    Nominal,
    /// A fault; transitions into it are failure transitions.
    Fault,
}

/// One mode of a component.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// The mode's name, which is the mode variable's value (`heating`).
    pub name: String,
    /// Nominal or fault.
    pub kind: ModeKind,
    /// The behaviour while in the mode (`M_j(x_j = v)`), over the plant's variables.
    pub constraint: Formula,
    /// The reward of being in the mode (`R_j(x_j = v)`; §6.1.3).
    pub reward: f64,
}

impl Mode {
    /// True for a fault mode whose behaviour is unconstrained (`failed`, `unknown`): it explains
    /// any observation, which makes it the estimator's fallback (DESIGN.md §8).
    pub fn is_unconstrained_fault(&self) -> bool {
        self.kind == ModeKind::Fault && self.constraint == Formula::True
    }
}

/// Where a transition leaves from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TransitionSource {
    /// One mode.
    Mode(ValueId),
    /// `"*"`: every nominal mode other than the target.
    AnyNominal,
}

/// A transition `⟨source, guard, target⟩` with its probability law (§6.1.2).
#[derive(Debug, Clone, PartialEq)]
pub struct Transition {
    /// The source mode, or every nominal mode.
    pub source: TransitionSource,
    /// The target mode.
    pub target: ValueId,
    /// The guard: enabled when the constraint store and the commands entail it.
    pub guard: Formula,
    /// How likely it is to fire in a step when enabled.
    pub law: TransitionLaw,
}

/// A component: one timed constraint automaton.
#[derive(Debug, Clone, PartialEq)]
pub struct Component {
    name: String,
    mode_var: VarId,
    attributes: Vec<VarId>,
    modes: Vec<Mode>,
    initial: Vec<f64>,
    transitions: Vec<Transition>,
    /// Per mode, the transitions that leave it (`"*"` expanded).
    outgoing: Vec<Vec<usize>>,
    /// Per mode, whether a transition leaving it needs the clock ([`Component::clock_matters`],
    /// asked for every candidate state in estimation, so decided once).
    timed: Vec<bool>,
}

impl Component {
    /// The component's name, which is also its mode variable's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The mode variable.
    pub fn mode_var(&self) -> VarId {
        self.mode_var
    }

    /// The attribute variables (`component.attribute`), in declaration order.
    pub fn attributes(&self) -> &[VarId] {
        &self.attributes
    }

    /// The modes; a mode's position is its value in the mode variable's domain.
    pub fn modes(&self) -> &[Mode] {
        &self.modes
    }

    /// One mode.
    pub fn mode(&self, mode: ValueId) -> &Mode {
        &self.modes[mode.index()]
    }

    /// The mode with this name.
    pub fn mode_named(&self, name: &str) -> Option<ValueId> {
        self.modes
            .iter()
            .position(|m| m.name == name)
            .map(|i| ValueId(i as u32))
    }

    /// `P_Θ`: the initial probability of each mode, by mode value.
    pub fn initial(&self) -> &[f64] {
        &self.initial
    }

    /// The transitions as declared (a `"*"` source stays one transition).
    pub fn transitions(&self) -> &[Transition] {
        &self.transitions
    }

    /// The transitions leaving `mode`, by index into [`Component::transitions`], with `"*"`
    /// expanded (none for a value that is not a mode of this component).
    pub fn outgoing(&self, mode: ValueId) -> &[usize] {
        self.outgoing.get(mode.index()).map_or(&[], Vec::as_slice)
    }

    /// True when some transition out of `mode` depends on the time spent in it. When not, the
    /// component's clock cannot matter until it changes mode (which resets it), so estimation
    /// forgets it and merges states that differ only there (DESIGN.md §8).
    pub fn clock_matters(&self, mode: ValueId) -> bool {
        self.timed.get(mode.index()).copied().unwrap_or(false)
    }
}

/// A control variable and the value it holds in a cycle without a command to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Control {
    /// The attribute variable.
    pub var: VarId,
    /// Its value when not commanded (`no-command`, `none`).
    pub idle: ValueId,
}

/// A validated TCCA plant model.
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    name: String,
    table: VarTable,
    components: Vec<Component>,
    controls: Vec<Control>,
    observables: Vec<VarId>,
    connections: Vec<Formula>,
    /// The monitors of numeric observables.
    monitors: Vec<Monitor>,
    /// The controls' acknowledgement observables.
    acknowledgements: Vec<Acknowledgement>,
    /// What is looked up about the components every step, computed once.
    index: ComponentIndex,
}

/// What estimation asks of the components every step, kept beside them rather than read out
/// of each [`Component`] (the components never change after loading; [`Plant::believing`]
/// changes an initial distribution only).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ComponentIndex {
    /// For each variable of the table, the component whose mode variable it is.
    component_of: Vec<Option<ComponentId>>,
    /// Per component, how many modes it has: checking a state's modes reads this one array
    /// (a belief's states are checked twice a step).
    mode_counts: Vec<usize>,
    /// Per component, its mode variable: shared by every belief of the plant rather than
    /// collected for each.
    mode_vars: Arc<[VarId]>,
}

impl ComponentIndex {
    /// The index of `components`, whose variables are among `variables` many.
    pub(crate) fn new(components: &[Component], variables: usize) -> ComponentIndex {
        let mut component_of = vec![None; variables];
        for (i, component) in components.iter().enumerate() {
            component_of[component.mode_var.index()] = Some(ComponentId(i as u32));
        }
        ComponentIndex {
            component_of,
            mode_counts: components.iter().map(|c| c.modes.len()).collect(),
            mode_vars: components.iter().map(|c| c.mode_var).collect(),
        }
    }
}

impl Plant {
    /// Reads and validates a plant model (the format is documented in [`file`](mod@self::file)).
    /// Every problem found is reported with its location.
    pub fn load(source: &Source) -> Result<Plant, SourceErrors> {
        file::load(source)
    }

    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The plant's variables: each component's mode variable followed by its attributes, in
    /// declaration order.
    pub fn table(&self) -> &VarTable {
        &self.table
    }

    /// The components, in declaration order.
    pub fn components(&self) -> &[Component] {
        &self.components
    }

    /// The model with `component` certainly in `mode` at power-on: its initial distribution
    /// all on that mode (a fault known before the run; a scenario's `believed`).
    pub fn believing(mut self, component: ComponentId, mode: ValueId) -> Plant {
        if let Some(c) = self.components.get_mut(component.index()) {
            let initial = &mut c.initial;
            initial.iter_mut().for_each(|p| *p = 0.0);
            if let Some(p) = initial.get_mut(mode.index()) {
                *p = 1.0;
            }
        }
        self
    }

    /// Each component's most likely initial mode (the first of equals): the state a schedule
    /// made before the first estimate starts from.
    pub fn most_likely_initial(&self) -> Vec<ValueId> {
        self.components
            .iter()
            .map(|c| {
                let best = c
                    .initial()
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::MIN),
                        |best, (i, p)| if *p > best.1 { (i, *p) } else { best },
                    );
                ValueId(best.0 as u32)
            })
            .collect()
    }

    /// One component.
    pub fn component(&self, id: ComponentId) -> &Component {
        &self.components[id.index()]
    }

    /// The component with this name.
    pub fn component_named(&self, name: &str) -> Option<ComponentId> {
        self.components
            .iter()
            .position(|c| c.name == name)
            .map(|i| ComponentId(i as u32))
    }

    /// The component whose mode variable `var` is (`None` for attributes).
    pub fn component_of(&self, var: VarId) -> Option<ComponentId> {
        self.index.component_of.get(var.index()).copied().flatten()
    }

    /// Per component, how many modes it has.
    pub(crate) fn mode_counts(&self) -> &[usize] {
        &self.index.mode_counts
    }

    /// Per component, its mode variable (shared).
    pub(crate) fn mode_vars(&self) -> &Arc<[VarId]> {
        &self.index.mode_vars
    }

    /// Component ids with their components.
    pub fn component_ids(&self) -> impl ExactSizeIterator<Item = (ComponentId, &Component)> {
        self.components
            .iter()
            .enumerate()
            .map(|(i, c)| (ComponentId(i as u32), c))
    }

    /// The control variables (`Π^c`) and their idle values.
    pub fn controls(&self) -> &[Control] {
        &self.controls
    }

    /// The observable variables (`Π^o`).
    pub fn observables(&self) -> &[VarId] {
        &self.observables
    }

    /// The monitors of the numeric observables, in declaration order
    /// ([`monitor`]).
    pub fn monitors(&self) -> &[Monitor] {
        &self.monitors
    }

    /// The position in [`Plant::monitors`] of the monitor of `var`, if it is numeric.
    pub fn monitor_of(&self, var: VarId) -> Option<usize> {
        self.monitors.iter().position(|m| m.observable == var)
    }

    /// The controls' acknowledgement observables ([`acknowledgement`]), in declaration order.
    pub fn acknowledgements(&self) -> &[Acknowledgement] {
        &self.acknowledgements
    }

    /// The acknowledgement `var` reports, if it is an acknowledgement observable.
    pub fn acknowledgement_of(&self, var: VarId) -> Option<&Acknowledgement> {
        self.acknowledgements.iter().find(|a| a.observable == var)
    }

    /// True for the variables a plant reports: its observables and its acknowledgement
    /// observables.
    pub fn is_reported(&self, var: VarId) -> bool {
        self.observables.contains(&var) || self.acknowledgement_of(var).is_some()
    }

    /// The interconnection constraints (`Q`).
    pub fn connections(&self) -> &[Formula] {
        &self.connections
    }

    /// Every constraint of the model: `component = mode => M(mode)` for each mode with a
    /// constraint, then the interconnections. This is `C_M` with the modes left open (the mode
    /// variables decide which behaviour holds).
    pub fn constraints(&self) -> Vec<Formula> {
        let mut out = Vec::new();
        for component in &self.components {
            for (i, mode) in component.modes.iter().enumerate() {
                if mode.constraint != Formula::True {
                    out.push(Formula::Implies(
                        Box::new(Formula::is(component.mode_var, ValueId(i as u32))),
                        Box::new(mode.constraint.clone()),
                    ));
                }
            }
        }
        out.extend(self.connections.iter().cloned());
        out
    }

    /// Encodes the plant into a fresh [`Theory`] (once per plant; the caller owns it and passes
    /// it to estimation, the sequencer and goal interpretation).
    pub fn theory(&self) -> Result<Theory, TheoryError> {
        self.theory_with(TheoryOptions::default())
    }

    /// [`Plant::theory`] with chosen options (conflict minimisation; BENCHMARKS.md
    /// measures their effect on estimation). The acknowledgement observables are left out of the
    /// solver until a question names one ([`Theory::with_unencoded`]): no constraint mentions
    /// them and estimation never assumes them, so encoded they would only add decisions to
    /// every satisfiable question (about 0.6 % of the EDL's instructions at a 1 s cycle).
    pub fn theory_with(&self, options: TheoryOptions) -> Result<Theory, TheoryError> {
        let acknowledgements: Vec<VarId> =
            self.acknowledgements.iter().map(|a| a.observable).collect();
        Theory::with_unencoded(
            self.table.clone(),
            &self.constraints(),
            options,
            &acknowledgements,
        )
    }
}

/// A system state (§6.2.2): every component's mode and the absolute time its clock started
/// (when it entered that mode). A clock start is `None` when the component's clock cannot matter
/// in its current mode ([`Component::clock_matters`]): estimation forgets it so that states
/// differing only there merge.
///
/// Both vectors are shared (`Arc<[_]>`): estimation copies states far more often than it makes
/// new ones — into the merge, into each belief, into the replay's record, into the plant
/// estimates — and a quiet step's states are the last step's own (a component that stays keeps
/// its clock), so a copy is a reference count and most comparisons are one pointer
/// comparison. A new state is built from vectors ([`SystemState::new`]) or with
/// `Arc::make_mut`.
#[derive(Debug, Clone)]
pub struct SystemState {
    /// Mode per component, by [`ComponentId`].
    pub modes: Arc<[ValueId]>,
    /// Clock start time per component, seconds, or `None` when it does not matter.
    pub clock_starts: Arc<[Option<f64>]>,
}

impl SystemState {
    /// The state of these modes and clock starts.
    pub fn new(modes: Vec<ValueId>, clock_starts: Vec<Option<f64>>) -> SystemState {
        SystemState {
            modes: modes.into(),
            clock_starts: clock_starts.into(),
        }
    }

    /// A state where every component entered its mode at `time`, with the clocks that do not
    /// matter forgotten.
    pub fn entered_at(plant: &Plant, modes: Vec<ValueId>, time: f64) -> SystemState {
        let clock_starts = vec![Some(time); modes.len()];
        SystemState::new(modes, clock_starts).forget_idle_clocks(plant)
    }

    /// Forgets the clocks that cannot matter in the components' current modes. A state whose
    /// idle clocks are already forgotten is returned as it is (still shared).
    pub fn forget_idle_clocks(mut self, plant: &Plant) -> SystemState {
        let idle = |(component, mode): (&Component, &ValueId)| !component.clock_matters(*mode);
        let remembered = (plant.components.iter().zip(self.modes.iter()))
            .zip(self.clock_starts.iter())
            .any(|(cm, start)| start.is_some() && idle(cm));
        if remembered {
            let modes = plant.components.iter().zip(self.modes.iter());
            for (cm, start) in modes.zip(Arc::make_mut(&mut self.clock_starts)) {
                if idle(cm) {
                    *start = None;
                }
            }
        }
        self
    }

    /// Component `component`'s clock at `time` (time since it entered its mode), if known.
    pub fn clock(&self, component: ComponentId, time: f64) -> Option<f64> {
        self.clock_starts
            .get(component.index())
            .copied()
            .flatten()
            .map(|start| time - start)
    }

    /// Checks that the state fits the plant: one mode and one clock start per component, each
    /// mode a mode of its component. States built by this module and by estimation always fit;
    /// the step functions refuse one that does not ([`StepError::Input`]).
    pub fn check(&self, plant: &Plant) -> Result<(), InputError> {
        if self.clock_starts.len() != self.modes.len() {
            return Err(InputError::StateShape);
        }
        step::check_modes(plant, &self.modes)
    }

    /// `component = mode, ...` with names.
    pub fn describe(&self, plant: &Plant) -> String {
        describe_modes(plant, &self.modes)
    }
}

/// Equality on modes and clock starts, clock starts compared bit for bit (they are times the
/// caller gave, copied, never computed). The modes are compared in one pass without an early
/// exit, which the compiler turns into a few wide comparisons: estimation compares states
/// that are nearly always equal (a merged state found again, a source met last step), so
/// stopping at the first difference saves nothing there.
impl PartialEq for SystemState {
    fn eq(&self, other: &Self) -> bool {
        let same_modes = || {
            self.modes.len() == other.modes.len()
                && (self.modes.iter().zip(other.modes.iter()))
                    .fold(true, |same, (a, b)| same & (a.0 == b.0))
        };
        let same_starts = || {
            self.clock_starts.len() == other.clock_starts.len()
                && (self.clock_starts.iter().zip(other.clock_starts.iter()))
                    .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits))
        };
        (Arc::ptr_eq(&self.modes, &other.modes) || same_modes())
            && (Arc::ptr_eq(&self.clock_starts, &other.clock_starts) || same_starts())
    }
}

impl Eq for SystemState {}

impl Hash for SystemState {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.modes.hash(state);
        for start in self.clock_starts.iter() {
            start.map(f64::to_bits).hash(state);
        }
    }
}

/// `component = mode, ...` for a mode vector, with names.
pub fn describe_modes(plant: &Plant, modes: &[ValueId]) -> String {
    plant
        .components
        .iter()
        .zip(modes)
        .map(|(c, m)| {
            let mode = c
                .modes
                .get(m.index())
                .map_or("?", |mode| mode.name.as_str());
            format!("{} = {mode}", c.name)
        })
        .collect::<Vec<_>>()
        .join(", ")
}
