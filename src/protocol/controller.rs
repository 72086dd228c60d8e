//! Controllers (seed 001 ¶6–¶7): the [`Controller`] trait the explorer drives, and the
//! course-of-action controller of the seed.

use std::collections::VecDeque;
use std::fmt::Debug;
use std::hash::Hash;

use super::messages::{ConstraintId, Message, Outcome, Reason};
use super::posandhead::{Command, Constraint, StateValue, coa, satisfy};

/// A controller of the position-and-heading state variable: it receives constraints and new
/// values and answers with messages (commands for the actuator, `endcstr` for the state
/// variable). A state of the explorer holds one, so it is a value: cloned, compared, hashed.
pub trait Controller: Clone + Eq + Hash + Debug {
    /// A constraint arrives (rule C-new when idle).
    fn on_constraint(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message>;
    /// `newval(v)` arrives (rule C-val when processing).
    fn on_newval(&mut self, value: StateValue) -> Vec<Message>;
    /// The constraints being processed now (`waitafter ≠ nomsg`); the protocol allows at most
    /// one (P-excl).
    fn processing(&self) -> Vec<ConstraintId>;
}

/// The constraint a [`CoaController`] is processing: its `waitafter` when not `nomsg`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Processing {
    id: ConstraintId,
    constraint: Constraint,
    /// The course of action's commands not issued yet (the stored tail, ¶6).
    rest: VecDeque<Command>,
}

/// The seed's course-of-action controller: on a constraint it plans `coa(v, c)` once from the
/// value it last heard and issues it command by command, each after the `newval` the previous
/// one caused (C-new, C-val of mds-goal-networks.md §4.1). One constraint at a time: those
/// that arrive while it processes one wait in a FIFO queue (§4.2 R5).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CoaController {
    /// The last value heard (the state variable's initial value, then each `newval`).
    value: StateValue,
    /// `None` is `nomsg`: idle.
    waitafter: Option<Processing>,
    /// Constraints that arrived while processing, oldest first.
    queue: VecDeque<(ConstraintId, Constraint)>,
}

impl CoaController {
    /// An idle controller that knows the state variable's initial value.
    pub fn new(value: StateValue) -> Self {
        CoaController {
            value,
            waitafter: None,
            queue: VecDeque::new(),
        }
    }

    /// C-new on `constraint`, then on queued constraints while they end at once.
    fn start(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        let mut out = Vec::new();
        let mut next = Some((id, constraint));
        while let Some((id, constraint)) = next.take() {
            if satisfy(&self.value, &constraint) {
                out.push(end(id, Outcome::Success));
            } else {
                let mut rest: VecDeque<Command> = coa(&self.value, &constraint).into();
                match rest.pop_front() {
                    // §5 C12: an empty course of action has no first command: it fails now.
                    None => out.push(end(id, Outcome::Failure(Reason::CoaNoSuccess))),
                    Some(command) => {
                        out.push(Message::Command { id, command });
                        self.waitafter = Some(Processing {
                            id,
                            constraint,
                            rest,
                        });
                        break;
                    }
                }
            }
            next = self.queue.pop_front();
        }
        out
    }
}

impl CoaController {
    /// Withdraws constraint `id` (beyond the seed, whose constraints only end by `endcstr`: the
    /// executive retired the goal it served). Being processed, its course of action stops — no
    /// further command — and the next queued constraint starts (its messages are returned);
    /// queued, it is dropped. Nothing is said back: the goal that asked is gone.
    pub fn retract(&mut self, id: ConstraintId) -> Vec<Message> {
        self.queue.retain(|(queued, _)| *queued != id);
        if self.waitafter.as_ref().is_none_or(|p| p.id != id) {
            return Vec::new();
        }
        self.waitafter = None;
        match self.queue.pop_front() {
            Some((next, constraint)) => self.start(next, constraint),
            None => Vec::new(),
        }
    }
}

/// The `endcstr` message.
fn end(id: ConstraintId, outcome: Outcome) -> Message {
    Message::EndCstr { id, outcome }
}

impl Controller for CoaController {
    fn on_constraint(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        if self.waitafter.is_some() {
            self.queue.push_back((id, constraint));
            return Vec::new();
        }
        self.start(id, constraint)
    }

    fn on_newval(&mut self, value: StateValue) -> Vec<Message> {
        self.value = value;
        let Some(processing) = &mut self.waitafter else {
            return Vec::new();
        };
        let outcome = if satisfy(&value, &processing.constraint) {
            Outcome::Success
        } else if let Some(command) = processing.rest.pop_front() {
            return vec![Message::Command {
                id: processing.id,
                command,
            }];
        } else {
            Outcome::Failure(Reason::CoaNoSuccess)
        };
        let id = processing.id;
        self.waitafter = None;
        let mut out = vec![end(id, outcome)];
        if let Some((next, constraint)) = self.queue.pop_front() {
            out.extend(self.start(next, constraint));
        }
        out
    }

    fn processing(&self) -> Vec<ConstraintId> {
        self.waitafter.iter().map(|p| p.id).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::posandhead::{Heading, Pose};

    fn at(x: i32, y: i32, heading: Heading) -> StateValue {
        StateValue::Known(Pose { x, y, heading })
    }

    fn reach(x: i32, y: i32) -> Constraint {
        Constraint::PosHead {
            x: Some(x),
            y: Some(y),
            heading: None,
        }
    }

    /// C-new's first branch: already satisfied, `endcstr` success and still idle.
    #[test]
    fn a_satisfied_constraint_ends_at_once() {
        let mut c = CoaController::new(at(2, 2, Heading::E));
        assert_eq!(c.on_constraint(0, reach(2, 2)), [end(0, Outcome::Success)]);
        assert!(c.processing().is_empty());
    }

    /// C-new then C-val: the plan is issued one command per `newval`, and a value that misses
    /// the goal after the last command ends it with `coanosuccess` (R3's blocked drive).
    #[test]
    fn commands_go_one_per_newval_and_an_exhausted_plan_fails() {
        let mut c = CoaController::new(at(0, 0, Heading::E));
        let drive = |id| Message::Command {
            id,
            command: Command::Drive,
        };
        assert_eq!(c.on_constraint(0, reach(2, 0)), [drive(0)]);
        assert_eq!(c.processing(), [0]);
        assert_eq!(c.on_newval(at(1, 0, Heading::E)), [drive(0)]);
        assert_eq!(
            c.on_newval(at(1, 0, Heading::E)),
            [end(0, Outcome::Failure(Reason::CoaNoSuccess))]
        );
        assert!(c.processing().is_empty());
    }

    /// A retracted constraint issues no further command; the one queued behind it starts.
    #[test]
    fn a_retracted_constraint_stops_and_the_next_starts() {
        let mut c = CoaController::new(at(0, 0, Heading::E));
        c.on_constraint(0, reach(2, 0));
        c.on_constraint(1, reach(0, 1));
        c.on_constraint(2, reach(1, 1));
        // Queued: dropped, nothing to say.
        assert!(c.retract(2).is_empty());
        assert_eq!(
            c.retract(0),
            [Message::Command {
                id: 1,
                command: Command::Turn(Heading::N)
            }]
        );
        assert_eq!(c.processing(), [1]);
        // The first constraint's drive reports back: heard, but it asks for nothing now.
        assert_eq!(
            c.on_newval(at(1, 0, Heading::N)),
            [Message::Command {
                id: 1,
                command: Command::Drive
            }]
        );
        assert!(c.retract(1).is_empty());
        assert!(c.processing().is_empty());
        assert!(c.on_newval(at(1, 1, Heading::N)).is_empty());
    }

    /// One constraint at a time (R5): a second one waits, and starts from the value the first
    /// left when the first ends.
    #[test]
    fn a_constraint_arriving_while_processing_waits_its_turn() {
        let mut c = CoaController::new(at(0, 0, Heading::E));
        c.on_constraint(0, reach(1, 0));
        assert!(c.on_constraint(1, reach(1, 1)).is_empty());
        assert_eq!(c.processing(), [0]);
        let out = c.on_newval(at(1, 0, Heading::E));
        assert_eq!(
            out,
            [
                end(0, Outcome::Success),
                Message::Command {
                    id: 1,
                    command: Command::Turn(Heading::N)
                }
            ]
        );
        assert_eq!(c.processing(), [1]);
    }
}
