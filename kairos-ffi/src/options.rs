//! How a handle's executive runs, as C sets it: κ, the cycle deadline, the estimator's budget,
//! and the bounded-time mode.
//!
//! # The bounded-time mode, and what it bounds
//!
//! With `bounded` set, the estimator's time budget is derived from the cycle deadline unless one
//! is given: `cycle_deadline_s / (2 κ)` per OPSAT enumeration. A normal cycle runs at most one
//! enumeration per tracked state (κ), so its searches together take about half the deadline,
//! leaving the rest to the sequencer and the planner. When a budget stops a search, the belief is
//! the best found so far and the step says so (`KAIROS_STEP_SEARCH_CUT`); a cycle that took longer
//! than the deadline says so too (`KAIROS_STEP_DEADLINE_OVERRUN`, with its elapsed time).
//!
//! What is guaranteed, precisely: each OPSAT enumeration of mode estimation stops at the first
//! search node it starts after its budget ran out (the node's SAT call is not interrupted). Not
//! guaranteed: the cycle's total. A cycle may run more enumerations than κ — when truncation may
//! have cost the truth, TimedME estimates its last 16 to 32 steps again tracking 8κ states
//! (docs/design/estimation.md, "The history window"), and an observation no tracked state
//! explains triggers a fall-back expansion — and building the OCSPs, goal interpretation and the
//! planner's look-ups have no budget. The deadline is a measured bound, reported when missed, not
//! an enforced one; docs/embedding.md has the figures.

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
    /// The estimator's time budget per OPSAT enumeration, in seconds; 0 for none, or, in the
    /// bounded-time mode, for the one derived from the deadline.
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
        let mut budget = Budget {
            max_nodes: (self.estimation_node_budget > 0).then_some(self.estimation_node_budget),
            max_time: seconds(self.estimation_time_budget_s, "estimation_time_budget_s")?,
        };
        if self.bounded != 0 {
            let Some(deadline) = deadline else {
                return Err(Failure::new(
                    KairosStatus::InvalidArgument,
                    "the bounded-time mode needs a cycle deadline (cycle_deadline_s > 0)",
                ));
            };
            budget.max_time = budget.max_time.or(Some(deadline / (2 * self.kappa)));
        }
        let mut builder = builder.kappa(self.kappa as usize).estimation_budget(budget);
        if let Some(deadline) = deadline {
            builder = builder.cycle_deadline(deadline);
        }
        Ok(builder)
    }
}
