//! Runs a fixed number of theory queries of one kind, for counting their instructions with
//! callgrind (load-independent, unlike wall time):
//!
//! ```sh
//! cargo build --release --example theory_queries
//! valgrind --tool=callgrind --callgrind-out-file=/tmp/q.out \
//!     target/release/examples/theory_queries batsat conflict 2000
//! ```
//! Instructions per query = (total at N − total at 0) / N. BENCHMARKS.md has the numbers.
//! Small queries run on the full adder of `models/ocsp/full_adder.ron`: `consistent` (the
//! single-fault diagnosis), `conflict` (the all-healthy candidate, refuted; `batsat+min`
//! minimises the conflict) and `entails`. Medium ones on the 60-variable chain of
//! `benches/theory.rs`: `chain-consistent`, `chain-conflict`. `search` runs OPSAT's best 10 on the
//! 40-variable chain and random problems of `benches/opsat.rs` (one query = one search).

use kairos::diagnostic::Source;
use kairos::logic::parse_formula;
#[path = "../tests/support/random_ocsp.rs"]
mod random_ocsp;

use kairos::logic::ValueId;
use kairos::opsat::{Literal, Theory, TheoryOptions, file};
use random_ocsp::{chain_ocsp, sample, sized_random_ocsp};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: theory_queries batsat[+min] consistent|conflict|entails N";
    let (Some(backend), Some(query), Some(count)) = (args.get(1), args.get(2), args.get(3)) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    // The solver is named on the command line so the recorded commands (BENCHMARKS.md) still
    // run: batsat is the only one (varisat's solver is not `Send`; `opsat/sat.rs`).
    let options = TheoryOptions {
        minimize_conflicts: backend.ends_with("+min"),
    };
    let count: usize = count.parse().unwrap_or(0);
    if query.starts_with("chain") || query == "search" {
        return medium(query, options, count);
    }
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/ocsp/full_adder.ron");
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let Ok(mut instance) = file::load_with(&Source::new(path, text), options) else {
        eprintln!("cannot load {path}");
        std::process::exit(2);
    };
    let theory = &mut instance.theory;
    let gate = |name: &str, value: &str| {
        let table = theory.table();
        let x = table.variable_id(name).expect("a gate of the full adder");
        Literal::Is(x, table.variable(x).value(value).expect("ok or broken"))
    };
    let healthy: Vec<Literal> = ["X1", "X2", "A1", "A2", "O1"]
        .iter()
        .map(|g| gate(g, "ok"))
        .collect();
    let mut diagnosis = healthy.clone();
    diagnosis[0] = gate("X1", "broken");
    let sum_high = parse_formula("sum = hi", theory.table()).expect("a valid formula");
    let mut answers = 0usize;
    for _ in 0..count {
        answers += match query.as_str() {
            "consistent" => usize::from(theory.consistent(&diagnosis).is_consistent()),
            "conflict" => usize::from(theory.consistent(&healthy).is_consistent()),
            _ => usize::from(theory.entails(&diagnosis, &sum_high).unwrap_or(false)),
        };
    }
    println!("{answers} of {count} queries answered yes");
}

/// The medium workloads: the 60-variable chain's theory, and whole searches.
fn medium(query: &str, options: TheoryOptions, count: usize) {
    if query == "search" {
        let problems = [
            sample(chain_ocsp(40), 0),
            sample(sized_random_ocsp(40, 40), 0),
        ];
        let mut found = 0;
        for _ in 0..count {
            for problem in &problems {
                let (mut theory, ocsp) = problem.build(options);
                found += ocsp.best(&mut theory, 10).solutions.len();
            }
        }
        println!("{found} solutions");
        return;
    }
    let problem = sample(chain_ocsp(60), 0);
    let (mut theory, ocsp) = problem.build(options);
    let feasible = ocsp
        .best(&mut theory, 1)
        .solutions
        .first()
        .map(|s| s.literals())
        .unwrap_or_default();
    let cheapest: Vec<Literal> = feasible
        .iter()
        .map(|l| match *l {
            Literal::Is(x, _) => Literal::Is(x, ValueId(0)),
            other => other,
        })
        .collect();
    let assumptions = if query == "chain-conflict" {
        &cheapest
    } else {
        &feasible
    };
    println!(
        "{} consistent",
        count_consistent(&mut theory, assumptions, count)
    );
}

fn count_consistent(theory: &mut Theory, assumptions: &[Literal], count: usize) -> usize {
    (0..count)
        .filter(|_| theory.consistent(assumptions).is_consistent())
        .count()
}
