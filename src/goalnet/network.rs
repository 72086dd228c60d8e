//! Goal networks in their two states (mds-goal-networks.md §1.6, §5 C5): the *unscheduled*
//! [`GoalNetwork`] (time points, temporal constraints and goals) and the scheduled
//! [`ExecutableNetwork`] (per state variable, its timeline of XGoals).

use super::goal::{Goal, GoalId};
use super::stn::{Inconsistency, Stn, StnError};
use super::temporal_constraint::{ConstraintId, TemporalConstraint};
use super::time_point::{TimePoint, TimePointId};
use super::xgoal::XGoal;
use crate::diagnostic::Span;
use crate::plant::ComponentId;

/// Time points (the nodes), temporal constraints and goals (the edges) of a goal network.
#[derive(Debug, Clone)]
pub struct GoalNetwork {
    points: Vec<TimePoint>,
    stn: Stn,
    goals: Vec<Goal>,
}

impl Default for GoalNetwork {
    fn default() -> Self {
        Self::new()
    }
}

/// The name of the origin point in missions and messages.
pub const ORIGIN_NAME: &str = "origin";

impl GoalNetwork {
    /// A network holding only the origin point (named [`ORIGIN_NAME`]).
    pub fn new() -> Self {
        GoalNetwork {
            points: vec![TimePoint::new(ORIGIN_NAME, 0..0)],
            stn: Stn::new(),
            goals: Vec::new(),
        }
    }

    /// Adds a time point.
    pub fn add_point(&mut self, name: impl Into<String>, span: Span) -> TimePointId {
        let id = self.stn.add_point();
        self.points.push(TimePoint::new(name, span));
        id
    }

    /// Adds a temporal constraint.
    pub fn add_constraint(
        &mut self,
        constraint: TemporalConstraint,
    ) -> Result<ConstraintId, StnError> {
        self.stn.add_constraint(constraint)
    }

    /// Adds a goal (its points must be in the network).
    pub fn add_goal(&mut self, goal: Goal) -> GoalId {
        self.goals.push(goal);
        GoalId(self.goals.len() as u32 - 1)
    }

    /// Takes a goal out of the network without moving any id: it keeps its name, points and
    /// parent but constrains no state variable (never scheduled, monitored or delegated) — a
    /// goal a re-elaboration or safing retired, or a safe goal dropped.
    pub fn retire_goal(&mut self, goal: GoalId) {
        if let Some(goal) = self.goals.get_mut(goal.index()) {
            goal.sv = None;
            goal.delegate = None;
        }
    }

    /// Every point, the origin first; a point's index is its id.
    pub fn points(&self) -> &[TimePoint] {
        &self.points
    }

    /// One point.
    pub fn point(&self, id: TimePointId) -> &TimePoint {
        &self.points[id.index()]
    }

    /// The point with this name.
    pub fn point_named(&self, name: &str) -> Option<TimePointId> {
        self.points
            .iter()
            .position(|p| p.name == name)
            .map(|i| TimePointId(i as u32))
    }

    /// Every goal, in order; a goal's index is its id.
    pub fn goals(&self) -> &[Goal] {
        &self.goals
    }

    /// One goal.
    pub fn goal(&self, id: GoalId) -> &Goal {
        &self.goals[id.index()]
    }

    /// The goal with this name.
    pub fn goal_named(&self, name: &str) -> Option<GoalId> {
        self.goals
            .iter()
            .position(|g| g.name == name)
            .map(|i| GoalId(i as u32))
    }

    /// The goals on one state variable, in network order.
    pub fn goals_on(&self, sv: ComponentId) -> impl Iterator<Item = (GoalId, &Goal)> {
        self.goals
            .iter()
            .enumerate()
            .filter(move |(_, g)| g.sv == Some(sv))
            .map(|(i, g)| (GoalId(i as u32), g))
    }

    /// The temporal network.
    pub fn stn(&self) -> &Stn {
        &self.stn
    }

    /// The temporal network, to propagate or ground.
    pub fn stn_mut(&mut self) -> &mut Stn {
        &mut self.stn
    }

    /// Propagates the temporal network.
    pub fn propagate(&mut self) -> Result<(), Inconsistency> {
        self.stn.propagate()
    }
}

/// One state variable's scheduled timeline: its points in their chosen order and the XGoal on
/// each interval between consecutive points.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    /// The state variable.
    pub sv: ComponentId,
    /// Its points, in the order the scheduler fixed (GP §3.6: fixed per timeline).
    pub points: Vec<TimePointId>,
    /// One XGoal per interval between consecutive points (intervals forced to zero length
    /// skipped).
    pub xgoals: Vec<XGoal>,
}

/// A scheduled network (AG §1.2.6; GP §3.6 "executable plan"): the goal network with the
/// scheduler's ordering constraints added and propagated, and the XGoal timeline of every state
/// variable that has goals.
#[derive(Debug, Clone)]
pub struct ExecutableNetwork {
    /// The network, with the scheduler's constraints.
    pub network: GoalNetwork,
    /// Per state variable with goals, its timeline, in state-effect order.
    pub timelines: Vec<Timeline>,
}

impl ExecutableNetwork {
    /// The timeline of a state variable, if it has goals.
    pub fn timeline(&self, sv: ComponentId) -> Option<&Timeline> {
        self.timelines.iter().find(|t| t.sv == sv)
    }
}
