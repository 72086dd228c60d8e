//! The RON shapes of scenario and script files, as serde reads them (the format is documented in
//! the module documentation of [`crate::simulation`]). Nothing here is validated; the loader
//! turns these into a [`Scenario`](super::Scenario) and reports every problem with its location.
//! Reference for users: `docs/reference/scenario.md`.

use serde::Deserialize;

use crate::diagnostic::locate::{Entries, NumberOrName};
use crate::estimation::Rerun;
use crate::executive::EventKind;

/// `Scenario(...)`: a whole run.
#[derive(Deserialize)]
#[serde(rename = "Scenario", deny_unknown_fields)]
pub(super) struct ScenarioFile {
    #[serde(default)]
    pub(super) name: Option<String>,
    #[serde(default)]
    pub(super) description: String,
    #[serde(default)]
    pub(super) program: Option<String>,
    #[serde(default)]
    pub(super) mission: Option<String>,
    #[serde(default)]
    pub(super) entry: Option<String>,
    pub(super) plant: String,
    pub(super) cycle: f64,
    pub(super) end: f64,
    #[serde(default)]
    pub(super) kappa: Option<i64>,
    #[serde(default)]
    pub(super) history: Option<i64>,
    #[serde(default)]
    pub(super) rerun: Option<Rerun>,
    #[serde(default)]
    pub(super) chatter_cycles: Option<i64>,
    #[serde(default)]
    pub(super) deadline: Option<f64>,
    #[serde(default)]
    pub(super) believed: Entries<String>,
    #[serde(default)]
    pub(super) include: Vec<String>,
    #[serde(default)]
    pub(super) hidden: Entries<Vec<String>>,
    #[serde(default)]
    pub(super) initial: Entries<NumberOrName>,
    #[serde(default)]
    pub(super) rules: Vec<RuleFile>,
    #[serde(default)]
    pub(super) expect: Vec<ExpectFile>,
    #[serde(default)]
    pub(super) simulator: Option<SimulatorFile>,
    #[serde(default)]
    pub(super) choose: Entries<f64>,
    #[serde(default)]
    pub(super) deliver: Vec<DeliverFile>,
}

/// `(at: 12.0, order: ["valve closes", "valve opens"])`: the order a run applies the effects
/// due at the cycle at that time in (a counterexample of `kairos explore`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DeliverFile {
    pub(super) at: f64,
    pub(super) order: Vec<String>,
}

/// `Model(seed: 7, faults: ["valve1 = stuck-closed @ 17103 s"], noise: 0.01)`: the plant
/// simulated by sampling its model rather than by a script.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum SimulatorFile {
    Model {
        #[serde(default)]
        seed: u64,
        #[serde(default)]
        faults: Vec<String>,
        #[serde(default)]
        noise: f64,
    },
}

/// `Script(...)`: the scripted plant's hidden state, initial observations and rules, in a file
/// of its own that scenarios include, or inline in a scenario.
#[derive(Deserialize)]
#[serde(rename = "Script", deny_unknown_fields)]
pub(super) struct ScriptFile {
    #[serde(default)]
    pub(super) hidden: Entries<Vec<String>>,
    #[serde(default)]
    pub(super) initial: Entries<NumberOrName>,
    #[serde(default)]
    pub(super) rules: Vec<RuleFile>,
}

/// `Rule(...)`.
#[derive(Deserialize)]
#[serde(rename = "Rule", deny_unknown_fields)]
pub(super) struct RuleFile {
    pub(super) name: String,
    pub(super) on: TriggerFile,
    #[serde(default)]
    pub(super) when: Option<String>,
    #[serde(default)]
    pub(super) after: Option<DelayFile>,
    #[serde(default)]
    pub(super) set: Entries<NumberOrName>,
    #[serde(default)]
    pub(super) drop: Vec<String>,
    #[serde(default)]
    pub(super) garble: Entries<String>,
    #[serde(default)]
    pub(super) once: bool,
    #[serde(default)]
    pub(super) fault: bool,
    #[serde(default)]
    pub(super) submit: Option<crate::goalnet::mission::NetworkFile>,
}

/// What makes a rule fire.
#[derive(Deserialize)]
pub(super) enum TriggerFile {
    Command(String),
    Estimate(String),
    While(String),
    Time(f64),
    Cycle(i64),
    Optional {
        from: f64,
        to: f64,
        #[serde(default)]
        every: Option<i64>,
    },
}

/// How long after firing a rule's effect shows.
#[derive(Deserialize, Clone, Copy)]
pub(super) enum DelayFile {
    Cycles(i64),
    Seconds(f64),
    /// An interval of seconds, `Between(from, to)` (rules only).
    Between(f64, f64),
}

/// One expectation.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum ExpectFile {
    Estimated {
        state: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    EstimatedAt {
        state: String,
        time: f64,
    },
    NeverEstimated {
        state: String,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    Commanded {
        command: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    CommandsInOrder {
        commands: Vec<String>,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    NeverCommanded {
        command: String,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    Diagnosed {
        fault: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
        #[serde(default)]
        within: Option<DelayFile>,
        #[serde(default)]
        of: Option<String>,
    },
    Achieved {
        goal: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    GoalFailed {
        #[serde(default)]
        goal: Option<String>,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    Completed {
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    Reported {
        event: EventName,
        #[serde(default)]
        saying: Option<String>,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    AnyOf(Vec<ExpectFile>),
    NeverReported {
        event: EventName,
        #[serde(default)]
        saying: Option<String>,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    Fired {
        point: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    NeverFired {
        point: String,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    Failed {
        goal: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    NeverFailed {
        #[serde(default)]
        goal: Option<String>,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    XGoalActive {
        sv: String,
        #[serde(default)]
        goal: Option<String>,
        time: f64,
    },
    Recovered {
        goal: String,
        #[serde(default)]
        after: Option<f64>,
        #[serde(default)]
        by: Option<f64>,
    },
    NeverXGoalActive {
        sv: String,
        #[serde(default)]
        goal: Option<String>,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
    Always {
        that: ConditionFile,
        #[serde(default)]
        from: Option<f64>,
        #[serde(default)]
        to: Option<f64>,
    },
}

/// A condition on one cycle, for `Always(that: ...)` (`simulation::condition`).
#[derive(Deserialize)]
pub(super) enum ConditionFile {
    Plant(String),
    Estimated(String),
    Reported(EventName),
    Active(String),
    Not(Box<ConditionFile>),
    All(Vec<ConditionFile>),
    Any(Vec<ConditionFile>),
    Implies(Box<ConditionFile>, Box<ConditionFile>),
    Once(Box<ConditionFile>),
}

/// The kinds of executive event an expectation can name (`Reported(event: Diagnosis)`).
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventName {
    /// A goal asserted by the program.
    GoalAsserted,
    /// A goal achieved.
    GoalAchieved,
    /// Goal interpretation failed.
    GoalFailed,
    /// A command was sent on a tracked plant state other than ŝ (the goal was unreachable
    /// from ŝ).
    Retrying,
    /// Two goals contradicted each other.
    GoalConflict,
    /// A `do … watching` or `maintaining` construct was preempted.
    Preempted,
    /// A program clock started.
    ClockStarted,
    /// A component's most likely mode changed.
    ModeChanged,
    /// A fault mode became most likely.
    Diagnosis,
    /// A command was issued.
    CommandIssued,
    /// A command that repairs a fault was issued.
    Repair,
    /// The planner started waiting for a timed transition.
    Waiting,
    /// The reactive planner had no action.
    PlanFailed,
    /// No tracked state explained the observation.
    EstimatorInconsistency,
    /// A search budget cut estimation short.
    SearchCut,
    /// An observation was ignored (unknown name or value).
    ObservationRejected,
    /// A numeric observable's monitor changed its value.
    Monitored,
    /// A numeric observable's readings went stale.
    Stale,
    /// The set of unreported observables changed.
    ObservationsMissing,
    /// A cycle overran its deadline.
    DeadlineOverrun,
    /// The program completed.
    ProgramCompleted,
    /// A time point of the mission fired on time.
    TimePointFired,
    /// A time point of the mission was forced at its latest time.
    TimePointForced,
    /// An XGoal became active on its state variable.
    XGoalDispatched,
    /// A goal of the mission's network failed.
    MissionGoalFailed,
    /// A delegated goal's constraint was sent to its controller.
    ConstraintSent,
    /// A controller of a delegated goal issued a command.
    ControllerCommand,
    /// A controller ended a delegated goal's constraint.
    ConstraintEnded,
    /// A retired delegated goal's constraint was withdrawn from its controller.
    ConstraintWithdrawn,
    /// Firing a time point contradicted the temporal constraints.
    TemporalInconsistency,
    /// A scenario rule's submission was refused.
    SubmissionRefused,
    /// Elaboration chose a tactic for a goal.
    TacticChosen,
    /// Elaboration rejected a tactic for a goal.
    TacticRejected,
    /// A failed goal's response was carried out.
    ResponseTaken,
    /// A proposed network was promoted.
    Promoted,
    /// A proposed network could not be promoted.
    PromotionFailed,
    /// The safe network was promoted.
    Safing,
    /// A mission goal that had failed holds again.
    GoalRecovered,
    /// The mission's network has points left that nothing will fire.
    NetworkStalled,
    /// A goal of the safe network was dropped (it could not be scheduled).
    SafeGoalDropped,
    /// A promotion took the active XGoal off a state variable.
    XGoalWithdrawn,
    /// A command would have left a mode an active goal requires (withheld).
    GoalContradicted,
    /// A component was commanded back into a mode it was commanded out of within N cycles.
    Chatter,
}

impl EventName {
    /// The name of an event's kind (`Repair` is a `CommandIssued` that repairs; this says
    /// `CommandIssued`).
    pub fn of(kind: &EventKind) -> EventName {
        use EventKind as E;
        match kind {
            E::GoalAsserted { .. } => EventName::GoalAsserted,
            E::GoalAchieved { .. } => EventName::GoalAchieved,
            E::GoalFailed { .. } => EventName::GoalFailed,
            E::Retrying { .. } => EventName::Retrying,
            E::GoalConflict { .. } => EventName::GoalConflict,
            E::Preempted { .. } => EventName::Preempted,
            E::ClockStarted { .. } => EventName::ClockStarted,
            E::ModeChanged { .. } => EventName::ModeChanged,
            E::Diagnosis { .. } => EventName::Diagnosis,
            E::CommandIssued { .. } => EventName::CommandIssued,
            E::Waiting { .. } => EventName::Waiting,
            E::PlanFailed { .. } => EventName::PlanFailed,
            E::EstimatorInconsistency { .. } => EventName::EstimatorInconsistency,
            E::SearchCut(_) => EventName::SearchCut,
            E::ObservationRejected { .. } => EventName::ObservationRejected,
            E::Monitored { .. } => EventName::Monitored,
            E::Stale { .. } => EventName::Stale,
            E::ObservationsMissing { .. } => EventName::ObservationsMissing,
            E::DeadlineOverrun { .. } => EventName::DeadlineOverrun,
            E::ProgramCompleted => EventName::ProgramCompleted,
            E::TimePointFired { .. } => EventName::TimePointFired,
            E::TimePointForced { .. } => EventName::TimePointForced,
            E::XGoalDispatched { .. } => EventName::XGoalDispatched,
            E::MissionGoalFailed { .. } => EventName::MissionGoalFailed,
            E::ConstraintSent { .. } => EventName::ConstraintSent,
            E::ControllerCommand { .. } => EventName::ControllerCommand,
            E::ConstraintEnded { .. } => EventName::ConstraintEnded,
            E::ConstraintWithdrawn { .. } => EventName::ConstraintWithdrawn,
            E::TemporalInconsistency { .. } => EventName::TemporalInconsistency,
            E::SubmissionRefused { .. } => EventName::SubmissionRefused,
            E::TacticChosen { .. } => EventName::TacticChosen,
            E::TacticRejected { .. } => EventName::TacticRejected,
            E::ResponseTaken { .. } => EventName::ResponseTaken,
            E::Promoted { .. } => EventName::Promoted,
            E::PromotionFailed { .. } => EventName::PromotionFailed,
            E::Safing { .. } => EventName::Safing,
            E::GoalRecovered { .. } => EventName::GoalRecovered,
            E::NetworkStalled { .. } => EventName::NetworkStalled,
            E::SafeGoalDropped { .. } => EventName::SafeGoalDropped,
            E::XGoalWithdrawn { .. } => EventName::XGoalWithdrawn,
            E::GoalContradicted { .. } => EventName::GoalContradicted,
            E::Chatter { .. } => EventName::Chatter,
        }
    }
}

/// The script parts of a scenario or script file.
pub(super) struct ScriptParts<'a> {
    pub(super) hidden: &'a Entries<Vec<String>>,
    pub(super) initial: &'a Entries<NumberOrName>,
    pub(super) rules: &'a [RuleFile],
}

impl ScenarioFile {
    pub(super) fn script(&self) -> ScriptParts<'_> {
        ScriptParts {
            hidden: &self.hidden,
            initial: &self.initial,
            rules: &self.rules,
        }
    }
}

impl ScriptFile {
    pub(super) fn script(&self) -> ScriptParts<'_> {
        ScriptParts {
            hidden: &self.hidden,
            initial: &self.initial,
            rules: &self.rules,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/scenario.md` lists every field and variant a scenario or script file
    /// accepts, and no other; a rule's `submit:` network is the mission's, documented on
    /// `docs/reference/mission.md`.
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        crate::goalnet::mission::trace_network(&mut tracer);
        reference::add::<EventName>(&mut tracer);
        reference::add::<DelayFile>(&mut tracer);
        reference::add::<TriggerFile>(&mut tracer);
        reference::add::<SimulatorFile>(&mut tracer);
        reference::add::<Rerun>(&mut tracer);
        reference::add::<ConditionFile>(&mut tracer);
        reference::add::<ExpectFile>(&mut tracer);
        reference::add::<ScriptFile>(&mut tracer);
        reference::add::<ScenarioFile>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[
                ("Scenario", "scenario.md", "`Scenario(...)`"),
                ("Script", "scenario.md", "`Script(...)`"),
                ("Rule", "scenario.md", "`Rule(...)`"),
                ("TriggerFile", "scenario.md", "Triggers"),
                ("DelayFile", "scenario.md", "Delays"),
                ("DeliverFile", "scenario.md", "Deliveries"),
                ("SimulatorFile", "scenario.md", "A model-driven plant"),
                ("Rerun", "scenario.md", "Re-run policies"),
                ("ExpectFile", "scenario.md", "Expectations"),
                ("ConditionFile", "scenario.md", "Conditions"),
                ("EventName", "scenario.md", "Event kinds"),
                ("Network", "mission.md", "`Network(...)`"),
                ("Constraint", "mission.md", "`Constraint(...)`"),
                ("Macro", "mission.md", "`Macro(...)`"),
                ("Goal", "mission.md", "`Goal(...)`"),
                ("KindFile", "mission.md", "Goal kinds"),
            ],
        );
    }
}
