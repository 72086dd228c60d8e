//! The protocol run one cycle at a time by the executive, for a mission goal *delegated* to a
//! course-of-action controller (mds-goal-networks.md §1.7, §2.9, §4).
//!
//! A [`Delegation`] holds the components of seed 001's configuration — the
//! [`CoaController`], the actuator, the rover on its [`Grid`], the sensor, the estimator and the
//! position-and-heading [`StateVariable`] — and delivers their messages first in, first out.
//! The explorer ([`explore()`](crate::exploration::protocol::explore())) tries every order;
//! the executive runs one, so a run is deterministic.
//!
//! The cycle follows mds-goal-networks.md §2.9: the device's report of the last command is a
//! measurement of *this* cycle (step 1), it goes through sensor and estimator to the state
//! variable (step 2) and as `newval` to the controller, which answers with its next command or
//! `endcstr` (step 6); the command goes through the actuator to the device, which executes it
//! between cycles — its report waits for the next cycle. So a course of action of n commands
//! takes n cycles after the constraint is sent, one command a cycle.

use std::collections::VecDeque;

use super::components::{StateVariable, actuator, estimator, sensor};
use super::controller::{CoaController, Controller};
use super::messages::{ConstraintId, Message, Outcome};
use super::posandhead::{Command, Constraint, Pose, StateValue};
use super::rover::Grid;

/// A course-of-action controller as a mission declares it: the state variable it controls
/// (not a plant component) and the device it commands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CoaDeclaration {
    /// The state variable's name, as goals name it (`"pose"`).
    pub sv: String,
    /// The grid the rover drives on.
    pub grid: Grid,
    /// The rover's true pose when the mission starts.
    pub rover: Pose,
    /// Whether the estimator starts knowing that pose (otherwise the state variable is `uk`).
    pub known: bool,
}

impl CoaDeclaration {
    /// The state variable's initial value.
    pub fn initial_value(&self) -> StateValue {
        match self.known {
            true => StateValue::Known(self.rover),
            false => StateValue::Unknown,
        }
    }
}

/// What the executive reports of a delegation's cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Delivered {
    /// The controller issued a command for a constraint.
    Command {
        /// The constraint it serves.
        id: ConstraintId,
        /// The command.
        command: Command,
    },
    /// The controller ended a constraint.
    Ended {
        /// The constraint.
        id: ConstraintId,
        /// How it ended.
        outcome: Outcome,
    },
}

/// A course-of-action controller and the components around it, run by the executive.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Delegation {
    controller: CoaController,
    grid: Grid,
    /// The rover's true pose.
    rover: Pose,
    sv: StateVariable,
    /// The device's reports not yet measured: they are the next cycle's measurements.
    reports: VecDeque<Message>,
}

impl Delegation {
    /// The components as declared, idle; the controller and the state variable start at the
    /// estimator's initial value.
    pub fn new(declaration: &CoaDeclaration) -> Self {
        let value = declaration.initial_value();
        Delegation {
            controller: CoaController::new(value),
            grid: declaration.grid.clone(),
            rover: declaration.rover,
            sv: StateVariable::new(value),
            reports: VecDeque::new(),
        }
    }

    /// The state variable's value (what the estimator last said).
    pub fn value(&self) -> StateValue {
        self.sv.value
    }

    /// The rover's true pose (the device's, which the executive never reads).
    pub fn rover(&self) -> Pose {
        self.rover
    }

    /// Sends a constraint to the controller (C-new): it ends at once, issues its first command
    /// (executed by the device before the next cycle), or waits in the controller's queue.
    pub fn send(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Delivered> {
        self.deliver(VecDeque::from([Message::Constraint { id, constraint }]))
    }

    /// Withdraws constraint `id` from the controller ([`CoaController::retract`]): no further
    /// command for it; what the controller starts instead is delivered.
    pub fn retract(&mut self, id: ConstraintId) -> Vec<Delivered> {
        let next = self.controller.retract(id);
        self.deliver(next.into())
    }

    /// One cycle: the reports of the last cycle's commands are measured and estimated, the
    /// controller hears the new value (C-val) and answers.
    pub fn cycle(&mut self) -> Vec<Delivered> {
        let reports = std::mem::take(&mut self.reports);
        self.deliver(reports)
    }

    /// Delivers messages first in, first out, until only the device's reports are left.
    fn deliver(&mut self, mut queue: VecDeque<Message>) -> Vec<Delivered> {
        let mut out = Vec::new();
        while let Some(message) = queue.pop_front() {
            let next: Vec<Message> = match message {
                Message::Constraint { id, constraint } => {
                    self.controller.on_constraint(id, constraint)
                }
                Message::Command { id, command } => {
                    out.push(Delivered::Command { id, command });
                    actuator(&message).into_iter().collect()
                }
                Message::Execute(command) => {
                    self.rover = self.grid.execute(self.rover, command);
                    self.reports.push_back(Message::Report(self.rover));
                    Vec::new()
                }
                Message::Report(_) => sensor(&message).into_iter().collect(),
                Message::Measurement(_) => estimator(&message).into_iter().collect(),
                Message::Estimate(_) => self.sv.receive(&message).into_iter().collect(),
                Message::NewVal(value) => self.controller.on_newval(value),
                Message::EndCstr { id, outcome } => {
                    self.sv.receive(&message);
                    out.push(Delivered::Ended { id, outcome });
                    Vec::new()
                }
            };
            queue.extend(next);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::messages::Reason;
    use crate::protocol::posandhead::Heading;

    fn declaration(obstacles: &[(i32, i32)]) -> CoaDeclaration {
        CoaDeclaration {
            sv: "pose".into(),
            grid: Grid {
                size: 5,
                obstacles: obstacles.iter().copied().collect(),
            },
            rover: Pose {
                x: 0,
                y: 0,
                heading: Heading::E,
            },
            known: true,
        }
    }

    fn reach(x: i32, y: i32) -> Constraint {
        Constraint::PosHead {
            x: Some(x),
            y: Some(y),
            heading: None,
        }
    }

    /// Runs cycles until the constraint ends; the commands per cycle and the outcome.
    fn run(delegation: &mut Delegation, constraint: Constraint) -> (Vec<Vec<Delivered>>, Outcome) {
        let mut cycles = vec![delegation.send(0, constraint)];
        for _ in 0..20 {
            if let Some(&Delivered::Ended { outcome, .. }) = cycles.last().and_then(|c| c.last()) {
                return (cycles, outcome);
            }
            cycles.push(delegation.cycle());
        }
        panic!("the constraint never ended: {cycles:?}");
    }

    /// §2.9 and §4.2 R3-like on a free grid: one command a cycle, `endcstr` success in the
    /// cycle whose `newval` satisfies the constraint, the state variable at the goal.
    #[test]
    fn a_free_course_of_action_issues_one_command_a_cycle_and_succeeds() {
        let mut delegation = Delegation::new(&declaration(&[]));
        let (cycles, outcome) = run(&mut delegation, reach(2, 1));
        assert_eq!(outcome, Outcome::Success);
        let commands: Vec<usize> = cycles
            .iter()
            .map(|c| {
                c.iter()
                    .filter(|d| matches!(d, Delivered::Command { .. }))
                    .count()
            })
            .collect();
        // drive, drive, turn(N), drive; then the success.
        assert_eq!(commands, [1, 1, 1, 1, 0]);
        assert!(satisfied(&delegation, reach(2, 1)));
    }

    /// §4.2 R3: the obstacle the controller does not know of blocks the drives; the course of
    /// action runs out and the constraint ends `coanosuccess`.
    #[test]
    fn an_obstacle_ends_the_constraint_with_coanosuccess() {
        let mut delegation = Delegation::new(&declaration(&[(2, 0)]));
        let (cycles, outcome) = run(&mut delegation, reach(3, 0));
        assert_eq!(outcome, Outcome::Failure(Reason::CoaNoSuccess));
        assert_eq!(cycles.len(), 4, "three drives, then the failure");
        assert_eq!(delegation.rover().x, 1);
    }

    /// C-new's first branch: a constraint satisfied now ends in the cycle it is sent.
    #[test]
    fn a_satisfied_constraint_ends_when_sent() {
        let mut delegation = Delegation::new(&declaration(&[]));
        let sent = delegation.send(4, reach(0, 0));
        assert_eq!(
            sent,
            [Delivered::Ended {
                id: 4,
                outcome: Outcome::Success
            }]
        );
    }

    /// A retracted constraint's course of action stops: the drive under way still reports,
    /// nothing more is commanded, and nothing ends.
    #[test]
    fn a_retracted_constraint_commands_nothing_more() {
        let mut delegation = Delegation::new(&declaration(&[]));
        assert_eq!(delegation.send(0, reach(3, 0)).len(), 1);
        assert_eq!(delegation.cycle().len(), 1);
        assert!(delegation.retract(0).is_empty());
        for _ in 0..5 {
            assert!(delegation.cycle().is_empty());
        }
        assert_eq!(delegation.rover().x, 2, "two drives, then none");
    }

    fn satisfied(delegation: &Delegation, constraint: Constraint) -> bool {
        crate::protocol::posandhead::satisfy(&delegation.value(), &constraint)
    }
}
