//! The incremental SAT solver the [`super::Theory`] is built on, behind one small interface.
//!
//! batsat, a maintained pure-Rust CDCL solver descended from MiniSat, with assumptions and
//! failed-assumption cores. It was chosen over varisat by measurement on the Theory's workloads
//! (BENCHMARKS.md, "The theory and OPSAT"). varisat was later removed: its solver holds trait
//! objects that are not `Send` (a proof writer, a checker), and the executive, which owns a
//! theory, must be `Send` so that a host can step it from any thread. batsat runs with
//! [`NoCallbacks`] for the same reason (its own `Basic` callbacks box a stop function that is
//! not `Send`).

use std::ops::Not;

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
/// building a fresh solver from them: the copy has the same clauses, hence the
/// same satisfiable assumption sets (it lacks only the learned clauses, which are consequences).
/// Explicit-state exploration (`crate::exploration`) clones the executive, whose theory holds
/// one.
#[derive(Default)]
pub(crate) struct RecordedSolver {
    solver: Batsat,
    vars: u32,
    /// Every clause, in the order given.
    clauses: Vec<Box<[SatLit]>>,
}

impl Clone for RecordedSolver {
    fn clone(&self) -> Self {
        let mut solver = Batsat::default();
        (0..self.vars).for_each(|_| {
            solver.new_var();
        });
        self.clauses.iter().for_each(|c| solver.add_clause(c));
        RecordedSolver {
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

/// batsat's callbacks that do nothing: `batsat::BasicSolver`'s boxed stop function is not
/// `Send`, this is (and the theory never interrupts a solve).
#[derive(Default)]
struct NoCallbacks;

impl batsat::Callbacks for NoCallbacks {}

#[derive(Default)]
struct Batsat {
    solver: batsat::Solver<NoCallbacks>,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batsat_reports_cores_over_the_assumptions() {
        let mut solver = Batsat::default();
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
}
