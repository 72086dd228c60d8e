//! The consistency and entailment theory every OPSAT caller queries (DESIGN.md §7).
//!
//! A [`Theory`] is a set of constraints over finite-domain variables, encoded once into an
//! incremental SAT solver:
//! - each variable `x` with domain `{v1..vn}` gets one Boolean per value, with "exactly one" clauses;
//! - each constraint is Tseitin-encoded (one definition literal per `and`/`or` node);
//! - a formula used in a query is encoded the first time it is seen and its definition literal
//!   is cached, so later queries with it only change assumptions.
//!
//! Queries are complete: [`Theory::consistent`] either proves a set of assumptions consistent with
//! the constraints or returns a [`Consistency::Conflict`] — a subset of the assumptions that is
//! itself inconsistent (the *conflict* conflict-directed A* learns from); [`Theory::entails`] is
//! the refutation of the formula's negation. Clock bounds and confidence atoms are decided
//! outside the theory ([`Formula::ground`]); a formula that still holds one is refused.
//!
//! # A search check's model, by deciding
//! OPSAT's candidate checks ([`Theory::search_conflict`]) are answered by the search's own
//! closure when it reaches a conflict or completes to a model with the stored one; the rest went
//! to the SAT solver. On Livingstone 2's breaker logs every such question was satisfiable (701
//! at 255 breakers, κ = 10; 2,263 on the 15-breaker log) and each cost the solver a search over
//! the whole theory — 2.6 M instructions at 255 breakers, 6 % of the replay. Such a check now
//! first goes to the other closure, the one kept as a set, which may decide up to
//! [`DECISIONS`] literals to complete its model (`propagate.rs`, "Two closures, kept apart"):
//! at 255 and 15 breakers it completes every one. The answer is exact — a completion found is a
//! model of every clause and assumption — and the search's closure is not touched, so the
//! conflicts later read off it, and with them every search, are what they were. What changes is
//! who answered: the solver, asked less, may return another core for a later inconsistent check
//! that propagation leaves open — another conflict, the same solutions in the same order
//! (`search.rs`, "Order") — and the search closure keeps its own model where the solver's used
//! to replace it. Beliefs and SAT calls are byte-identical on every shipped log and scenario.
//! Measured: Livingstone 2's 15-breaker log at κ = 10 6.935 G → 6.714 G instructions (CPU 0.94,
//! 0.89–1.13, 7 pairs); 255 breakers κ = 10 CPU 0.97 (0.92–1.01, 9 pairs, load 2–3); the quiet
//! EDL cycle unchanged (42.4 k instructions).

use petgraph::unionfind::UnionFind;
use rustc_hash::FxHashMap;

use super::propagate::{Solver, Value};
use super::sat::{Outcome, RecordedSolver, SatLit, SatSolver};
use crate::logic::{Atom, Formula, ValueId, VarId, VarTable};

/// How many literals unit propagation may decide, one at a time, to complete the stored model
/// into one of a question's assumptions before the SAT solver is asked instead
/// ([`Propagator::completes_by_deciding`]). Each decision costs a propagation and a check of
/// the clauses the completion changed; a SAT call assigns the whole theory, so its cost grows
/// with the plant while a completion's grows with the distance from the stored model. At 16,
/// Livingstone 2's 1,023-breaker tree sent 35 questions a step to the solver (10.7 M
/// instructions each: 40 % of its first cycle with `--history 0`, where estimation asks whether
/// each mode is possible under a new observation); at 64 the completions found make that
/// cycle 24.50 G → 13.43 G instructions (256 gives the same), CPU 0.90 of before at κ = 10
/// (the 28-step log, 2 pairs), 0.98 at 255 breakers (5 pairs), the 15-breaker log 6.714 G →
/// 6.712 G. Answers, beliefs and SAT calls are byte-identical: a completion is a model.
const DECISIONS: usize = 64;

/// Above this many values, "at most one" is the product encoding rather than one clause per
/// pair: a control with 5,000 values made 12.5 million clauses and 917 MB.
const PAIRWISE_AT_MOST_ONE: usize = 8;

/// Clauses saying at most one of `lits` is true: pairwise for small domains (no new variables,
/// the encoding every shipped model uses); for larger ones Chen's product encoding ("A new SAT
/// encoding of the at-most-one constraint", ModRef 2010): the literals on a ⌈√n⌉-wide grid, each
/// implying its row's and its column's auxiliary variable, at most one row and one column (the
/// same encoding, recursively). About 2n clauses and 2√n auxiliary variables: a sequential
/// counter (n auxiliary variables) made every SAT call decide thousands of them and validation
/// of a 5,000-mode component eight times slower.
fn at_most_one(solver: &mut dyn SatSolver, lits: &[SatLit]) {
    if lits.len() <= PAIRWISE_AT_MOST_ONE {
        for (i, &a) in lits.iter().enumerate() {
            for &b in &lits[i + 1..] {
                solver.add_clause(&[!a, !b]);
            }
        }
        return;
    }
    let root = lits.len().isqrt();
    let width = root + usize::from(root * root < lits.len());
    let rows: Vec<SatLit> = (0..lits.len().div_ceil(width))
        .map(|_| solver.new_var())
        .collect();
    let columns: Vec<SatLit> = (0..width).map(|_| solver.new_var()).collect();
    for (i, &lit) in lits.iter().enumerate() {
        solver.add_clause(&[!lit, rows[i / width]]);
        solver.add_clause(&[!lit, columns[i % width]]);
    }
    at_most_one(solver, &rows);
    at_most_one(solver, &columns);
}

/// A variable's value literals, one per value of its `size`, exactly one of them true.
fn domain_literals(solver: &mut dyn SatSolver, size: usize) -> Vec<SatLit> {
    let lits: Vec<SatLit> = (0..size).map(|_| solver.new_var()).collect();
    solver.add_clause(&lits);
    at_most_one(solver, &lits);
    lits
}

/// The assumptions (as given) whose solver literals make up `core`, a subset of
/// `sat_assumptions` (their translation, position by position).
fn conflict_of(
    core: &[SatLit],
    sat_assumptions: &[SatLit],
    assumptions: &[Literal],
) -> Vec<Literal> {
    core.iter()
        .filter_map(|c| {
            let i = sat_assumptions.iter().position(|a| a == c)?;
            Some(assumptions[i])
        })
        .collect()
}

/// A formula the theory has encoded for use in assumptions (see [`Theory::define`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Definition(u32);

/// Something a query may assume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Literal {
    /// `x = v`
    Is(VarId, ValueId),
    /// `x != v`
    IsNot(VarId, ValueId),
    /// A defined formula holds.
    Holds(Definition),
    /// A defined formula does not hold.
    Fails(Definition),
}

impl std::ops::Not for Literal {
    type Output = Literal;
    fn not(self) -> Literal {
        match self {
            Literal::Is(x, v) => Literal::IsNot(x, v),
            Literal::IsNot(x, v) => Literal::Is(x, v),
            Literal::Holds(d) => Literal::Fails(d),
            Literal::Fails(d) => Literal::Holds(d),
        }
    }
}

/// The answer to [`Theory::consistent`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Consistency {
    /// The constraints and the assumptions have a common model.
    Consistent,
    /// These assumptions (a subset of those given) cannot hold together with the constraints.
    Conflict(Vec<Literal>),
}

impl Consistency {
    /// True for [`Consistency::Consistent`].
    pub fn is_consistent(&self) -> bool {
        matches!(self, Consistency::Consistent)
    }
}

/// Why the theory refused a formula.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TheoryError {
    /// Clock and confidence atoms must be grounded before a formula reaches the theory.
    #[error("a clock or confidence atom must be decided before the formula reaches the theory")]
    ExternalAtom,
}

/// How a theory is built. The default (conflicts as the solver finds them) was chosen by
/// measurement (BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TheoryOptions {
    /// Shrink every conflict [`Theory::consistent`] returns to a minimal one by deletion (one
    /// SAT call per member). Off by default: in conflict-directed search the SAT solver's own
    /// cores prune nearly as well at half the SAT calls (BENCHMARKS.md). Callers that show a
    /// conflict to a person ask [`Theory::minimal_conflict`] instead.
    pub minimize_conflicts: bool,
}

/// Counts of the work a theory has done, for benchmarks and budgets.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TheoryStats {
    /// Calls to [`Theory::consistent`].
    pub consistency_checks: u64,
    /// Calls to [`Theory::entails`].
    pub entailment_checks: u64,
    /// SAT solver calls, including those spent minimising conflicts: satisfiability questions
    /// asked, whether the solver ran or unit propagation answered ([`TheoryStats::propagated`]).
    pub sat_calls: u64,
    /// Of `sat_calls`, those unit propagation over the clauses answered without the solver.
    pub propagated: u64,
}

/// Constraints over finite-domain variables, encoded once, queried many times. A clone is a
/// theory with the same clauses and definitions on a fresh solver (`RecordedSolver`): every
/// consistency and entailment question gets the original's answer (a conflict returned may be
/// another inconsistent subset, the solver's learned clauses being gone).
#[derive(Clone)]
pub struct Theory {
    table: VarTable,
    solver: Solver,
    /// Whether unit propagation answers what it can decide before the solver is asked.
    propagation: bool,
    /// The last assumptions found consistent: any prefix of them is consistent too.
    consistent_with: Vec<SatLit>,
    /// Reused for each query's solver literals.
    scratch: Vec<SatLit>,
    /// The last assumptions translated into solver literals, and their translation (see
    /// [`Theory::sat_literals`]).
    translated_from: Vec<Literal>,
    translated: Vec<SatLit>,
    options: TheoryOptions,
    /// `value_lits[x][v]` is true exactly when `x = v`; empty for a variable left out of the
    /// solver until first mentioned ([`Theory::with_unencoded`]).
    value_lits: Vec<Vec<SatLit>>,
    constant_true: SatLit,
    /// Definition literal of each defined formula, by [`Definition`] number.
    definitions: Vec<SatLit>,
    definition_vars: Vec<Vec<VarId>>,
    /// Fx-hashed: a guard's definition is looked up on every entailment (SipHash was 10 % of
    /// a breaker tree's busy step).
    defined: FxHashMap<Formula, Definition>,
    /// Variables linked by some constraint share a root (OPSAT's decomposition).
    component_root: Vec<usize>,
    stats: TheoryStats,
    /// Search checks the set-kept closure proved consistent ("A search check's model, by
    /// deciding"), for the tests to see the path taken.
    #[cfg(test)]
    decided_checks: u64,
}

impl Theory {
    /// Encodes `constraints` over the variables of `table` with the default options.
    pub fn new(table: VarTable, constraints: &[Formula]) -> Result<Theory, TheoryError> {
        Theory::with_options(table, constraints, TheoryOptions::default())
    }

    /// Encodes `constraints` over the variables of `table`.
    pub fn with_options(
        table: VarTable,
        constraints: &[Formula],
        options: TheoryOptions,
    ) -> Result<Theory, TheoryError> {
        Theory::with_unencoded(table, constraints, options, &[])
    }

    /// [`Theory::with_options`], with the variables of `unencoded` left out of the solver until
    /// a constraint, a defined formula or an assumption first mentions one (it is then encoded
    /// as any other). The answers are the same: a variable nothing mentions is free, and adding
    /// it with its "exactly one" clauses changes no question's satisfiability. The work is not:
    /// every satisfiable question decides each encoded variable, so one that no constraint
    /// mentions and that queries seldom name (a command's acknowledgement, evidence about the
    /// command rather than about a mode) would cost every question a few decisions.
    pub fn with_unencoded(
        table: VarTable,
        constraints: &[Formula],
        options: TheoryOptions,
        unencoded: &[VarId],
    ) -> Result<Theory, TheoryError> {
        let mut solver = Solver::new(RecordedSolver::default());
        let constant_true = solver.new_var();
        solver.add_clause(&[constant_true]);
        let mut value_lits = Vec::with_capacity(table.len());
        for (x, variable) in table.variables() {
            value_lits.push(if unencoded.contains(&x) {
                Vec::new()
            } else {
                domain_literals(&mut solver, variable.domain_size())
            });
        }
        let mut links = UnionFind::new(table.len());
        for constraint in constraints {
            if let Some((first, rest)) = constraint.variables().split_first() {
                rest.iter().for_each(|x| {
                    links.union(first.index(), x.index());
                });
            }
        }
        let component_root = (0..table.len()).map(|i| links.find(i)).collect();
        let mut theory = Theory {
            table,
            solver,
            propagation: true,
            consistent_with: Vec::new(),
            scratch: Vec::new(),
            translated_from: Vec::new(),
            translated: Vec::new(),
            options,
            value_lits,
            constant_true,
            definitions: Vec::new(),
            definition_vars: Vec::new(),
            defined: FxHashMap::default(),
            component_root,
            stats: TheoryStats::default(),
            #[cfg(test)]
            decided_checks: 0,
        };
        for constraint in constraints {
            theory.assert(constraint)?;
        }
        Ok(theory)
    }

    /// The variables the theory is over.
    pub fn table(&self) -> &VarTable {
        &self.table
    }

    /// The options it was built with.
    pub fn options(&self) -> TheoryOptions {
        self.options
    }

    /// Work done so far.
    pub fn stats(&self) -> TheoryStats {
        self.stats
    }

    /// Whether unit propagation over the clauses answers the questions it decides before the
    /// SAT solver is asked (on by default; `propagate.rs`). Its answers are the solver's — a
    /// conflict still goes to the solver for its core — so this changes the work, never an
    /// answer: off, it is the reference the exactness tests compare against.
    pub fn set_propagation(&mut self, on: bool) {
        self.propagation = on;
    }

    /// Encodes a formula (once; later calls return the same definition) so that queries may
    /// assume it holds ([`Literal::Holds`]) or fails ([`Literal::Fails`]).
    pub fn define(&mut self, formula: &Formula) -> Result<Literal, TheoryError> {
        if let Some(&definition) = self.defined.get(formula) {
            return Ok(Literal::Holds(definition));
        }
        let lit = self.encode(formula)?;
        let definition = Definition(self.definitions.len() as u32);
        self.definitions.push(lit);
        self.definition_vars.push(formula.variables());
        self.defined.insert(formula.clone(), definition);
        Ok(Literal::Holds(definition))
    }

    /// The variables a defined formula mentions.
    pub fn definition_variables(&self, definition: Definition) -> &[VarId] {
        &self.definition_vars[definition.0 as usize]
    }

    /// Variables that share a constraint, directly or through others, have the same root; OPSAT
    /// splits problems along these components.
    pub fn component_root(&self, var: VarId) -> usize {
        self.component_root[var.index()]
    }

    /// Are the constraints and `assumptions` consistent? If not, which assumptions conflict?
    /// With `minimize_conflicts` the conflict is minimal: dropping any member makes it consistent.
    pub fn consistent(&mut self, assumptions: &[Literal]) -> Consistency {
        let minimize = self.options.minimize_conflicts;
        self.check(assumptions, minimize, false)
    }

    /// Whether the constraints and `assumptions` are consistent, for callers that need no
    /// conflict: a conflict unit propagation reaches is then answer enough, and the solver is
    /// asked only what propagation leaves open.
    pub fn is_consistent(&mut self, assumptions: &[Literal]) -> bool {
        self.stats.consistency_checks += 1;
        let sat_assumptions = self.sat_literals(assumptions);
        let decided = if !self.propagation {
            None
        } else if !self.solver.propagator.closure_of(&sat_assumptions) {
            Some(false)
        } else if self.consistent_by_propagation(&sat_assumptions, false) {
            Some(true)
        } else {
            None
        };
        let consistent = match decided {
            Some(answer) => {
                self.stats.sat_calls += 1;
                self.stats.propagated += 1;
                answer
            }
            None => matches!(self.solve(&sat_assumptions), Outcome::Satisfiable),
        };
        self.scratch = sat_assumptions;
        consistent
    }

    /// Records that the constraints and `assumptions` are consistent, which the caller knows
    /// without asking (an OPSAT solution: every solution a search returns was found consistent
    /// with the theory and its OCSP's assumptions, `search.rs`), so that the entailment
    /// questions asked under them next ([`Theory::entails`]) may be answered by unit propagation
    /// as after a [`Theory::is_consistent`] that said yes. No SAT call and no change of answer:
    /// it only saves the check whose answer is known.
    pub(crate) fn known_consistent(&mut self, assumptions: &[Literal]) {
        let sat_assumptions = self.sat_literals(assumptions);
        self.consistent_with.clear();
        self.consistent_with.extend_from_slice(&sat_assumptions);
        self.scratch = sat_assumptions;
    }

    /// [`Theory::consistent`], with the conflict always minimal: dropping any member makes it
    /// consistent. For explanations a person reads ("engine = standby is unreachable: engine is
    /// failed"), where every member should be to blame.
    pub fn minimal_conflict(&mut self, assumptions: &[Literal]) -> Consistency {
        self.check(assumptions, true, false)
    }

    /// [`Theory::consistent`] for conflict-directed search, which may learn any conflict: one
    /// that unit propagation reaches is read off its implication graph
    /// ([`Propagator::conflict_assumptions`]) instead of asking the solver for its core. The
    /// answer (consistent or not) is the solver's; the conflict may be another inconsistent
    /// subset, which changes no search's solutions nor their order (`search.rs`, "Order").
    /// Other callers keep the solver's core (the mission log names the observations in it).
    pub(crate) fn search_conflict(&mut self, assumptions: &[Literal]) -> Consistency {
        let minimize = self.options.minimize_conflicts;
        self.check(assumptions, minimize, true)
    }

    fn check(
        &mut self,
        assumptions: &[Literal],
        minimize: bool,
        propagated_cores: bool,
    ) -> Consistency {
        self.stats.consistency_checks += 1;
        let sat_assumptions = self.sat_literals(assumptions);
        if self.consistent_by_propagation(&sat_assumptions, propagated_cores) {
            self.stats.sat_calls += 1;
            self.stats.propagated += 1;
            self.scratch = sat_assumptions;
            return Consistency::Consistent;
        }
        let propagated = propagated_cores && self.propagation && self.solver.search.in_conflict();
        if propagated_cores
            && !propagated
            && self.consistent_by_propagation(&sat_assumptions, false)
        {
            // A search check propagation left open, proved consistent by the other closure
            // ("A search check's model, by deciding"): the search closure is untouched.
            #[cfg(test)]
            {
                self.decided_checks += 1;
            }
            self.stats.sat_calls += 1;
            self.stats.propagated += 1;
            self.scratch = sat_assumptions;
            return Consistency::Consistent;
        }
        let answer = if propagated {
            self.stats.sat_calls += 1;
            self.stats.propagated += 1;
            let core = self.solver.search.conflict_assumptions();
            let core = if minimize { self.minimize(core) } else { core };
            Consistency::Conflict(conflict_of(&core, &sat_assumptions, assumptions))
        } else {
            // The solver's core, which OPSAT learns from and the mission log shows.
            match self.solve(&sat_assumptions) {
                Outcome::Satisfiable => Consistency::Consistent,
                Outcome::Unsatisfiable { core } => {
                    let core = if minimize { self.minimize(core) } else { core };
                    Consistency::Conflict(conflict_of(&core, &sat_assumptions, assumptions))
                }
            }
        };
        self.scratch = sat_assumptions;
        answer
    }

    /// The solver's literals for `assumptions`, in the scratch buffer taken out of the theory
    /// (put it back in `self.scratch`: a query then allocates nothing).
    /// The last list translated is kept with its translation: estimation asks one question
    /// per guard and per observed value under the same store of every component's mode, and
    /// translating the store each time (two lookups per literal, scattered) was 11 % of a
    /// 1,023-breaker replay; comparing and copying is sequential.
    fn sat_literals(&mut self, assumptions: &[Literal]) -> Vec<SatLit> {
        let mut sat = std::mem::take(&mut self.scratch);
        sat.clear();
        if self.translated_from != assumptions {
            let mut translated = std::mem::take(&mut self.translated);
            translated.clear();
            translated.extend(assumptions.iter().map(|&l| self.sat_lit(l)));
            self.translated = translated;
            self.translated_from.clear();
            self.translated_from.extend_from_slice(assumptions);
        }
        sat.extend_from_slice(&self.translated);
        sat
    }

    /// Whether propagation proves `assumptions` consistent: its closure has no conflict and,
    /// completed by the last model, satisfies every clause ([`Propagator::completes_to_model`]).
    fn consistent_by_propagation(&mut self, assumptions: &[SatLit], search: bool) -> bool {
        let propagator = self.solver.for_search(search);
        let proved = self.propagation
            && propagator.closure_of(assumptions)
            && if search {
                // Deciding would move the search closure's watches, and with them the
                // conflicts it reads off later (see "Two closures, kept apart").
                propagator.completes_to_model()
            } else {
                propagator.completes_by_deciding(DECISIONS)
            };
        if proved {
            self.consistent_with.clear();
            self.consistent_with.extend_from_slice(assumptions);
        }
        proved
    }

    /// Do the constraints and `assumptions` entail `formula` (is it true in every model)? From
    /// inconsistent assumptions everything is entailed.
    pub fn entails(
        &mut self,
        assumptions: &[Literal],
        formula: &Formula,
    ) -> Result<bool, TheoryError> {
        self.stats.entailment_checks += 1;
        match formula {
            Formula::True => return Ok(true),
            Formula::Atom(Atom::Is(x, v)) => {
                let lit = self.value_lit(*x, *v);
                return Ok(self.refutes(assumptions, !lit));
            }
            _ => {}
        }
        let Literal::Holds(definition) = self.define(formula)? else {
            unreachable!("define returns Holds");
        };
        let lit = self.definitions[definition.0 as usize];
        Ok(self.refutes(assumptions, !lit))
    }

    /// True when `assumptions` and `extra` together are inconsistent: by unit propagation
    /// when it decides, else by the solver.
    fn refutes(&mut self, assumptions: &[Literal], extra: SatLit) -> bool {
        let mut sat_assumptions = self.sat_literals(assumptions);
        let refuted = match self.refuted_by_propagation(&sat_assumptions, extra) {
            Some(refuted) => {
                self.stats.sat_calls += 1;
                self.stats.propagated += 1;
                refuted
            }
            None => {
                sat_assumptions.push(extra);
                matches!(self.solve(&sat_assumptions), Outcome::Unsatisfiable { .. })
            }
        };
        self.scratch = sat_assumptions;
        refuted
    }

    /// Whether `base ∧ extra` is inconsistent, when unit propagation decides it — the same
    /// answer the solver would give, since propagation is sound:
    /// - a conflict in the closure of `base`, or of `base ∧ extra`: inconsistent;
    /// - `extra` already true in the closure of `base`: as consistent as `base`, which is known
    ///   when a list starting with `base` was found consistent (estimation checks the
    ///   modes — with the observation after them — before asking what they entail);
    /// - no conflict, and the closure completed by the last model satisfies every clause
    ///   ([`Propagator::completes_to_model`]): consistent.
    ///
    /// Otherwise `None`: the solver decides.
    fn refuted_by_propagation(&mut self, base: &[SatLit], extra: SatLit) -> Option<bool> {
        if !self.propagation {
            return None;
        }
        let propagator = &mut self.solver.propagator;
        if !propagator.closure_of(base) {
            return Some(true);
        }
        match propagator.value(extra) {
            Value::False => Some(true),
            Value::True if self.consistent_with.starts_with(base) => Some(false),
            Value::True => propagator.completes_to_model().then_some(false),
            Value::Unassigned => {
                let mark = propagator.mark();
                let answer = if propagator.extend(extra) {
                    propagator.completes_to_model().then_some(false)
                } else {
                    Some(true)
                };
                propagator.undo(mark);
                answer
            }
        }
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        self.stats.sat_calls += 1;
        let outcome = self.solver.solve(assumptions);
        if let Outcome::Satisfiable = outcome {
            self.consistent_with.clear();
            self.consistent_with.extend_from_slice(assumptions);
        }
        outcome
    }

    /// Deletion-based minimisation: drop each member in turn and keep it out when the rest still
    /// conflict. A member found necessary stays necessary as the set shrinks, so one pass gives
    /// a minimal conflict.
    fn minimize(&mut self, mut core: Vec<SatLit>) -> Vec<SatLit> {
        // A literal assumed twice would survive every deletion; keep one of each.
        let mut seen = std::collections::HashSet::new();
        core.retain(|l| seen.insert(*l));
        let mut i = 0;
        while i < core.len() {
            let trial: Vec<SatLit> = core
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &l)| l)
                .collect();
            match self.solve(&trial) {
                Outcome::Satisfiable => i += 1,
                Outcome::Unsatisfiable { core: smaller } => {
                    let kept_before = core[..i].iter().filter(|l| smaller.contains(l)).count();
                    core.retain(|l| smaller.contains(l));
                    i = kept_before;
                }
            }
        }
        core
    }

    /// The literal of `x = v`, encoding `x` first if it was left out ([`Theory::with_unencoded`]).
    /// Hot (every assumption of every question): the check is the bounds check indexing made.
    #[inline]
    fn value_lit(&mut self, x: VarId, v: ValueId) -> SatLit {
        match self.value_lits[x.index()].get(v.index()) {
            Some(&lit) => lit,
            None => self.encode_late(x, v),
        }
    }

    /// Encodes a variable left out until now and returns the literal of `x = v`.
    #[cold]
    fn encode_late(&mut self, x: VarId, v: ValueId) -> SatLit {
        let size = self.table.variable(x).domain_size();
        self.value_lits[x.index()] = domain_literals(&mut self.solver, size);
        self.value_lits[x.index()][v.index()]
    }

    fn sat_lit(&mut self, literal: Literal) -> SatLit {
        match literal {
            Literal::Is(x, v) => self.value_lit(x, v),
            Literal::IsNot(x, v) => !self.value_lit(x, v),
            Literal::Holds(d) => self.definitions[d.0 as usize],
            Literal::Fails(d) => !self.definitions[d.0 as usize],
        }
    }

    /// Adds a constraint, avoiding definition literals at the top level.
    fn assert(&mut self, formula: &Formula) -> Result<(), TheoryError> {
        match formula {
            Formula::And(parts) => parts.iter().try_for_each(|p| self.assert(p)),
            Formula::Or(parts) => {
                let clause = parts
                    .iter()
                    .map(|p| self.encode(p))
                    .collect::<Result<Vec<_>, _>>()?;
                self.solver.add_clause(&clause);
                Ok(())
            }
            Formula::Implies(a, b) => {
                let clause = [!self.encode(a)?, self.encode(b)?];
                self.solver.add_clause(&clause);
                Ok(())
            }
            other => {
                let lit = self.encode(other)?;
                self.solver.add_clause(&[lit]);
                Ok(())
            }
        }
    }

    /// Tseitin encoding: a literal equivalent to `formula`.
    fn encode(&mut self, formula: &Formula) -> Result<SatLit, TheoryError> {
        Ok(match formula {
            Formula::True => self.constant_true,
            Formula::False => !self.constant_true,
            Formula::Atom(Atom::Is(x, v)) => self.value_lit(*x, *v),
            Formula::Atom(Atom::Same(x, y)) => {
                let same = self.same_value(*x, *y);
                self.encode(&same)?
            }
            Formula::Atom(_) => return Err(TheoryError::ExternalAtom),
            Formula::Not(inner) => !self.encode(inner)?,
            Formula::And(parts) => {
                let inputs = parts
                    .iter()
                    .map(|p| self.encode(p))
                    .collect::<Result<Vec<_>, _>>()?;
                self.and_gate(&inputs)
            }
            Formula::Or(parts) => {
                let inputs = parts
                    .iter()
                    .map(|p| self.encode(p).map(|l| !l))
                    .collect::<Result<Vec<_>, _>>()?;
                !self.and_gate(&inputs)
            }
            Formula::Implies(a, b) => {
                let inputs = [self.encode(a)?, !self.encode(b)?];
                !self.and_gate(&inputs)
            }
        })
    }

    /// `x = y` over value names: some value both domains share is held by both.
    fn same_value(&self, x: VarId, y: VarId) -> Formula {
        let (vx, vy) = (self.table.variable(x), self.table.variable(y));
        Formula::Or(
            vx.value_ids()
                .filter_map(|a| {
                    let b = vy.value(vx.value_name(a))?;
                    Some(Formula::And(vec![Formula::is(x, a), Formula::is(y, b)]))
                })
                .collect(),
        )
    }

    /// A fresh literal equivalent to the conjunction of `inputs`.
    fn and_gate(&mut self, inputs: &[SatLit]) -> SatLit {
        match inputs {
            [] => self.constant_true,
            [one] => *one,
            _ => {
                let gate = self.solver.new_var();
                for &input in inputs {
                    self.solver.add_clause(&[!gate, input]);
                }
                let mut clause: Vec<SatLit> = inputs.iter().map(|&l| !l).collect();
                clause.push(gate);
                self.solver.add_clause(&clause);
                gate
            }
        }
    }
}

#[cfg(test)]
mod tests;
