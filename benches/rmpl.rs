//! RMPL and sequencer benchmarks (DESIGN.md §14):
//! - compiling `programs/mars_edl.rmpl`: parsing, linking against the lander's variables,
//!   building the THCA, and the three together;
//! - one `Step_THCA` cycle on the EDL automaton during powered descent (its busiest marking),
//!   with the assignment oracle (the sequencer's own cost) and with a SAT-backed `Theory` oracle;
//! - one cycle on synthetic programs of growing size, to show the cost is linear in the size of
//!   the program (thesis §5.3).
//!
//! Run: `cargo bench --bench rmpl`. Numbers are in BENCHMARKS.md.

#[path = "../tests/support/rmpl.rs"]
mod rmpl_support;

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use kairos::diagnostic::Source;
use kairos::opsat::Theory;
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::{AssignmentOracle, Entailment, Sequencer, StateEstimate, TheoryOracle};
use rmpl_support::{IdealPlant, MARS_LANDER_INITIAL, load_program, mars_lander_plant};

fn edl_source() -> Source {
    let path = format!("{}/programs/mars_edl.rmpl", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the EDL program");
    Source::new("programs/mars_edl.rmpl", text)
}

fn compile(c: &mut Criterion) {
    let source = edl_source();
    let plant = mars_lander_plant();
    let options = LinkOptions {
        entry: None,
        plant: Some(&plant),
    };
    let file = rmpl::parse(&source.text).expect("parses");
    let linked = rmpl::link(&source, &file, &options).expect("links");
    let mut group = c.benchmark_group("compile mars_edl");
    group.bench_function("parse", |b| b.iter(|| rmpl::parse(black_box(&source.text))));
    group.bench_function("link", |b| {
        b.iter(|| rmpl::link(&source, black_box(&file), &options))
    });
    group.bench_function("build THCA", |b| {
        b.iter(|| rmpl::compile(black_box(&linked), &source))
    });
    group.bench_function("parse+link+build", |b| {
        b.iter(|| rmpl::load(black_box(&source), &options))
    });
    group.finish();
}

/// Times one full cycle (both halves) of `sequencer` in its current marking, with a constant
/// estimate so that the marking stays the same from cycle to cycle.
fn bench_cycles<E: Entailment>(
    b: &mut criterion::Bencher<'_>,
    sequencer: &Sequencer,
    estimate: &E::Estimate,
    oracle: &mut E,
) {
    let mut sequencer = sequencer.clone();
    let mut time = 100_000.0;
    b.iter(|| {
        time += 0.5;
        let step = sequencer
            .step(time, estimate, estimate, oracle)
            .expect("cycles alternate");
        black_box(step)
    });
}

fn step_edl(c: &mut Criterion) {
    let plant = mars_lander_plant();
    let thca = load_program("programs/mars_edl.rmpl", Some(&plant));
    let mut run = IdealPlant::new(thca, MARS_LANDER_INITIAL, 1.0);
    run.run_until(
        17250.0,
        &[
            (17000.0, &[("entry", "initiated")]),
            (17100.0, &[("Mach_trigger", "triggered")]),
            (17200.0, &[("alt_vel_trigger", "triggered")]),
        ],
    );
    let marked = run.sequencer.marking().count();
    let estimate = run.estimate.clone();
    let mut group = c.benchmark_group(format!("step mars_edl powered descent ({marked} marked)"));
    group.bench_function("assignment oracle", |b| {
        let mut oracle = AssignmentOracle::new(&plant);
        bench_cycles(b, &run.sequencer, &estimate, &mut oracle)
    });
    group.bench_function("theory oracle", |b| {
        let mut theory = Theory::new(plant.clone(), &[]).expect("no constraints");
        let mut oracle = TheoryOracle::new(&mut theory);
        bench_cycles(b, &run.sequencer, &estimate, &mut oracle)
    });
    group.finish();
}

/// `threads` copies of a thread that keeps every kind of location busy: a composite watching a
/// condition, an `always` re-marking a goal, a `whenever` looping and a `when` waiting.
fn synthetic_program(threads: usize) -> String {
    let thread = |k: usize| {
        format!(
            "do {{ always (x{k} = on), whenever (c{k} = yes) donext (y{k} = on), \
             when (d{k} = yes) donext (z{k} = on) }} watching (stop{k} = yes)"
        )
    };
    let body: Vec<String> = (0..threads).map(thread).collect();
    format!("P() :: {{ {} }}", body.join(",\n"))
}

fn step_scaling(c: &mut Criterion) {
    let mut group = c.benchmark_group("step synthetic");
    for threads in [10, 100, 1000] {
        let source = Source::new("synthetic.rmpl", synthetic_program(threads));
        let thca = rmpl::load(&source, &LinkOptions::default()).expect("compiles");
        let locations = thca.locations().len();
        let mut oracle = AssignmentOracle::new(thca.table());
        let sequencer = Sequencer::new(thca);
        group.throughput(Throughput::Elements(locations as u64));
        group.bench_with_input(
            BenchmarkId::new("locations", locations),
            &sequencer,
            |b, sequencer| bench_cycles(b, sequencer, &StateEstimate::new(), &mut oracle),
        );
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = compile, step_edl, step_scaling
}
criterion_main!(benches);
