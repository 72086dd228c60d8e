//! Theory query latency on batsat, with and without conflict minimisation (BENCHMARKS.md, "The
//! theory and OPSAT"; the ids keep the solver's name from when varisat was compared beside it).
//! Small: the 5-gate full adder (13 variables); medium: a 60-variable chain-coupled problem with
//! ~90 clauses.
//! Run: `cargo bench --bench theory`.

#[path = "../tests/support/random_ocsp.rs"]
mod random_ocsp;

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use kairos::diagnostic::Source;
use kairos::opsat::{Consistency, Literal, Theory, TheoryOptions, file};
use random_ocsp::{chain_ocsp, sample};

/// The SAT solver's name in the benchmark ids.
const BACKEND: &str = "batsat";

/// The full adder of `models/ocsp/full_adder.ron`, encoded with `options`.
fn full_adder(options: TheoryOptions) -> Theory {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/ocsp/full_adder.ron");
    let text = std::fs::read_to_string(path).expect("the example exists");
    file::load_with(&Source::new(path, text), options)
        .expect("the example loads")
        .theory
}

fn is(theory: &Theory, var: &str, value: &str) -> Literal {
    let table = theory.table();
    let x = table.variable_id(var).expect("known variable");
    Literal::Is(x, table.variable(x).value(value).expect("known value"))
}

fn bench_small(c: &mut Criterion) {
    let mut group = c.benchmark_group("theory_small_full_adder");
    group.measurement_time(Duration::from_secs(2));
    for minimize_conflicts in [false, true] {
        let mut theory = full_adder(TheoryOptions { minimize_conflicts });
        let healthy: Vec<Literal> = ["X1", "X2", "A1", "A2", "O1"]
            .iter()
            .map(|g| is(&theory, g, "ok"))
            .collect();
        let mut diagnosis = healthy.clone();
        diagnosis[0] = is(&theory, "X1", "broken");
        assert!(matches!(
            theory.consistent(&healthy),
            Consistency::Conflict(_)
        ));
        assert_eq!(theory.consistent(&diagnosis), Consistency::Consistent);
        let tag = format!("{BACKEND}{}", if minimize_conflicts { "+min" } else { "" });
        group.bench_function(BenchmarkId::new("consistent", &tag), |b| {
            b.iter(|| black_box(theory.consistent(&diagnosis)))
        });
        group.bench_function(BenchmarkId::new("conflict", &tag), |b| {
            b.iter(|| black_box(theory.consistent(&healthy)))
        });
        if !minimize_conflicts {
            let sum_hi = kairos::logic::parse_formula("sum = hi", theory.table()).expect("ok");
            group.bench_function(BenchmarkId::new("entails", &tag), |b| {
                b.iter(|| black_box(theory.entails(&diagnosis, &sum_hi)))
            });
        }
    }
    group.finish();
}

fn bench_medium(c: &mut Criterion) {
    let problem = sample(chain_ocsp(60), 0);
    let best = {
        let (mut theory, ocsp) = problem.build(TheoryOptions::default());
        ocsp.best(&mut theory, 1).solutions.into_iter().next()
    };
    let Some(best) = best else { return };
    let mut group = c.benchmark_group("theory_medium_chain60");
    group.measurement_time(Duration::from_secs(2));
    for minimize_conflicts in [false, true] {
        let (mut theory, _) = problem.build(TheoryOptions { minimize_conflicts });
        let feasible = best.literals();
        // The all-cheapest assignment: in a chain biased against cheap values it conflicts.
        let cheapest: Vec<Literal> = feasible
            .iter()
            .map(|l| match *l {
                Literal::Is(x, _) => Literal::Is(x, kairos::logic::ValueId(0)),
                other => other,
            })
            .collect();
        let tag = format!("{BACKEND}{}", if minimize_conflicts { "+min" } else { "" });
        group.bench_function(BenchmarkId::new("consistent", &tag), |b| {
            b.iter(|| black_box(theory.consistent(&feasible)))
        });
        group.bench_function(BenchmarkId::new("conflict", &tag), |b| {
            b.iter(|| black_box(theory.consistent(&cheapest)))
        });
    }
    group.bench_function(BenchmarkId::new("encode", BACKEND), |b| {
        b.iter(|| {
            black_box(problem.build(TheoryOptions {
                minimize_conflicts: true,
            }))
        })
    });
    group.finish();
}

criterion_group!(benches, bench_small, bench_medium);
criterion_main!(benches);
