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
    /// unchanged. The submission is made at `now` — the time of the cycle it is made before,
    /// at or after the last cycle's (a time before it is refused): new points fire no earlier,
    /// and a point whose window would lie before it is refused (DESIGN.md §15.2). Before the
    /// first cycle ŝ is the plant's most likely initial state.
    ///
    /// The time it takes is the next cycle's: [`PhaseTimes::submission`](super::PhaseTimes),
    /// counted in its total and so against its deadline.
    pub fn submit(&mut self, submission: &Submission, now: f64) -> Result<(), SubmitError> {
        let started = std::time::Instant::now();
        let outcome = self.submit_now(submission, now);
        self.submission_time += started.elapsed();
        outcome
    }

    fn submit_now(&mut self, submission: &Submission, now: f64) -> Result<(), SubmitError> {
        let modes = if self.most_likely.is_empty() {
            self.plant.most_likely_initial()
        } else {
            self.most_likely.to_vec()
        };
        // NaN is not at or after anything: refused too.
        let before = |last: &f64| now.partial_cmp(last).is_none_or(|o| o.is_lt());
        if let Some(last) = self.last_time.filter(before) {
            return Err(SubmitError::Late { now, last });
        }
        match &mut self.control.0 {
            Program::Rmpl(_) => Err(SubmitError::NotAMission),
            Program::Mission(mission) => {
                mission.submit(submission, now, &modes, &self.reconfiguration)
            }
        }
    }
}
