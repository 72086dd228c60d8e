//! Goals (mds-goal-networks.md §1.3; DESIGN.md §15.1): a constraint on one state variable over
//! the interval between a start and an end time point.

use super::constraint_set::ConstraintSet;
use super::time_point::TimePointId;
use crate::diagnostic::Span;
use crate::plant::ComponentId;
use crate::protocol::posandhead::Constraint;

/// A goal's index in its network.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GoalId(pub u32);

impl GoalId {
    /// The index as a `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// How a goal's constraint is judged over its interval (AG §3.4; GP §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum GoalKind {
    /// Constrains nothing (the identity of merge).
    Unconstrained,
    /// The estimate must be known: an estimator achieves it; never a command (§15.3).
    Knowledge,
    /// Reach the set by the end point; not a failure while getting there.
    Transition,
    /// Hold the set throughout; any excursion of ŝ is a failure.
    Maintain,
}

impl GoalKind {
    /// The stronger of two kinds, as an XGoal merging both is judged (mds-goal-networks.md §1.4:
    /// "Maintain if either input is Maintain").
    pub fn stronger(self, other: GoalKind) -> GoalKind {
        self.max(other)
    }

    /// The word used in mission files and messages.
    pub fn name(self) -> &'static str {
        match self {
            GoalKind::Unconstrained => "Unconstrained",
            GoalKind::Knowledge => "Knowledge",
            GoalKind::Transition => "Transition",
            GoalKind::Maintain => "Maintain",
        }
    }
}

/// A goal of a goal network.
#[derive(Debug, Clone, PartialEq)]
pub struct Goal {
    /// Its name in the mission (`"heater1"`), unique in its network.
    pub name: String,
    /// The state variable: a component, whose mode variable it constrains. `None` for a *macro*
    /// goal, which constrains nothing itself and exists to be elaborated (AG §3.9).
    pub sv: Option<ComponentId>,
    /// How the constraint is judged.
    pub kind: GoalKind,
    /// The constraint on the SV's values.
    pub constraint: ConstraintSet,
    /// For a goal on a state variable that is not a component (`sv` is `None`): the
    /// controller it is delegated to and the constraint sent to it.
    pub delegate: Option<Delegate>,
    /// The constraint as written (the constraint language), for messages.
    pub text: String,
    /// The point where it starts to apply.
    pub start: TimePointId,
    /// The point where it stops applying.
    pub end: TimePointId,
    /// The goal it was elaborated from (or declared under).
    pub parent: Option<GoalId>,
    /// Its priority (MM ¶2; carried, not yet used to shed goals — mds-goal-networks.md §5 C10).
    pub priority: i32,
    /// Where it is declared (empty for a goal submitted at run time).
    pub span: Span,
}

impl Goal {
    /// Whether it is a macro goal (no state variable, not delegated).
    pub fn is_macro(&self) -> bool {
        self.sv.is_none() && self.delegate.is_none()
    }
}

/// A goal delegated to the controller a mission declares for a state variable that is not a
/// plant component (mds-goal-networks.md §1.7: the SV's controller achieves
/// its control goals). The goal is on no component timeline: the scheduler and mode
/// reconfiguration never see it; its controller judges it, and its end point waits for the
/// controller's `endcstr`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Delegate {
    /// The controller: its index in the mission's `controllers`.
    pub controller: usize,
    /// The constraint sent to it when the goal's start point fires.
    pub constraint: Constraint,
}
