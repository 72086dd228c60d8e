//! The sequencer's questions to the deductive controller: "is this entailed by the plant model
//! and the estimate?" and "is this consistent with the plant model?" (thesis §5.1.1, §5.3).
//!
//! The sequencer grounds clock atoms itself (it owns the clock values ω); confidence atoms
//! (`P(x = v) >= p`) are decided by the oracle, which knows the belief. Two oracles ship:
//! [`AssignmentOracle`] evaluates against an explicit (possibly partial) state assignment, for
//! tests, benchmarks and programs run without a plant model; [`TheoryOracle`] asks an
//! [`opsat::Theory`](crate::opsat::Theory) built from a plant model, as the executive does.

use std::collections::HashMap;

use crate::logic::{Atom, Formula, ValueId, VarId, VarTable};
use crate::opsat::{Consistency, Literal, Theory};

/// What the sequencer asks of the deductive controller. Estimates are the caller's type, so the
/// same oracle can answer for ŝ(i) and ŝ(i+1) within one cycle.
pub trait Entailment {
    /// A most-likely state estimate ŝ.
    type Estimate: ?Sized;

    /// Is `formula` entailed by the plant model together with `estimate`? The formula holds no
    /// clock atoms (the sequencer grounds them); it may hold confidence atoms.
    fn entailed(&mut self, estimate: &Self::Estimate, formula: &Formula) -> bool;

    /// Is `formula` consistent with the plant model (can some plant state satisfy it)? Used to
    /// detect contradictory goals asserted by concurrent threads.
    fn consistent(&mut self, formula: &Formula) -> bool;

    /// A name for what `estimate` entails: whenever two calls return the same `Some(n)`,
    /// [`Entailment::entailed`] answers every formula the same for both estimates. The
    /// sequencer then keeps its answers from one cycle to the next while the revision and the
    /// clock atoms' truth values stay the same (`evaluate.rs`). `None` (the default): every
    /// question is asked.
    fn revision(&self, estimate: &Self::Estimate) -> Option<u64> {
        let _ = estimate;
        None
    }
}

/// Entailment of a formula some of whose atoms nobody can decide (a clock not yet started, a
/// belief not reported): entailed only if entailed whatever truth values those atoms take.
/// `open` says which atoms are undecided; `entailed` answers for formulas without them.
pub fn entailed_in_every_case(
    formula: &Formula,
    open: &impl Fn(&Atom) -> bool,
    entailed: &mut impl FnMut(&Formula) -> bool,
) -> bool {
    match formula {
        Formula::True => return true,
        Formula::False => return false,
        _ => {}
    }
    let undecided = formula.atoms().into_iter().find(|a| open(a)).cloned();
    match undecided {
        None => entailed(formula),
        Some(atom) => [true, false].into_iter().all(|value| {
            let case = formula.ground(&mut |a| (*a == atom).then_some(value));
            entailed_in_every_case(&case, open, entailed)
        }),
    }
}

/// A most-likely state estimate: some variables have a value, the others are unknown; beliefs in
/// individual assignments may be given for confidence atoms.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StateEstimate {
    values: HashMap<VarId, ValueId>,
    beliefs: HashMap<(VarId, ValueId), f64>,
}

impl StateEstimate {
    /// An estimate in which every variable is unknown.
    pub fn new() -> Self {
        StateEstimate::default()
    }

    /// An estimate from assignments.
    pub fn from_assignments(assignments: impl IntoIterator<Item = (VarId, ValueId)>) -> Self {
        StateEstimate {
            values: assignments.into_iter().collect(),
            beliefs: HashMap::new(),
        }
    }

    /// Sets `var = value`.
    pub fn set(&mut self, var: VarId, value: ValueId) {
        self.values.insert(var, value);
    }

    /// Makes `var` unknown.
    pub fn forget(&mut self, var: VarId) {
        self.values.remove(&var);
    }

    /// The estimated value of `var`, if known.
    pub fn value(&self, var: VarId) -> Option<ValueId> {
        self.values.get(&var).copied()
    }

    /// Every known assignment, in variable order.
    pub fn assignments(&self) -> Vec<(VarId, ValueId)> {
        let mut out: Vec<_> = self.values.iter().map(|(&x, &v)| (x, v)).collect();
        out.sort_unstable();
        out
    }

    /// Records the estimator's belief in `var = value`.
    pub fn set_belief(&mut self, var: VarId, value: ValueId, probability: f64) {
        self.beliefs.insert((var, value), probability);
    }

    /// The belief in `var = value`: as recorded; otherwise 1 for the estimated value and 0 for
    /// the others of an estimated variable; unknown for a variable without an estimate.
    pub fn belief(&self, var: VarId, value: ValueId) -> Option<f64> {
        if let Some(&p) = self.beliefs.get(&(var, value)) {
            return Some(p);
        }
        self.value(var).map(|v| if v == value { 1.0 } else { 0.0 })
    }

    /// Decides a confidence atom from the beliefs, if they say enough.
    fn decide_confidence(&self, atom: &Atom) -> Option<bool> {
        match atom {
            Atom::Confidence {
                var,
                value,
                op,
                probability,
            } => self
                .belief(*var, *value)
                .map(|p| op.holds(p, probability.0)),
            _ => None,
        }
    }

    /// The formula with every confidence atom the beliefs decide replaced by its truth value.
    fn ground_confidence(&self, formula: &Formula) -> Formula {
        formula.ground(&mut |atom| self.decide_confidence(atom))
    }
}

/// Entailment by three-valued evaluation against the estimate alone (no plant model): a formula
/// is entailed when the known values make it true. Unknown variables stay unknown, so `unless c`
/// over an unknown state proceeds and `if c` dies. Consistency is satisfiability over the
/// variables' domains.
pub struct AssignmentOracle {
    table: VarTable,
    domains: Theory,
}

impl AssignmentOracle {
    /// An oracle over the variables of `table` (a THCA's table will do; clocks are ignored).
    pub fn new(table: &VarTable) -> Self {
        let domains = Theory::new(table.clone(), &[])
            .unwrap_or_else(|_| unreachable!("a theory without constraints holds no clock atom"));
        AssignmentOracle {
            table: table.clone(),
            domains,
        }
    }
}

impl Entailment for AssignmentOracle {
    type Estimate = StateEstimate;

    fn entailed(&mut self, estimate: &StateEstimate, formula: &Formula) -> bool {
        let grounded = estimate.ground_confidence(formula);
        grounded.eval_assignment(&self.table, &|x| estimate.value(x)) == Some(true)
    }

    fn consistent(&mut self, formula: &Formula) -> bool {
        consistent_in(&mut self.domains, formula)
    }
}

/// Entailment by the plant model's [`Theory`] together with the estimate's assignments (complete:
/// SAT with assumptions). Confidence atoms the estimate's beliefs cannot decide are treated as
/// unknown ([`entailed_in_every_case`]).
pub struct TheoryOracle<'t> {
    theory: &'t mut Theory,
}

impl<'t> TheoryOracle<'t> {
    /// An oracle asking `theory` (the plant model's constraints, encoded once).
    pub fn new(theory: &'t mut Theory) -> Self {
        TheoryOracle { theory }
    }
}

impl Entailment for TheoryOracle<'_> {
    type Estimate = StateEstimate;

    fn entailed(&mut self, estimate: &StateEstimate, formula: &Formula) -> bool {
        let assumptions: Vec<Literal> = estimate
            .assignments()
            .into_iter()
            .map(|(x, v)| Literal::Is(x, v))
            .collect();
        let grounded = estimate.ground_confidence(formula);
        let theory = &mut *self.theory;
        entailed_in_every_case(&grounded, &Atom::is_external, &mut |f| {
            // Every external atom has been split away above, so the theory accepts `f`.
            theory.entails(&assumptions, f).unwrap_or(false)
        })
    }

    fn consistent(&mut self, formula: &Formula) -> bool {
        consistent_in(self.theory, formula)
    }
}

/// Is `formula` satisfiable together with the theory's constraints? Beliefs and clocks are not
/// state, so their atoms may take either value: consistent when some case is.
fn consistent_in(theory: &mut Theory, formula: &Formula) -> bool {
    !entailed_in_every_case(formula, &Atom::is_external, &mut |case| {
        !satisfiable(theory, case)
    })
}

fn satisfiable(theory: &mut Theory, formula: &Formula) -> bool {
    match theory.define(formula) {
        Ok(holds) => theory.consistent(&[holds]) == Consistency::Consistent,
        // Unreachable: external atoms were split away. Claiming consistency reports no conflict
        // that was not proven.
        Err(_) => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logic::parse_formula;

    fn table() -> VarTable {
        let mut table = VarTable::new();
        table
            .add_variable("engine", ["off", "standby", "firing"])
            .unwrap();
        table.add_variable("thrust", ["zero", "full"]).unwrap();
        table.add_clock("t1").unwrap();
        table
    }

    fn f(text: &str) -> Formula {
        parse_formula(text, &table()).unwrap()
    }

    fn estimate(engine: Option<u32>) -> StateEstimate {
        StateEstimate::from_assignments(engine.map(|v| (VarId(0), ValueId(v))))
    }

    #[test]
    fn assignment_oracle_leaves_unknown_variables_unknown() {
        let mut oracle = AssignmentOracle::new(&table());
        assert!(oracle.entailed(&estimate(Some(1)), &f("engine = standby")));
        assert!(!oracle.entailed(&estimate(None), &f("engine = standby")));
        assert!(!oracle.entailed(&estimate(None), &f("not engine = standby")));
        assert!(oracle.consistent(&f("engine = standby and thrust = full")));
        assert!(!oracle.consistent(&f("engine = standby and engine = off")));
    }

    #[test]
    fn theory_oracle_uses_the_model() {
        let table = table();
        let constraint =
            f("(engine = firing => thrust = full) and (thrust = full => engine = firing)");
        let mut theory = Theory::new(table, &[constraint]).unwrap();
        let mut oracle = TheoryOracle::new(&mut theory);
        // The model entails thrust from the engine's mode; the estimate alone would not.
        assert!(oracle.entailed(&estimate(Some(2)), &f("thrust = full")));
        assert!(oracle.entailed(&estimate(Some(1)), &f("thrust = zero")));
        assert!(!oracle.entailed(&estimate(None), &f("thrust = zero")));
        assert!(!oracle.consistent(&f("engine = firing and thrust = zero")));
        assert!(oracle.consistent(&f("engine = off")));
    }

    #[test]
    fn confidence_atoms_are_decided_by_beliefs_or_left_open() {
        let mut oracle = AssignmentOracle::new(&table());
        let mut believed = estimate(Some(1));
        assert!(oracle.entailed(&believed, &f("P(engine = standby) >= 0.95")));
        believed.set_belief(VarId(0), ValueId(1), 0.6);
        assert!(!oracle.entailed(&believed, &f("P(engine = standby) >= 0.95")));
        let table = table();
        let mut theory = Theory::new(table, &[]).unwrap();
        let mut oracle = TheoryOracle::new(&mut theory);
        // Unknown belief: entailed only when it does not matter.
        assert!(!oracle.entailed(&estimate(None), &f("P(engine = off) >= 0.5")));
        assert!(oracle.entailed(
            &estimate(None),
            &f("P(engine = off) >= 0.5 or not P(engine = off) >= 0.5")
        ));
        assert!(oracle.consistent(&f("P(engine = off) >= 0.5")));
    }

    #[test]
    fn every_case_splits_on_open_atoms_only() {
        let open = |a: &Atom| matches!(a, Atom::Clock { .. });
        let mut calls = 0;
        let tautology = f("t1 >= 3 or not t1 >= 3");
        assert!(entailed_in_every_case(&tautology, &open, &mut |_| {
            calls += 1;
            false
        }));
        assert_eq!(calls, 0, "grounding alone decides a tautology");
        assert!(!entailed_in_every_case(&f("t1 >= 3"), &open, &mut |_| true));
    }
}
