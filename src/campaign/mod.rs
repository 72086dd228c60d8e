//! Monte Carlo campaigns (DESIGN.md §11, §17): many seeded runs of one scenario
//! against its model-driven plant, each judged by the scenario's expectations, tabulated.
//!
//! Run `i` of a campaign of seed `S` plays the plant seed [`run_seed`]`(S, i)`, whatever the
//! number of threads or the shard that runs it, so a campaign split into shards and merged gives
//! the records one process would. A record ([`RunRecord`]) says what a flight-software review
//! asks of a run: its seed (to replay it: `kairos run SCENARIO --seed SEED`), its verdict, the
//! first expectation that failed, the faults drawn and how long each took to be diagnosed, the
//! cycles, and — apart, in [`Timing`], because they differ from machine to machine — its wall
//! time and cycle times. Reference for users (the records and the summary):
//! `docs/reference/campaign.md`.

mod histogram;
pub mod plot;
mod summary;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use histogram::Histogram;
pub use summary::{Summary, wilson_interval};

use crate::executive::EventKind;
use crate::plant::ComponentId;
use crate::simulation::{self, Outcome, RunOptions, Scenario};

/// The plant seed of run `index` of a campaign of seed `seed`: output `index` of SplitMix64
/// started at `seed` (Steele, Lea & Flood, 2014), so that neighbouring runs get unrelated seeds.
pub fn run_seed(seed: u64, index: u64) -> u64 {
    let mut z = seed.wrapping_add(index.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunVerdict {
    /// Every expectation held.
    Pass,
    /// An expectation failed.
    Fail,
    /// The run could not go on (the executive refused a cycle, the plant a command) or
    /// panicked: a failure of the software under test, never a silent one.
    Error,
}

/// A fault the plant drew (or was forced into) and when the executive diagnosed it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaultRecord {
    /// `component = mode`.
    pub fault: String,
    /// When the plant entered it, seconds.
    pub time: f64,
    /// True when forced by the scenario.
    pub forced: bool,
    /// Seconds from the fault to the first `Diagnosis` event naming that component and mode at
    /// or after it; `None` when never diagnosed.
    pub diagnosed_after: Option<f64>,
    /// Seconds from the fault to the first observation that could not have come from the
    /// component in the mode it left; `None` when the fault stayed latent — unobservable, as a
    /// valve stuck closed while it is closed — to the end of the run (no estimator can diagnose
    /// it, so it is not a missed diagnosis). Records written before this field read as
    /// observable at once.
    #[serde(default = "at_once")]
    pub revealed_after: Option<f64>,
}

/// A fault read from a record that predates `revealed_after`: observable from its first cycle.
fn at_once() -> Option<f64> {
    Some(0.0)
}

/// What one run of a campaign showed; one JSON line of `runs.jsonl`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The run's index in the campaign.
    pub index: u64,
    /// The plant seed: `kairos run SCENARIO --seed SEED` replays the run.
    pub seed: u64,
    /// Pass, fail or error.
    pub verdict: RunVerdict,
    /// The first expectation that failed (`label: reason`), or what stopped the run.
    pub first_failure: Option<String>,
    /// The faults, oldest first.
    pub faults: Vec<FaultRecord>,
    /// True when the executive reported a failure (a `GoalFailed` or `PlanFailed` event, or for
    /// a mission a `MissionGoalFailed` or `Safing`): a run that failed without one failed
    /// silently.
    pub failure_reported: bool,
    /// Cycles run.
    pub cycles: u64,
    /// Machine-dependent measurements, apart so that records compare across machines.
    pub timing: Timing,
}

/// A run's wall time and the distribution of its cycle times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Wall time of the run, seconds.
    pub wall: f64,
    /// Cycle times (the executive's step), microseconds.
    pub cycles: Histogram,
}

/// Runs `indices` of the campaign of seed `seed` on `jobs` threads (0: one per core), calling
/// `done` after each run (from any thread). Records come back in the order of `indices`.
pub fn run_campaign(
    scenario: &Scenario,
    seed: u64,
    indices: &[u64],
    jobs: usize,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<RunRecord>, rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    Ok(pool.install(|| {
        indices
            .par_iter()
            .map(|&index| {
                let record = run_one(scenario, index, run_seed(seed, index));
                done();
                record
            })
            .collect()
    }))
}

/// One run with plant seed `seed`, recorded; a panic is caught and recorded as an error.
pub fn run_one(scenario: &Scenario, index: u64, seed: u64) -> RunRecord {
    let started = Instant::now();
    let mut cycles = Histogram::default();
    let mut diagnoses: Vec<(ComponentId, String, f64)> = Vec::new();
    let mut failure_reported = false;
    let options = RunOptions {
        seed: Some(seed),
        events: 0,
        ..RunOptions::default()
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        simulation::run(scenario, options, &mut |record| {
            cycles.add(record.step.times.total.as_secs_f64() * 1e6);
            for event in &record.step.events {
                match &event.kind {
                    EventKind::Diagnosis {
                        component, mode, ..
                    } => diagnoses.push((*component, mode.clone(), record.step.time)),
                    EventKind::GoalFailed { .. }
                    | EventKind::PlanFailed { .. }
                    | EventKind::MissionGoalFailed { .. }
                    | EventKind::Safing { .. } => {
                        failure_reported = true;
                    }
                    _ => {}
                }
            }
        })
    }));
    let (verdict, first_failure, faults, count) = match outcome {
        Ok(Ok(outcome)) => {
            let first = outcome.verdicts.iter().find_map(|v| match &v.outcome {
                Outcome::Failed { reason } => Some(format!("{}: {reason}", v.label)),
                Outcome::Met { .. } => None,
            });
            let verdict = if first.is_some() {
                RunVerdict::Fail
            } else {
                RunVerdict::Pass
            };
            let faults = outcome
                .faults
                .iter()
                .map(|f| fault_record(scenario, f, &diagnoses))
                .collect();
            (verdict, first, faults, outcome.cycles)
        }
        Ok(Err(error)) => (RunVerdict::Error, Some(error.to_string()), Vec::new(), 0),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            (
                RunVerdict::Error,
                Some(format!("panic: {message}")),
                Vec::new(),
                0,
            )
        }
    };
    RunRecord {
        index,
        seed,
        verdict,
        first_failure,
        faults,
        failure_reported,
        cycles: count,
        timing: Timing {
            wall: started.elapsed().as_secs_f64(),
            cycles,
        },
    }
}

fn fault_record(
    scenario: &Scenario,
    fault: &simulation::FaultDrawn,
    diagnoses: &[(ComponentId, String, f64)],
) -> FaultRecord {
    let component = scenario.plant.component(fault.component);
    let mode = &component.mode(fault.mode).name;
    let diagnosed_after = diagnoses
        .iter()
        .find(|(c, m, t)| *c == fault.component && m == mode && *t >= fault.time)
        .map(|(_, _, t)| t - fault.time);
    FaultRecord {
        fault: format!("{} = {mode}", component.name()),
        time: fault.time,
        forced: fault.forced,
        diagnosed_after,
        revealed_after: fault.revealed.map(|t| t - fault.time),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/campaign.md` lists every field and variant of a run record, and no
    /// other.
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        reference::add::<RunVerdict>(&mut tracer);
        reference::add::<RunRecord>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[
                ("RunRecord", "campaign.md", "A run: one line"),
                ("RunVerdict", "campaign.md", "Verdicts"),
                ("FaultRecord", "campaign.md", "Faults"),
                ("Timing", "campaign.md", "Timing"),
            ],
        );
    }
}
