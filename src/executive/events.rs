//! What the executive reports, cycle by cycle (DESIGN.md §10): every event has the time and the
//! cycle it happened in and, where it concerns the program, the source span of the location.

use std::fmt;
use std::time::Duration;

use crate::diagnostic::Span;
use crate::estimation::Fallback;
use crate::opsat::Cut;
use crate::plant::ComponentId;
use crate::sequencer::{Construct, GoalSource, LocationId};

/// One notable thing in one cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Cycle number, from 0.
    pub cycle: u64,
    /// Time of the cycle, in seconds.
    pub time: f64,
    /// What happened.
    pub kind: EventKind,
}

/// The kinds of [`Event`].
#[derive(Debug, Clone, PartialEq)]
pub enum EventKind {
    /// A program location started asserting a goal.
    GoalAsserted {
        /// The goal, as text.
        goal: String,
        /// The asserting location.
        location: LocationId,
        /// Where the goal is written.
        span: Span,
        /// True when the location asserted it before in the run, and stopped: the sequencer
        /// re-entered it (after a preemption, or in a loop).
        again: bool,
    },
    /// A goal is entailed by the estimate; its location moves on.
    GoalAchieved {
        /// The location.
        location: LocationId,
        /// Where the goal is written.
        span: Span,
    },
    /// Goal interpretation found no reachable state achieving the configuration goal.
    GoalFailed {
        /// The configuration goal, as text.
        goal: String,
        /// Why, naming components and modes.
        reason: String,
    },
    /// The goal is unreachable from ŝ but reachable from another tracked plant state: the
    /// planner's command from that state is sent, so that the next estimate decides. A
    /// `CommandIssued` with the command follows.
    Retrying {
        /// The configuration goal, as text.
        goal: String,
        /// The command's `variable = value` assignments, as text.
        assignments: Vec<String>,
        /// Where the state acted on differs from ŝ: `valve2 = closed`.
        hypothesis: String,
        /// That state's probability.
        probability: f64,
        /// Which retry of the goal this is, from 1.
        attempt: u32,
        /// How many retries a goal gets.
        budget: u32,
    },
    /// Two goals asserted in the same cycle contradict each other; neither is pursued.
    GoalConflict {
        /// One goal.
        first: GoalSource,
        /// The goal contradicting it.
        second: GoalSource,
    },
    /// A `do … watching` or `maintaining` construct was preempted: its maintenance no longer
    /// holds, because the watched condition became entailed or the maintained one is not.
    Preempted {
        /// The composite location.
        location: LocationId,
        /// Its construct.
        span: Span,
        /// Which construct it is (`do … watching`, `maintaining`).
        construct: Construct,
        /// The condition whose entailment preempted, rendered from its formula with the
        /// program's names (the log prints its source text where it has the program).
        condition: String,
        /// Where the condition is written.
        condition_span: Span,
        /// True when the condition became entailed (`do … watching c`); false when it is not
        /// entailed (`… maintaining c`).
        entailed: bool,
    },
    /// A program clock started.
    ClockStarted {
        /// The clock's name.
        clock: String,
        /// Where it is started.
        span: Span,
    },
    /// The most likely mode of a component changed.
    ModeChanged {
        /// The component.
        component: ComponentId,
        /// Its previous most likely mode's name.
        from: String,
        /// Its new most likely mode's name.
        to: String,
        /// The new mode's marginal probability.
        probability: f64,
    },
    /// A fault mode became the most likely mode of a component.
    Diagnosis {
        /// The component.
        component: ComponentId,
        /// The fault mode's name.
        mode: String,
        /// Its marginal probability.
        probability: f64,
        /// The component's other modes the belief holds, with their marginals, most probable
        /// first (the next candidates; the least likely are left out).
        next: Vec<(String, f64)>,
        /// The observations the previous most likely state, stepped by the last command, cannot
        /// explain (`variable = value`; Livingstone's discrepant observations), against the
        /// initial state in cycle 0. When none is discrepant alone but some are together, one
        /// entry names a minimal such set: `a = x & b = y`.
        evidence: Vec<String>,
    },
    /// A command was issued.
    CommandIssued {
        /// `variable = value` assignments, as text.
        assignments: Vec<String>,
        /// What it is for: `engine: off -> heating`.
        purpose: String,
        /// True when it repairs a fault.
        repair: bool,
        /// The goals its transition serves (see [`Served`]); empty when none is asserted.
        serves: Vec<Served>,
    },
    /// The planner started waiting for a transition that happens by itself.
    Waiting {
        /// What is awaited: `engine: heating -> standby, after Uniform(30, 60) s`.
        purpose: String,
    },
    /// The reactive planner has no action toward the goal state.
    PlanFailed {
        /// Why.
        reason: String,
    },
    /// No state reachable from the tracked ones explains the observations (DESIGN.md §8).
    EstimatorInconsistency {
        /// What the estimator fell back to.
        fallback: Fallback,
    },
    /// A search budget cut mode estimation short; the belief is the best found so far.
    SearchCut(Cut),
    /// An observation was ignored for this cycle.
    ObservationRejected {
        /// The name given.
        variable: String,
        /// The value given.
        value: String,
        /// Why it was ignored.
        reason: String,
    },
    /// A numeric observable's monitor changed its value on a reading (the plant model's
    /// `monitors`; `plant::monitor`).
    Monitored {
        /// The observable.
        variable: String,
        /// The reading that changed it.
        reading: f64,
        /// The reading's unit.
        unit: String,
        /// The value before (`None`: none yet, or stale).
        from: Option<String>,
        /// The value now.
        to: String,
    },
    /// A numeric observable had no reading for longer than its monitor's staleness: it is
    /// unknown until the next one.
    Stale {
        /// The observable.
        variable: String,
        /// The time of its last reading, seconds.
        last: f64,
        /// The staleness, seconds.
        limit: f64,
    },
    /// Observables that were not reported (they count as unknown); reported when the set of
    /// missing observables changes.
    ObservationsMissing {
        /// Their names (empty: all observables are reported again).
        variables: Vec<String>,
    },
    /// The cycle took longer than its deadline.
    DeadlineOverrun {
        /// Wall time the cycle took.
        elapsed: Duration,
        /// The deadline.
        deadline: Duration,
    },
    /// No program location is marked any more: the program has finished.
    ProgramCompleted,
    /// A time point of the mission's goal network fired on time (DESIGN.md §15.3).
    TimePointFired {
        /// The point's name.
        point: String,
        /// Its window `[earliest, latest]` when it fired, seconds.
        window: (f64, f64),
    },
    /// A time point fired at its latest time with an XGoal starting there not ready.
    TimePointForced {
        /// The point's name.
        point: String,
        /// Its window when it fired, seconds.
        window: (f64, f64),
        /// How late past its latest time, seconds.
        late_by: f64,
    },
    /// An XGoal became active on its state variable.
    XGoalDispatched {
        /// The state variable (a component).
        sv: ComponentId,
        /// Its merged constraint, as text (`switch1 ∈ {closed, stuck-closed}, known`).
        constraint: String,
        /// Its kind (`Maintain`, `Transition`, ...).
        kind: &'static str,
        /// The points it lies between.
        interval: (String, String),
        /// The goals merged into it.
        goals: Vec<String>,
    },
    /// A goal of the mission's network failed (narrowed from its XGoal to the constituent goal
    /// that fails on its own); it stays failed.
    MissionGoalFailed {
        /// The constituent goal's name.
        goal: String,
        /// Why, in words.
        reason: String,
        /// The mode ŝ gives its state variable.
        mode: String,
        /// That mode's marginal probability.
        probability: f64,
    },
    /// A delegated goal's start point fired: its constraint was sent to the controller of its
    /// state variable (the protocol's constraint message).
    ConstraintSent {
        /// The goal.
        goal: String,
        /// The controlled state variable (not a plant component).
        sv: String,
        /// The constraint, as the protocol prints it (`(x=3, y=2)`).
        constraint: String,
    },
    /// The controller of a state variable issued a command to its device (through its
    /// actuator), for a delegated goal.
    ControllerCommand {
        /// The controlled state variable.
        sv: String,
        /// The command (`drive`, `turn(N)`).
        command: String,
        /// The goal the command serves.
        goal: String,
    },
    /// The controller of a state variable ended a delegated goal's constraint (`endcstr`).
    ConstraintEnded {
        /// The goal.
        goal: String,
        /// The controlled state variable.
        sv: String,
        /// `success` or the reason it failed (`coanosuccess`).
        outcome: String,
        /// The state variable's value as the controller last heard it.
        value: String,
    },
    /// A delegated goal was retired (a re-elaboration, safing) while its controller worked on
    /// it: its constraint was withdrawn and no further command is issued for it.
    ConstraintWithdrawn {
        /// The goal.
        goal: String,
        /// The controlled state variable.
        sv: String,
        /// The state variable's value as the controller last heard it.
        value: String,
    },
    /// Grounding a fired point contradicted the temporal constraints.
    TemporalInconsistency {
        /// The point.
        point: String,
        /// The constraints of the negative cycle, as text.
        cycle: Vec<String>,
    },
    /// A submission to the running mission ([`Executive::submit`](super::Executive::submit))
    /// was refused; the running network is unchanged. Reported by whoever submits (a scenario
    /// run, for its rules' `submit`), in the cycle that follows.
    SubmissionRefused {
        /// Who submitted: a scenario rule's name.
        by: String,
        /// The goals submitted.
        goals: Vec<String>,
        /// Why ([`SubmitError`](super::SubmitError) in words).
        reason: String,
        /// The goals of the running network it conflicts with (every one, DESIGN.md §15.2);
        /// empty when it was refused for another reason.
        conflicts: Vec<String>,
    },
    /// Elaboration chose a tactic for a goal of the network it then promoted
    /// (mds-goal-networks.md §2.1).
    TacticChosen {
        /// The goal's name.
        goal: String,
        /// The tactic's number in its goal type's list, from 1 (as the seed counts).
        tactic: usize,
    },
    /// Elaboration rejected a tactic for a goal: the candidate network did not schedule, or
    /// every tactic of a child was rejected (chronological backtracking, §2.1).
    TacticRejected {
        /// The goal's name.
        goal: String,
        /// The tactic's number, from 1.
        tactic: usize,
        /// Why, on one line.
        reason: String,
    },
    /// A failed goal's response was carried out (§2.5–2.7): the whole chain, from the failure
    /// to its outcome.
    ResponseTaken {
        /// The goal that failed.
        goal: String,
        /// Its type's response (`fail up`, `re-elaborate`, `ignore`, `safing`).
        response: &'static str,
        /// The chain: "heater1 failed: switch1 = stuck-open (p 0.97) → fail up → stay-warm
        /// re-elaborated with tactic 2 → promoted".
        explanation: String,
    },
    /// A proposed network replaced the running one (§2.3 steps d–j).
    Promoted {
        /// Why it was proposed (`re-elaboration of stay-warm`, `a submission`).
        cause: String,
    },
    /// A proposal could not be promoted; the running network runs on.
    PromotionFailed {
        /// Why, on one line.
        reason: String,
    },
    /// The mission's safe network replaced the running one (§2.8): nothing of the old network
    /// fires after it.
    Safing {
        /// The failure that led there, explained, on one line.
        cause: String,
    },
    /// A goal of the mission's network that had failed holds again (DESIGN.md §15.2): it is
    /// monitored again, and a new failure is reported and answered again.
    GoalRecovered {
        /// The goal's name.
        goal: String,
        /// The mode ŝ gives its state variable.
        mode: String,
        /// That mode's marginal probability.
        probability: f64,
    },
    /// The mission's network has points left that nothing will fire (DESIGN.md §15.2: a
    /// network that has stopped firing with time left says why); reported when that set
    /// changes.
    NetworkStalled {
        /// Each stalled point and what it waits for, in words (`TP_E waits for TP_S, which
        /// has not fired, past its latest time 161 s`).
        points: Vec<String>,
    },
    /// A goal of the safe network could not be scheduled from the state safing found and was
    /// dropped; the rest of the safe network runs (DESIGN.md §15.2: best effort).
    SafeGoalDropped {
        /// The goal's name.
        goal: String,
        /// Why, on one line (the scheduler's explanation).
        reason: String,
    },
    /// A promotion (a re-elaboration, a submission, safing) left no XGoal active on a state
    /// variable that had one: what it held is no longer asked for (DESIGN.md §15.2: the
    /// promotion replaced the retired XGoals).
    XGoalWithdrawn {
        /// The state variable (a component).
        sv: ComponentId,
        /// The goals the withdrawn XGoal merged.
        goals: Vec<String>,
    },
    /// The planner's command would have moved a component out of a mode an active goal
    /// requires (DESIGN.md §9, goal-faithful commands): the command was withheld.
    GoalContradicted {
        /// The goal it would have broken, as text.
        goal: String,
        /// The command's `variable = value` assignments, as text.
        command: Vec<String>,
        /// The component it would have moved.
        component: ComponentId,
        /// The mode the goal requires, which the command would have left.
        mode: String,
    },
    /// A component was commanded back into a mode it was commanded out of within the last N
    /// cycles, with no diagnosis in between (DESIGN.md §9): the executive works against itself.
    Chatter {
        /// The component.
        component: ComponentId,
        /// The mode it is commanded back into.
        mode: String,
        /// How many cycles ago it was commanded out of it.
        cycles: u64,
    },
}

/// A goal a command serves: the goal of the component the planner's descent started from
/// (`reconfiguration::Command::serves`) — the PDE's `on` serves `engine = standby` when the
/// engine's heating needs the PDE on. For a program, the conjuncts of g(i) whose formula names
/// that component's mode; for a mission, the constituent goals of the XGoal active on it; when
/// neither names it, its mode in the intended configuration, with the goal it is there for (a
/// helper brought back after the goal it was moved for, or a mode the goal state needs).
#[derive(Debug, Clone, PartialEq)]
pub enum Served {
    /// A goal the program asserts.
    Program {
        /// The goal, as text.
        goal: String,
        /// Where it is written.
        span: Span,
    },
    /// A goal of the mission's network, by name.
    Mission {
        /// The goal's name.
        goal: String,
    },
    /// The component's mode in the intended configuration, which no asserted goal names, and
    /// the goal it is there for.
    Intended {
        /// `component = mode, bringing back a helper moved for GOAL`, or `component = mode in
        /// the goal state of GOAL`, as text.
        goal: String,
    },
}

impl EventKind {
    /// The program location the event concerns, if any.
    pub fn location(&self) -> Option<LocationId> {
        match self {
            EventKind::GoalAsserted { location, .. }
            | EventKind::GoalAchieved { location, .. }
            | EventKind::Preempted { location, .. } => Some(*location),
            _ => None,
        }
    }

    /// The program source span the event concerns, if any.
    pub fn span(&self) -> Option<&Span> {
        match self {
            EventKind::GoalAsserted { span, .. }
            | EventKind::GoalAchieved { span, .. }
            | EventKind::Preempted { span, .. }
            | EventKind::ClockStarted { span, .. } => Some(span),
            EventKind::GoalConflict { first, .. } => Some(&first.span),
            _ => None,
        }
    }
}

/// The event as the mission log words it, without the plant and program the log has: component
/// ids stand for names, byte ranges for source lines (the wording is
/// [`describe_event`](super::describe_event)'s, shared, not copied).
///
/// ```
/// use kairos::executive::{Event, EventKind};
/// use kairos::plant::ComponentId;
///
/// let event = Event {
///     cycle: 12,
///     time: 1.2,
///     kind: EventKind::Diagnosis {
///         component: ComponentId(0),
///         mode: "resettable".to_string(),
///         probability: 0.91,
///         next: vec![("on".to_string(), 0.09)],
///         evidence: vec!["component 0.status = fault".to_string()],
///     },
/// };
/// assert_eq!(
///     event.to_string(),
///     "[1.200 s] #12 DIAGNOSIS component 0 = resettable (p 0.91); evidence: component 0.status = fault; next: component 0 = on (p 0.09)"
/// );
/// assert_eq!(
///     EventKind::ProgramCompleted.to_string(),
///     "completed the program has completed"
/// );
/// ```
impl fmt::Display for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{:.3} s] #{} {}", self.time, self.cycle, self.kind)
    }
}

/// The kind as the mission log words it (its tag, then its text), without names: see
/// [`Event`]'s `Display`.
impl fmt::Display for EventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (tag, text) = super::describe::describe_bare(self);
        write!(f, "{tag} {text}")
    }
}
