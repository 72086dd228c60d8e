//! Proposed networks (mds-goal-networks.md §2.3, AG §1.2.4, §1.2.6): a proposal is a copy of
//! the running network — the same ids for the same points and goals, so events before and
//! after a promotion speak of the same things — that is edited, elaborated, scheduled, checked
//! and promoted by [`GoalController::promote`].
//!
//! The copy keeps what happened: fired points stay grounded at their times (their `Fired`
//! constraints), written and submitted constraints stay. It drops the scheduler's constraints
//! (the proposal is scheduled afresh) and everything that touches a *retired* point (an unfired
//! point of a removed elaboration, which never fires). A retired goal stays in the list, as a
//! goal with no state variable, so that no id moves; it is never scheduled.

#[cfg(doc)]
use super::controller::GoalController;
use super::elaborate::{ElaborationState, fresh};
use super::goal::{Goal, GoalId};
use super::network::GoalNetwork;
use super::stn::StnError;
use super::tactic::TypeId;
use super::temporal_constraint::{ConstraintId, Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use crate::diagnostic::Span;

/// A proposed network, being edited.
#[derive(Debug, Clone)]
pub struct Proposal {
    pub(super) network: GoalNetwork,
    pub(super) state: ElaborationState,
    /// Per point, whether it is retired (never fires).
    pub(super) retired_points: Vec<bool>,
    /// The goals to elaborate at promotion, each with the tactic to try first.
    pub(super) roots: Vec<(GoalId, usize)>,
    /// Points from this index on are new (anchored at or after the promotion).
    pub(super) anchor_from: usize,
    /// Why it is proposed, for the `Promoted` event.
    pub(super) cause: String,
}

impl Proposal {
    /// The proposed network as edited so far.
    pub fn network(&self) -> &GoalNetwork {
        &self.network
    }

    /// The proposal with `cause` as the reason the `Promoted` event gives.
    pub fn because(mut self, cause: impl Into<String>) -> Self {
        self.cause = cause.into();
        self
    }

    /// Adds a time point (a name already taken gets a prime).
    pub fn add_point(&mut self, name: &str, span: Span) -> TimePointId {
        let name = fresh(name, |n| self.network.point_named(n).is_some());
        self.retired_points.push(false);
        self.network.add_point(name, span)
    }

    /// Adds a temporal constraint.
    pub fn add_constraint(
        &mut self,
        constraint: TemporalConstraint,
    ) -> Result<ConstraintId, StnError> {
        self.network.add_constraint(constraint)
    }

    /// Adds a goal; one with a type is elaborated at promotion.
    pub fn add_goal(&mut self, goal: Goal, goal_type: Option<TypeId>) -> GoalId {
        let id = self.network.add_goal(goal);
        self.state.types.push(goal_type);
        self.state.retired.push(false);
        if goal_type.is_some() {
            self.roots.push((id, 0));
        }
        id
    }
}

/// The copy of `network` a proposal starts from: scheduler constraints dropped, retired points
/// cut loose, retired goals without a state variable.
pub(super) fn copy(
    network: &GoalNetwork,
    retired_goals: &[bool],
    retired_points: &[bool],
) -> GoalNetwork {
    let mut out = GoalNetwork::new();
    for point in &network.points()[1..] {
        out.add_point(point.name.clone(), point.span.clone());
    }
    let retired = |p: TimePointId| retired_points.get(p.index()).copied().unwrap_or(false);
    for c in network.stn().constraints() {
        let derived = matches!(
            c.provenance,
            Provenance::AfterOrigin | Provenance::Scheduled { .. } | Provenance::GoalInterval
        );
        if derived || retired(c.from) || retired(c.to) {
            continue;
        }
        // Both points exist (same ids) and the bounds were valid in the original.
        let _ = out.add_constraint(c.clone());
    }
    for (i, goal) in network.goals().iter().enumerate() {
        let mut goal = goal.clone();
        if retired_goals.get(i).copied().unwrap_or(false) {
            goal.sv = None;
            goal.delegate = None;
        }
        out.add_goal(goal);
    }
    out
}

/// Appends `safe` to `network` (safing, §2.8): the safe network's origin becomes a new
/// promotion point fired at `now`; its points, constraints and goals follow with fresh names.
/// Returns the promotion point.
pub(super) fn append_safe(
    network: &mut GoalNetwork,
    state: &mut ElaborationState,
    safe: &GoalNetwork,
    now: f64,
) -> TimePointId {
    let name = fresh("safing", |n| network.point_named(n).is_some());
    let promotion = network.add_point(name, 0..0);
    let grounded =
        TemporalConstraint::new(TimePointId::ORIGIN, promotion, now, now, Provenance::Fired);
    // A new point grounded after every fired one: consistent.
    let _ = network.add_constraint(grounded);
    let mut points = vec![promotion];
    for point in &safe.points()[1..] {
        let name = fresh(&point.name, |n| network.point_named(n).is_some());
        points.push(network.add_point(name, point.span.clone()));
    }
    let map = |p: TimePointId| points[p.index()];
    for c in safe.stn().constraints() {
        if c.provenance == Provenance::AfterOrigin {
            continue;
        }
        let mut c = c.clone();
        (c.from, c.to) = (map(c.from), map(c.to));
        // The safe network loaded consistent; relative to a point at `now` it still is.
        let _ = network.add_constraint(c);
    }
    let offset = network.goals().len() as u32;
    for goal in safe.goals() {
        let mut goal = goal.clone();
        (goal.start, goal.end) = (map(goal.start), map(goal.end));
        goal.parent = goal.parent.map(|p| GoalId(p.0 + offset));
        goal.name = fresh(&goal.name, |n| network.goal_named(n).is_some());
        network.add_goal(goal);
        state.types.push(None);
        state.retired.push(false);
    }
    promotion
}
