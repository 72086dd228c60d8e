//! Mode reconfiguration (DESIGN.md §14): goal interpretation and one reactive-planner
//! step on the propulsion subsystem (§6.3.3) and on a synthetic plant of 100 components (a bus,
//! 9 drivers, 90 devices), and policy compilation. The target is Burton's: one planner step in
//! constant time, at most 5 µs median on propulsion. Run: `cargo bench --bench reconfiguration`.

#[path = "../tests/support/reconfiguration_plants.rs"]
mod plants;
#[path = "../tests/support/reconfiguration.rs"]
mod support;

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use kairos::reconfiguration::Reconfiguration;
use plants::synthetic_plant_ron;
use support::{Setup, plant_from};

/// The workloads: a plant, a start state, a goal, and a state in the middle of the plan.
struct Workload {
    name: &'static str,
    setup: Setup,
    start: Vec<kairos::logic::ValueId>,
    goal: &'static str,
}

fn workloads() -> Vec<Workload> {
    let propulsion = Setup::model("propulsion");
    let start = propulsion.state(&[]);
    let synthetic = Setup::new(plant_from("synthetic.ron", &synthetic_plant_ron(9, 10)));
    assert_eq!(synthetic.plant.components().len(), 100);
    let synthetic_start = synthetic.state(&[]);
    vec![
        Workload {
            name: "propulsion",
            setup: propulsion,
            start,
            goal: "engine = firing",
        },
        Workload {
            name: "synthetic_100",
            setup: synthetic,
            start: synthetic_start,
            goal: "d3v4 = open and d7v1 = open and d8v9 = open",
        },
    ]
}

fn reconfiguration(c: &mut Criterion) {
    let mut group = c.benchmark_group("reconfiguration");
    group.measurement_time(Duration::from_secs(3));
    for mut workload in workloads() {
        let name = workload.name;
        let goal = workload.setup.formula(workload.goal);
        let goal_state = workload
            .setup
            .interpret(&workload.start, workload.goal)
            .expect("a goal state");
        // Every state the nominal plan passes through: the planner step is timed on each.
        let run = workload.setup.run(&workload.start, &goal_state);
        let states: Vec<_> = std::iter::once(workload.start.clone())
            .chain(run.steps.iter().map(|s| s.state.clone()))
            .collect();
        let Setup {
            plant,
            reconfiguration,
            mut theory,
        } = workload.setup;
        group.bench_function(format!("gi/{name}"), |b| {
            b.iter(|| {
                reconfiguration
                    .interpret(&mut theory, black_box(&workload.start), &goal)
                    .expect("a goal state")
            })
        });
        group.bench_function(format!("rp_step/{name}"), |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) % states.len();
                reconfiguration.next_action(black_box(&states[i]), &goal_state)
            })
        });
        group.bench_function(format!("rp_step_first/{name}"), |b| {
            b.iter(|| reconfiguration.next_action(black_box(&workload.start), &goal_state))
        });
        group.sample_size(10);
        group.bench_function(format!("compile/{name}"), |b| {
            b.iter(|| Reconfiguration::compile(black_box(&plant)).expect("compiles"))
        });
        group.sample_size(100);
    }
    group.finish();
}

criterion_group!(benches, reconfiguration);
criterion_main!(benches);
