//! Random OCSPs and a brute-force reference solver, shared by the property tests
//! (`tests/opsat_properties.rs`) and the benchmarks (`benches/opsat.rs`).
#![allow(dead_code)] // each includer uses a different part

use kairos::logic::{Formula, ValueId, VarId, VarTable};
use kairos::opsat::{Literal, Ocsp, Theory, TheoryOptions};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

/// A literal of a clause: (variable index, value index, positive?).
pub type ClauseLiteral = (usize, usize, bool);

/// An OCSP described by plain numbers, so it can be built into a theory and solved by brute
/// force independently.
#[derive(Debug, Clone)]
pub struct RandomOcsp {
    /// Per decision variable, the cost of each value.
    pub decision_costs: Vec<Vec<f64>>,
    /// Domain size of each auxiliary variable (variables numbered after the decisions).
    pub aux_domains: Vec<usize>,
    /// Constraints, as disjunctions of literals.
    pub clauses: Vec<Vec<ClauseLiteral>>,
    /// Literals every solution must satisfy, given to OPSAT as per-problem assumptions
    /// (`Ocsp::assume`) rather than as theory constraints.
    pub assumed: Vec<ClauseLiteral>,
}

impl RandomOcsp {
    /// Domain size of every variable, decisions first.
    pub fn domains(&self) -> Vec<usize> {
        self.decision_costs
            .iter()
            .map(Vec::len)
            .chain(self.aux_domains.iter().copied())
            .collect()
    }

    /// The variable table: decisions `d0..`, auxiliaries `a0..`, values `v0..`.
    pub fn table(&self) -> VarTable {
        let mut table = VarTable::new();
        for (i, costs) in self.decision_costs.iter().enumerate() {
            let values: Vec<String> = (0..costs.len()).map(|v| format!("v{v}")).collect();
            table.add_variable(format!("d{i}"), values).unwrap();
        }
        for (i, &size) in self.aux_domains.iter().enumerate() {
            let values: Vec<String> = (0..size).map(|v| format!("v{v}")).collect();
            table.add_variable(format!("a{i}"), values).unwrap();
        }
        table
    }

    /// The clauses as formulas.
    pub fn formulas(&self) -> Vec<Formula> {
        self.clauses
            .iter()
            .map(|clause| {
                Formula::Or(
                    clause
                        .iter()
                        .map(|&(x, v, positive)| {
                            let atom = Formula::is(VarId(x as u32), ValueId(v as u32));
                            if positive { atom } else { atom.negate() }
                        })
                        .collect(),
                )
            })
            .collect()
    }

    /// The theory and the OCSP over it.
    pub fn build(&self, options: TheoryOptions) -> (Theory, Ocsp) {
        let theory = Theory::with_options(self.table(), &self.formulas(), options).unwrap();
        let mut ocsp = Ocsp::new();
        for (i, costs) in self.decision_costs.iter().enumerate() {
            let choices = costs
                .iter()
                .enumerate()
                .map(|(v, &c)| (ValueId(v as u32), c));
            ocsp.decide(VarId(i as u32), choices).unwrap();
        }
        for &(x, v, positive) in &self.assumed {
            let literal = Literal::Is(VarId(x as u32), ValueId(v as u32));
            ocsp.assume(if positive { literal } else { !literal });
        }
        (theory, ocsp)
    }

    /// Does a full assignment of every variable satisfy every clause and assumption?
    pub fn satisfies(&self, values: &[usize]) -> bool {
        let holds = |&(x, v, positive): &ClauseLiteral| (values[x] == v) == positive;
        self.clauses.iter().all(|clause| clause.iter().any(holds)) && self.assumed.iter().all(holds)
    }

    /// Is a full assignment of the decision variables feasible (some auxiliary values complete
    /// it)?
    pub fn feasible(&self, decisions: &[usize]) -> bool {
        let mut values = decisions.to_vec();
        values.resize(decisions.len() + self.aux_domains.len(), 0);
        let aux = decisions.len()..values.len();
        let domains = self.domains();
        loop {
            if self.satisfies(&values) {
                return true;
            }
            if !increment(&mut values, aux.clone(), &domains) {
                return false;
            }
        }
    }

    /// Every feasible decision assignment with its cost, cheapest first.
    pub fn brute_force(&self) -> Vec<(Vec<usize>, f64)> {
        let n = self.decision_costs.len();
        let domains = self.domains();
        let mut values = vec![0; n];
        let mut out = Vec::new();
        loop {
            if self.feasible(&values) {
                let cost: f64 = values
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| self.decision_costs[i][v])
                    .sum();
                out.push((values.clone(), cost));
            }
            if !increment(&mut values, 0..n, &domains) {
                break;
            }
        }
        out.sort_by(|a, b| a.1.total_cmp(&b.1));
        out
    }
}

/// Odometer step over `positions`; false after the last assignment.
fn increment(values: &mut [usize], positions: std::ops::Range<usize>, domains: &[usize]) -> bool {
    for i in positions {
        values[i] += 1;
        if values[i] < domains[i] {
            return true;
        }
        values[i] = 0;
    }
    false
}

/// Costs from a small set, so exact ties happen, plus some arbitrary ones.
fn cost() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => (0u8..6).prop_map(|c| f64::from(c) * 0.5),
        1 => 0.0..5.0f64,
    ]
}

fn clause(
    domains: Vec<usize>,
    lengths: std::ops::RangeInclusive<usize>,
) -> impl Strategy<Value = Vec<ClauseLiteral>> {
    let n = domains.len();
    prop::collection::vec(
        (
            0..n,
            any::<prop::sample::Index>(),
            prop::bool::weighted(0.3),
        )
            .prop_map(move |(x, v, positive)| (x, v.index(domains[x]), positive)),
        lengths,
    )
}

/// Random OCSPs: up to `max_decisions` decision variables with domains of 2–4 values, up to
/// `max_aux` auxiliary variables with 2–3 values, and up to `max_clauses` clauses of 1–3
/// literals over any variables.
pub fn random_ocsp(
    max_decisions: usize,
    max_aux: usize,
    max_clauses: usize,
) -> impl Strategy<Value = RandomOcsp> {
    (
        prop::collection::vec(prop::collection::vec(cost(), 2..=4), 1..=max_decisions),
        prop::collection::vec(2usize..=3, 0..=max_aux),
    )
        .prop_flat_map(move |(decision_costs, aux_domains)| {
            let domains: Vec<usize> = decision_costs
                .iter()
                .map(Vec::len)
                .chain(aux_domains.iter().copied())
                .collect();
            prop::collection::vec(clause(domains, 1..=3), 0..=max_clauses).prop_map(
                move |clauses| RandomOcsp {
                    decision_costs: decision_costs.clone(),
                    aux_domains: aux_domains.clone(),
                    clauses,
                    assumed: Vec::new(),
                },
            )
        })
}

/// Chain-coupled OCSPs: `n` decision variables of 3 values in a row, each clause over a window
/// of three neighbours, biased against the cheap values so conflicts are common — the shape of
/// components coupled along a bus or a propellant line.
pub fn chain_ocsp(n: usize) -> impl Strategy<Value = RandomOcsp> {
    let costs = prop::collection::vec(prop::collection::vec(cost(), 3), n);
    let clauses = prop::collection::vec(
        (0..n.saturating_sub(2).max(1)).prop_flat_map(move |start| {
            let width = 3.min(n);
            prop::collection::vec(
                (start..start + width, 0usize..3, prop::bool::weighted(0.2)),
                2..=3,
            )
        }),
        n..=2 * n,
    );
    (costs, clauses).prop_map(|(mut decision_costs, clauses)| {
        // Sort each domain so value 0 is the cheapest: the clauses above mostly forbid low
        // values, so the cheapest candidates are the ones that conflict.
        for costs in &mut decision_costs {
            costs.sort_by(f64::total_cmp);
        }
        RandomOcsp {
            decision_costs,
            aux_domains: Vec::new(),
            clauses,
            assumed: Vec::new(),
        }
    })
}

/// One value of a strategy, the same on every run (for benchmarks).
pub fn sample<S: Strategy>(strategy: S, seed_offset: usize) -> S::Value {
    let mut runner = TestRunner::deterministic();
    let mut value = strategy.new_tree(&mut runner).unwrap().current();
    for _ in 0..seed_offset {
        value = strategy.new_tree(&mut runner).unwrap().current();
    }
    value
}

/// Unstructured OCSPs of exactly `n` decision variables (domains 2–4) with `clauses` random
/// clauses of 2–3 literals over all of them.
pub fn sized_random_ocsp(n: usize, clauses: usize) -> impl Strategy<Value = RandomOcsp> {
    prop::collection::vec(prop::collection::vec(cost(), 2..=4), n).prop_flat_map(
        move |mut decision_costs| {
            for costs in &mut decision_costs {
                costs.sort_by(f64::total_cmp);
            }
            let domains: Vec<usize> = decision_costs.iter().map(Vec::len).collect();
            prop::collection::vec(clause(domains, 2..=3), clauses).prop_map(move |clauses| {
                RandomOcsp {
                    decision_costs: decision_costs.clone(),
                    aux_domains: Vec::new(),
                    clauses,
                    assumed: Vec::new(),
                }
            })
        },
    )
}

/// [`random_ocsp`] with up to `max_assumed` random literals assumed per problem, over decision
/// and auxiliary variables alike.
pub fn random_ocsp_with_assumptions(
    max_decisions: usize,
    max_aux: usize,
    max_clauses: usize,
    max_assumed: usize,
) -> impl Strategy<Value = RandomOcsp> {
    random_ocsp(max_decisions, max_aux, max_clauses).prop_flat_map(move |problem| {
        let domains = problem.domains();
        prop::collection::vec(clause(domains, 1..=1), 0..=max_assumed).prop_map(move |literals| {
            let mut problem = problem.clone();
            problem.assumed = literals.into_iter().flatten().collect();
            problem
        })
    })
}
