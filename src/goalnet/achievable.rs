//! Whether the goals delegated to a controller can be achieved
//! (mds-goal-networks.md §1.7 `is_achievable(xgoal)`, which a state variable's achievers answer):
//! the scheduler's question for a state variable that is not a component, asked of its
//! controller instead of mode reconfiguration.
//!
//! A goal delegated to seed 001's course-of-action controller is achievable when the state
//! variable's current value satisfies it, or when the course of action the controller would
//! plan from that value (`coa`, fixed when the constraint arrives) reaches it on the
//! controller's own model of the device: the grid without obstacles, which the controller does
//! not know of (§4.2 R3) — so a goal an obstacle blocks is accepted here and fails when the
//! controller answers `coanosuccess`. From `uk` there is nothing to plan from: unachievable.
//! Only goals whose start point has not fired are judged (the others are the controller's
//! already), each from the current value, not from where an earlier delegated goal on the same
//! state variable will leave it.

use super::network::GoalNetwork;
use super::schedule::ScheduleError;
use super::time_point::TimePointId;
use crate::protocol::CoaDeclaration;
use crate::protocol::posandhead::{StateValue, coa, satisfy};
use crate::protocol::rover::Grid;

/// The first delegated goal of `network` whose start has not fired and that its controller
/// cannot achieve from `values` (one per controller of `controllers`), as a scheduling error.
pub fn judge_delegated(
    network: &GoalNetwork,
    controllers: &[CoaDeclaration],
    values: &[StateValue],
    fired: impl Fn(TimePointId) -> bool,
) -> Result<(), ScheduleError> {
    for (i, goal) in network.goals().iter().enumerate() {
        let Some(delegate) = goal.delegate else {
            continue;
        };
        let (declaration, value) = (
            &controllers[delegate.controller],
            values[delegate.controller],
        );
        let model = Grid {
            size: declaration.grid.size,
            obstacles: Default::default(),
        };
        let reached =
            coa(&value, &delegate.constraint)
                .into_iter()
                .try_fold(value, |v, command| match v {
                    StateValue::Known(pose) => {
                        Some(StateValue::Known(model.execute(pose, command)))
                    }
                    StateValue::Unknown => None,
                });
        // An empty course of action leaves the value as it is: achievable only if satisfied.
        let achievable = reached.is_some_and(|v| satisfy(&v, &delegate.constraint));
        if !achievable && !fired(goal.start) {
            return Err(ScheduleError::DelegatedUnachievable {
                goal: super::goal::GoalId(i as u32),
                sv: declaration.sv.clone(),
                value: value.to_string(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Span;
    use crate::goalnet::constraint_set::ConstraintSet;
    use crate::goalnet::goal::{Delegate, Goal, GoalKind};
    use crate::protocol::posandhead::{Constraint, Heading, Pose};

    fn network(constraint: Constraint) -> GoalNetwork {
        let mut network = GoalNetwork::new();
        let end = network.add_point("TP_E", Span::default());
        network.add_goal(Goal {
            name: "go".into(),
            sv: None,
            kind: GoalKind::Transition,
            constraint: ConstraintSet::unconstrained(0),
            delegate: Some(Delegate {
                controller: 0,
                constraint,
            }),
            text: String::new(),
            start: TimePointId::ORIGIN,
            end,
            parent: None,
            priority: 0,
            span: Span::default(),
        });
        network
    }

    fn declaration(obstacles: &[(i32, i32)]) -> Vec<CoaDeclaration> {
        let rover = Pose {
            x: 0,
            y: 0,
            heading: Heading::E,
        };
        vec![CoaDeclaration {
            sv: "pose".into(),
            grid: Grid {
                size: 5,
                obstacles: obstacles.iter().copied().collect(),
            },
            rover,
            known: true,
        }]
    }

    fn to(x: i32, y: i32) -> Constraint {
        Constraint::PosHead {
            x: Some(x),
            y: Some(y),
            heading: None,
        }
    }

    /// A known pose reaches any cell by its course of action; an obstacle the controller does
    /// not know of does not make the goal unachievable (§4.2 R3 is a run-time failure).
    #[test]
    fn a_known_pose_can_reach_any_cell_whatever_the_obstacles() {
        let value = StateValue::Known(declaration(&[])[0].rover);
        let never = |_| false;
        assert!(
            judge_delegated(&network(to(3, 2)), &declaration(&[(2, 0)]), &[value], never).is_ok()
        );
        assert!(judge_delegated(&network(to(0, 0)), &declaration(&[]), &[value], never).is_ok());
    }

    /// From `uk` there is no course of action (§5 C12): unachievable, naming the state
    /// variable and its value — unless the goal has started (it is the controller's already).
    #[test]
    fn from_uk_a_goal_is_unachievable_until_it_has_started() {
        let uk = [StateValue::Unknown];
        let error = judge_delegated(&network(to(1, 1)), &declaration(&[]), &uk, |_| false);
        assert_eq!(
            error,
            Err(ScheduleError::DelegatedUnachievable {
                goal: crate::goalnet::GoalId(0),
                sv: "pose".into(),
                value: "uk".into()
            })
        );
        assert!(judge_delegated(&network(to(1, 1)), &declaration(&[]), &uk, |_| true).is_ok());
        assert!(
            judge_delegated(&network(Constraint::NoCstr), &declaration(&[]), &uk, |_| {
                false
            })
            .is_ok()
        );
    }
}
