//! The messages of the protocol (seed 001 ¶4–¶9; their names, which the seed leaves out, as
//! mds-goal-networks.md §5 C12 reads them): a constraint for the controller, commands down
//! through the actuator to the device, the device's report up through sensor and estimator to
//! the state variable, `newval` to the controller, and `endcstr` back to the state variable.

use std::fmt;

use super::posandhead::{Command, Constraint, Pose, StateValue};

/// A constraint's index in its scenario (the order it is declared in).
pub type ConstraintId = usize;

/// Why a constraint was not achieved (¶4's sort `Reason`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Reason {
    /// `coanosuccess`: the course of action ran out and the constraint is not satisfied (¶7).
    CoaNoSuccess,
}

/// What an `endcstr` says: achieved, or not with a reason (¶4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Outcome {
    /// The constraint is satisfied.
    Success,
    /// It is not, for this reason.
    Failure(Reason),
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Outcome::Success => f.write_str("success"),
            Outcome::Failure(Reason::CoaNoSuccess) => f.write_str("coanosuccess"),
        }
    }
}

/// A message in flight. Each has one recipient; any message in flight may be delivered next
/// (Maude's configurations are multisets: no channel keeps order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Message {
    /// Environment → controller: achieve this constraint.
    Constraint {
        /// Which of the scenario's constraints.
        id: ConstraintId,
        /// The constraint.
        constraint: Constraint,
    },
    /// Controller → actuator: a command issued for a constraint.
    Command {
        /// The constraint it serves (what P-cmds checks it against).
        id: ConstraintId,
        /// The command.
        command: Command,
    },
    /// Actuator → device: the command as a device message (a sort conversion, ¶9, ¶12).
    Execute(Command),
    /// Device → sensor: the rover's pose after a command (¶8).
    Report(Pose),
    /// Sensor → estimator: the report as a measurement (`executecmd`, a sort conversion, ¶12).
    Measurement(Pose),
    /// Estimator → state variable: the measurement as a value (`verifystate`, ¶12).
    Estimate(StateValue),
    /// State variable → controller: `newval(v)` (¶7).
    NewVal(StateValue),
    /// Controller → state variable: `endcstr`, the constraint's outcome (¶6, ¶7).
    EndCstr {
        /// Which constraint ended.
        id: ConstraintId,
        /// How.
        outcome: Outcome,
    },
}

impl Message {
    /// Sender and recipient, for traces.
    pub fn route(&self) -> &'static str {
        match self {
            Message::Constraint { .. } => "environment → controller",
            Message::Command { .. } => "controller → actuator",
            Message::Execute(_) => "actuator → rover",
            Message::Report(_) => "rover → sensor",
            Message::Measurement(_) => "sensor → estimator",
            Message::Estimate(_) => "estimator → state variable",
            Message::NewVal(_) => "state variable → controller",
            Message::EndCstr { .. } => "controller → state variable",
        }
    }

    /// The message with its route, constraints named by `name`.
    pub fn describe(&self, name: &dyn Fn(ConstraintId) -> String) -> String {
        let body = match self {
            Message::Constraint { id, constraint } => {
                format!("constraint `{}` {constraint}", name(*id))
            }
            Message::Command { id, command } => format!("{command} (for `{}`)", name(*id)),
            Message::Execute(command) => command.to_string(),
            Message::Report(pose) | Message::Measurement(pose) => pose.to_string(),
            Message::Estimate(value) => value.to_string(),
            Message::NewVal(value) => format!("newval {value}"),
            Message::EndCstr { id, outcome } => format!("endcstr `{}` {outcome}", name(*id)),
        };
        format!("{}: {body}", self.route())
    }
}
