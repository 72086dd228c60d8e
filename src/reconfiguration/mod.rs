//! Mode reconfiguration (DESIGN.md §9; thesis §4.3.2, §6.3): choosing the commands that move the
//! plant to a state achieving the configuration goal, in two parts, as in Burton and Titan:
//!
//! - **Goal interpretation** ([`Reconfiguration::interpret`], §6.3.1): the maximum-reward state
//!   reachable from the current one that is consistent with the model and entails the goal — an
//!   OCSP over each component's reachable modes, solved by OPSAT on the plant's [`Theory`]. No
//!   solution is a [`GoalFailed`] whose reason names the goals, components and modes in the
//!   conflict.
//! - **Reactive planning** ([`Reconfiguration::next_action`], §6.3.2–§6.3.3): each cycle, the
//!   first control action toward that goal state ([`Action`]: a command, Idle while a timed
//!   transition is awaited, achieved, or failure), read off per-component **concurrent
//!   policies** compiled offline over the **causal graph** of components.
//!
//! Compilation ([`Reconfiguration::compile`]) does everything that needs no current state:
//! - the causal graph ([`CausalGraph`], `causal.rs`): which components' modes each component's
//!   guards depend on, strongly connected components collapsed into units;
//! - per transition the planner may use, its [`Requirement`] (`requirement.rs`): the upstream
//!   modes and the control assignment that make its guard hold, found by entailment on the
//!   plant's theory — the engine's `engine.cmd = standby` needs `PDE = on` and `PDE.cmd =
//!   engine-standby`;
//! - per component, its [`Reachability`] (reversible regions, irreversible frontiers) and its
//!   [`ConcurrentPolicy`] (`policy.rs`): for each (current, target) mode the next step.
//!
//! Goal interpretation adds what depends on the current state (`feasible.rs`): which modes the
//! planner can really reach and hold given what the components upstream can reach, so that it
//! never proposes a state the planner cannot achieve. [`Reconfiguration::simulate_nominal`] runs
//! the planner against nominal transitions (`kairos plan`).
//!
//! When the goal is unreachable from ŝ, [`Ambiguity`] (`hypotheses.rs`) looks
//! at the other plant states mode estimation tracks and returns the planner's next command from
//! the most probable one that can serve the goal, a bounded number of times per goal.

mod causal;
mod display;
mod feasible;
mod goal;
mod hypotheses;
mod planner;
mod policy;
mod reachability;
mod requirement;
mod simulate;
#[cfg(test)]
mod testing;

pub use causal::CausalGraph;
pub use goal::{FailureCause, GoalFailed, GoalState, HOLD_COST, MOVE_COST};
pub use hypotheses::{Ambiguity, AmbiguityOptions, Hypothesis, Retry, Tried, Unserved};
pub use planner::{Action, Command, PlanFailure, Progress, Wait};
pub use policy::{ConcurrentPolicy, PolicyEntry, PolicyStep};
pub use reachability::Reachability;
pub use requirement::{Condition, Requirement, Unplannable};
pub use simulate::{Move, NominalRun, PlanOutcome, PlanStep};

use crate::logic::{Formula, ValueId};
use crate::opsat::{Theory, TheoryError};
use crate::plant::{ComponentId, ModeKind, Plant, StepError};
use causal::{Dependencies, Influence};
use requirement::GuardCompiler;

/// Everything mode reconfiguration compiles from a plant model, and its two online queries.
#[derive(Debug, Clone)]
pub struct Reconfiguration {
    plant: Plant,
    causal: CausalGraph,
    policies: Vec<ConcurrentPolicy>,
    /// Components upstream first (the causal units in topological order).
    upstream_first: Vec<ComponentId>,
    /// What each transition's guard depends on (upstream modes and controls), by component and
    /// transition index: while the planner waits on a timed transition it commands only what
    /// cannot touch the awaited transition's guard.
    guards: Vec<Vec<Dependencies>>,
    /// The plant's *resting* condition: no component is in a mode that a nominal transition
    /// leaves by itself, given the other components' modes and every control idle (see
    /// [`Reconfiguration::resting`]); `None` when no transition depends on other components.
    resting: Option<Formula>,
}

/// See [`Reconfiguration::resting`].
fn resting_condition(plant: &Plant) -> Option<Formula> {
    let idle = |atom: &crate::logic::Atom| match *atom {
        crate::logic::Atom::Is(x, v) => plant
            .controls()
            .iter()
            .find(|c| c.var == x)
            .map(|c| c.idle == v),
        _ => None,
    };
    let mut parts = Vec::new();
    for (_, component) in plant.component_ids() {
        for m in 0..component.modes().len() as u32 {
            let source = ValueId(m);
            if component.mode(source).kind == ModeKind::Fault {
                continue;
            }
            for &t in component.outgoing(source) {
                let transition = &component.transitions()[t];
                if component.mode(transition.target).kind == ModeKind::Fault {
                    continue;
                }
                let guard = transition.guard.ground(&mut |atom| idle(atom));
                if matches!(guard, Formula::True | Formula::False) {
                    continue;
                }
                let at = Formula::is(component.mode_var(), source);
                parts.push(Formula::Implies(Box::new(at), Box::new(guard.negate())));
            }
        }
    }
    (!parts.is_empty()).then(|| Formula::all(parts))
}

impl Reconfiguration {
    /// Compiles the causal graph, the requirements of every transition the planner may use and
    /// every component's concurrent policy. Uses a temporary theory of its own; errors only if
    /// a guard holds a clock or confidence atom (which plant models cannot express).
    pub fn compile(plant: &Plant) -> Result<Reconfiguration, TheoryError> {
        let influence = Influence::new(plant);
        let upstream: Vec<Vec<ComponentId>> = plant
            .component_ids()
            .map(|(id, component)| {
                let mut ups = Vec::new();
                for transition in component.transitions() {
                    if component.mode(transition.target).kind == ModeKind::Nominal {
                        let vars = transition.guard.variables();
                        ups.extend(influence.dependencies(plant, id, &vars).modes);
                    }
                }
                ups.sort_unstable();
                ups.dedup();
                ups
            })
            .collect();
        let causal = CausalGraph::new(&upstream);
        let guards = plant
            .component_ids()
            .map(|(id, component)| {
                component
                    .transitions()
                    .iter()
                    .map(|t| influence.dependencies(plant, id, &t.guard.variables()))
                    .collect()
            })
            .collect();
        let mut compiler = GuardCompiler::new(plant, &influence)?;
        let mut policies = plant
            .component_ids()
            .map(|(id, _)| ConcurrentPolicy::compile(plant, id, &mut compiler))
            .collect::<Result<Vec<_>, _>>()?;
        let mut rank = vec![0; plant.components().len()];
        for (position, c) in causal.downstream_first().iter().enumerate() {
            rank[c.index()] = position;
        }
        for policy in &mut policies {
            policy.order_sub_goals(&rank);
        }
        let upstream_first = causal.units().iter().flatten().copied().collect();
        Ok(Reconfiguration {
            plant: plant.clone(),
            causal,
            policies,
            upstream_first,
            guards,
            resting: resting_condition(plant),
        })
    }

    /// The condition goal interpretation puts on a goal state so that the plant stays in it
    /// (DESIGN.md §9, goal-faithful commands): for every nominal transition whose guard, with
    /// every control idle, depends on the modes of components (a payload that is unpowered
    /// once its supply goes, a temperature that warms while a heater is on), `component = its
    /// source mode ⇒ not guard`. A goal state that breaks it is one the plant leaves by itself:
    /// the planner would restore it, the plant leave it again, and the two would take turns for
    /// ever. Transitions that need nothing (transient modes, timed exits) are goal
    /// interpretation's domain rule instead.
    pub fn resting(&self) -> Option<&Formula> {
        self.resting.as_ref()
    }

    /// The plant the policies were compiled from.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The causal graph of the components.
    pub fn causal_graph(&self) -> &CausalGraph {
        &self.causal
    }

    /// Every component's concurrent policy, by [`ComponentId`].
    pub fn policies(&self) -> &[ConcurrentPolicy] {
        &self.policies
    }

    /// One component's concurrent policy.
    pub fn policy(&self, c: ComponentId) -> &ConcurrentPolicy {
        &self.policies[c.index()]
    }

    /// What the guard of transition `transition` of `c` depends on.
    pub(crate) fn guard_dependencies(&self, c: ComponentId, transition: usize) -> &Dependencies {
        &self.guards[c.index()][transition]
    }

    /// Components upstream first.
    pub(crate) fn upstream_first(&self) -> &[ComponentId] {
        &self.upstream_first
    }

    /// Goal interpretation (§6.3.1): the state reachable from `current` (a mode per component:
    /// the estimate ŝ) that is consistent with the model, entails `goal`, changes no component
    /// the goal does not name unless it must, and has the maximum reward among those.
    /// `theory` is the plant's own ([`Plant::theory`]); GI adds definitions to it. The goal must
    /// be grounded (no clock or confidence atoms). Call it when the goal or the estimate changes.
    pub fn interpret(
        &self,
        theory: &mut Theory,
        current: &[ValueId],
        goal: &Formula,
    ) -> Result<GoalState, GoalFailed> {
        goal::interpret(self, theory, current, goal, current)
    }

    /// [`Reconfiguration::interpret`], keeping the components the goal does not name in the
    /// modes of `keep` (the configuration the plant is meant to be in — the previous goal state)
    /// rather than in their current modes: a helper switched on to serve an earlier goal (the
    /// PDE) is then still returned to its kept mode.
    pub fn interpret_keeping(
        &self,
        theory: &mut Theory,
        current: &[ValueId],
        goal: &Formula,
        keep: &[ValueId],
    ) -> Result<GoalState, GoalFailed> {
        goal::interpret(self, theory, current, goal, keep)
    }

    /// The intended configuration to keep once the plant is in `current`: `goal` with every
    /// *transient* mode the goal named (one the component leaves by a transition that needs no
    /// command, §6.1.2: a picture being taken) that the component has reached replaced by the
    /// mode it leaves it for by itself. A goal on a transient mode is achieved once, not held:
    /// kept as it is, the planner would command the picture again as soon as the camera
    /// returned to idle, and keep doing so once the program has completed. Modes the goal did
    /// not name are not moved on: a component merely kept where it is (the EDL's `entry =
    /// not-initiated`, left by itself at atmospheric entry) is not asked to go anywhere. But
    /// once it has left such a mode for good — for a nominal mode from which the kept one
    /// cannot be reached again (a flag the IUS set, entry initiated, a wing that latched) — the
    /// goal keeps it where it is, rather than asking the planner every cycle for a move no plan
    /// makes. A kept mode lost to a fault stays in the goal (no plan is then the news). When the
    /// model leaves a transient mode for several modes, the goal keeps it (the model does not
    /// say where the component settles).
    pub fn settle(&self, goal: &GoalState, current: &[ValueId]) -> GoalState {
        goal.settled(self, current)
    }

    /// [`Reconfiguration::settle`] in place: for a goal state kept from cycle to cycle, which
    /// is then neither copied nor, when nothing settles, changed.
    pub fn settle_in_place(&self, goal: &mut GoalState, current: &[ValueId]) {
        goal.settle(self, current);
    }

    /// The reactive planner (§6.3.2–§6.3.3): the first action toward `goal` from `current` (a
    /// mode per component). Cheap enough for every cycle: a walk over the components and table
    /// look-ups, no theory.
    pub fn next_action(&self, current: &[ValueId], goal: &GoalState) -> Action {
        planner::next_action(self, current, goal)
    }

    /// The planner's measure of progress from `current` toward `goal`: under nominal
    /// execution it strictly decreases every cycle (see [`Progress`]).
    pub fn progress(&self, current: &[ValueId], goal: &GoalState) -> Progress {
        planner::progress(self, current, goal)
    }

    /// The planner run from `start` against nominal transitions (every command succeeds; a
    /// wait lasts until the awaited transition fires), for at most `max_steps` cycles.
    pub fn simulate_nominal(
        &self,
        theory: &mut Theory,
        start: &[ValueId],
        goal: &GoalState,
        max_steps: usize,
    ) -> Result<NominalRun, StepError> {
        simulate::simulate_nominal(self, theory, start, goal, max_steps)
    }
}
