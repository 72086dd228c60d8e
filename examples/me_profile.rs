//! Replays the nominal Mars EDL (`models/mars_lander.ron`, §7.2.2) through TimedME, for
//! measuring mode estimation under callgrind (instruction counts are repeatable on a shared
//! machine; wall time is not).
//!
//! ```text
//! cargo build --release --example me_profile
//! target/release/examples/me_profile CASE [--kappa K] [--history H] [--steps N] [--warmup W] [--dump FILE]
//! valgrind --tool=callgrind --toggle-collect='*measured_step*' \
//!     --callgrind-out-file=cg.out target/release/examples/me_profile cruise --steps 200
//! ```
//! Instructions per step = the callgrind total ÷ the measured steps the program prints: only
//! `measured_step` is collected, so the warm-up that reaches the case does not count.
//!
//! Cases (all at the executive's 0.1 s cycle where they are measured):
//! - `cruise`: quiet steps of the 16,200 s cruise wait, from 1,000 s;
//! - `heating`: the engine inside its Uniform(30, 60) s heating window (heating from 0.2 s,
//!   standby at 43.2 s), from 25 s (so measured from 30 s with the default warm-up, and inside
//!   the window for `--steps 100`; BENCHMARKS.md skips the window's opening with
//!   `--warmup 60`);
//! - `entry`: the entry trigger's Gaussian(16800, 30) window, from 15,700 s (per-step
//!   probability non-zero, drag not yet sensed);
//! - `events`: every cycle whose observation changed or that follows a command (mode changes),
//!   over the whole EDL (quiet stretches replayed on a 600 s grid, not measured);
//! - `edl`: the whole EDL, every 0.1 s cycle (≈ 171,600 steps); prints the total.
//!
//! `--history H` sets the window TimedME may re-run (default 16; 0: none). The summary counts the
//! steps re-run at 8κ: on the `events` case's 600 s grid most of its time is those re-runs, not
//! the event steps themselves (`--history 0` measures the steps alone).
//!
//! `--dump FILE` writes every step's belief (modes, clock starts and probabilities, exactly) so
//! that two builds can be compared for identical answers.

#[path = "../tests/support/mod.rs"]
#[allow(dead_code)]
mod support;

use std::fs::File;
use std::hint::black_box;
use std::io::{BufWriter, Write};
use std::time::{Duration, Instant};

use kairos::estimation::log::LogRecord;
use kairos::estimation::{Belief, ModeEstimator, TimedMe, TimedMeOptions, Update};
use kairos::opsat::Theory;
use kairos::plant::Plant;
use support::lander_edl::{CYCLE, Faults, edl, ms, nominal_edl};
use support::plants::model;

/// What to replay and which steps to measure.
struct Case {
    records: Vec<LogRecord>,
    /// Per record (after the first): measure this step.
    measured: Vec<bool>,
}

/// Quiet steps every 0.1 s from `from` s: `warmup` unmeasured, then `steps` measured; before
/// that, the EDL on a 600 s grid (with its events).
fn window(plant: &Plant, from: f64, warmup: usize, steps: usize) -> Case {
    let timeline = nominal_edl(Faults::default());
    let start = ms(from);
    let fine = (0..(warmup + steps) as u64).map(|k| start + k * ms(CYCLE));
    let mut times: Vec<u64> = timeline
        .times(edl::END, 600.0)
        .into_iter()
        .filter(|&t| t < start)
        .chain(fine)
        .collect();
    times.sort_unstable();
    times.dedup();
    let records = timeline.records(plant, &times);
    let first_measured = records.len() - steps;
    let measured = (1..records.len()).map(|i| i >= first_measured).collect();
    Case { records, measured }
}

/// Every cycle that follows a command or sees an observation change, over the EDL replayed on
/// a 600 s grid.
fn events(plant: &Plant) -> Case {
    let timeline = nominal_edl(Faults::default());
    let records = timeline.records(plant, &timeline.times(edl::END, 600.0));
    let measured = records
        .windows(2)
        .map(|pair| {
            let idle = pair[0].commands.issued(plant).next().is_none();
            !idle || pair[0].observation != pair[1].observation
        })
        .collect();
    Case { records, measured }
}

/// The whole EDL at 0.1 s, every step measured.
fn whole(plant: &Plant) -> Case {
    let timeline = nominal_edl(Faults::default());
    let records = timeline.records(plant, &timeline.times(edl::END, CYCLE));
    let measured = vec![true; records.len() - 1];
    Case { records, measured }
}

struct Args {
    case: String,
    kappa: usize,
    history: usize,
    steps: usize,
    warmup: usize,
    dump: Option<String>,
}

fn args() -> Args {
    let mut args = Args {
        case: String::new(),
        kappa: 10,
        history: kairos::estimation::DEFAULT_HISTORY,
        steps: 200,
        warmup: 50,
        dump: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().expect("a value after the option");
        match arg.as_str() {
            "--kappa" => args.kappa = value().parse().expect("κ"),
            "--history" => args.history = value().parse().expect("history steps"),
            "--steps" => args.steps = value().parse().expect("steps"),
            "--warmup" => args.warmup = value().parse().expect("warm-up steps"),
            "--dump" => args.dump = Some(value()),
            case => args.case = case.to_string(),
        }
    }
    args
}

#[inline(never)]
fn measured_step(
    estimator: &mut TimedMe,
    plant: &Plant,
    theory: &mut Theory,
    belief: &Belief,
    before: &LogRecord,
    now: &LogRecord,
) -> Update {
    black_box(step(estimator, plant, theory, belief, before, now))
}

#[inline(never)]
fn step(
    estimator: &mut TimedMe,
    plant: &Plant,
    theory: &mut Theory,
    belief: &Belief,
    before: &LogRecord,
    now: &LogRecord,
) -> Update {
    estimator
        .update(
            plant,
            theory,
            belief,
            &before.commands,
            &now.observation,
            now.time,
        )
        .expect("update")
}

/// One step's belief, exactly: time, then per state its probability, modes and clock starts.
fn dump(out: &mut impl Write, belief: &Belief) {
    write!(out, "{}", belief.time()).expect("write");
    for weighted in belief.states() {
        let modes: Vec<u32> = weighted.state.modes.iter().map(|m| m.0).collect();
        let clocks: Vec<String> = weighted
            .state
            .clock_starts
            .iter()
            .map(|c| c.map_or("-".to_string(), |s| s.to_string()))
            .collect();
        write!(
            out,
            " | {:e} {:?} {}",
            weighted.probability,
            modes,
            clocks.join(",")
        )
        .expect("write");
    }
    writeln!(out).expect("write");
}

fn main() {
    let args = args();
    let plant = model("mars_lander");
    let case = match args.case.as_str() {
        "cruise" => window(&plant, 1000.0, args.warmup, args.steps),
        "heating" => window(&plant, 25.0, args.warmup, args.steps),
        "entry" => window(&plant, 15700.0, args.warmup, args.steps),
        "events" => events(&plant),
        "edl" => whole(&plant),
        other => panic!("unknown case `{other}`: cruise, heating, entry, events or edl"),
    };
    let mut theory = plant.theory().expect("theory");
    let options = TimedMeOptions {
        history: args.history,
        ..TimedMeOptions::kappa(args.kappa)
    };
    let mut estimator = TimedMe::new(options);
    let mut out = args
        .dump
        .as_ref()
        .map(|path| BufWriter::new(File::create(path).expect("dump file")));
    let first = &case.records[0];
    let mut belief = estimator
        .initial(&plant, &mut theory, first.time, &first.observation)
        .expect("initial")
        .belief;
    let (mut count, mut sat_calls, mut propagated, mut events) = (0u64, 0u64, 0u64, 0usize);
    let (mut replayed, mut rerun) = (0u64, 0u64);
    let mut times: Vec<Duration> = Vec::new();
    for (pair, &measure) in case.records.windows(2).zip(&case.measured) {
        let (before, now) = (&pair[0], &pair[1]);
        let update = if measure {
            let propagated_before = theory.stats().propagated;
            let started = Instant::now();
            let update = measured_step(&mut estimator, &plant, &mut theory, &belief, before, now);
            times.push(started.elapsed());
            count += 1;
            sat_calls += update.stats.sat_calls;
            replayed += u64::from(update.stats.replayed);
            rerun += u64::from(update.stats.rerun);
            propagated += theory.stats().propagated - propagated_before;
            update
        } else {
            step(&mut estimator, &plant, &mut theory, &belief, before, now)
        };
        events += update.events.len();
        belief = update.belief;
        if let Some(out) = out.as_mut() {
            dump(out, &belief);
        }
    }
    let total: Duration = times.iter().sum();
    times.sort_unstable();
    let median = times.get(times.len() / 2).copied().unwrap_or_default();
    println!(
        "case {} kappa {}: {count} measured steps of {}; total {:.3} s, mean {:.1} us, median {:.1} us, max {:.1} us; {:.1} SAT calls per step ({:.1} of them answered by unit propagation); {replayed} replayed; {rerun} steps re-run; {events} estimation events",
        args.case,
        args.kappa,
        case.records.len() - 1,
        total.as_secs_f64(),
        total.as_secs_f64() * 1e6 / count.max(1) as f64,
        median.as_secs_f64() * 1e6,
        times.last().copied().unwrap_or_default().as_secs_f64() * 1e6,
        sat_calls as f64 / count.max(1) as f64,
        propagated as f64 / count.max(1) as f64,
    );
    let last = belief.most_likely_plant_state();
    println!(
        "final estimate: {}",
        kairos::plant::describe_modes(&plant, &last.modes)
    );
}
