//! Livingstone 2's circuit-breaker benchmark (its `cb` model and `cycle-7-8` script,
//! generalised; `tests/support/l2_breakers.rs`): TimedME per step of the script at 15, 63 and
//! 255 breakers (1023 with `KAIROS_BENCH_HUGE=1`), κ = 5 and 10. Each iteration runs one cycle
//! of the script (16 steps at 15 breakers) on from where the last one ended, after ten cycles
//! of warm-up, so the estimator is in its steady state (its caches and history window as a long
//! run has them); criterion's throughput is steps per second. Run with
//! `cargo bench --bench l2_breakers`; numbers in BENCHMARKS.md.

#[path = "../tests/support/l2_breakers.rs"]
mod l2_breakers;

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use kairos::diagnostic::Source;
use kairos::estimation::log::{LogRecord, parse_log};
use kairos::estimation::{Belief, ModeEstimator, TimedMe, TimedMeOptions};
use kairos::opsat::Theory;
use kairos::plant::Plant;

/// The estimator running the script, cycle after cycle.
struct Running {
    plant: Plant,
    theory: Theory,
    estimator: TimedMe,
    belief: Belief,
    /// One cycle's records after the first (the first only holds the initial observation).
    cycle: Vec<LogRecord>,
    /// The log's first record, whose commands start every cycle.
    first: LogRecord,
    /// The time the next cycle starts from.
    time: f64,
}

impl Running {
    fn new(n: usize, kappa: usize) -> Running {
        let plant = Plant::load(&Source::new("l2_breakers.ron", l2_breakers::model_ron(n)))
            .expect("the generated model loads");
        let log = Source::new("l2_breakers.jsonl", l2_breakers::log(n, 1));
        let mut records = parse_log(&log, &plant).expect("the generated log parses");
        let mut theory = plant.theory().expect("theory");
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(kappa));
        let first = records.remove(0);
        let initial = estimator
            .initial(&plant, &mut theory, first.time, &first.observation)
            .expect("initial");
        let mut running = Running {
            plant,
            theory,
            estimator,
            belief: initial.belief,
            time: 0.0,
            first,
            cycle: records,
        };
        for _ in 0..10 {
            running.run_cycle();
        }
        running
    }

    /// One cycle of the script, on from the current belief; each step's record is the cycle's,
    /// moved to the running time.
    fn run_cycle(&mut self) {
        let steps = self.cycle.len();
        for i in 0..steps {
            let record = &self.cycle[i];
            let commands = if i == 0 {
                &self.first.commands
            } else {
                &self.cycle[i - 1].commands
            };
            let time = self.time + record.time;
            let update = self
                .estimator
                .update(
                    &self.plant,
                    &mut self.theory,
                    &self.belief,
                    commands,
                    &record.observation,
                    time,
                )
                .expect("update");
            self.belief = update.belief;
        }
        self.time += steps as f64;
    }
}

fn cycles(c: &mut Criterion) {
    let mut group = c.benchmark_group("me_step/l2_breakers");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(5));
    let huge = std::env::var("KAIROS_BENCH_HUGE").is_ok();
    let mut sizes = vec![(15, 5), (15, 10), (63, 5), (63, 10), (255, 10)];
    if huge {
        sizes.push((1023, 10));
    }
    for (n, kappa) in sizes {
        let mut running: Option<Running> = None;
        let steps = l2_breakers::cycle(n).len() as u64;
        group.throughput(Throughput::Elements(steps));
        group.bench_with_input(BenchmarkId::new(format!("kappa_{kappa}"), n), &n, |b, _| {
            let r = running.get_or_insert_with(|| Running::new(n, kappa));
            b.iter(|| r.run_cycle())
        });
    }
    group.finish();
}

criterion_group!(benches, cycles);
criterion_main!(benches);
