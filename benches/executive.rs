//! A full executive cycle on the propulsion scenario (DESIGN.md §14), with the shares
//! of mode estimation, the sequencer and mode reconfiguration measured separately.
//!
//! The workload is `scenarios/propulsion/pde_resettable.ron` (§6.3.3's sequence with a PDE
//! repair) run through `kairos::simulation::run` to 300 s: about 48 *busy* cycles (a mode
//! change, a goal, a command: something happens) and 250 *quiet* ones (the engine fires, nothing
//! changes). Each benchmark reports the mean time per cycle of one phase over one class of
//! cycles, from the executive's own per-phase timers (`Step::times`), so the phases are measured
//! one by one on the very same cycles and building the executive is not counted.
//!
//! The cost a goal network adds to a quiet cycle (DESIGN.md §15.3): the
//! thermostat's StayWarm run as RMPL (`scenarios/thermostat/stay_warm.ron`) and as a mission
//! (`scenarios/thermostat/stay_warm_mission.ron`), same plant, same script, same tactic; the mean
//! quiet cycle (no event: the device held warm) of each, whole and its control-program share (the
//! sequencer, or the network's monitoring, firing and configuration goal). Run: `cargo bench
//! --bench executive`; numbers in BENCHMARKS.md.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use kairos::executive::PhaseTimes;
use kairos::simulation::{self, RunOptions, Scenario};

/// The scenario, kept running to its end time: an expectation that is never shown keeps the run
/// from stopping once the engine fires.
fn scenario() -> Scenario {
    let mut scenario = load("scenarios/propulsion/pde_resettable.ron");
    let never = simulation::load_source(
        &kairos::diagnostic::Source::new(
            "keep-running.ron",
            r#"Scenario(program: "programs/propulsion_fire.rmpl", plant: "models/propulsion.ron",
               cycle: 1.0, end: 300.0, expect: [Estimated(state: "tank1 = empty")])"#,
        ),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    )
    .expect("loads");
    scenario.expectations = never.expectations;
    scenario
}

/// A scenario of the crate, by its path from the crate's root.
fn load(path: &str) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    simulation::load(&path).expect("the scenario loads")
}

#[derive(Clone, Copy, PartialEq)]
enum Class {
    Busy,
    Quiet,
}

#[derive(Clone, Copy)]
enum Phase {
    Total,
    Estimation,
    Sequencer,
    Reconfiguration,
}

impl Phase {
    fn of(self, times: &PhaseTimes) -> Duration {
        match self {
            Phase::Total => times.total,
            Phase::Estimation => times.estimation,
            Phase::Sequencer => times.sequencer,
            Phase::Reconfiguration => times.reconfiguration,
        }
    }
}

/// Runs the scenario once; returns the summed time of `phase` over the cycles of `class` and
/// how many there were.
fn one_run(scenario: &Scenario, class: Class, phase: Phase) -> (Duration, u32) {
    let (mut sum, mut cycles) = (Duration::ZERO, 0);
    simulation::run(scenario, RunOptions::default(), &mut |record| {
        let busy = !record.step.events.is_empty();
        if (class == Class::Busy) == busy {
            sum += phase.of(&record.step.times);
            cycles += 1;
        }
    })
    .expect("the run goes");
    (sum, cycles)
}

fn cycle(c: &mut Criterion) {
    let scenario = scenario();
    let mut group = c.benchmark_group("executive/propulsion");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    for (class, class_name) in [(Class::Busy, "busy"), (Class::Quiet, "quiet")] {
        for (phase, phase_name) in [
            (Phase::Total, "cycle"),
            (Phase::Estimation, "estimation"),
            (Phase::Sequencer, "sequencer"),
            (Phase::Reconfiguration, "reconfiguration"),
        ] {
            let id = BenchmarkId::new(phase_name, class_name);
            // One iteration is one cycle: whole runs are made until `iters` cycles of the class
            // have been timed, and the per-cycle mean is scaled to `iters`.
            group.bench_function(id, |b| per_cycle(b, &scenario, class, phase));
        }
    }
    group.finish();
}

/// One iteration is one cycle: whole runs are made until `iters` cycles of the class have been
/// timed, and the per-cycle mean is scaled to `iters`.
fn per_cycle(b: &mut criterion::Bencher<'_>, scenario: &Scenario, class: Class, phase: Phase) {
    b.iter_custom(|iters| {
        let (mut sum, mut cycles) = (Duration::ZERO, 0u64);
        while cycles < iters {
            let (run_sum, run_cycles) = one_run(black_box(scenario), class, phase);
            sum += run_sum;
            cycles += u64::from(run_cycles.max(1));
        }
        sum.mul_f64(iters as f64 / cycles as f64)
    });
}

/// A quiet thermostat cycle under StayWarm, as RMPL, as a mission, and as the mission with the
/// seed's goal types run by the goal controller.
fn thermostat(c: &mut Criterion) {
    let mut group = c.benchmark_group("executive/thermostat_quiet");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(3));
    for (program, path) in [
        ("rmpl", "scenarios/thermostat/stay_warm.ron"),
        ("mission", "scenarios/thermostat/stay_warm_mission.ron"),
        (
            "mission-elaborated",
            "scenarios/thermostat/system_test_4.ron",
        ),
    ] {
        let scenario = load(path);
        for (phase, phase_name) in [(Phase::Total, "cycle"), (Phase::Sequencer, "program")] {
            let id = BenchmarkId::new(phase_name, program);
            group.bench_function(id, |b| per_cycle(b, &scenario, Class::Quiet, phase));
        }
    }
    group.finish();
}

criterion_group!(benches, cycle, thermostat);
criterion_main!(benches);
