//! The components between the controller and the device, and the state variable (seed 001
//! ¶9, ¶12). The rover adaptation makes the actuator, sensor and estimator *sort conversions*:
//! each passes its input on unchanged as a message of the next interface, so the estimate is
//! the rover's true pose. They are still separate hops, each a delivery the explorer
//! interleaves with the others.

use super::messages::{ConstraintId, Message, Outcome};
use super::posandhead::StateValue;

/// The actuator: a controller command becomes a device message (same name, another sort).
pub fn actuator(message: &Message) -> Option<Message> {
    match message {
        Message::Command { command, .. } => Some(Message::Execute(*command)),
        _ => None,
    }
}

/// The sensor: a device report becomes a measurement (`executecmd`).
pub fn sensor(message: &Message) -> Option<Message> {
    match message {
        Message::Report(pose) => Some(Message::Measurement(*pose)),
        _ => None,
    }
}

/// The estimator: a measurement becomes the state variable's value (`verifystate`).
pub fn estimator(message: &Message) -> Option<Message> {
    match message {
        Message::Measurement(pose) => Some(Message::Estimate(StateValue::Known(*pose))),
        _ => None,
    }
}

/// The position-and-heading state variable (¶10): its value, which it passes on to the
/// controller as `newval`, and the `endcstr`s it has received, in order.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct StateVariable {
    /// The current value.
    pub value: StateValue,
    /// Every `endcstr` received.
    pub ended: Vec<(ConstraintId, Outcome)>,
}

impl StateVariable {
    /// A state variable holding its initial value, no constraint ended.
    pub fn new(value: StateValue) -> Self {
        StateVariable {
            value,
            ended: Vec::new(),
        }
    }

    /// Receives an estimate (answered by `newval`) or an `endcstr` (recorded).
    pub fn receive(&mut self, message: &Message) -> Option<Message> {
        match message {
            Message::Estimate(value) => {
                self.value = *value;
                Some(Message::NewVal(*value))
            }
            Message::EndCstr { id, outcome } => {
                self.ended.push((*id, *outcome));
                None
            }
            _ => None,
        }
    }
}
