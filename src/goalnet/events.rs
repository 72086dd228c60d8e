//! What the [`GoalController`] reports each cycle (DESIGN.md §15.3 "Events"): the execution's
//! [`GoalEvent`]s and the mission-level ones — tactics chosen and rejected, failure responses
//! with their explanation chains (mds-goal-networks.md §6 item 3), promotions and safing.

use std::fmt;

#[cfg(doc)]
use super::controller::GoalController;
use super::execution::GoalEvent;
use super::goal::GoalId;
use super::tactic::Response;

/// Something that happened to the mission this cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum MissionEvent {
    /// An event of the running network's execution (its ids are the running network's).
    Goal(GoalEvent),
    /// Elaboration chose this tactic for a goal (of the network then promoted).
    TacticChosen {
        /// The goal's name.
        goal: String,
        /// The tactic's number in its type's list, from 1 as the seed counts.
        tactic: usize,
    },
    /// Elaboration rejected a tactic for a goal (of a candidate network).
    TacticRejected {
        /// The goal's name.
        goal: String,
        /// The tactic's number, from 1.
        tactic: usize,
        /// Why (the scheduler's explanation, or the children's tactics all rejected).
        reason: String,
    },
    /// A failed goal's response, carried out, with the whole chain: one per failure.
    ResponseTaken {
        /// The goal that failed.
        goal: GoalId,
        /// Its type's response (the first step of the chain); `None` when no response is
        /// taken (the mission declares none, or the safe network runs).
        response: Option<Response>,
        /// The chain, from the failure to its outcome.
        explanation: Explanation,
    },
    /// A proposed network replaced the running one (mds-goal-networks.md §2.3 steps d–j).
    Promoted {
        /// Why it was proposed.
        cause: String,
    },
    /// A proposal could not be promoted; the old network runs on.
    PromotionFailed {
        /// Why.
        reason: String,
    },
    /// The safe network replaced the running one (§2.8); nothing of the old one fires again.
    Safing {
        /// The failure that led there, explained.
        cause: String,
    },
    /// A goal of the safe network could not be scheduled from the state safing found, and was
    /// dropped; the rest of the safe network runs (DESIGN.md §15.2, best effort).
    SafeGoalDropped {
        /// The goal's name.
        goal: String,
        /// The scheduler's reason.
        reason: String,
    },
}

/// One link of a failure's explanation chain.
#[derive(Debug, Clone, PartialEq)]
pub enum ResponseStep {
    /// The failure passed to the parent.
    FailUp,
    /// The failure is ignored.
    Ignored,
    /// The goal was re-elaborated with this tactic (numbered from 1).
    ReElaborated {
        /// The goal.
        goal: String,
        /// The tactic.
        tactic: usize,
    },
    /// The proposal was promoted.
    Promoted,
    /// Re-elaboration of the goal found no tactic (or no budget) left.
    NoTacticLeft {
        /// The goal.
        goal: String,
        /// Why.
        reason: String,
    },
    /// The goal to re-elaborate has not failed itself and its interval ends this cycle (its end
    /// point has fired or is due now): there is no time left that a tactic could serve, so the
    /// failure below it needs no repair; the goal is judged on its own at its end.
    IntervalEnds {
        /// The goal.
        goal: String,
        /// Its end point.
        point: String,
    },
    /// The failure reached a goal with no parent.
    Root {
        /// The goal.
        goal: String,
    },
    /// The safe network was promoted.
    Safing,
    /// Another failure of the same cycle led to safing first, so this one's response (a
    /// re-elaboration) was not tried: safing wins (mds-goal-networks.md §2.5 step 4).
    Superseded,
    /// The goal to re-elaborate lies inside the subtree of a goal another failure of the same
    /// cycle re-elaborated: that re-elaboration replaced it, so it is not re-elaborated again.
    Replaced {
        /// The ancestor re-elaborated in this cycle.
        by: String,
    },
    /// The mission declares no goal types, so no responses: the network runs on.
    NoResponses,
    /// Safing has been invoked: the safe network runs, and its failures get no response.
    SafeNetworkRuns,
}

/// Why a goal failed and what was done about it: "heater1 failed: switch1 = stuck-open (p 0.97)
/// → fail up → stay-warm re-elaborated with tactic 2 → promoted".
#[derive(Debug, Clone, PartialEq)]
pub struct Explanation {
    /// The failed goal's name.
    pub goal: String,
    /// Its state variable's name.
    pub sv: String,
    /// The mode ŝ had it in.
    pub mode: String,
    /// The probability of that mode.
    pub probability: f64,
    /// The responses, in order.
    pub steps: Vec<ResponseStep>,
}

impl fmt::Display for ResponseStep {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            ResponseStep::FailUp => write!(f, "fail up"),
            ResponseStep::Ignored => write!(f, "ignored"),
            ResponseStep::ReElaborated { goal, tactic } => {
                write!(f, "{goal} re-elaborated with tactic {tactic}")
            }
            ResponseStep::Promoted => write!(f, "promoted"),
            ResponseStep::NoTacticLeft { goal, reason } => {
                write!(f, "{goal}: no tactic left ({reason})")
            }
            ResponseStep::IntervalEnds { goal, point } => {
                write!(
                    f,
                    "{goal}'s interval ends at {point}: nothing left to re-elaborate"
                )
            }
            ResponseStep::Root { goal } => write!(f, "{goal} is a root"),
            ResponseStep::Safing => write!(f, "safing"),
            ResponseStep::Superseded => write!(f, "safing (another failure of this cycle)"),
            ResponseStep::Replaced { by } => write!(f, "replaced by the re-elaboration of {by}"),
            ResponseStep::NoResponses => {
                write!(
                    f,
                    "no response (the mission declares none): the network runs on"
                )
            }
            ResponseStep::SafeNetworkRuns => {
                write!(f, "no response (the safe network runs)")
            }
        }
    }
}

impl fmt::Display for Explanation {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        // Two decimals, as the log's diagnoses print a probability.
        write!(
            f,
            "{} failed: {} = {} (p {:.2})",
            self.goal, self.sv, self.mode, self.probability
        )?;
        for step in &self.steps {
            write!(f, " → {step}")?;
        }
        Ok(())
    }
}
