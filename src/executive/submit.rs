//! Submitting goals to a running mission (DESIGN.md §15.4; mds-goal-networks.md §2.1–2.2): new
//! time points, the temporal constraints that place them, and goals over them, added to the
//! network being executed and rescheduled with the points already fired held at their times. A
//! submission that cannot be scheduled is refused and the running network is left as it was.
//! What a submission is lives with the goal network ([`Submission`]).

use super::Executive;
use super::control::Program;
use crate::goalnet::{Submission, SubmitError};

impl Executive {
    /// Adds goals, with their time points and temporal constraints, to the running mission
    /// (DESIGN.md §15.4) and reschedules it from ŝ with the points already fired held at their
    /// times. A submission that does not resolve or cannot be scheduled (inconsistent,
    /// unmergeable, unachievable) is refused with the reason, and the running network is left
    /// unchanged. New points fire no earlier than the last cycle's time. Before the first cycle
    /// ŝ is the plant's most likely initial state.
    ///
    /// The time it takes is the next cycle's: [`PhaseTimes::submission`](super::PhaseTimes),
    /// counted in its total and so against its deadline.
    pub fn submit(&mut self, submission: &Submission) -> Result<(), SubmitError> {
        let started = std::time::Instant::now();
        let outcome = self.submit_now(submission);
        self.submission_time += started.elapsed();
        outcome
    }

    fn submit_now(&mut self, submission: &Submission) -> Result<(), SubmitError> {
        let modes = if self.most_likely.is_empty() {
            self.plant.most_likely_initial()
        } else {
            self.most_likely.clone()
        };
        let now = self.last_time.unwrap_or(0.0);
        match &mut self.control.0 {
            Program::Rmpl(_) => Err(SubmitError::NotAMission),
            Program::Mission(mission) => {
                mission.submit(submission, now, &modes, &self.reconfiguration)
            }
        }
    }
}
