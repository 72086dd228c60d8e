//! A campaign's summary table: pass rate with its 95 % Wilson interval, failures grouped by the
//! first expectation that failed with the seeds that replay them, faults and their diagnosis
//! latencies, cycle-time percentiles.

use std::collections::BTreeMap;
use std::fmt;

use super::{Histogram, RunRecord, RunVerdict};

/// The normal quantile of a two-sided 95 % interval.
const Z95: f64 = 1.959_963_984_540_054;

/// How many replay seeds a failure group lists.
const SEEDS_SHOWN: usize = 5;

/// The 95 % Wilson score interval of a proportion `successes / trials` (Wilson, 1927): unlike
/// the normal approximation it stays within [0, 1] and is sound at 0 or `trials` successes,
/// which is where a good campaign lands. `(0, 1)` for no trials.
pub fn wilson_interval(successes: u64, trials: u64) -> (f64, f64) {
    if trials == 0 {
        return (0.0, 1.0);
    }
    let n = trials as f64;
    let p = successes as f64 / n;
    let z2 = Z95 * Z95;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = Z95 / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// Failures sharing a first failing expectation.
#[derive(Debug, Clone, PartialEq)]
pub struct FailureGroup {
    /// The expectation's label and reason, or what stopped the run.
    pub first_failure: String,
    /// How many runs.
    pub runs: u64,
    /// Their seeds, in run order.
    pub seeds: Vec<u64>,
}

/// What a set of run records adds up to.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Runs.
    pub runs: u64,
    /// Runs whose expectations all held.
    pub passed: u64,
    /// Runs that stopped on an error or a panic.
    pub errors: u64,
    /// Runs that did not pass and in which the executive reported no failure (`GoalFailed`,
    /// `PlanFailed`, `GoalContradicted`, `Chatter`, ...) and did not stop on an error: silent
    /// failures.
    pub silent: u64,
    /// Failures by first failing expectation, most frequent first.
    pub groups: Vec<FailureGroup>,
    /// Runs in which the plant entered a fault mode.
    pub runs_with_faults: u64,
    /// Faults entered, in all runs.
    pub faults: u64,
    /// Seconds from each diagnosed fault to its diagnosis.
    pub latencies: Vec<f64>,
    /// Faults never diagnosed that stayed latent (unobservable) to the end of their run: no
    /// estimator could have told them, so they are not missed diagnoses.
    pub latent: u64,
    /// Cycle times of all runs, microseconds.
    pub cycle_times: Histogram,
    /// Sum of the runs' wall times, seconds.
    pub run_time: f64,
}

impl Summary {
    /// Adds up `records`.
    pub fn of(records: &[RunRecord]) -> Summary {
        let mut groups: BTreeMap<&str, FailureGroup> = BTreeMap::new();
        let mut cycle_times = Histogram::default();
        let mut latencies = Vec::new();
        for record in records {
            cycle_times.merge(&record.timing.cycles);
            latencies.extend(record.faults.iter().filter_map(|f| f.diagnosed_after));
            if record.verdict != RunVerdict::Pass {
                let first = record.first_failure.as_deref().unwrap_or("(no reason)");
                let group = groups.entry(first).or_insert_with(|| FailureGroup {
                    first_failure: first.to_string(),
                    runs: 0,
                    seeds: Vec::new(),
                });
                group.runs += 1;
                group.seeds.push(record.seed);
            }
        }
        let mut groups: Vec<FailureGroup> = groups.into_values().collect();
        groups.sort_by_key(|g| std::cmp::Reverse(g.runs));
        latencies.sort_by(f64::total_cmp);
        let count = |verdict| records.iter().filter(|r| r.verdict == verdict).count() as u64;
        Summary {
            runs: records.len() as u64,
            passed: count(RunVerdict::Pass),
            errors: count(RunVerdict::Error),
            silent: records
                .iter()
                .filter(|r| r.verdict == RunVerdict::Fail && !r.failure_reported)
                .count() as u64,
            groups,
            runs_with_faults: records.iter().filter(|r| !r.faults.is_empty()).count() as u64,
            faults: records.iter().map(|r| r.faults.len() as u64).sum(),
            latent: (records.iter().flat_map(|r| &r.faults))
                .filter(|f| f.diagnosed_after.is_none() && f.revealed_after.is_none())
                .count() as u64,
            latencies,
            cycle_times,
            run_time: records.iter().map(|r| r.timing.wall).sum(),
        }
    }

    /// The pass rate's 95 % Wilson interval.
    pub fn interval(&self) -> (f64, f64) {
        wilson_interval(self.passed, self.runs)
    }
}

fn percent(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rate = if self.runs == 0 {
            0.0
        } else {
            self.passed as f64 / self.runs as f64
        };
        let (low, high) = self.interval();
        writeln!(
            f,
            "runs: {}   passed: {}   pass rate: {} (95 % Wilson interval {} – {})",
            self.runs,
            self.passed,
            percent(rate),
            percent(low),
            percent(high)
        )?;
        writeln!(
            f,
            "failed: {}   of which errors (run stopped or panicked): {}, silent (no failure \
             reported by the executive): {}",
            self.runs - self.passed,
            self.errors,
            self.silent
        )?;
        for group in &self.groups {
            let shown: Vec<String> = group
                .seeds
                .iter()
                .take(SEEDS_SHOWN)
                .map(u64::to_string)
                .collect();
            let more = if group.seeds.len() > SEEDS_SHOWN {
                ", ..."
            } else {
                ""
            };
            writeln!(
                f,
                "  {:>6} × {}\n         replay: --seed {}{more}",
                group.runs,
                group.first_failure,
                shown.join(", ")
            )?;
        }
        let diagnosed = self.latencies.len();
        writeln!(
            f,
            "faults: {} in {} runs; diagnosed: {diagnosed}; missed (observable, never \
             diagnosed): {}; latent (never observable in its run): {}",
            self.faults,
            self.runs_with_faults,
            self.faults - diagnosed as u64 - self.latent,
            self.latent
        )?;
        if diagnosed > 0 {
            let at = |q: f64| self.latencies[((q * (diagnosed - 1) as f64).round()) as usize];
            writeln!(
                f,
                "diagnosis latency: median {:.1} s, p90 {:.1} s, max {:.1} s",
                at(0.5),
                at(0.9),
                at(1.0)
            )?;
        }
        let q = |p: f64| {
            self.cycle_times
                .quantile(p)
                .map_or_else(|| "-".to_string(), |us| format!("{:.0} µs", us))
        };
        writeln!(
            f,
            "cycle time (≤ bucket bound, +19 %): p50 {}, p90 {}, p99 {}, max {} over {} cycles",
            q(0.5),
            q(0.9),
            q(0.99),
            q(1.0),
            self.cycle_times.count()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wilson (1927): with no success in n trials the upper bound is z²/(n + z²) — 0.2775 for
    /// n = 10 — and symmetrically for n successes; 50 of 100 gives 0.5 ± 0.0962.
    #[test]
    fn wilson_intervals_match_the_textbook() {
        let close =
            |(a, b): (f64, f64), (c, d): (f64, f64)| (a - c).abs() < 1e-3 && (b - d).abs() < 1e-3;
        assert!(close(
            wilson_interval(0, 10),
            (0.0, Z95 * Z95 / (10.0 + Z95 * Z95))
        ));
        assert!(close(wilson_interval(0, 10), (0.0, 0.2775)));
        assert!(close(wilson_interval(10, 10), (0.7225, 1.0)));
        assert!(close(wilson_interval(50, 100), (0.4038, 0.5962)));
        assert_eq!(wilson_interval(0, 0), (0.0, 1.0));
    }
}
