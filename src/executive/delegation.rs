//! Goals delegated to the controllers a mission declares for state variables that are not plant
//! components (mds-goal-networks.md §1.7, §2.9): the executive runs each
//! controller's protocol ([`crate::protocol::Delegation`]) one cycle at a time beside the goal
//! controller.
//!
//! Per cycle, around [`GoalController::step`]:
//! 1. before it ([`Delegations::cycle`], §2.9 steps 1–2): each device's report of the last
//!    command is measured and estimated, its controller hears `newval` and answers — the next
//!    command, or `endcstr`; an `endcstr` is handed to the goal controller, a failure
//!    (`coanosuccess`) as the goal's failure, so that this cycle's monitoring reports it and the
//!    failure responses apply;
//! 2. after it ([`Delegations::dispatch`], §2.9 step 6): every delegated goal whose start point
//!    has fired and whose constraint was not sent yet has it sent to its controller, in goal
//!    order; the first command goes out to the device, which executes it before the next cycle.
//!    Before that, the constraint of every goal the step retired (a re-elaboration, safing)
//!    while its controller still worked on it is withdrawn (beyond the seed: a safed mission
//!    must not go on driving): no further command is issued for it.
//!
//! Everything is delivered first in, first out: a run is deterministic.

use std::collections::{BTreeMap, BTreeSet};

use super::events::EventKind;
use crate::goalnet::{FailureReason, GoalController, GoalId, Mission};
use crate::protocol::messages::Outcome;
use crate::protocol::posandhead::StateValue;
use crate::protocol::{Delegation, Delivered};

/// The protocols of a mission's controllers and the delegated goals already sent.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(super) struct Delegations {
    /// One per declared controller, in the mission's order.
    runs: Vec<Delegation>,
    /// The goals whose constraint was sent (a constraint is sent once).
    sent: BTreeSet<GoalId>,
    /// Those whose constraint has not ended (nor been withdrawn) yet, with their controller.
    open: BTreeMap<GoalId, usize>,
}

impl Delegations {
    /// The mission's controllers, idle.
    pub(super) fn new(mission: &Mission) -> Self {
        Delegations {
            runs: mission.controllers.iter().map(Delegation::new).collect(),
            sent: BTreeSet::new(),
            open: BTreeMap::new(),
        }
    }

    /// The values of the controlled state variables, one per controller.
    pub(super) fn values(&self) -> Vec<StateValue> {
        self.runs.iter().map(Delegation::value).collect()
    }

    /// The value controller `controller`'s state variable holds, as the log prints it.
    pub(super) fn value(&self, controller: usize) -> String {
        self.runs[controller].value().to_string()
    }

    /// §2.9 steps 1–2 and the controllers' answers to the new values; every `endcstr` is
    /// handed to `goals`.
    pub(super) fn cycle(
        &mut self,
        mission: &Mission,
        goals: &mut GoalController,
    ) -> Vec<EventKind> {
        let mut events = Vec::new();
        for controller in 0..self.runs.len() {
            let delivered = self.runs[controller].cycle();
            events.extend(self.report(mission, controller, delivered, goals));
        }
        events
    }

    /// Sends the constraint of every delegated goal whose start point has fired (§2.9 step 6).
    pub(super) fn dispatch(
        &mut self,
        mission: &Mission,
        goals: &mut GoalController,
    ) -> Vec<EventKind> {
        let execution = goals.execution();
        let due: Vec<(GoalId, usize, _)> = (goals.network().goals().iter().enumerate())
            .filter_map(|(i, goal)| {
                let id = GoalId(i as u32);
                let delegate = goal.delegate?;
                let started = execution.fired_at(goal.start).is_some();
                let due = started && !execution.has_failed(id) && !self.sent.contains(&id);
                due.then_some((id, delegate.controller, delegate.constraint))
            })
            .collect();
        let mut events = self.withdraw_retired(mission, goals);
        for (goal, controller, constraint) in due {
            self.sent.insert(goal);
            self.open.insert(goal, controller);
            events.push(EventKind::ConstraintSent {
                goal: goals.network().goal(goal).name.clone(),
                sv: mission.controllers[controller].sv.clone(),
                constraint: constraint.to_string(),
            });
            let delivered = self.runs[controller].send(goal.index(), constraint);
            events.extend(self.report(mission, controller, delivered, goals));
        }
        events
    }

    /// Withdraws the constraints of the goals retired while their controllers worked on them
    /// (a retired goal's copy in the running network has no delegate).
    fn withdraw_retired(
        &mut self,
        mission: &Mission,
        goals: &mut GoalController,
    ) -> Vec<EventKind> {
        let retired: Vec<(GoalId, usize)> = (self.open.iter())
            .filter(|&(&g, _)| goals.network().goal(g).delegate.is_none())
            .map(|(&g, &c)| (g, c))
            .collect();
        let mut events = Vec::new();
        for (goal, controller) in retired {
            self.open.remove(&goal);
            events.push(EventKind::ConstraintWithdrawn {
                goal: goals.network().goal(goal).name.clone(),
                sv: mission.controllers[controller].sv.clone(),
                value: self.value(controller),
            });
            let delivered = self.runs[controller].retract(goal.index());
            events.extend(self.report(mission, controller, delivered, goals));
        }
        events
    }

    /// The events of what controller `controller` delivered; its `endcstr`s go to `goals`.
    fn report(
        &mut self,
        mission: &Mission,
        controller: usize,
        delivered: Vec<Delivered>,
        goals: &mut GoalController,
    ) -> Vec<EventKind> {
        let sv = &mission.controllers[controller].sv;
        let value = self.value(controller);
        let name = |goals: &GoalController, id: usize| {
            goals.network().goal(GoalId(id as u32)).name.clone()
        };
        delivered
            .into_iter()
            .map(|d| match d {
                Delivered::Command { id, command } => EventKind::ControllerCommand {
                    sv: sv.clone(),
                    command: command.to_string(),
                    goal: name(goals, id),
                },
                Delivered::Ended { id, outcome } => {
                    let goal = GoalId(id as u32);
                    self.open.remove(&goal);
                    // A goal retired while its controller worked on it (a re-elaboration or
                    // safing took it out) has nothing left to fail.
                    let live = goals.network().goal(goal).delegate.is_some();
                    let failure =
                        (outcome != Outcome::Success && live).then(|| FailureReason::Delegated {
                            value: Some(value.clone()),
                            why: format!(
                                "the controller of {sv} ended its constraint {outcome}: its \
                                 course of action ran out with the constraint unsatisfied"
                            ),
                        });
                    goals.end_delegated(goal, failure);
                    EventKind::ConstraintEnded {
                        goal: name(goals, id),
                        sv: sv.clone(),
                        outcome: outcome.to_string(),
                        value: value.clone(),
                    }
                }
            })
            .collect()
    }
}
