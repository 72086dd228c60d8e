//! `kairos bench`: how long the executive's cycles take, per phase, for sizing a flight computer
//! (DESIGN.md §12, §14).
//!
//! - `kairos bench SCENARIO [--kappa K ...] [--history N] [--rerun doubt|surprise] [--json]`
//!   runs a scenario as `kairos run` does (no
//!   log), once per κ given (the scenario's own κ when none is), and reports,
//!   per phase (estimation, sequencer, reconfiguration, goals submitted before the cycle, whole
//!   cycle, submissions included), the minimum, median, 99th
//!   percentile and maximum wall time of its *quiet* and *busy* cycles separately.
//! - `kairos bench --plant MODEL --log LOG [--kappa K ...] [--history N] [--rerun ...] [--json]`
//!   replays an estimation log
//!   (the format of `kairos estimate`) through TimedME once per κ and reports the same figures
//!   for the estimation step alone, with the satisfiability questions asked per cycle.
//!
//! Each section ends with the mean over all its cycles, quiet and busy together: what a whole
//! run costs per cycle (a log replayed with a command every cycle, as Livingstone 2's benchmark
//! is, has only busy cycles).
//!
//! A cycle is **busy** when something new reaches the executive — a command was issued in the
//! previous cycle, the observation differs from the previous cycle's, or (for a scenario) the
//! cycle reported an event; every other cycle is **quiet**. The two cost very different amounts
//! (a quiet estimation step replays cached work), so a single median would hide the busy tail
//! a deadline has to cover. Times are wall clock on this machine: run on the target, or on an
//! idle machine, and prefer the medians.

use std::path::Path;
use std::time::{Duration, Instant};

use kairos::estimation::TimedMe;
use kairos::estimation::log::{LogRecord, parse_log, replay_with};
use kairos::executive::NamedValue;
use kairos::simulation::{self, RunOptions};
use serde_json::{Value, json};

use super::output::emit;
use super::window_args::{WindowArgs, describe};
use super::{Failure, load_plant, read_source};

/// What to benchmark.
pub enum BenchTarget<'a> {
    /// A scenario, run whole once per κ (its own when none is given).
    Scenario(&'a Path, &'a [usize]),
    /// Estimation alone over a replay log, once per κ.
    Log {
        /// The plant model.
        plant: &'a Path,
        /// The replay log.
        log: &'a Path,
        /// The κ values to measure.
        kappas: &'a [usize],
    },
}

/// Runs the benchmark, mode estimation's history window set by `window`, and prints its table
/// (or JSON).
pub fn run(target: &BenchTarget, window: WindowArgs, json: bool) -> Result<(), Failure> {
    let report = match target {
        BenchTarget::Scenario(path, kappas) => bench_scenario(path, kappas, window)?,
        BenchTarget::Log { plant, log, kappas } => bench_log(plant, log, kappas, window)?,
    };
    let text = if json {
        format!("{}\n", report.to_json())
    } else {
        report.to_text()
    };
    emit(&text).map(|_| ())
}

/// The phases a cycle's time is split into, in the order the report shows them.
const PHASES: [&str; 5] = [
    "estimation",
    "sequencer",
    "reconfiguration",
    "submission",
    "cycle",
];

/// The times of one kind of cycle (quiet or busy), per phase, in nanoseconds.
#[derive(Default)]
struct Samples {
    phases: [Vec<u64>; 5],
}

impl Samples {
    fn push(&mut self, times: [Duration; 5]) {
        for (samples, time) in self.phases.iter_mut().zip(times) {
            samples.push(u64::try_from(time.as_nanos()).unwrap_or(u64::MAX));
        }
    }

    fn count(&self) -> usize {
        self.phases[0].len()
    }
}

/// Minimum, median, 99th percentile and maximum of some durations, in nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Summary {
    min: u64,
    median: u64,
    p99: u64,
    max: u64,
}

impl Summary {
    /// The summary of `samples` (nearest-rank percentiles); `None` when there are none.
    fn of(samples: &[u64]) -> Option<Summary> {
        let mut sorted = samples.to_vec();
        sorted.sort_unstable();
        let rank = |q: f64| {
            let n = sorted.len();
            let index = ((q * n as f64).ceil() as usize).clamp(1, n) - 1;
            sorted[index]
        };
        Some(Summary {
            min: *sorted.first()?,
            median: rank(0.5),
            p99: rank(0.99),
            max: *sorted.last()?,
        })
    }
}

/// One measured configuration: a scenario, or a log at one κ.
struct Section {
    title: String,
    quiet: Samples,
    busy: Samples,
    /// Satisfiability questions asked by estimation over the replay (a log only).
    sat_calls: Option<u64>,
    /// Phases that do not apply (estimation alone has no sequencer), left out of the report.
    phases: Vec<usize>,
}

/// Everything measured, ready to print.
struct Report {
    subject: String,
    wall: Duration,
    sections: Vec<Section>,
}

/// Runs the scenario once per κ of `kappas` (its own κ when none is given).
fn bench_scenario(path: &Path, kappas: &[usize], window: WindowArgs) -> Result<Report, Failure> {
    let mut scenario = simulation::load(path).map_err(Failure::bad_input)?;
    window.apply(&mut scenario);
    let kappas = if kappas.is_empty() {
        vec![scenario.kappa]
    } else {
        kappas.to_vec()
    };
    let started = Instant::now();
    let mut sections = Vec::new();
    let mut cycles = 0;
    for kappa in kappas {
        scenario.kappa = kappa;
        let (section, ran) = bench_run(&scenario)?;
        sections.push(section);
        cycles = ran;
    }
    Ok(Report {
        subject: format!("{} ({cycles} cycles)", path.display()),
        wall: started.elapsed(),
        sections,
    })
}

/// One run of the scenario, its cycles sorted into quiet and busy; and how many it ran.
fn bench_run(scenario: &simulation::Scenario) -> Result<(Section, u64), Failure> {
    let mut section = Section {
        title: format!(
            "scenario `{}`, {}",
            scenario.name,
            describe(&scenario.estimation())
        ),
        quiet: Samples::default(),
        busy: Samples::default(),
        sat_calls: None,
        phases: vec![0, 1, 2, 3, 4],
    };
    let mut previous: Option<Vec<NamedValue>> = None;
    let mut commanded = false;
    let outcome = simulation::run(scenario, RunOptions::default(), &mut |record| {
        let step = record.step;
        let busy =
            commanded || previous.as_deref() != Some(record.observation) || !step.events.is_empty();
        let times = step.times;
        let samples = [
            times.estimation,
            times.sequencer,
            times.reconfiguration,
            times.submission,
            times.total,
        ];
        if busy {
            section.busy.push(samples);
        } else {
            section.quiet.push(samples);
        }
        commanded = !step.command.is_empty();
        if previous.as_deref() != Some(record.observation) {
            previous = Some(record.observation.to_vec());
        }
    })
    .map_err(|e| Failure::failed(format!("error: {e}")))?;
    Ok((section, outcome.cycles))
}

fn bench_log(
    plant_path: &Path,
    log: &Path,
    kappas: &[usize],
    window: WindowArgs,
) -> Result<Report, Failure> {
    let plant = load_plant(plant_path)?;
    let source = read_source(log)?;
    let records = parse_log(&source, &plant).map_err(Failure::bad_input)?;
    let started = Instant::now();
    let mut sections = Vec::new();
    for &kappa in kappas {
        let mut theory = plant
            .theory()
            .map_err(|e| Failure::bad_input(format!("error: {e}")))?;
        let options = window.options(kappa);
        let mut estimator = TimedMe::new(options);
        let mut section = Section {
            title: format!("estimation, TimedME {}", describe(&options)),
            quiet: Samples::default(),
            busy: Samples::default(),
            sat_calls: Some(0),
            phases: vec![0],
        };
        replay_timed(&plant, &mut theory, &mut estimator, &records, &mut section)?;
        sections.push(section);
    }
    Ok(Report {
        subject: format!(
            "{} on {} ({} cycles)",
            log.display(),
            plant_path.display(),
            records.len()
        ),
        wall: started.elapsed(),
        sections,
    })
}

/// Replays `records` as `kairos estimate` does, sorting each update's time into quiet or busy.
fn replay_timed(
    plant: &kairos::plant::Plant,
    theory: &mut kairos::opsat::Theory,
    estimator: &mut TimedMe,
    records: &[LogRecord],
    section: &mut Section,
) -> Result<(), Failure> {
    replay_with(
        plant,
        theory,
        estimator,
        records,
        &mut |index, update, elapsed| {
            // Record i's update uses record i−1's commands; the initial belief is not a cycle.
            let Some(before) = index.checked_sub(1).map(|i| &records[i]) else {
                return;
            };
            if let Some(calls) = section.sat_calls.as_mut() {
                *calls += update.stats.sat_calls;
            }
            let now = &records[index];
            let busy = before.commands.issued(plant).next().is_some()
                || before.observation != now.observation;
            let samples = [
                elapsed,
                Duration::ZERO,
                Duration::ZERO,
                Duration::ZERO,
                elapsed,
            ];
            if busy {
                section.busy.push(samples);
            } else {
                section.quiet.push(samples);
            }
        },
    )
    .map_err(|e| Failure::failed(format!("error: estimation stopped: {e}")))
}

/// Every cycle of a section, quiet and busy together.
struct All {
    count: usize,
    /// The mean time of the whole cycle (or of estimation alone, for a log), nanoseconds.
    mean: u64,
}

impl Section {
    /// The mean over every cycle of the last phase measured (the whole cycle, or estimation
    /// for a log): what a run of the log or scenario costs per cycle.
    fn all(&self) -> All {
        let phase = self.phases[self.phases.len() - 1];
        let times = self.quiet.phases[phase]
            .iter()
            .chain(&self.busy.phases[phase]);
        let count = self.quiet.count() + self.busy.count();
        let total: u128 = times.map(|&t| u128::from(t)).sum();
        All {
            count,
            mean: u64::try_from(total / count.max(1) as u128).unwrap_or(u64::MAX),
        }
    }
}

/// A duration in nanoseconds, for a person: `812 ns`, `18.4 µs`, `1.27 ms`, `2.10 s`.
fn human(nanos: u64) -> String {
    let n = nanos as f64;
    if n < 1e3 {
        format!("{nanos} ns")
    } else if n < 1e6 {
        format!("{:.1} µs", n / 1e3)
    } else if n < 1e9 {
        format!("{:.2} ms", n / 1e6)
    } else {
        format!("{:.2} s", n / 1e9)
    }
}

impl Report {
    fn to_text(&self) -> String {
        let mut out = format!(
            "kairos bench: {} — {:.2} s wall\n",
            self.subject,
            self.wall.as_secs_f64()
        );
        for section in &self.sections {
            out.push_str(&format!("\n{}\n", section.title));
            out.push_str(&format!(
                "  {:<7} {:<16} {:>8} {:>10} {:>10} {:>10} {:>10}\n",
                "cycles", "phase", "count", "min", "median", "p99", "max"
            ));
            for (kind, samples) in [("quiet", &section.quiet), ("busy", &section.busy)] {
                for &phase in &section.phases {
                    let Some(s) = Summary::of(&samples.phases[phase]) else {
                        continue;
                    };
                    out.push_str(&format!(
                        "  {:<7} {:<16} {:>8} {:>10} {:>10} {:>10} {:>10}\n",
                        kind,
                        PHASES[phase],
                        samples.count(),
                        human(s.min),
                        human(s.median),
                        human(s.p99),
                        human(s.max)
                    ));
                }
            }
            let all = section.all();
            if all.count > 0 {
                out.push_str(&format!(
                    "  {:<7} {:<16} {:>8} mean {}",
                    "all",
                    PHASES[section.phases[section.phases.len() - 1]],
                    all.count,
                    human(all.mean)
                ));
                if let Some(calls) = section.sat_calls {
                    out.push_str(&format!(
                        ", {:.1} satisfiability questions a cycle",
                        calls as f64 / all.count as f64
                    ));
                }
                out.push('\n');
            }
        }
        out
    }

    fn to_json(&self) -> Value {
        let sections: Vec<Value> = self
            .sections
            .iter()
            .map(|section| {
                let kinds =
                    [("quiet", &section.quiet), ("busy", &section.busy)].map(|(kind, samples)| {
                        let mut phases = serde_json::Map::new();
                        for &phase in &section.phases {
                            if let Some(s) = Summary::of(&samples.phases[phase]) {
                                phases.insert(
                                    PHASES[phase].to_string(),
                                    json!({"min_ns": s.min, "median_ns": s.median,
                                           "p99_ns": s.p99, "max_ns": s.max}),
                                );
                            }
                        }
                        (kind, json!({"count": samples.count(), "phases": phases}))
                    });
                let all = section.all();
                json!({
                    "title": section.title,
                    kinds[0].0: kinds[0].1,
                    kinds[1].0: kinds[1].1,
                    "all": {"count": all.count, "mean_ns": all.mean, "sat_calls": section.sat_calls},
                })
            })
            .collect();
        json!({
            "subject": self.subject,
            "wall_s": self.wall.as_secs_f64(),
            "sections": sections,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{Summary, human};

    #[test]
    fn percentiles_are_nearest_rank() {
        let samples: Vec<u64> = (1..=200).collect();
        let s = Summary::of(&samples).expect("a summary");
        assert_eq!((s.min, s.median, s.p99, s.max), (1, 100, 198, 200));
        assert_eq!(Summary::of(&[]), None);
        let one = Summary::of(&[7]).expect("a summary");
        assert_eq!((one.min, one.median, one.p99, one.max), (7, 7, 7, 7));
    }

    #[test]
    fn durations_read_in_their_unit() {
        assert_eq!(human(812), "812 ns");
        assert_eq!(human(18_400), "18.4 µs");
        assert_eq!(human(1_270_000), "1.27 ms");
        assert_eq!(human(2_100_000_000), "2.10 s");
    }
}
