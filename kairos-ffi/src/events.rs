//! The event kinds as C sees them: one code per [`EventKind`] variant. The match is exhaustive
//! and has no wildcard, so a kind added to the executive does not compile here until it has a
//! code (codes are never renumbered: C programs store them).

use std::ffi::{CString, c_char};
use std::ptr;

use kairos::executive::EventKind;

/// The kind of an event (what the mission log tags it with); `line` words it in full.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum KairosEventKind {
    /// No event (an index out of range).
    None = 0,
    GoalAsserted = 1,
    GoalAchieved = 2,
    GoalFailed = 3,
    Retrying = 4,
    GoalConflict = 5,
    Preempted = 6,
    ClockStarted = 7,
    ModeChanged = 8,
    Diagnosis = 9,
    CommandIssued = 10,
    Waiting = 11,
    PlanFailed = 12,
    EstimatorInconsistency = 13,
    SearchCut = 14,
    ObservationRejected = 15,
    ObservationsMissing = 16,
    DeadlineOverrun = 17,
    ProgramCompleted = 18,
    TimePointFired = 19,
    TimePointForced = 20,
    XGoalDispatched = 21,
    MissionGoalFailed = 22,
    ConstraintSent = 23,
    ControllerCommand = 24,
    ConstraintEnded = 25,
    ConstraintWithdrawn = 26,
    TemporalInconsistency = 27,
    SubmissionRefused = 28,
    TacticChosen = 29,
    TacticRejected = 30,
    ResponseTaken = 31,
    Promoted = 32,
    PromotionFailed = 33,
    Safing = 34,
    /// A command would have left a mode an active goal requires; it was withheld.
    GoalContradicted = 35,
    /// A component was commanded back into a mode it was commanded out of within a few cycles.
    Chatter = 36,
    GoalRecovered = 37,
    NetworkStalled = 38,
    SafeGoalDropped = 39,
    XGoalWithdrawn = 40,
    Monitored = 41,
    Stale = 42,
}

impl KairosEventKind {
    pub(crate) fn of(kind: &EventKind) -> KairosEventKind {
        use KairosEventKind as K;
        match kind {
            EventKind::GoalAsserted { .. } => K::GoalAsserted,
            EventKind::GoalAchieved { .. } => K::GoalAchieved,
            EventKind::GoalFailed { .. } => K::GoalFailed,
            EventKind::Retrying { .. } => K::Retrying,
            EventKind::GoalConflict { .. } => K::GoalConflict,
            EventKind::Preempted { .. } => K::Preempted,
            EventKind::ClockStarted { .. } => K::ClockStarted,
            EventKind::ModeChanged { .. } => K::ModeChanged,
            EventKind::Diagnosis { .. } => K::Diagnosis,
            EventKind::CommandIssued { .. } => K::CommandIssued,
            EventKind::Waiting { .. } => K::Waiting,
            EventKind::PlanFailed { .. } => K::PlanFailed,
            EventKind::EstimatorInconsistency { .. } => K::EstimatorInconsistency,
            EventKind::SearchCut(_) => K::SearchCut,
            EventKind::ObservationRejected { .. } => K::ObservationRejected,
            EventKind::ObservationsMissing { .. } => K::ObservationsMissing,
            EventKind::DeadlineOverrun { .. } => K::DeadlineOverrun,
            EventKind::ProgramCompleted => K::ProgramCompleted,
            EventKind::TimePointFired { .. } => K::TimePointFired,
            EventKind::TimePointForced { .. } => K::TimePointForced,
            EventKind::XGoalDispatched { .. } => K::XGoalDispatched,
            EventKind::MissionGoalFailed { .. } => K::MissionGoalFailed,
            EventKind::ConstraintSent { .. } => K::ConstraintSent,
            EventKind::ControllerCommand { .. } => K::ControllerCommand,
            EventKind::ConstraintEnded { .. } => K::ConstraintEnded,
            EventKind::ConstraintWithdrawn { .. } => K::ConstraintWithdrawn,
            EventKind::TemporalInconsistency { .. } => K::TemporalInconsistency,
            EventKind::SubmissionRefused { .. } => K::SubmissionRefused,
            EventKind::TacticChosen { .. } => K::TacticChosen,
            EventKind::TacticRejected { .. } => K::TacticRejected,
            EventKind::ResponseTaken { .. } => K::ResponseTaken,
            EventKind::Promoted { .. } => K::Promoted,
            EventKind::PromotionFailed { .. } => K::PromotionFailed,
            EventKind::Safing { .. } => K::Safing,
            EventKind::GoalRecovered { .. } => K::GoalRecovered,
            EventKind::NetworkStalled { .. } => K::NetworkStalled,
            EventKind::SafeGoalDropped { .. } => K::SafeGoalDropped,
            EventKind::XGoalWithdrawn { .. } => K::XGoalWithdrawn,
            EventKind::GoalContradicted { .. } => K::GoalContradicted,
            EventKind::Chatter { .. } => K::Chatter,
            EventKind::Monitored { .. } => K::Monitored,
            EventKind::Stale { .. } => K::Stale,
        }
    }
}

/// One event of a step: its kind and its line as the mission log words it, with the plant's and
/// the program's names (`[12.000 s] #12 DIAGNOSIS valve2 = stuck-closed (p 0.97); ...`). The
/// line is owned by the step; NULL (and kind `KAIROS_EVENT_KIND_NONE`) for an index out of range.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KairosEvent {
    /// What kind of event it is.
    pub kind: KairosEventKind,
    /// The event in words.
    pub line: *const c_char,
}

/// An event kept by a step.
pub(crate) struct StoredEvent {
    pub(crate) kind: KairosEventKind,
    pub(crate) line: CString,
}

impl StoredEvent {
    pub(crate) fn view(&self) -> KairosEvent {
        KairosEvent {
            kind: self.kind,
            line: self.line.as_ptr(),
        }
    }

    pub(crate) const NONE: KairosEvent = KairosEvent {
        kind: KairosEventKind::None,
        line: ptr::null(),
    };
}
