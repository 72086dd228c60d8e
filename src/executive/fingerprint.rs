//! A stable fingerprint of an executive's state, for explicit-state exploration
//! (`crate::exploration`): two executives with the same fingerprint make the same decisions
//! from here on, given the same observations.
//!
//! What is hashed: the cycle count and last time, the belief (each system state's modes and
//! clock starts, and its probability rounded to [`PROBABILITY_RESOLUTION`]), ŝ, the control program's
//! state (the sequencer's marking, clock references and open half-cycle, or the mission's
//! firing times, active XGoals and failed goals), the intended configuration, the helpers still
//! to bring back and the recent commanded moves (`faithful.rs`), the last command
//! μ (estimation's next step reads it), the monitors' state, and what has been reported already (which decides the
//! events of later cycles). What is not: caches that are pure functions of what is hashed
//! (goal interpretation's last answer, the sequencer's entailment answers, the estimator's
//! memo, the last observation's typed form) and history (the timelines), which no decision
//! reads.

use std::hash::{Hash, Hasher};

use super::Executive;

/// Probabilities closer than this are the same: beliefs reached along two paths whose floating
/// point sums were taken in another order agree to about 10⁻¹⁵, and a belief that differs by
/// less than 10⁻⁹ does not change ŝ unless two states tie to that precision (TimedME breaks
/// ties at 10⁻⁹ too, `estimation::TIE`).
pub const PROBABILITY_RESOLUTION: f64 = 1e-9;

impl Executive {
    /// Feeds the state that decides the executive's future to `state` (see the module
    /// documentation of `executive::fingerprint` for what is left out and why).
    pub fn fingerprint<H: Hasher>(&self, state: &mut H) {
        self.cycle.hash(state);
        self.last_time.map(f64::to_bits).hash(state);
        if let Some(belief) = &self.belief {
            belief.time().to_bits().hash(state);
            for weighted in belief.states() {
                weighted.state.modes.hash(state);
                for start in weighted.state.clock_starts.iter() {
                    start.map(f64::to_bits).hash(state);
                }
                ((weighted.probability / PROBABILITY_RESOLUTION).round() as i64).hash(state);
            }
        }
        self.most_likely.hash(state);
        self.control.fingerprint(state);
        if let Some(intended) = &self.intended {
            intended.modes().hash(state);
            (0..intended.modes().len())
                .map(|c| intended.is_named(crate::plant::ComponentId(c as u32)))
                .for_each(|named| named.hash(state));
        }
        self.last_command.hash(state);
        // The helpers to bring back, the recent commanded moves (chatter) and the last
        // contradiction reported decide later commands and events.
        self.faithful.hash(state);
        self.monitoring.fingerprint(state);
        let reported = &self.reported;
        reported.goal_locations.hash(state);
        reported.asserted.hash(state);
        reported.achieved.hash(state);
        reported.conflicts.hash(state);
        reported.goal_failure.hash(state);
        reported.plan_failure.hash(state);
        reported.awaited.hash(state);
        reported.missing.hash(state);
    }
}
