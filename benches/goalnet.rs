//! Goal networks (DESIGN.md §14–15): STN propagation and incremental grounding on
//! networks of 10–10,000 points, scheduling the thermostat mission, the cost a goal network
//! adds to a quiet executive cycle (monitoring and a firing pass that fires nothing), and how
//! scheduling and submissions grow with the number of goals (the workloads of
//! tests/support/goal_workload.rs: `schedule_goals/KIND/N` schedules a mission of N goals,
//! `submissions/knowledge/N` runs a scenario that submits N goals, one a cycle). Run:
//! `cargo bench --bench goalnet`; numbers in BENCHMARKS.md.
//!
//! The random networks are a chain `p(i−1) → p(i) ∈ [1, 10]` (a timeline) plus, per point, one
//! constraint `p(j) → p(i) ∈ [0, 100 · (i − j)]` from an earlier point `j` drawn by a fixed LCG:
//! consistent, with long-range edges, like a network with goals on a few SVs.

use std::hint::black_box;
use std::path::Path;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use kairos::diagnostic::Source;
use kairos::goalnet::{
    EstimateView, Execution, Provenance, Stn, TemporalConstraint, TimePointId, mission, schedule,
};
use kairos::logic::ValueId;
use kairos::reconfiguration::Reconfiguration;
use kairos::simulation;

#[path = "../tests/support/goal_workload.rs"]
mod goal_workload;

use goal_workload::Kind;

fn network(points: u32) -> Stn {
    let mut stn = Stn::new();
    let mut state: u64 = 0x6b61_6972_6f73;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        state >> 33
    };
    let ids: Vec<TimePointId> = (0..points).map(|_| stn.add_point()).collect();
    let written = || Provenance::Written(0..0);
    for i in 1..ids.len() {
        let chain = TemporalConstraint::new(ids[i - 1], ids[i], 1.0, 10.0, written());
        stn.add_constraint(chain).expect("valid");
        let j = (next() as usize) % i;
        let span = 100.0 * (i - j) as f64;
        let long = TemporalConstraint::new(ids[j], ids[i], 0.0, span, written());
        stn.add_constraint(long).expect("valid");
    }
    stn
}

fn stn(c: &mut Criterion) {
    let mut group = c.benchmark_group("stn");
    for points in [10u32, 100, 1_000, 10_000] {
        let unpropagated = network(points);
        let mut full = unpropagated.clone();
        // A network propagated once from scratch (the incremental path starts from a full one).
        full.propagate().expect("consistent");
        group.bench_with_input(BenchmarkId::new("propagate", points), &points, |b, _| {
            // The first propagation of a network is a full one (Bellman–Ford both ways).
            b.iter_batched(
                || unpropagated.clone(),
                |mut stn| black_box(stn.propagate()),
                BatchSize::LargeInput,
            );
        });
        // Grounding the middle point at its earliest time: incremental re-propagation.
        let middle = TimePointId(points / 2);
        let time = full.window(middle).expect("propagated").lb;
        group.bench_with_input(BenchmarkId::new("ground", points), &points, |b, _| {
            b.iter_batched(
                || full.clone(),
                |mut stn| black_box(stn.ground(middle, time)),
                BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

fn thermostat(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/missions/thermostat_stay_warm.ron"
    );
    let mission = mission::load(Path::new(path)).expect("loads");
    let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
    let initial = vec![ValueId(0); mission.plant.components().len()];
    c.bench_function("schedule/thermostat_stay_warm", |b| {
        b.iter(|| black_box(schedule(&mission.network, &reconfiguration, &initial)))
    });
    // A quiet cycle in the middle of the maintain interval: switch 1 closed, warm.
    let executable = schedule(&mission.network, &reconfiguration, &initial).expect("schedules");
    let mut execution = Execution::new(executable, mission.knowledge_threshold);
    let plant = &mission.plant;
    let mode = |c: &str, m: &str| {
        let id = plant.component_named(c).expect("component");
        (id, plant.component(id).mode_named(m).expect("mode"))
    };
    let mut modes = initial.clone();
    for (c, m) in [mode("switch1", "closed"), mode("temperature", "warm")] {
        modes[c.index()] = m;
    }
    let beliefs: Vec<Vec<f64>> = plant
        .components()
        .iter()
        .zip(&modes)
        .map(|(c, v)| {
            (0..c.modes().len())
                .map(|i| f64::from(u8::from(i == v.index())))
                .collect()
        })
        .collect();
    let view = EstimateView {
        modes: &modes,
        beliefs: &beliefs,
    };
    for t in 0..=200 {
        let warm_enough = if t < 11 {
            EstimateView {
                modes: &initial,
                beliefs: &beliefs,
            }
        } else {
            view
        };
        execution.step(f64::from(t), warm_enough, &reconfiguration);
    }
    let mut now = 200.0;
    c.bench_function("execution/quiet_cycle", |b| {
        b.iter(|| {
            now += 1e-6; // still inside the maintain interval: nothing fires
            black_box(execution.step(now, view, &reconfiguration))
        })
    });
}

/// Scheduling N goals, and a run with N submissions (one a cycle).
fn workloads(c: &mut Criterion) {
    let mut group = c.benchmark_group("schedule_goals");
    group.sample_size(10);
    for kind in [Kind::Knowledge, Kind::Transition] {
        let name = format!("{kind:?}").to_lowercase();
        for n in [50, 100, 150, 300, 1000] {
            let source = Source::new("workload.ron", goal_workload::mission(n, kind));
            let mission = mission::load_source(&source, goal_workload::dir()).expect("loads");
            let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
            let initial = vec![ValueId(0); mission.plant.components().len()];
            group.bench_with_input(BenchmarkId::new(&name, n), &n, |b, _| {
                b.iter(|| black_box(schedule(&mission.network, &reconfiguration, &initial)))
            });
        }
    }
    group.finish();
    let mut group = c.benchmark_group("submissions");
    group.sample_size(10);
    for n in [50, 100, 150, 300] {
        let source = Source::new("workload.ron", goal_workload::scenario(n, Kind::Knowledge));
        let scenario = simulation::load_source(&source, goal_workload::dir()).expect("loads");
        group.bench_with_input(BenchmarkId::new("knowledge", n), &n, |b, _| {
            b.iter(|| {
                let outcome = simulation::run(&scenario, Default::default(), &mut |_| {});
                black_box(outcome.expect("runs"))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, stn, thermostat, workloads);
criterion_main!(benches);
