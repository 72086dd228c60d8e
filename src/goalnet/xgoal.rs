//! Executable goals (mds-goal-networks.md §1.6; AG §1.2.6, GP §3.6): the merge of every goal on
//! one state variable that covers the interval between two consecutive points of that SV's
//! timeline.

use super::constraint_set::ConstraintSet;
use super::goal::{Goal, GoalId, GoalKind};
use super::time_point::TimePointId;
use crate::plant::ComponentId;

/// One interval of a state variable's timeline and the merged constraint that holds on it.
#[derive(Debug, Clone, PartialEq)]
pub struct XGoal {
    /// The state variable.
    pub sv: ComponentId,
    /// The interval's first point.
    pub start: TimePointId,
    /// The interval's last point.
    pub end: TimePointId,
    /// The merge of the constituents' constraints (the *ordinary* constraint).
    pub constraint: ConstraintSet,
    /// The strongest constituent kind (`Unconstrained` when there is none).
    pub kind: GoalKind,
    /// The goals merged into it, in network order.
    pub constituents: Vec<GoalId>,
}

impl XGoal {
    /// Merges the given goals (all on `sv`) over `[start, end]`; with none, the XGoal is
    /// unconstrained over a domain of `domain` values.
    pub fn merge<'a>(
        sv: ComponentId,
        start: TimePointId,
        end: TimePointId,
        domain: usize,
        goals: impl IntoIterator<Item = (GoalId, &'a Goal)>,
    ) -> XGoal {
        let mut xgoal = XGoal {
            sv,
            start,
            end,
            constraint: ConstraintSet::unconstrained(domain),
            kind: GoalKind::Unconstrained,
            constituents: Vec::new(),
        };
        for (id, goal) in goals {
            xgoal.constraint = xgoal.constraint.merge(&goal.constraint);
            xgoal.kind = xgoal.kind.stronger(goal.kind);
            xgoal.constituents.push(id);
        }
        xgoal
    }

    /// Whether its constituents cannot hold together (empty control set).
    pub fn is_empty(&self) -> bool {
        self.constraint.is_empty()
    }
}
