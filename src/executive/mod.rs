//! The executive: the cycle loop that runs a timed model-based program against a plant
//! (DESIGN.md §3, §10; thesis §4.4, §7.1, Figure 7-1). It is the only module that knows all the
//! others.
//!
//! One call to [`Executive::step`] at time t(i) with the observation o(i) runs one cycle:
//! 1. the observation is checked against the plant (unknown names and values become events);
//! 2. **mode estimation** (TimedME) advances the belief from t(i−1) with the command μ(i−1) and
//!    o(i); ŝ(i) is its most likely plant state;
//! 3. the **sequencer** finishes the previous cycle with ŝ(i) (Figure 5-3 steps 7–10: goals
//!    achieved, transitions taken) and begins this one (steps 1–4: clocks, maintenance, the
//!    configuration goal g(i));
//! 4. **mode reconfiguration** interprets g(i) into a goal state (cached while the goal and ŝ
//!    stay the same) and the reactive planner returns the first action toward it: μ(i).
//!
//! The goal state becomes the plant's *intended configuration*. Goal interpretation keeps the
//! components a new goal does not name in their intended modes (`interpret_keeping`), and when
//! no goal is asserted — between goals, or after the program completes — the planner still
//! works toward the intended configuration, so helpers switched on for a goal (the PDE) are
//! returned to their intended modes. The executive never changes what no goal asked for.
//!
//! The caller sends μ(i) to the plant and calls `step` again at t(i+1) with o(i+1). This is the
//! cycle of DESIGN.md §3 started at its estimation step, so that each call consumes the evidence
//! of the previous command and returns the next one. Everything is a value: no globals, no
//! threads, no panics on any input; given the same inputs the executive makes the same decisions.
//! [`adapters`] has the traits and the loop runner for embedding it in a flight loop.

pub mod adapters;
mod builder;
mod control;
mod delegation;
mod describe;
mod events;
mod evidence;
mod faithful;
mod fingerprint;
pub mod fprime;
mod load;
mod mission;
mod monitoring;
mod named;
mod observations;
mod oracle;
mod reconfigure;
mod submit;
mod timeline;

use std::collections::BTreeSet;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Goals submitted to a running mission ([`Executive::submit`]); defined with the goal network.
pub use crate::goalnet::{Submission, SubmitError, SubmittedConstraint, SubmittedGoal};
pub use builder::{BuildError, CHATTER_CYCLES, ExecutiveBuilder, ExecutiveOptions};
pub use control::ControlProgram;
pub use describe::{NamedEvent, describe_event};
pub use events::{Event, EventKind, Served};
pub use fingerprint::PROBABILITY_RESOLUTION;
pub use load::LoadError;
pub use mission::ScheduledMission;
pub use named::NamedEstimate;
pub use observations::{NamedValue, Value};
pub use timeline::{Interval, IssuedCommand, ObservationChange, Retention, Timeline, Timelines};

use crate::diagnostic::Source;
use crate::estimation::{
    Belief, EstimationError, EstimationEvent, ModeEstimator, PlantEstimate, PlantGrouping, TimedMe,
};
use crate::logic::{Formula, ValueId, VarId};
use crate::opsat::{Budget, Theory};
use crate::plant::{Commands, ComponentId, ModeKind, Plant};
use crate::reconfiguration::{Action, Ambiguity, GoalFailed, GoalState, Reconfiguration};
use crate::sequencer::{self, ConfigurationGoal, LocationId, Sense, SequencerError, Thca};
use control::Program;
use faithful::Faithful;
use monitoring::Monitoring;
use observations::{LastObservation, Report};
use oracle::{AnswerCache, CachedOracle, VersionedEstimate};
use reconfigure::Purpose;

/// A diagnosis names at most this many other candidate modes of the component.
const NEXT_DIAGNOSES: usize = 3;

/// A candidate mode below this marginal is not named next to a diagnosis (it would show as
/// p 0.00).
const NEXT_DIAGNOSIS_MIN: f64 = 0.005;

/// Why a cycle could not run at all (bad data is reported as events instead).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// Times must be finite and increase from cycle to cycle.
    #[error("time {now} s is not after the previous cycle's {previous} s")]
    TimeNotAfter {
        /// The previous cycle's time (−∞ before the first).
        previous: f64,
        /// The time given.
        now: f64,
    },
    /// Mode estimation refused its inputs.
    #[error("mode estimation failed: {0}")]
    Estimation(#[from] EstimationError),
    /// The sequencer refused a call.
    #[error("the sequencer failed: {0}")]
    Sequencer(#[from] SequencerError),
}

/// Wall time spent in each part of a cycle (for `kairos bench` and deadline reports).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PhaseTimes {
    /// Checking the observation and mode estimation.
    pub estimation: Duration,
    /// Both halves of the sequencer's step.
    pub sequencer: Duration,
    /// Goal interpretation and reactive planning.
    pub reconfiguration: Duration,
    /// Goals submitted to the mission since the previous cycle ([`Executive::submit`]):
    /// rescheduling the network is the cycle's work too, done between its steps.
    pub submission: Duration,
    /// The whole cycle, including bookkeeping and the submissions before it: what a deadline
    /// is held to.
    pub total: Duration,
}

/// What one cycle produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Cycle number, from 0.
    pub cycle: u64,
    /// The cycle's time t(i).
    pub time: f64,
    /// μ(i): the control assignments to send (non-idle values only; empty means idle).
    pub command: Vec<(VarId, ValueId)>,
    /// The configuration goal g(i); `None` once the program has completed.
    pub goal: Option<ConfigurationGoal>,
    /// The intended configuration the planner works toward: the goal state goal interpretation
    /// chose for g(i), or the previous one when g(i) asserts nothing.
    pub goal_state: Option<GoalState>,
    /// The reactive planner's decision; `None` when there is nothing to pursue (no intended
    /// configuration yet, or goal interpretation failed).
    pub action: Option<Action>,
    /// ŝ(i): the most likely mode of each component, by component index (shared with the
    /// executive's own copy).
    pub most_likely: Arc<[ValueId]>,
    /// The plant states of the belief with their probabilities, most likely first.
    pub estimates: Vec<PlantEstimate>,
    /// How far the belief may be from the exact update's ([`Belief::distance_bound`]).
    pub distance_bound: f64,
    /// What each monitor of a numeric observable made of its readings: the value estimation
    /// read (`None`: absent). Empty for a plant without monitors.
    pub monitored: Vec<(VarId, Option<ValueId>)>,
    /// The marked program locations after the sequencer's step.
    pub marking: Vec<LocationId>,
    /// What happened.
    pub events: Vec<Event>,
    /// True once the program has completed.
    pub completed: bool,
    /// Where the time went.
    pub times: PhaseTimes,
}

impl Step {
    /// True when the program has completed and the plant is in its intended configuration
    /// (nothing left to command): a loop may stop here.
    pub fn is_settled(&self) -> bool {
        self.completed
            && !matches!(
                self.action,
                Some(Action::Command(_)) | Some(Action::Idle(_))
            )
    }
}

/// Reports the observables missing from `observed` when they are not the ones last reported.
fn report_missing(
    plant: &Plant,
    reported: &mut Reported,
    observed: &[(VarId, ValueId)],
    log: &mut EventLog,
) {
    let missing: Vec<VarId> = plant
        .observables()
        .iter()
        .copied()
        .filter(|var| !observed.iter().any(|(x, _)| x == var))
        .collect();
    if missing != reported.missing {
        let table = plant.table();
        let variables = missing
            .iter()
            .map(|&v| table.variable(v).name().to_string())
            .collect();
        log.push(EventKind::ObservationsMissing { variables });
        reported.missing = missing;
    }
}

/// Goal interpretation's last answer, kept while the goal, ŝ and the kept configuration are
/// unchanged.
#[derive(Clone)]
struct Interpretation {
    goal: Formula,
    modes: Vec<ValueId>,
    keep: Vec<ValueId>,
    result: Result<GoalState, GoalFailed>,
}

/// What has been reported already, so repeated conditions are reported once.
#[derive(Clone, Default)]
struct Reported {
    goal_locations: Vec<LocationId>,
    /// Every location whose goal has been asserted in the run: one asserting again, after a
    /// cycle without it (the sequencer re-entered it, after a preemption or in a loop), is
    /// reported re-asserted.
    asserted: BTreeSet<LocationId>,
    /// The locations whose goal the sequencer found achieved in the previous cycle: a
    /// maintained goal (`always`) is re-asserted and found achieved every cycle it holds, and is
    /// reported achieved again only after a cycle in which it was not.
    achieved: Vec<LocationId>,
    conflicts: Vec<(LocationId, LocationId)>,
    goal_failure: Option<String>,
    plan_failure: Option<String>,
    awaited: Option<(ComponentId, ValueId, ValueId)>,
    missing: Vec<VarId>,
}

/// A timed model-based executive: a linked program, a plant model, and the state of both. A
/// clone is an independent executive in the same state (explicit-state exploration branches
/// with it); [`Executive::fingerprint`] hashes the part of the state that decides the future.
///
/// # Examples
///
/// Open the valve of thesis §6.1 (`models/driver_valve.ron`): the executive turns the driver
/// on, sends `open` through it, sees the flow, and turns the driver off again. The loop is the
/// embedder's own; observations go in and commands come out by name.
///
/// ```
/// use std::path::Path;
/// use kairos::executive::{Executive, NamedValue};
///
/// let root = Path::new(env!("CARGO_MANIFEST_DIR"));
/// let mut executive = Executive::load(
///     &root.join("models/driver_valve.ron"),
///     &root.join("programs/valve_open.rmpl"),
/// )?
/// .build()?;
/// let (mut driver_on, mut valve_open) = (false, false);
/// let mut sent = Vec::new();
/// for cycle in 0..50 {
///     let flow_out = if valve_open { "nominal" } else { "zero" };
///     let observed = [
///         NamedValue::new("valve.flow_in", "nominal"),
///         NamedValue::new("valve.flow_out", flow_out),
///     ];
///     let step = executive.step(f64::from(cycle) * 0.1, &observed)?;
///     for command in step.commands_named(executive.plant()) {
///         match command.value.symbol().unwrap_or_default() {
///             "on" => driver_on = true,
///             "off" => driver_on = false,
///             "open" if driver_on => valve_open = true,
///             _ => {}
///         }
///         sent.push(command.to_string());
///     }
///     if step.is_settled() {
///         assert_eq!(step.mode_of(executive.plant(), "valve"), Some("open"));
///         break;
///     }
/// }
/// assert_eq!(sent, ["driver.dcmd_in = on", "driver.dcmd_in = open", "driver.dcmd_in = off"]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// `examples/embed.rs` is the same loop with the device written out; [`adapters`] has traits
/// and a runner for a loop driven by a clock.
#[derive(Clone)]
pub struct Executive {
    plant: Plant,
    theory: Theory,
    reconfiguration: Reconfiguration,
    estimator: TimedMe,
    control: ControlProgram,
    /// The program's or mission's text, when the builder was given it (shared: exploration
    /// clones executives by the thousand).
    source: Option<Arc<Source>>,
    options: ExecutiveOptions,
    belief: Option<Belief>,
    /// ŝ of `belief`, computed once per update: the cycle reads it four times (mode changes,
    /// the sequencer's view, reconfiguration, the step's result).
    most_likely: Arc<[ValueId]>,
    /// The plant states of `belief`, grouped once per update and handed to the step's result.
    estimates: Vec<PlantEstimate>,
    /// How the last belief's states grouped into plant states (kept: a quiet cycle's group
    /// the same way).
    grouping: PlantGrouping,
    /// Each component's marginal of ŝ's mode, refilled every update (kept for its room).
    marginals: Vec<f64>,
    estimate: VersionedEstimate,
    /// The last report and its checked, typed form ([`LastObservation`]).
    observed: LastObservation,
    /// The monitors of numeric observables, which read the report first.
    monitoring: Monitoring,
    answers: AnswerCache,
    interpretation: Option<Interpretation>,
    /// The hypotheses other than ŝ acted on for the current goal.
    ambiguity: Ambiguity,
    intended: Option<GoalState>,
    /// The ŝ `intended` was last settled on (`reconfigure.rs`): while ŝ is the same, settling
    /// it again would change nothing. Set wherever `intended` is written.
    intended_settled_on: Option<Arc<[ValueId]>>,
    /// Helpers to bring back, recent commanded moves, the last contradiction reported
    /// (`faithful.rs`).
    faithful: Faithful,
    reported: Reported,
    confidence_atoms: Vec<(VarId, ValueId)>,
    timelines: Timelines,
    last_command: Commands,
    cycle: u64,
    last_time: Option<f64>,
    /// Wall time spent in [`Executive::submit`] since the last cycle (counted in its times).
    submission_time: Duration,
}

// An executive moves between threads (one call at a time, DESIGN.md §10): an embedding host
// steps it from whichever thread runs its flight loop, and the C ABI's handle is one executive.
// Everything it owns is therefore `Send` — mode estimation's shared caches by `Arc`, the theory
// on batsat with callbacks of its own (`opsat/sat.rs`) — and this fails to compile if a change
// makes it otherwise.
const _: () = {
    const fn assert_send<T: Send>() {}
    assert_send::<Executive>();
};

impl Executive {
    /// Starts building an executive for `program`: an RMPL program's [`Thca`], which must have
    /// been linked against `plant`'s variables (`rmpl::load` with `LinkOptions { plant:
    /// Some(plant.table()), .. }`), or a [`ScheduledMission`] bound to the same plant model.
    pub fn builder(plant: Plant, program: impl Into<ControlProgram>) -> ExecutiveBuilder {
        ExecutiveBuilder {
            plant,
            program: program.into(),
            options: ExecutiveOptions::default(),
            source: None,
        }
    }

    /// The plant model.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The RMPL program's automaton (`None` when the executive runs a mission).
    pub fn program(&self) -> Option<&Thca> {
        self.control.thca()
    }

    /// The text of the program or mission it runs, when it was given one
    /// ([`ExecutiveBuilder::source`]).
    pub fn source(&self) -> Option<&Source> {
        self.source.as_deref()
    }

    /// The control program: the RMPL program or the mission, with its execution state.
    pub fn control(&self) -> &ControlProgram {
        &self.control
    }

    /// The options it runs with.
    pub fn options(&self) -> &ExecutiveOptions {
        &self.options
    }

    /// The current belief (`None` before the first cycle).
    pub fn belief(&self) -> Option<&Belief> {
        self.belief.as_ref()
    }

    /// The time of the last cycle (`None` before the first).
    pub fn last_time(&self) -> Option<f64> {
        self.last_time
    }

    /// The state timelines and the command and observation histories.
    pub fn timelines(&self) -> &Timelines {
        &self.timelines
    }

    /// The compiled reconfiguration (policies, causal graph).
    pub fn reconfiguration(&self) -> &Reconfiguration {
        &self.reconfiguration
    }

    /// True once the program has completed (for a mission: every time point has fired).
    pub fn is_complete(&self) -> bool {
        self.control.is_complete()
    }

    /// Cycles run so far.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Runs one cycle at time `now` with the observations the monitors reported since the last
    /// cycle (see the module documentation). Observations that do not fit the plant are
    /// reported as events and ignored; errors are only for times that do not increase.
    pub fn step(&mut self, now: f64, observed: &[NamedValue]) -> Result<Step, StepError> {
        self.cycle_with(now, Report::Borrowed(observed))
    }

    /// [`Executive::step`] with a shared report. A monitor that hands over the same `Arc` as
    /// last cycle when nothing changed (a simulation's quiet cycles) spares the executive
    /// comparing the report with the last one: the same allocation, kept alive by the
    /// executive, is the same report.
    pub fn step_shared(
        &mut self,
        now: f64,
        observed: &Arc<[NamedValue]>,
    ) -> Result<Step, StepError> {
        self.cycle_with(now, Report::Shared(observed))
    }

    /// One cycle (see [`Executive::step`]).
    fn cycle_with(&mut self, now: f64, observed: Report<'_>) -> Result<Step, StepError> {
        let previous = self.last_time.unwrap_or(f64::NEG_INFINITY);
        if !now.is_finite() || now <= previous {
            return Err(StepError::TimeNotAfter { previous, now });
        }
        let mut log = EventLog {
            cycle: self.cycle,
            time: now,
            events: Vec::new(),
        };
        // One clock reading per phase boundary, each phase ending where the next starts: four
        // readings a cycle, not eight (they were 4 % of the nominal EDL's run time).
        let started = Instant::now();
        if let Some(deadline) = self.options.estimation_deadline {
            self.estimator.set_budget(Budget {
                until: Some(started + deadline.saturating_sub(self.submission_time)),
                ..self.options.estimation_budget
            });
        }
        self.estimate(now, observed, &mut log)?;
        let estimated = Instant::now();
        let goal = self.sequence(now, &mut log)?;
        let sequenced = Instant::now();
        let (goal_state, mut action) = self.reconfigure(goal.as_ref(), &mut log);
        self.keep_faithful(&mut action, goal.as_ref(), &mut log);
        let purpose = Purpose {
            goal: goal.as_ref(),
            intended: goal_state.as_ref(),
        };
        let command = self.issue(action.as_ref(), purpose, &mut log);
        let ended = Instant::now();
        let (estimation, sequencer) = (estimated - started, sequenced - estimated);
        let submission = std::mem::take(&mut self.submission_time);
        let (reconfiguration, total) = (ended - sequenced, ended - started + submission);
        if let Some(deadline) = self.options.cycle_deadline.filter(|&d| total > d) {
            log.push(EventKind::DeadlineOverrun {
                elapsed: total,
                deadline,
            });
        }
        self.last_time = Some(now);
        self.cycle += 1;
        Ok(Step {
            cycle: log.cycle,
            time: now,
            command,
            goal,
            goal_state,
            action,
            most_likely: self.most_likely(),
            estimates: std::mem::take(&mut self.estimates),
            distance_bound: self.belief.as_ref().map_or(0.0, Belief::distance_bound),
            monitored: self.monitoring.outputs().to_vec(),
            marking: self.control.marking(),
            events: log.events,
            completed: self.control.is_complete(),
            times: PhaseTimes {
                estimation,
                sequencer,
                reconfiguration,
                submission,
                total,
            },
        })
    }

    /// ŝ: the most likely mode per component (empty before the first cycle).
    pub fn most_likely(&self) -> Arc<[ValueId]> {
        Arc::clone(&self.most_likely)
    }

    /// Steps 1–2 of the cycle: check the observation, update the belief, report what changed.
    fn estimate(
        &mut self,
        now: f64,
        observed: Report<'_>,
        log: &mut EventLog,
    ) -> Result<(), StepError> {
        let monitored;
        let observed = if self.monitoring.is_empty() {
            observed
        } else {
            let mut events = Vec::new();
            monitored = (self.monitoring).apply(&self.plant, now, observed.values(), &mut events);
            events.into_iter().for_each(|kind| log.push(kind));
            Report::Borrowed(&monitored)
        };
        let (checked, observation, repeated) = self
            .observed
            .check(&self.plant, observed)
            .map_err(EstimationError::from)?;
        checked
            .rejected
            .iter()
            .for_each(|kind| log.push(kind.clone()));
        // Both only note changes of the typed values, which a repeated report cannot have.
        if !repeated {
            report_missing(&self.plant, &mut self.reported, &checked.values, log);
            self.timelines.record_observation(now, &checked.values);
        }
        let update = match &self.belief {
            None => self
                .estimator
                .initial(&self.plant, &mut self.theory, now, observation)?,
            Some(belief) => self.estimator.update(
                &self.plant,
                &mut self.theory,
                belief,
                &self.last_command,
                observation,
                now,
            )?,
        };
        for event in update.events {
            log.push(match event {
                EstimationEvent::InconsistentObservation { fallback } => {
                    EventKind::EstimatorInconsistency { fallback }
                }
                EstimationEvent::SearchCut(cut) => EventKind::SearchCut(cut),
            });
        }
        // ŝ and the plant states are derived here, where the belief changes, and nowhere else
        // (the belief is set only here), so the cached copies always belong to the belief.
        let estimates = self.grouping.plant_states(&update.belief);
        let after = Belief::most_likely_among(&estimates)
            .map(|e| Arc::clone(&e.modes))
            .unwrap_or_else(|| Arc::from([]));
        let before = std::mem::replace(&mut self.most_likely, after.clone());
        self.estimates = estimates;
        let previous = self.belief.replace(update.belief);
        self.report_mode_changes(&before, &after, previous.as_ref(), log);
        self.refresh_estimate(&after, before != after);
        let mut marginals = std::mem::take(&mut self.marginals);
        match &self.belief {
            Some(belief) => self.grouping.marginals(belief, &after, &mut marginals),
            None => marginals.clear(),
        }
        self.timelines.record_states(now, &after, &marginals);
        self.marginals = marginals;
        Ok(())
    }

    /// The belief in `component = mode` (the belief is over this plant's components, in
    /// order, so the component's index names its mode variable: every cycle asks this of each
    /// component, without a variable look-up).
    fn marginal(&self, component: ComponentId, mode: ValueId) -> f64 {
        self.belief
            .as_ref()
            .and_then(|b| b.component_marginal(component.index(), mode))
            .unwrap_or(0.0)
    }

    /// The cycle's mode changes and diagnoses; `previous` is the belief ŝ(i−1) (`before`) came
    /// from, for a diagnosis's evidence.
    fn report_mode_changes(
        &mut self,
        before: &[ValueId],
        after: &[ValueId],
        previous: Option<&Belief>,
        log: &mut EventLog,
    ) {
        // Computed once, and only in a cycle with a diagnosis.
        let mut evidence: Option<Vec<String>> = None;
        for (c, &to) in after.iter().enumerate() {
            let from = before.get(c).copied();
            if from == Some(to) {
                continue;
            }
            let component_id = ComponentId(c as u32);
            let fault = self.plant.component(component_id).mode(to).kind == ModeKind::Fault;
            if fault && evidence.is_none() {
                evidence = Some(self.evidence(before, previous, log.time));
            }
            let component = self.plant.component(component_id);
            let probability = self.marginal(component_id, to);
            let mode = component.mode(to);
            if let Some(from) = from {
                log.push(EventKind::ModeChanged {
                    component: component_id,
                    from: component.mode(from).name.clone(),
                    to: mode.name.clone(),
                    probability,
                });
            }
            if mode.kind == ModeKind::Fault {
                log.push(EventKind::Diagnosis {
                    component: component_id,
                    mode: mode.name.clone(),
                    probability,
                    next: self.next_diagnoses(component_id, to),
                    evidence: evidence.clone().unwrap_or_default(),
                });
            }
        }
    }

    /// The observations ŝ(i−1) (`before`, of the belief `previous`), stepped by the last
    /// command, cannot explain, or in cycle 0 the initial state (`evidence::discrepant`); a
    /// minimal set when they are discrepant only together. An explanation is best effort: were
    /// the theory to refuse the step, the diagnosis goes without evidence rather than the
    /// cycle failing.
    fn evidence(&mut self, before: &[ValueId], previous: Option<&Belief>, now: f64) -> Vec<String> {
        let Some(observation) = self.observed.observation() else {
            return Vec::new();
        };
        evidence::discrepant(
            &self.plant,
            &mut self.theory,
            previous,
            before,
            &self.last_command,
            observation,
            now,
        )
        .unwrap_or_default()
    }

    /// The component's other modes the belief holds, most probable first: the candidates a
    /// diagnosis of `mode` is to be read against. At most
    /// [`NEXT_DIAGNOSES`], each at least [`NEXT_DIAGNOSIS_MIN`] (a log shows two decimals).
    fn next_diagnoses(&self, component: ComponentId, mode: ValueId) -> Vec<(String, f64)> {
        let modes = self.plant.component(component).modes();
        let mut next: Vec<(String, f64)> = (0..modes.len() as u32)
            .map(ValueId)
            .filter(|&m| m != mode)
            .map(|m| (modes[m.index()].name.clone(), self.marginal(component, m)))
            .filter(|&(_, p)| p >= NEXT_DIAGNOSIS_MIN)
            .collect();
        next.sort_by(|a, b| b.1.total_cmp(&a.1));
        next.truncate(NEXT_DIAGNOSES);
        next
    }

    /// Rebuilds the sequencer's view of ŝ, bumping its version when it changed (the
    /// entailment cache depends on it).
    fn refresh_estimate(&mut self, modes: &[ValueId], modes_changed: bool) {
        let mut changed = modes_changed || self.estimate.version == 0;
        if changed {
            let mut state = sequencer::StateEstimate::new();
            for (component, &mode) in self.plant.components().iter().zip(modes) {
                state.set(component.mode_var(), mode);
            }
            self.estimate.state = state;
        }
        for &(var, value) in &self.confidence_atoms {
            let belief = self.belief.as_ref().and_then(|b| b.marginal(var, value));
            let belief = belief.unwrap_or(0.0);
            if self.estimate.state.belief(var, value) != Some(belief) {
                self.estimate.state.set_belief(var, value, belief);
                changed = true;
            }
        }
        if changed {
            self.estimate.version += 1;
        }
    }

    /// Step 3: the control program's configuration goal g(i) from ŝ(i) — the sequencer ends
    /// the previous cycle and begins this one, or the mission's network is monitored and fired
    /// (`mission.rs`).
    fn sequence(
        &mut self,
        now: f64,
        log: &mut EventLog,
    ) -> Result<Option<ConfigurationGoal>, StepError> {
        let sequencer = match &mut self.control.0 {
            Program::Rmpl(sequencer) => sequencer,
            // No tracked state explains what was observed (ŝ is empty): the network can be
            // neither scheduled nor monitored from it, so it waits for the next cycle with an
            // estimate, as a program does after INCONSISTENT; nothing is commanded meanwhile.
            Program::Mission(_) if self.most_likely.len() != self.plant.components().len() => {
                return Ok(None);
            }
            Program::Mission(mission) => {
                let (events, formula) = mission.step(
                    now,
                    &self.most_likely,
                    &self.estimates,
                    &self.reconfiguration,
                );
                events.into_iter().for_each(|kind| log.push(kind));
                return Ok((!mission.is_complete()).then_some(ConfigurationGoal {
                    formula,
                    conjuncts: Vec::new(),
                }));
            }
        };
        let mut oracle = CachedOracle {
            theory: &mut self.theory,
            cache: &mut self.answers,
        };
        let mut events = Vec::new();
        if log.cycle > 0 && !sequencer.is_complete() {
            let end = sequencer.end_cycle(&self.estimate, &mut oracle)?;
            events.extend(end.events);
        }
        let goal = if sequencer.is_complete() {
            None
        } else {
            let start = sequencer.begin_cycle(now, &self.estimate, &mut oracle)?;
            events.extend(start.events);
            Some(start.goal)
        };
        let achieved: Vec<LocationId> = events
            .iter()
            .filter_map(|event| match event {
                sequencer::Event::GoalAchieved { location, .. } => Some(*location),
                _ => None,
            })
            .collect();
        for event in events {
            let repeated = matches!(&event, sequencer::Event::GoalAchieved { location, .. }
                if self.reported.achieved.contains(location));
            if repeated {
                continue;
            }
            report_sequencer_event(sequencer.thca(), &mut self.reported, event, log);
        }
        self.reported.achieved = achieved;
        if let Some(goal) = &goal {
            self.report_new_goals(goal, log);
        }
        Ok(goal)
    }

    fn report_new_goals(&mut self, goal: &ConfigurationGoal, log: &mut EventLog) {
        let locations: Vec<LocationId> = goal.conjuncts.iter().map(|c| c.location).collect();
        for conjunct in &goal.conjuncts {
            if !self.reported.goal_locations.contains(&conjunct.location) {
                log.push(EventKind::GoalAsserted {
                    goal: conjunct.formula.display(self.plant.table()).to_string(),
                    location: conjunct.location,
                    span: conjunct.span.clone(),
                    again: !self.reported.asserted.insert(conjunct.location),
                });
            }
        }
        self.reported.goal_locations = locations;
        // A conflict reported once is reported again only after it went away.
        self.reported.conflicts.retain(|(a, b)| {
            goal.conjuncts
                .iter()
                .all(|c| c.location != *a && c.location != *b)
        });
    }
}

/// Collects a cycle's events with its cycle number and time.
struct EventLog {
    cycle: u64,
    time: f64,
    events: Vec<Event>,
}

impl EventLog {
    fn push(&mut self, kind: EventKind) {
        self.events.push(Event {
            cycle: self.cycle,
            time: self.time,
            kind,
        });
    }
}

/// A sequencer event as the executive reports it: clocks and conditions by name, a goal conflict
/// once until it goes away (`reported`).
fn report_sequencer_event(
    thca: &Thca,
    reported: &mut Reported,
    event: sequencer::Event,
    log: &mut EventLog,
) {
    use sequencer::Event as S;
    let kind = match event {
        S::ClockStarted { clock, span, .. } => EventKind::ClockStarted {
            clock: thca.table().clock_name(clock).to_string(),
            span,
        },
        S::Preempted {
            location,
            span,
            construct,
            condition,
        }
        | S::MaintenanceViolated {
            location,
            span,
            construct,
            condition,
        } => EventKind::Preempted {
            location,
            span,
            construct,
            condition: thca
                .formula(condition.formula)
                .display(thca.table())
                .to_string(),
            condition_span: condition.span,
            entailed: condition.sense == Sense::NotEntailed,
        },
        S::GoalConflict { first, second } => {
            let pair = (first.location, second.location);
            if reported.conflicts.contains(&pair) {
                return;
            }
            reported.conflicts.push(pair);
            EventKind::GoalConflict { first, second }
        }
        S::GoalAchieved { location, span } => EventKind::GoalAchieved { location, span },
        S::Completed => EventKind::ProgramCompleted,
    };
    log.push(kind);
}
