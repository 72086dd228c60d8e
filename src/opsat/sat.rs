//! The incremental SAT solvers the [`super::Theory`] is built on, behind one small interface.
//!
//! Two maintained pure-Rust CDCL solvers with assumptions and failed-assumption cores are wired
//! in: batsat (a MiniSat descendant) and varisat. `benches/theory.rs` measures both on the
//! Theory's workloads; BENCHMARKS.md records the numbers and the choice of the default.

use std::ops::Not;

/// Which SAT solver a [`super::Theory`] runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SatBackend {
    /// `batsat`: the default, chosen by benchmark (BENCHMARKS.md).
    #[default]
    Batsat,
    /// `varisat`.
    Varisat,
}

/// A literal in the solver-independent numbering: variable index times two, plus one when
/// negated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct SatLit(u32);

impl SatLit {
    pub(crate) fn new(var: u32, positive: bool) -> SatLit {
        SatLit(var << 1 | u32::from(!positive))
    }

    pub(crate) fn var(self) -> u32 {
        self.0 >> 1
    }

    pub(crate) fn is_positive(self) -> bool {
        self.0 & 1 == 0
    }

    /// A dense index over literals (2 per variable), for per-literal tables.
    pub(crate) fn code(self) -> usize {
        self.0 as usize
    }
}

impl Not for SatLit {
    type Output = SatLit;
    fn not(self) -> SatLit {
        SatLit(self.0 ^ 1)
    }
}

/// The answer to one satisfiability question.
pub(crate) enum Outcome {
    /// The clauses and the assumptions have a model.
    Satisfiable,
    /// They have none; `core` is a subset of the assumptions that has none either.
    Unsatisfiable {
        /// Assumption literals, as they were passed in.
        core: Vec<SatLit>,
    },
}

/// An incremental SAT solver: clauses only grow; each `solve` may assume different literals.
pub(crate) trait SatSolver {
    fn new_var(&mut self) -> SatLit;
    fn add_clause(&mut self, clause: &[SatLit]);
    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome;
    /// After a [`Outcome::Satisfiable`] answer, the model's value of each variable, in order
    /// (the propagator's fast path starts from it).
    fn model(&self) -> Vec<bool>;
}

/// A solver that keeps every variable and clause it was given, so that it can be cloned by
/// building a fresh solver of the same kind from them: the copy has the same clauses, hence the
/// same satisfiable assumption sets (it lacks only the learned clauses, which are consequences).
/// Explicit-state exploration (`crate::exploration`) clones the executive, whose theory holds
/// one.
pub(crate) struct RecordedSolver {
    backend: SatBackend,
    solver: Box<dyn SatSolver>,
    vars: u32,
    /// Every clause, in the order given.
    clauses: Vec<Box<[SatLit]>>,
}

impl RecordedSolver {
    /// A fresh solver of the chosen kind.
    pub(crate) fn new(backend: SatBackend) -> Self {
        RecordedSolver {
            backend,
            solver: new_solver(backend),
            vars: 0,
            clauses: Vec::new(),
        }
    }
}

impl Clone for RecordedSolver {
    fn clone(&self) -> Self {
        let mut solver = new_solver(self.backend);
        (0..self.vars).for_each(|_| {
            solver.new_var();
        });
        self.clauses.iter().for_each(|c| solver.add_clause(c));
        RecordedSolver {
            backend: self.backend,
            solver,
            vars: self.vars,
            clauses: self.clauses.clone(),
        }
    }
}

impl SatSolver for RecordedSolver {
    fn new_var(&mut self) -> SatLit {
        self.vars += 1;
        self.solver.new_var()
    }

    fn add_clause(&mut self, clause: &[SatLit]) {
        self.clauses.push(clause.into());
        self.solver.add_clause(clause);
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        self.solver.solve(assumptions)
    }

    fn model(&self) -> Vec<bool> {
        self.solver.model()
    }
}

/// A fresh solver of the chosen kind.
fn new_solver(backend: SatBackend) -> Box<dyn SatSolver> {
    match backend {
        SatBackend::Batsat => Box::new(Batsat::default()),
        SatBackend::Varisat => Box::new(Varisat::default()),
    }
}

#[derive(Default)]
struct Batsat {
    solver: batsat::BasicSolver,
    /// batsat's variable for each of ours, in creation order.
    vars: Vec<batsat::Var>,
    scratch: Vec<batsat::Lit>,
}

impl Batsat {
    fn lit(&self, lit: SatLit) -> batsat::Lit {
        batsat::Lit::new(self.vars[lit.var() as usize], lit.is_positive())
    }
}

impl SatSolver for Batsat {
    fn new_var(&mut self) -> SatLit {
        use batsat::SolverInterface;
        self.vars.push(self.solver.new_var_default());
        SatLit::new(self.vars.len() as u32 - 1, true)
    }

    fn add_clause(&mut self, clause: &[SatLit]) {
        use batsat::SolverInterface;
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.clear();
        scratch.extend(clause.iter().map(|&l| self.lit(l)));
        // `false` only says the clause set is now unsatisfiable, which later solves report.
        let _ = self.solver.add_clause_reuse(&mut scratch);
        self.scratch = scratch;
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        use batsat::SolverInterface;
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.clear();
        scratch.extend(assumptions.iter().map(|&l| self.lit(l)));
        let answer = self.solver.solve_limited(&scratch);
        self.scratch = scratch;
        if answer == batsat::lbool::FALSE {
            // MiniSat's final conflict is a clause over negated assumptions.
            let failed: Vec<batsat::Lit> = self.solver.unsat_core().iter().map(|&l| !l).collect();
            let core = assumptions
                .iter()
                .copied()
                .filter(|&a| failed.contains(&self.lit(a)))
                .collect();
            Outcome::Unsatisfiable { core }
        } else {
            Outcome::Satisfiable
        }
    }

    fn model(&self) -> Vec<bool> {
        use batsat::SolverInterface;
        let model = self.solver.get_model();
        self.vars
            .iter()
            .map(|v| model.get(v.idx() as usize) == Some(&batsat::lbool::TRUE))
            .collect()
    }
}

#[derive(Default)]
struct Varisat {
    solver: varisat::Solver<'static>,
    scratch: Vec<varisat::Lit>,
}

fn to_varisat(lit: SatLit) -> varisat::Lit {
    varisat::Lit::from_index(lit.var() as usize, lit.is_positive())
}

impl SatSolver for Varisat {
    fn new_var(&mut self) -> SatLit {
        use varisat::ExtendFormula;
        let var = self.solver.new_var();
        SatLit::new(var.index() as u32, true)
    }

    fn add_clause(&mut self, clause: &[SatLit]) {
        use varisat::ExtendFormula;
        self.scratch.clear();
        self.scratch.extend(clause.iter().map(|&l| to_varisat(l)));
        self.solver.add_clause(&self.scratch);
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        self.scratch.clear();
        self.scratch
            .extend(assumptions.iter().map(|&l| to_varisat(l)));
        self.solver.assume(&self.scratch);
        match self.solver.solve() {
            Ok(true) => Outcome::Satisfiable,
            Ok(false) => {
                let failed = self.solver.failed_core().unwrap_or(&[]);
                let core = assumptions
                    .iter()
                    .copied()
                    .filter(|&a| failed.contains(&to_varisat(a)))
                    .collect();
                Outcome::Unsatisfiable { core }
            }
            // varisat fails only when interrupted or writing a proof; this solver does neither.
            Err(error) => unreachable!("varisat failed without proof or interrupt: {error}"),
        }
    }

    fn model(&self) -> Vec<bool> {
        let mut values = Vec::new();
        for lit in self.solver.model().unwrap_or_default() {
            let var = lit.var().index();
            if values.len() <= var {
                values.resize(var + 1, false);
            }
            values[var] = lit.is_positive();
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_backend(backend: SatBackend) {
        let mut solver = new_solver(backend);
        let (a, b, c) = (solver.new_var(), solver.new_var(), solver.new_var());
        solver.add_clause(&[!a, b]); // a => b
        solver.add_clause(&[!b, c]); // b => c
        assert!(matches!(solver.solve(&[a]), Outcome::Satisfiable));
        match solver.solve(&[b, a, !c]) {
            Outcome::Unsatisfiable { core } => {
                assert!(core.contains(&!c), "{core:?}");
                assert!(core.iter().all(|l| [a, b, !c].contains(l)), "{core:?}");
            }
            Outcome::Satisfiable => panic!("a, b, not c contradicts a => b => c"),
        }
        assert!(matches!(solver.solve(&[]), Outcome::Satisfiable));
    }

    #[test]
    fn batsat_reports_cores_over_the_assumptions() {
        check_backend(SatBackend::Batsat);
    }

    #[test]
    fn varisat_reports_cores_over_the_assumptions() {
        check_backend(SatBackend::Varisat);
    }
}
