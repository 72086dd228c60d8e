//! Command acknowledgements: flight software's answer to the last command on a control, used
//! by mode estimation as evidence about whether the command happened (DESIGN.md §8, §9;
//! PLEXIL's command handles, F´'s command responses).
//!
//! A control may declare an **acknowledgement observable** (`acknowledgements: { "PDE.cmd":
//! "PDE.ack" }`): an attribute whose values are among [`Answer`]'s names — `accepted`,
//! `rejected` and `none` at least, `completed` and `failed` optionally. It is reported with the
//! observation o(i+1) and answers for the command μ(i) sent on its control in the cycle before;
//! in a cycle in which the control was not commanded it says nothing (a held report of an older
//! command's answer is not evidence about this cycle).
//!
//! What estimation makes of it ([`Commands::acknowledged`](super::Commands::acknowledged)):
//! - `rejected` or `failed`: the command was **not carried out** — the step is estimated with
//!   the control at its idle value, as if the command had not been sent. Nothing the command
//!   would have enabled can explain what follows, so an unchanged plant is not evidence of a
//!   fault.
//! - `accepted` or `completed`: the command **reached the hardware**. The model's stay
//!   probability beside a commanded transition (the valve's 0.001 of "the command did not
//!   take") is the chance that it did not; given the acknowledgement that branch is impossible,
//!   so a component with a transition the command enables does not stay in its mode for want of
//!   it: the stay's likelihood is 0 (`plant::Enabled::delivered`), and the belief is then
//!   renormalised as for any evidence. A component that cannot obey (stuck) has no transition
//!   the command enables and is unaffected, which is what makes "accepted but no flow" a fault
//!   with nothing else left to explain it.
//! - `none`, or no report: no evidence; the step is estimated as without acknowledgements.
//!
//! The acknowledgement is kept out of the constraint store: it is evidence about the command,
//! not about a mode, so no constraint may mention it (the loader refuses one that does). It is
//! also left out of the SAT solver until a question names it ([`Plant::theory`](super::Plant::theory)):
//! encoded, its values would be decided in every satisfiable question, about 0.6 % of the EDL's
//! instructions at a 1 s cycle. An answer that says nothing this cycle (held from an earlier
//! command, or on a control not commanded) costs no copy of the commands.

use crate::logic::{ValueId, VarId};

/// One answer of flight software to a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Answer {
    /// No answer (yet): no evidence.
    None,
    /// Taken for execution: it reached the hardware.
    Accepted,
    /// Refused: it was not carried out.
    Rejected,
    /// Carried out to the end.
    Completed,
    /// Taken but not carried out (an execution error in flight software).
    Failed,
}

impl Answer {
    /// The values an acknowledgement observable must have.
    pub const REQUIRED: [&'static str; 3] = ["none", "accepted", "rejected"];

    /// The values it may have besides.
    pub const OPTIONAL: [&'static str; 2] = ["completed", "failed"];

    /// The answer a value's name stands for.
    pub fn named(name: &str) -> Option<Answer> {
        Some(match name {
            "none" => Answer::None,
            "accepted" => Answer::Accepted,
            "rejected" => Answer::Rejected,
            "completed" => Answer::Completed,
            "failed" => Answer::Failed,
            _ => return None,
        })
    }

    /// Whether the command was carried out: `Some(true)` when it reached the hardware,
    /// `Some(false)` when it did not, `None` when the answer does not say.
    pub fn carried_out(self) -> Option<bool> {
        match self {
            Answer::None => None,
            Answer::Accepted | Answer::Completed => Some(true),
            Answer::Rejected | Answer::Failed => Some(false),
        }
    }
}

/// A control's acknowledgement observable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Acknowledgement {
    /// The control it answers for.
    pub control: VarId,
    /// The observable that reports the answer.
    pub observable: VarId,
    /// The answer each value of the observable stands for, by value.
    answers: Vec<Answer>,
}

impl Acknowledgement {
    /// `observable` answers for `control`; `answers` by the observable's values, in order.
    pub fn new(control: VarId, observable: VarId, answers: Vec<Answer>) -> Acknowledgement {
        Acknowledgement {
            control,
            observable,
            answers,
        }
    }

    /// The answer `value` of the observable stands for (no evidence for a value out of range).
    pub fn answer(&self, value: ValueId) -> Answer {
        self.answers
            .get(value.index())
            .copied()
            .unwrap_or(Answer::None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_is_an_answer_and_says_whether_the_command_was_carried_out() {
        let carried: Vec<_> = Answer::REQUIRED
            .iter()
            .chain(&Answer::OPTIONAL)
            .map(|name| Answer::named(name).map(Answer::carried_out))
            .collect();
        assert_eq!(
            carried,
            [
                Some(None),
                Some(Some(true)),
                Some(Some(false)),
                Some(Some(true)),
                Some(Some(false)),
            ]
        );
        assert_eq!(Answer::named("ok"), None);
    }
}
