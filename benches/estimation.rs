//! Mode estimation benchmarks (DESIGN.md §14): one estimation step on the Mars
//! lander at κ ∈ {1, 10} during the EDL (a quiet cruise cycle, the engine heating, the entry
//! trigger's window, a new observation); on the propulsion subsystem at κ ∈ {1, 5, 10, 50}; the exact update against TimedME on an 8-component plant;
//! TimedME on synthetic chain and tree plants of 10, 100 and 1000 components.
//!
//! "warm" steps repeat a cycle the estimator has seen (a quiet cycle: the caches of enabled
//! transitions, OCSP solutions and observation factors answer); "jittery" steps are quiet cycles
//! whose length varies by up to 5 %, so every probability that depends on it moves; "cold"
//! steps start from fresh caches, so every SAT call and OPSAT search is made; "heating" steps
//! advance the engine's clock inside its 30–60 s window. Run with `cargo bench --bench estimation`; numbers in BENCHMARKS.md.

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;
use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use kairos::diagnostic::Source;
use kairos::estimation::log::{LogRecord, replay};
use kairos::estimation::{Belief, BeliefUpdate, ModeEstimator, TimedMe, TimedMeOptions, Update};
use kairos::opsat::{Theory, TheoryOptions};
use kairos::plant::{Commands, Observation, Plant};
use support::lander_edl::{CYCLE, Faults, edl, ms, nominal_edl};
use support::plants::{log, model};
use support::random_ocsp::sample;
use support::random_plant::{random_plant, random_run};

/// The propulsion subsystem after `until` seconds of the warm-up of
/// `tests/estimation_diagnosis.rs` (PDE on, engine commanded to standby at 1 s), with the
/// belief TimedME(κ) holds then and the observation of the next cycle.
fn propulsion_at(
    plant: &Plant,
    theory: &mut Theory,
    kappa: usize,
    until: u32,
    warm: bool,
) -> (Belief, Observation) {
    let sensors = |t: u32| {
        let (power, temp) = match t {
            0 | 1 => ("zero", "low"),
            t if warm && t >= 47 => ("nominal", "nominal"),
            _ => ("nominal", "low"),
        };
        format!(
            "\"observations\": {{\"valve1.outlet\": \"low\", \"valve2.outlet\": \"low\", \"engine.power\": \"{power}\", \"engine.temp\": \"{temp}\", \"engine.thrust\": \"zero\"}}"
        )
    };
    let mut text = String::new();
    for t in 0..=until {
        let command = match t {
            0 => ", \"commands\": {\"PDE.cmd\": \"on\"}",
            1 => ", \"commands\": {\"PDE.cmd\": \"engine-standby\"}",
            _ => "",
        };
        text += &format!("{{\"time\": {t}.0, {}{command}}}\n", sensors(t));
    }
    let records = log(plant, &text);
    let mut estimator = TimedMe::new(TimedMeOptions::kappa(kappa));
    let updates = replay(plant, theory, &mut estimator, &records).expect("replay");
    let belief = updates.last().expect("updates").belief.clone();
    let next = log(
        plant,
        &format!("{{\"time\": {}.0, {}}}\n", until + 1, sensors(until + 1)),
    );
    (belief, next[0].observation.clone())
}

fn propulsion(c: &mut Criterion) {
    let plant = model("propulsion");
    let idle = Commands::idle(&plant);
    let mut group = c.benchmark_group("me_step/propulsion");
    group.measurement_time(Duration::from_secs(3));
    for kappa in [1usize, 5, 10, 50] {
        let mut theory = plant.theory().expect("theory");
        let (quiet, observation) = propulsion_at(&plant, &mut theory, kappa, 100, true);
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(kappa));
        group.bench_with_input(BenchmarkId::new("quiet_warm", kappa), &kappa, |b, _| {
            b.iter(|| {
                estimator
                    .update(
                        &plant,
                        &mut theory,
                        black_box(&quiet),
                        &idle,
                        &observation,
                        101.0,
                    )
                    .expect("update")
            })
        });
        let mut jitter = 0u32;
        group.bench_with_input(BenchmarkId::new("quiet_jittery", kappa), &kappa, |b, _| {
            b.iter(|| {
                // Cycle lengths that differ by a few per cent from one cycle to the next.
                jitter = jitter.wrapping_add(7919);
                let time = 101.0 + f64::from(jitter % 1000) * 5e-5;
                estimator
                    .update(
                        &plant,
                        &mut theory,
                        black_box(&quiet),
                        &idle,
                        &observation,
                        time,
                    )
                    .expect("update")
            })
        });
        group.bench_with_input(BenchmarkId::new("quiet_cold", kappa), &kappa, |b, _| {
            b.iter_batched(
                || TimedMe::new(TimedMeOptions::kappa(kappa)),
                |mut fresh| {
                    fresh
                        .update(
                            &plant,
                            &mut theory,
                            black_box(&quiet),
                            &idle,
                            &observation,
                            101.0,
                        )
                        .expect("update")
                },
                BatchSize::SmallInput,
            )
        });
        let mut plain = unminimised(&plant);
        group.bench_with_input(
            BenchmarkId::new("quiet_cold_unminimised", kappa),
            &kappa,
            |b, _| {
                b.iter_batched(
                    || TimedMe::new(TimedMeOptions::kappa(kappa)),
                    |mut fresh| {
                        fresh
                            .update(
                                &plant,
                                &mut plain,
                                black_box(&quiet),
                                &idle,
                                &observation,
                                101.0,
                            )
                            .expect("update")
                    },
                    BatchSize::SmallInput,
                )
            },
        );
        let (heating, observation) = propulsion_at(&plant, &mut theory, kappa, 40, false);
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(kappa));
        let mut nudge = 0u32;
        group.bench_with_input(BenchmarkId::new("heating", kappa), &kappa, |b, _| {
            b.iter(|| {
                // A slightly different cycle length each time: the heating engine's transition
                // probabilities change, as they do from one cycle to the next.
                nudge = nudge.wrapping_add(1);
                let time = 41.0 + f64::from(nudge % 1000) * 1e-6;
                estimator
                    .update(
                        &plant,
                        &mut theory,
                        black_box(&heating),
                        &idle,
                        &observation,
                        time,
                    )
                    .expect("update")
            })
        });
    }
    group.finish();
}

/// The Mars lander's nominal EDL (`tests/support/lander_edl.rs`) replayed through TimedME(κ) (quiet
/// stretches on a 600 s grid, every 0.1 s cycle from `from` s on), and the next `steps` cycles as
/// they came: the belief before each and its records.
struct LanderRun {
    theory: Theory,
    estimator: TimedMe,
    steps: Vec<(Belief, LogRecord, LogRecord)>,
    next: usize,
    lap: u32,
}

impl LanderRun {
    fn new(plant: &Plant, kappa: usize, from: f64, steps: usize) -> LanderRun {
        let timeline = nominal_edl(Faults::default());
        let start = ms(from);
        let fine = (0..=steps as u64).map(|k| start + k * ms(CYCLE));
        let mut times: Vec<u64> = timeline
            .times(edl::END, 600.0)
            .into_iter()
            .filter(|&t| t < start)
            .chain(fine)
            .collect();
        times.sort_unstable();
        times.dedup();
        let records = timeline.records(plant, &times);
        let mut theory = plant.theory().expect("theory");
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(kappa));
        let updates = replay(plant, &mut theory, &mut estimator, &records).expect("replay");
        let first = records.len() - steps - 1;
        let steps = (first..records.len() - 1)
            .map(|i| {
                let belief = updates[i].belief.clone();
                (belief, records[i].clone(), records[i + 1].clone())
            })
            .collect();
        LanderRun {
            theory,
            estimator,
            steps,
            next: 0,
            lap: 0,
        }
    }

    /// The next of the recorded steps, round robin. Each lap shifts the step's end by 1 ns, so
    /// that every clock reading and step length is new to the estimator, as in a real run
    /// (whose cycle lengths differ in their last bits from cycle to cycle).
    fn step(&mut self, plant: &Plant) -> Update {
        let (belief, before, now) = &self.steps[self.next];
        let time = now.time + f64::from(self.lap) * 1e-9;
        self.next += 1;
        if self.next == self.steps.len() {
            self.next = 0;
            self.lap += 1;
        }
        self.estimator
            .update(
                plant,
                &mut self.theory,
                black_box(belief),
                &before.commands,
                &now.observation,
                time,
            )
            .expect("update")
    }
}

fn mars_lander(c: &mut Criterion) {
    let plant = model("mars_lander");
    let mut group = c.benchmark_group("me_step/mars_lander");
    group.measurement_time(Duration::from_secs(3));
    // (name, first cycle): quiet cruise steps; the engine inside its Uniform(30, 60) s heating
    // window (heating from 0.2 s, standby at 43.2 s); the entry trigger's Gaussian window, its
    // per-step probability non-zero from ≈ 15,675 s.
    let quiet: [(&str, f64); 3] = [
        ("cruise", 1000.0),
        ("heating", 31.0),
        ("entry_window", 16000.0),
    ];
    for kappa in [1usize, 10] {
        for (name, from) in quiet {
            let mut run: Option<LanderRun> = None;
            group.bench_with_input(BenchmarkId::new(name, kappa), &kappa, |b, _| {
                let run = run.get_or_insert_with(|| LanderRun::new(&plant, kappa, from, 100));
                b.iter(|| run.step(&plant))
            });
        }
        // The engine reaches standby: `engine.temp = nominal` is observed for the first time
        // (43.2 s), every quiet cycle before it already seen by the estimator.
        group.sample_size(20);
        group.bench_with_input(
            BenchmarkId::new("new_observation", kappa),
            &kappa,
            |b, _| {
                b.iter_batched(
                    || LanderRun::new(&plant, kappa, edl::STANDBY - 1.0, 10),
                    |mut run| {
                        run.next = 9;
                        run.step(&plant)
                    },
                    BatchSize::SmallInput,
                )
            },
        );
        group.sample_size(100);
    }
    group.finish();
}

fn exact_against_timed(c: &mut Criterion) {
    // An 8-component random plant and a simulated run; the beliefs after five cycles.
    let spec = (0..)
        .map(|seed| sample(random_plant(8), seed))
        .find(|spec| spec.components.len() == 8 && spec.plant().is_some())
        .expect("an 8-component plant");
    let plant = spec.plant().expect("valid");
    let mut theory = plant.theory().expect("theory");
    let run = sample(random_run(8, 6), 0);
    let (first, cycles) = run.simulate(&plant, &mut theory);
    let mut exact = BeliefUpdate::new();
    let mut timed = TimedMe::new(TimedMeOptions::kappa(10));
    let mut e = exact
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("initial")
        .belief;
    let mut t = timed
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("initial")
        .belief;
    let (last, history) = cycles.split_last().expect("cycles");
    for cycle in history {
        e = exact
            .update(
                &plant,
                &mut theory,
                &e,
                &cycle.commands,
                &cycle.observation,
                cycle.time,
            )
            .expect("update")
            .belief;
        t = timed
            .update(
                &plant,
                &mut theory,
                &t,
                &cycle.commands,
                &cycle.observation,
                cycle.time,
            )
            .expect("update")
            .belief;
    }
    println!(
        "8-component plant: exact belief holds {} system states, TimedME {}",
        e.states().len(),
        t.states().len()
    );
    let mut group = c.benchmark_group("me_step/random8");
    group.measurement_time(Duration::from_secs(3));
    group.bench_function("exact_cold", |b| {
        b.iter_batched(
            BeliefUpdate::new,
            |mut fresh| {
                fresh
                    .update(
                        &plant,
                        &mut theory,
                        &e,
                        &last.commands,
                        &last.observation,
                        last.time,
                    )
                    .expect("update")
            },
            BatchSize::SmallInput,
        )
    });
    group.bench_function("timed_me_k10_cold", |b| {
        b.iter_batched(
            || TimedMe::new(TimedMeOptions::kappa(10)),
            |mut fresh| {
                fresh
                    .update(
                        &plant,
                        &mut theory,
                        &t,
                        &last.commands,
                        &last.observation,
                        last.time,
                    )
                    .expect("update")
            },
            BatchSize::SmallInput,
        )
    });
    group.bench_function("exact_warm", |b| {
        b.iter(|| {
            exact
                .update(
                    &plant,
                    &mut theory,
                    &e,
                    &last.commands,
                    &last.observation,
                    last.time,
                )
                .expect("update")
        })
    });
    group.bench_function("timed_me_k10_warm", |b| {
        b.iter(|| {
            timed
                .update(
                    &plant,
                    &mut theory,
                    &t,
                    &last.commands,
                    &last.observation,
                    last.time,
                )
                .expect("update")
        })
    });
    group.finish();
}

/// A synthetic plant of `n` pipe segments: segment i's inlet is wired to the outlet of segment
/// `upstream(i)` (a chain: i − 1; a tree: (i − 1) / 2), segment 0 is fed; each segment is `ok`
/// (outlet = inlet), or faulty: `blocked` (outlet low) or `failed` (unconstrained). Every
/// fourth outlet is observed. Coupling is bounded: each segment talks to one upstream.
fn pipes(n: usize, upstream: impl Fn(usize) -> usize) -> Plant {
    let mut components = Vec::new();
    let mut connections = Vec::new();
    for i in 0..n {
        let ok = if i == 0 {
            format!("s{i}.outlet = high")
        } else {
            format!("s{i}.outlet = s{i}.inlet")
        };
        components.push(format!(
            "Component(name: \"s{i}\", attributes: {{ \"inlet\": [\"low\", \"high\"], \"outlet\": [\"low\", \"high\"] }}, \
             modes: [Mode(name: \"ok\", constraint: \"{ok}\"), Mode(name: \"blocked\", kind: Fault, constraint: \"s{i}.outlet = low\"), \
             Mode(name: \"failed\", kind: Fault)], initial: {{ \"ok\": 1.0 }}, \
             transitions: [(from: \"*\", to: \"blocked\", rate: 0.0001), (from: \"*\", to: \"failed\", rate: 0.00001)])"
        ));
        if i > 0 {
            connections.push(format!("\"s{}.outlet = s{i}.inlet\"", upstream(i)));
        }
    }
    let observables: Vec<String> = (0..n)
        .step_by(4)
        .map(|i| format!("\"s{i}.outlet\""))
        .collect();
    let text = format!(
        "Plant(name: \"pipes\", components: [{}], observables: [{}], connections: [{}])",
        components.join(",\n"),
        observables.join(", "),
        connections.join(", ")
    );
    Plant::load(&Source::new("pipes.ron", text)).unwrap_or_else(|e| panic!("{e}"))
}

/// The plant's theory without conflict minimisation (see BENCHMARKS.md for why it is measured).
fn unminimised(plant: &Plant) -> Theory {
    plant
        .theory_with(TheoryOptions {
            minimize_conflicts: false,
        })
        .expect("theory")
}

/// Which segment feeds segment i.
type Upstream = fn(usize) -> usize;

/// A theory and a TimedME (κ = 10) that has run three quiet cycles on a synthetic plant, with its
/// belief.
struct Warmed {
    theory: Theory,
    estimator: TimedMe,
    belief: Belief,
}

impl Warmed {
    fn new(plant: &Plant, mut theory: Theory, observation: &Observation) -> Warmed {
        let idle = Commands::idle(plant);
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(10));
        let mut belief = estimator
            .initial(plant, &mut theory, 0.0, observation)
            .expect("initial")
            .belief;
        for t in 1..=3 {
            belief = estimator
                .update(
                    plant,
                    &mut theory,
                    &belief,
                    &idle,
                    observation,
                    f64::from(t),
                )
                .expect("update")
                .belief;
        }
        Warmed {
            theory,
            estimator,
            belief,
        }
    }
}

fn scaling(c: &mut Criterion) {
    let mut group = c.benchmark_group("me_step/synthetic");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(4));
    // A cold step on 1000 components takes tens of seconds: opt in with KAIROS_BENCH_HUGE=1.
    let huge = std::env::var("KAIROS_BENCH_HUGE").is_ok();
    let shapes: [(&str, Upstream); 2] = [("chain", |i| i - 1), ("tree", |i| (i - 1) / 2)];
    for (shape, upstream) in shapes {
        for n in [10usize, 100, 300, 1000] {
            let plant = pipes(n, upstream);
            let high: Vec<_> = plant
                .observables()
                .iter()
                .map(|&x| (x, plant.table().variable(x).value("high").expect("high")))
                .collect();
            let observation = Observation::new(&plant, &high).expect("observation");
            let idle = Commands::idle(&plant);
            for minimised in [true, false] {
                let variant = if minimised { "" } else { "_unminimised" };
                let theory = || {
                    if minimised {
                        plant.theory().expect("theory")
                    } else {
                        unminimised(&plant)
                    }
                };
                // Built on first use, so that benchmarks left out by a filter cost nothing.
                let mut warmed: Option<Warmed> = None;
                group.bench_with_input(
                    BenchmarkId::new(format!("{shape}_warm{variant}"), n),
                    &n,
                    |b, _| {
                        let w = warmed
                            .get_or_insert_with(|| Warmed::new(&plant, theory(), &observation));
                        b.iter(|| {
                            w.estimator
                                .update(&plant, &mut w.theory, &w.belief, &idle, &observation, 4.0)
                                .expect("update")
                        })
                    },
                );
                let cold_fits = n <= 100 || (n <= 300 && !minimised) || huge;
                if cold_fits {
                    group.bench_with_input(
                        BenchmarkId::new(format!("{shape}_cold{variant}"), n),
                        &n,
                        |b, _| {
                            let w = warmed
                                .get_or_insert_with(|| Warmed::new(&plant, theory(), &observation));
                            b.iter_batched(
                                || TimedMe::new(TimedMeOptions::kappa(10)),
                                |mut fresh| {
                                    fresh
                                        .update(
                                            &plant,
                                            &mut w.theory,
                                            &w.belief,
                                            &idle,
                                            &observation,
                                            4.0,
                                        )
                                        .expect("update")
                                },
                                BatchSize::SmallInput,
                            )
                        },
                    );
                }
            }
        }
    }
    group.finish();
}

criterion_group!(
    benches,
    mars_lander,
    propulsion,
    exact_against_timed,
    scaling
);
criterion_main!(benches);
