//! How a handle's executive runs, as C sets it: κ, the cycle deadline, the estimator's budget,
//! and the bounded-time mode.
//!
//! Mode estimation's history window (`ExecutiveOptions::history`, `ExecutiveOptions::rerun`) is
//! not here, by decision: [`KairosOptions`] is read through a pointer the caller allocated, at
//! the size of the header it was compiled against, and carries no size or version field, so a
//! field added at its end would be read past a present caller's struct. A C caller keeps the
//! defaults (16 steps, re-run on doubt); the bounded-time mode bounds the window's re-runs with
//! the rest of estimation. Exposing them needs a new ABI revision (a struct carrying its own
//! size), not a field.
//!
//! # The bounded-time mode, and what it bounds
//!
//! With `bounded` set, mode estimation must end half the cycle deadline after the cycle starts
//! (`ExecutiveOptions::estimation_deadline`): every OPSAT search of the cycle's estimation — one
//! per tracked state, and any re-estimation of the history window or fall-back expansion — stops
//! at that one instant, and the belief is the best found so far. The other half is left to the
//! sequencer, the planner and this library. When the instant (or a per-search budget) stops a
//! search the step says so (`KAIROS_STEP_SEARCH_CUT` and a search-cut event); a cycle that took
//! longer than the deadline says so too (`KAIROS_STEP_DEADLINE_OVERRUN`, with its elapsed time).
//!
//! What is guaranteed, precisely: no OPSAT search of mode estimation starts a node after the
//! instant (the node's SAT call is not interrupted, and building a search's problem is not
//! timed). Mode estimation is the phase whose cost varies by orders of magnitude (a quiet cycle
//! takes microseconds, a diagnosis milliseconds); the sequencer and the planner's look-ups have
//! no budget, so the cycle's total is bounded by measurement, and reported when missed, not
//! enforced. `kairos-ffi/tests/bounded.rs` checks the mode; docs/embedding.md has the figures.

use std::time::Duration;

use kairos::executive::ExecutiveBuilder;
use kairos::opsat::Budget;

use crate::error::{Failure, KairosStatus};

/// Options for a new handle; start from `kairos_options_default()` and change what you need.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KairosOptions {
    /// κ: how many system states mode estimation tracks (at least 1; 10 by default).
    pub kappa: u32,
    /// The cycle's wall-time deadline in seconds; 0 for none. A cycle that takes longer reports
    /// `KAIROS_STEP_DEADLINE_OVERRUN` and a deadline-overrun event.
    pub cycle_deadline_s: f64,
    /// Non-zero: the bounded-time mode (the module documentation of `options.rs` and
    /// docs/embedding.md say what it bounds); needs a deadline.
    pub bounded: u32,
    /// The estimator's time budget per OPSAT enumeration, in seconds; 0 for none.
    pub estimation_time_budget_s: f64,
    /// The estimator's budget in search nodes per OPSAT enumeration; 0 for none.
    pub estimation_node_budget: u64,
    /// How many of the most likely plant states each step names (`kairos_step_estimate_*`);
    /// 0 for none (the most likely state is always named: `kairos_step_mode`).
    pub estimates: u32,
}

impl Default for KairosOptions {
    fn default() -> Self {
        KairosOptions {
            kappa: 10,
            cycle_deadline_s: 0.0,
            bounded: 0,
            estimation_time_budget_s: 0.0,
            estimation_node_budget: 0,
            estimates: 3,
        }
    }
}

fn seconds(value: f64, what: &str) -> Result<Option<Duration>, Failure> {
    if value == 0.0 {
        return Ok(None);
    }
    Duration::try_from_secs_f64(value).map(Some).map_err(|_| {
        Failure::new(
            KairosStatus::InvalidArgument,
            format!("{what} is {value}: a finite number of seconds, 0 or more, is expected"),
        )
    })
}

impl KairosOptions {
    /// The builder with these options set; an error for an option out of its range.
    pub(crate) fn apply(&self, builder: ExecutiveBuilder) -> Result<ExecutiveBuilder, Failure> {
        if self.kappa == 0 {
            return Err(Failure::new(
                KairosStatus::InvalidArgument,
                "kappa is 0: at least 1 state must be tracked",
            ));
        }
        let deadline = seconds(self.cycle_deadline_s, "cycle_deadline_s")?;
        let budget = Budget {
            max_nodes: (self.estimation_node_budget > 0).then_some(self.estimation_node_budget),
            max_time: seconds(self.estimation_time_budget_s, "estimation_time_budget_s")?,
            until: None,
        };
        let mut builder = builder.kappa(self.kappa as usize).estimation_budget(budget);
        if self.bounded != 0 {
            let Some(deadline) = deadline else {
                return Err(Failure::new(
                    KairosStatus::InvalidArgument,
                    "the bounded-time mode needs a cycle deadline (cycle_deadline_s > 0)",
                ));
            };
            builder = builder.estimation_deadline(deadline / 2);
        }
        if let Some(deadline) = deadline {
            builder = builder.cycle_deadline(deadline);
        }
        Ok(builder)
    }
}
