//! Unit propagation over the theory's compiled clauses: the fast path in front of the SAT solver
//! (Livingstone's truth maintenance answers most of its queries the same
//! way).
//!
//! Estimation asks many questions of one assumption set in a row — every guard of a source
//! state's components under the same modes and commands, every observed value under the same
//! candidate modes — and with every mode and command assumed, propagation alone decides nearly
//! all of them. Asking the SAT solver each time costs a whole search per question: it assigns
//! every variable of the theory (every definition ever encoded included) to exhibit a model, so
//! a plant of n components paid O(n) per question and O(n²) per step.
//!
//! [`Propagator`] keeps a copy of every clause the solver is given (binary clauses in implication
//! lists, longer ones with two watched literals) and computes the unit-propagation closure of a
//! set of assumptions. Propagation is sound — a literal it derives holds in every model of the
//! clauses and the assumptions, and a conflict it reaches means there is no model — so the
//! answers it gives are exactly the solver's; what it cannot decide goes to the solver
//! ([`super::theory`] decides which).
//!
//! # Two closures, kept apart
//! OPSAT's candidate checks and everyone else's questions (estimation's guards and observed
//! values, yes/no consistency) interleave, and their assumption lists have nothing in order in
//! common: one closure for both was rebuilt from scratch at almost every switch. So [`Solver`]
//! keeps two. The search's keeps what a new list shares with the last as a *prefix* (a
//! conflict's assumptions are read off its implication graph, and must stay those the search
//! always learned — see `search.rs`, "Order"). The other one is kept *as a set*
//! ([`Propagator::closure_of`] with `as_set`): estimation's successive stores (the modes of one
//! candidate, then of the next) differ in the one or two components whose mode changed, which
//! sat anywhere in the list, and undoing to the first of them re-propagated half the trail —
//! at 1,023 breakers ≈ 1,450 such questions a busy step, 7,700 literals each. As a set, only
//! the literals derived from an assumption no longer asked are retracted (its cone in the
//! implication graph, [`Propagator::retract`]); the rest stays, since the closure of a set does
//! not depend on the order of its members. Only yes/no answers come out of this closure (a
//! conflict for the caller's core goes to the SAT solver), and those are the same whatever the
//! order. For the same reason this closure may also *decide* a few literals to complete the
//! stored model ([`Propagator::completes_by_deciding`]) before a "consistent?" goes to the
//! solver: estimation asks one such question per mode the observation might refute, and the
//! solver answered each by assigning the whole theory.
//!
//! # Cost per literal
//! [`Propagator::propagate`] reads a falsified literal's binary implications in place, the
//! propagator's fields borrowed apart, rather than indexing the list afresh for each literal
//! it forces: the same assignments in the same order, 0.9 % of the instructions of
//! Livingstone 2's 15-breaker log at κ = 10 (7.414 G → 7.347 G, measured with a memory of
//! consistent search checks since measured and rejected, `docs/design/opsat.md`).
//!
//! # A model's agreement, kept
//! A check that propagation proves consistent completes the closure by the stored model
//! ([`Propagator::completes_to_model`]): the trail's literals that the model has the other way
//! are where a clause might now be false, and finding them scanned the whole trail — on
//! Livingstone 2's 255-breaker tree ≈ 5,000 literals a search check, of which the check's own
//! propagation re-derives a quarter. After a successful completion the model holds every
//! literal of the trail, and the next check keeps most of it. So the propagator keeps
//! `agrees`: the trail's first `agrees` literals hold in the model. A completion found sets it
//! to the trail's length; undoing or retracting lowers it to what is left of the trail; a new
//! model (the SAT solver's) or a cleared trail resets it to 0; assigning only appends. The scan
//! starts there and finds the same literals in the same order, so every answer and every stored
//! model is what it was (`the_agreement_kept_with_the_model_changes_no_completion` checks it
//! against a propagator that rescans the whole trail). Measured (callgrind, whole process):
//! Livingstone 2's 15-breaker log 3.741 G → 3.684 G instructions at κ = 5, 7.619 G → 7.505 G
//! at κ = 10; CPU time at 255 breakers, κ = 10, 0.98 of before (`farm-bench --vs`, 5 pairs,
//! median, load ≈ 5).
//!
//! # Binary implications in one array
//! For each literal made false, propagation reads the literals its binary clauses force: most
//! of a breaker tree's clauses (each component's "at most one mode", the connections'
//! equalities). Kept as one list per literal, each list was its own allocation, and at 255
//! breakers a quarter of propagation's time sat on loading it. [`Implications`] holds them
//! all in one array, literal after literal in code order — the values of one variable are
//! adjacent, and a mode assumed makes its siblings false one after another. It is rebuilt from
//! the lists before the first closure after clauses were added (a theory gets its clauses
//! when it is built and when a formula is first encoded, and every addition already restarts
//! the closure from the units). Every list keeps its order, so propagation assigns the same
//! literals in the same order for the same reasons. Measured: CPU time at 255 breakers, κ = 10,
//! 0.94 and 0.95 of before (`farm-bench --vs`, two calls of 5 pairs, medians, load 5–6). On
//! the 15-breaker log, whose theory fits in cache, a lookup's extra bound check costs 1.4 % more
//! instructions (κ = 5 3.684 G → 3.734 G, κ = 10 7.505 G → 7.608 G) for no change in CPU time
//! (1.00 and 0.99, 11 pairs).

use super::sat::{Outcome, RecordedSolver, SatLit, SatSolver};

/// The SAT solver and two [`Propagator`]s (see "Two closures, kept apart"), each given every
/// clause the solver is.
#[derive(Clone)]
pub(crate) struct Solver {
    /// The complete backstop.
    pub(crate) sat: RecordedSolver,
    /// The fast path for the questions of callers outside OPSAT's search (entailments, yes/no
    /// consistency).
    pub(crate) propagator: Propagator,
    /// The fast path for OPSAT's candidate checks ([`Solver::for_search`]).
    pub(crate) search: Propagator,
}

impl Solver {
    /// A solver with no clauses.
    pub(crate) fn new(sat: RecordedSolver) -> Self {
        Solver {
            sat,
            propagator: Propagator::kept_as_set(),
            search: Propagator::default(),
        }
    }

    /// The propagator for OPSAT's candidate checks (`search`) or for everything else.
    pub(crate) fn for_search(&mut self, search: bool) -> &mut Propagator {
        if search {
            &mut self.search
        } else {
            &mut self.propagator
        }
    }
}

impl SatSolver for Solver {
    fn new_var(&mut self) -> SatLit {
        self.sat.new_var()
    }

    fn add_clause(&mut self, clause: &[SatLit]) {
        self.sat.add_clause(clause);
        self.propagator.add_clause(clause);
        self.search.add_clause(clause);
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        let outcome = self.sat.solve(assumptions);
        if let Outcome::Satisfiable = outcome {
            let model = self.sat.model();
            self.search.set_model(model.clone());
            self.propagator.set_model(model);
        }
        outcome
    }

    fn model(&self) -> Vec<bool> {
        self.sat.model()
    }
}

/// Every literal code's binary implications back to back, in the order the clauses were added:
/// `forced[start..end]`, `(start, end) = at[l]`, are those of code `l` ("Binary implications
/// in one array"; a pair per code rather than shared bounds, so that a lookup is one bounds
/// check and a slice).
#[derive(Debug, Default, Clone)]
struct Implications {
    at: Vec<(u32, u32)>,
    forced: Vec<SatLit>,
    /// A binary clause was added since the arrays were built.
    stale: bool,
}

impl Implications {
    /// Rebuilds the arrays from the per-code lists, if anything was added since.
    fn compile(&mut self, implied: &[Vec<SatLit>]) {
        if !self.stale {
            return;
        }
        self.at.clear();
        self.forced.clear();
        self.at.reserve(implied.len());
        self.forced.reserve(implied.iter().map(Vec::len).sum());
        for list in implied {
            let start = self.forced.len() as u32;
            self.forced.extend_from_slice(list);
            self.at.push((start, self.forced.len() as u32));
        }
        self.stale = false;
    }

    /// The literals forced once the literal of `code` is false. A code past the arrays is of a
    /// variable added since, by an assumption: it is in no clause, so it forces nothing.
    #[inline]
    fn of(&self, code: usize) -> &[SatLit] {
        let (start, end) = self.at.get(code).copied().unwrap_or((0, 0));
        &self.forced[start as usize..end as usize]
    }
}

/// A clause's literals in the shared store.
#[derive(Debug, Clone, Copy)]
struct Span {
    start: u32,
    len: u32,
}

/// The clauses and one propagation's assignment.
#[derive(Debug, Default, Clone)]
pub(crate) struct Propagator {
    /// Literals of the clauses of three or more literals, back to back; a clause's first two
    /// are its watched ones.
    literals: Vec<SatLit>,
    long: Vec<Span>,
    /// Per literal code, the clauses of three or more literals watching it.
    watches: Vec<Vec<u32>>,
    /// Per literal code, the clauses of three or more literals containing it.
    occurs: Vec<Vec<u32>>,
    /// Per literal code `l`, the literals a binary clause `(l ∨ m)` forces once `l` is false,
    /// as clauses are added; propagation reads them from [`Implications`].
    implied: Vec<Vec<SatLit>>,
    /// `implied` in one array, rebuilt before a closure after clauses were added ("Binary
    /// implications in one array").
    implications: Implications,
    /// Clauses of one literal: true in every model.
    units: Vec<SatLit>,
    /// An empty clause was added: nothing is consistent.
    empty: bool,
    /// Per variable: 0 unassigned, 1 true, 2 false.
    value: Vec<u8>,
    /// The literals made true, in order.
    trail: Vec<SatLit>,
    /// Scratch for normalising a clause.
    scratch: Vec<SatLit>,
    /// A model of every clause (the solver's last, then repaired by the fast path), by
    /// variable; `None` once a clause is added after it.
    model: Option<Vec<bool>>,
    /// Scratch: the trail's literals the model has the other way.
    flipped: Vec<SatLit>,
    /// The trail's first `agrees` literals hold in `model` ("A model's agreement, kept").
    agrees: usize,
    /// The assumptions the assignment is the closure of, in order (callers of
    /// [`Propagator::extend`] undo what they add); with a conflict, the last one is where it
    /// arose.
    closure_assumptions: Vec<SatLit>,
    /// `levels[i]`: the trail's length once the units and the first `i` assumptions were
    /// propagated — so a next set of assumptions sharing a prefix with these keeps that much.
    levels: Vec<usize>,
    /// Whether the closure reached a conflict (in the units when no assumption is listed).
    conflict: bool,
    /// Whether the assignment is a closure at all (a new clause resets it).
    started: bool,
    /// Per variable, why it is assigned (meaningful while it is).
    reasons: Vec<Reason>,
    /// The last conflict propagation reached (in a closure or an extension).
    falsified: Option<Falsified>,
    /// The conflict the current closure reached, when `conflict` is set (`None`: in the units).
    closure_falsified: Option<Falsified>,
    /// Scratch for [`Propagator::conflict_assumptions`]: variables visited.
    visited: Vec<bool>,
    /// Whether a closure keeps the previous one's assumptions that the new list holds anywhere
    /// (see [`Propagator::closure_of`]) rather than only a shared prefix.
    as_set: bool,
    /// Scratch for [`Propagator::closure_of_set`]: per literal code, in the list asked about.
    in_query: Vec<bool>,
    /// Scratch for [`Propagator::retract`]: the literals retracted.
    gone: Vec<SatLit>,
    /// With `as_set`: the assumptions last asked about, as given (the closure is theirs).
    last_query: Vec<SatLit>,
}

/// Why a variable has its value: what the implication graph records for reading a conflict's
/// assumptions off it ([`Propagator::conflict_assumptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reason {
    /// A unit clause: true in every model, no assumption's doing.
    Unit,
    /// An assumption of the closure.
    Assumed,
    /// A binary clause `(l ∨ x)` whose `l` (recorded) is false.
    Binary(SatLit),
    /// A long clause (by number) whose other literals are all false.
    Long(u32),
}

/// A clause that propagation found false, or an assumption that was already false.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Falsified {
    Binary(SatLit, SatLit),
    Long(u32),
    Assumption(SatLit),
}

/// A literal's value under the current assignment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Value {
    True,
    False,
    Unassigned,
}

impl Propagator {
    /// A propagator whose closure is kept as a set ([`Propagator::closure_of`] with `as_set`),
    /// for every question but OPSAT's candidate checks.
    pub(crate) fn kept_as_set() -> Propagator {
        Propagator {
            as_set: true,
            ..Propagator::default()
        }
    }

    /// Makes room for the variable of `lit`.
    #[inline]
    fn grow(&mut self, lit: SatLit) {
        let vars = lit.var() as usize + 1;
        if self.value.len() < vars {
            self.grow_to(vars);
        }
    }

    /// Makes room for `vars` variables.
    fn grow_to(&mut self, vars: usize) {
        self.value.resize(vars, 0);
        self.reasons.resize(vars, Reason::Unit);
        self.visited.resize(vars, false);
        self.watches.resize_with(2 * vars, Vec::new);
        self.occurs.resize_with(2 * vars, Vec::new);
        // New codes force nothing yet: `Implications::of` answers so past its arrays.
        self.implied.resize_with(2 * vars, Vec::new);
        self.in_query.resize(2 * vars, false);
    }

    /// Records a clause (the solver gets the same one). Forgets the current assignment: a new
    /// clause's watches assume nothing is assigned.
    pub(crate) fn add_clause(&mut self, clause: &[SatLit]) {
        self.clear();
        self.model = None;
        let mut lits = std::mem::take(&mut self.scratch);
        lits.clear();
        lits.extend_from_slice(clause);
        lits.sort_unstable();
        lits.dedup();
        let tautology = lits.windows(2).any(|w| w[0].var() == w[1].var());
        if let Some(&last) = lits.last() {
            self.grow(last);
        }
        match lits.as_slice() {
            _ if tautology => {}
            [] => self.empty = true,
            [unit] => self.units.push(*unit),
            [a, b] => {
                self.implied[a.code()].push(*b);
                self.implied[b.code()].push(*a);
                self.implications.stale = true;
            }
            [a, b, ..] => {
                let id = self.long.len() as u32;
                self.watches[a.code()].push(id);
                self.watches[b.code()].push(id);
                for lit in &lits {
                    self.occurs[lit.code()].push(id);
                }
                self.long.push(Span {
                    start: self.literals.len() as u32,
                    len: lits.len() as u32,
                });
                self.literals.extend_from_slice(&lits);
            }
        }
        self.scratch = lits;
    }

    /// Makes the assignment the propagation closure of the unit clauses and `assumptions`;
    /// false when propagation reaches a conflict (then no model satisfies them). Incremental:
    /// each assumption is propagated to a fixpoint before the next, and what the previous
    /// closure's assumptions share as a prefix with these is kept — a caller asks several
    /// questions of one set in a row (kept whole), and OPSAT's successive candidates share
    /// their first assumptions (the observation, the components before the first one changed).
    /// With `as_set`, what they share as a set is kept ([`Propagator::closure_of_set`]).
    pub(crate) fn closure_of(&mut self, assumptions: &[SatLit]) -> bool {
        if !self.started {
            self.clear();
            self.implications.compile(&self.implied);
            self.started = true;
            self.closure_assumptions.clear();
            self.last_query.clear();
            self.levels.clear();
            let units = std::mem::take(&mut self.units);
            self.conflict = self.empty
                || !(units.iter().all(|&u| self.assign(u, Reason::Unit)) && self.propagate(0));
            self.units = units;
            // A conflict among the units involves no assumption.
            self.closure_falsified = None;
            self.levels.push(self.trail.len());
        }
        if self.as_set {
            return self.closure_of_set(assumptions);
        }
        let common = self
            .closure_assumptions
            .iter()
            .zip(assumptions)
            .take_while(|(a, b)| a == b)
            .count();
        if self.conflict && common == self.closure_assumptions.len() {
            // The units, or a prefix of these assumptions, already conflict.
            return false;
        }
        // Back to the shared prefix (with a conflict, `common` stops before its assumption).
        self.undo(self.levels[common]);
        self.levels.truncate(common + 1);
        self.closure_assumptions.truncate(common);
        self.conflict = false;
        self.assume_all(&assumptions[common..])
    }

    /// Assumes each of `assumptions` in turn on top of the current closure, each propagated
    /// to a fixpoint and listed with its level; false at the first conflict. With `as_set`, a
    /// literal the closure already holds is not listed: what holds it is.
    fn assume_all(&mut self, assumptions: &[SatLit]) -> bool {
        for &lit in assumptions {
            if self.as_set && self.value(lit) == Value::True {
                continue;
            }
            self.grow(lit);
            self.closure_assumptions.push(lit);
            let head = self.trail.len();
            let holds = if self.assign(lit, Reason::Assumed) {
                self.propagate(head)
            } else {
                self.falsified = Some(Falsified::Assumption(lit));
                false
            };
            if !holds {
                self.conflict = true;
                self.closure_falsified = self.falsified;
                return false;
            }
            self.levels.push(self.trail.len());
        }
        true
    }

    /// [`Propagator::closure_of`] with `as_set`: the previous closure's assumptions that are
    /// not among `assumptions` are retracted with what was derived from them (and only that:
    /// [`Propagator::retract`]), then the new ones are assumed. The closure of a set does not
    /// depend on the order its members are propagated in, so this is the closure of
    /// `assumptions` — at a cost in the retracted assumptions' consequences, not in the
    /// assumptions listed after them.
    fn closure_of_set(&mut self, assumptions: &[SatLit]) -> bool {
        if self.last_query == assumptions {
            // Asked again (a guard or an observed value after another under the same store).
            return !self.conflict;
        }
        self.last_query.clear();
        self.last_query.extend_from_slice(assumptions);
        for &lit in assumptions {
            self.grow(lit);
            self.in_query[lit.code()] = true;
        }
        let listed = self.closure_assumptions.len();
        let first_gone = self
            .closure_assumptions
            .iter()
            .position(|lit| !self.in_query[lit.code()]);
        let holds = match first_gone {
            // Every assumption of a conflicting closure is asked again: still a conflict.
            None if self.conflict => false,
            None => true,
            Some(first) => {
                if self.conflict {
                    // Back to the fixpoint before the assumption that conflicted.
                    self.undo(self.levels[listed - 1]);
                    self.closure_assumptions.pop();
                    self.levels.truncate(listed);
                    self.conflict = false;
                }
                first >= self.closure_assumptions.len() || self.retract(first)
            }
        };
        for &lit in assumptions {
            self.in_query[lit.code()] = false;
        }
        if first_gone.is_some() && !holds {
            // The retraction failed (see `retract`): the closure from scratch.
            self.clear();
            return self.closure_of(assumptions);
        }
        holds && self.assume_all(assumptions)
    }

    /// Retracts the listed assumptions from the `first`-th on that are not marked in
    /// `in_query`, and every literal whose reason leads back to one of them; the rest of the
    /// trail stays, in order, with its reasons. What is left is sound but may miss literals
    /// that the retracted ones had derived first and the rest still implies: each clause that
    /// held such a literal true while another of its watches was false is visited again, and
    /// the literal re-derived and propagated. No conflict can arise (the closure before held
    /// every literal derived here, without one): false if one did all the same, and then the
    /// assignment is to be cleared.
    fn retract(&mut self, first: usize) -> bool {
        let start = self.levels[first];
        // The trail from `start` on is rewritten.
        self.agrees = self.agrees.min(start);
        let mut gone = std::mem::take(&mut self.gone);
        gone.clear();
        // Marks the retracted: an assumption no longer asked, or a literal one of whose
        // antecedents is retracted (antecedents come earlier on the trail).
        for at in start..self.trail.len() {
            let lit = self.trail[at];
            let var = lit.var();
            let retracted = match self.reasons[var as usize] {
                Reason::Unit => false,
                Reason::Assumed => !self.in_query[lit.code()],
                Reason::Binary(falsified) => self.visited[falsified.var() as usize],
                Reason::Long(id) => self
                    .clause(id)
                    .iter()
                    .any(|m| m.var() != var && self.visited[m.var() as usize]),
            };
            if retracted {
                self.visited[var as usize] = true;
                gone.push(lit);
            }
        }
        // Compacts the trail, and the listed assumptions with their levels.
        let mut kept = start;
        let mut listed = first;
        let mut next_level = first;
        for at in start..self.trail.len() {
            let lit = self.trail[at];
            if next_level < self.closure_assumptions.len() && at == self.levels[next_level] {
                if !self.visited[lit.var() as usize] {
                    self.closure_assumptions[listed] = lit;
                    self.levels[listed] = kept;
                    listed += 1;
                }
                next_level += 1;
            }
            if !self.visited[lit.var() as usize] {
                self.trail[kept] = lit;
                kept += 1;
            }
        }
        self.trail.truncate(kept);
        self.closure_assumptions.truncate(listed);
        self.levels.truncate(listed);
        for &lit in &gone {
            self.visited[lit.var() as usize] = false;
            self.value[lit.var() as usize] = 0;
        }
        let head = self.trail.len();
        for &lit in &gone {
            self.rederive(lit);
        }
        let consistent = self.propagate(head);
        self.levels.push(self.trail.len());
        self.gone = gone;
        consistent
    }

    /// After `lit` (true before) was retracted: assigns it again if a clause still forces it —
    /// a binary clause whose other literal is false, or a long one watching it whose other
    /// watch is false and that has no other literal left to watch — and otherwise moves the
    /// false watch of each clause watching it to a literal that is not false.
    fn rederive(&mut self, lit: SatLit) {
        for i in 0..self.implications.of(lit.code()).len() {
            let other = self.implications.of(lit.code())[i];
            if self.value(other) == Value::False {
                self.assign(lit, Reason::Binary(other));
                return;
            }
        }
        let watching = std::mem::take(&mut self.watches[lit.code()]);
        for &id in &watching {
            let span = self.long[id as usize];
            let (start, end) = (span.start as usize, (span.start + span.len) as usize);
            if self.literals[start] != lit {
                self.literals.swap(start, start + 1);
            }
            // `lit` is at `start`, the other watch at `start + 1`.
            let other = self.literals[start + 1];
            if self.value(other) != Value::False || self.value(lit) == Value::True {
                continue;
            }
            let replacement =
                (start + 2..end).find(|&j| self.value(self.literals[j]) != Value::False);
            match replacement {
                Some(j) => {
                    self.literals.swap(start + 1, j);
                    let watch = self.literals[start + 1];
                    self.watches[other.code()].retain(|&w| w != id);
                    self.watches[watch.code()].push(id);
                }
                None => {
                    self.assign(lit, Reason::Long(id));
                }
            }
        }
        self.watches[lit.code()] = watching;
    }

    /// Makes `model` the stored model; it may disagree with any literal of the trail.
    fn set_model(&mut self, model: Vec<bool>) {
        self.model = Some(model);
        self.agrees = 0;
    }

    /// Unassigns everything.
    fn clear(&mut self) {
        self.started = false;
        self.agrees = 0;
        for lit in self.trail.drain(..) {
            self.value[lit.var() as usize] = 0;
        }
    }

    /// The value of `lit` under the current assignment.
    pub(crate) fn value(&self, lit: SatLit) -> Value {
        match self.value.get(lit.var() as usize).copied().unwrap_or(0) {
            0 => Value::Unassigned,
            v if (v == 1) == lit.is_positive() => Value::True,
            _ => Value::False,
        }
    }

    /// Whether the current (conflict-free) assignment, completed by the stored model where it
    /// leaves variables open, satisfies every clause — then it is a model, and becomes the
    /// stored one. Only clauses with a literal the assignment makes false and the model made
    /// true can be falsified by the switch, so only those are checked: the cost is the
    /// assignment's length and the occurrences of what it changed, not the theory's size.
    pub(crate) fn completes_to_model(&mut self) -> bool {
        self.repair().is_ok()
    }

    /// [`Propagator::completes_to_model`], and while it fails, up to `decisions` times: an open
    /// literal of a clause the completion falsifies is assumed and propagated, and the
    /// completion checked again. What is decided is taken back (the assignment is the closure
    /// again); a completion found is a model of the clauses and every assumption, so the
    /// answer "consistent" is exact, and it becomes the stored model. Without a completion the
    /// caller asks the SAT solver, as before. The questions this is for ask a mode or an
    /// observed value that the stored model contradicts (estimation's `Possible`, one question
    /// per mode): the clauses it falsifies are the few around that component, each a
    /// propagation away from a model, where the solver assigned the whole theory.
    pub(crate) fn completes_by_deciding(&mut self, decisions: usize) -> bool {
        let mark = self.trail.len();
        let mut completed = false;
        for _ in 0..=decisions {
            match self.repair() {
                Ok(()) => {
                    completed = true;
                    break;
                }
                Err(Some(open)) if self.extend(open) => {}
                Err(_) => break,
            }
        }
        self.undo(mark);
        completed
    }

    /// Checks the assignment completed by the stored model (see
    /// [`Propagator::completes_to_model`]); when it is a model it becomes the stored one.
    /// Otherwise `Err` with an open literal of the first clause it falsifies (`None` if the
    /// model is missing or the clause has none).
    fn repair(&mut self) -> Result<(), Option<SatLit>> {
        let Some(model) = &self.model else {
            return Err(None);
        };
        let mut flipped = std::mem::take(&mut self.flipped);
        flipped.clear();
        // The literals before `agrees` hold in the model: none of them is flipped.
        flipped.extend(
            self.trail[self.agrees..]
                .iter()
                .filter(|lit| model.get(lit.var() as usize).copied() != Some(lit.is_positive())),
        );
        let holds = |lit: SatLit| match self.value(lit) {
            Value::True => true,
            Value::False => false,
            Value::Unassigned => model.get(lit.var() as usize).copied() == Some(lit.is_positive()),
        };
        let open = |lit: &SatLit| self.value(*lit) == Value::Unassigned;
        let mut falsified_clause = None;
        for &lit in &flipped {
            let falsified = !lit;
            if let Some(&m) = self
                .implications
                .of(falsified.code())
                .iter()
                .find(|&&m| !holds(m))
            {
                falsified_clause = Some([m].into_iter().find(open));
                break;
            }
            let long = self.occurs[falsified.code()].iter().find(|&&id| {
                let span = self.long[id as usize];
                let (start, end) = (span.start as usize, (span.start + span.len) as usize);
                !self.literals[start..end].iter().any(|&m| holds(m))
            });
            if let Some(&id) = long {
                falsified_clause = Some(self.clause(id).iter().copied().find(open));
                break;
            }
        }
        let answer = match falsified_clause {
            Some(open) => Err(open),
            None => {
                if let Some(model) = &mut self.model {
                    for lit in &flipped {
                        model[lit.var() as usize] = lit.is_positive();
                    }
                }
                self.agrees = self.trail.len();
                Ok(())
            }
        };
        self.flipped = flipped;
        answer
    }

    /// The current trail length, to undo to with [`Propagator::undo`].
    pub(crate) fn mark(&self) -> usize {
        self.trail.len()
    }

    /// Unassigns what was assigned after `mark`.
    pub(crate) fn undo(&mut self, mark: usize) {
        self.agrees = self.agrees.min(mark);
        for lit in self.trail.drain(mark..) {
            self.value[lit.var() as usize] = 0;
        }
    }

    /// Assumes `lit` on top of the current assignment and propagates; false on a conflict.
    /// [`Propagator::undo`] to the previous [`Propagator::mark`] takes it back.
    pub(crate) fn extend(&mut self, lit: SatLit) -> bool {
        self.implications.compile(&self.implied);
        let head = self.trail.len();
        self.grow(lit);
        self.assign(lit, Reason::Assumed) && self.propagate(head)
    }

    /// Makes `lit` true for `reason`; false if it is already false. Its variable has room: it is
    /// in a clause, or an assumption (grown for by the caller: this runs for every literal
    /// propagated, and checking there was 7 % of a breaker tree's busy step).
    fn assign(&mut self, lit: SatLit, reason: Reason) -> bool {
        assign_to(
            &mut self.value,
            &mut self.reasons,
            &mut self.trail,
            lit,
            reason,
        )
    }

    /// Whether the current closure reached a conflict ([`Propagator::closure_of`] was false).
    pub(crate) fn in_conflict(&self) -> bool {
        self.conflict
    }

    /// After [`Propagator::closure_of`] reached a conflict: assumptions of that closure that
    /// cannot hold together with the clauses, read off the implication graph from the clause
    /// found false back to the assumptions it was derived from. Sound because propagation
    /// is: every literal on the way is implied by those assumptions and the clauses, so they
    /// imply the falsified clause's negation. Empty when the units alone conflict.
    pub(crate) fn conflict_assumptions(&mut self) -> Vec<SatLit> {
        let mut core = Vec::new();
        let mut stack: Vec<u32> = Vec::new();
        match self.closure_falsified {
            None => return core,
            Some(Falsified::Binary(a, b)) => stack.extend([a.var(), b.var()]),
            Some(Falsified::Long(id)) => stack.extend(self.clause(id).iter().map(|l| l.var())),
            Some(Falsified::Assumption(lit)) => {
                core.push(lit);
                stack.push(lit.var());
            }
        }
        let mut visited = std::mem::take(&mut self.visited);
        let mut seen: Vec<u32> = Vec::new();
        while let Some(var) = stack.pop() {
            let v = var as usize;
            if visited[v] {
                continue;
            }
            visited[v] = true;
            seen.push(var);
            match self.reasons[v] {
                Reason::Unit => {}
                Reason::Assumed => core.push(SatLit::new(var, self.value[v] == 1)),
                Reason::Binary(falsified) => stack.push(falsified.var()),
                Reason::Long(id) => stack.extend(
                    self.clause(id)
                        .iter()
                        .map(|l| l.var())
                        .filter(|&x| x != var),
                ),
            }
        }
        for var in seen {
            visited[var as usize] = false;
        }
        self.visited = visited;
        core
    }

    /// The literals of long clause `id`.
    fn clause(&self, id: u32) -> &[SatLit] {
        let span = self.long[id as usize];
        &self.literals[span.start as usize..(span.start + span.len) as usize]
    }

    /// Propagates the trail from `head` to a fixpoint; false on a conflict.
    fn propagate(&mut self, mut head: usize) -> bool {
        while let Some(&lit) = self.trail.get(head) {
            head += 1;
            let falsified = !lit;
            // The fields apart, so that the implication list is read in place: indexing it
            // afresh per literal forced was a fifth of propagation's instructions.
            let Propagator {
                implications,
                value,
                reasons,
                trail,
                ..
            } = self;
            let reason = Reason::Binary(falsified);
            for &forced in implications.of(falsified.code()) {
                if !assign_to(value, reasons, trail, forced, reason) {
                    self.falsified = Some(Falsified::Binary(falsified, forced));
                    return false;
                }
            }
            if !self.visit_watches(falsified) {
                return false;
            }
        }
        true
    }

    /// Visits the long clauses watching `falsified` (now false): each finds another watch, is
    /// satisfied, forces its other watch, or is in conflict (false).
    fn visit_watches(&mut self, falsified: SatLit) -> bool {
        let mut watching = std::mem::take(&mut self.watches[falsified.code()]);
        let mut kept = 0;
        let mut consistent = true;
        let mut i = 0;
        while i < watching.len() {
            let id = watching[i];
            i += 1;
            if !consistent {
                watching[kept] = id;
                kept += 1;
                continue;
            }
            let span = self.long[id as usize];
            let (start, end) = (span.start as usize, (span.start + span.len) as usize);
            // The falsified watch goes to position 1.
            if self.literals[start] == falsified {
                self.literals.swap(start, start + 1);
            }
            let other = self.literals[start];
            if self.value(other) == Value::True {
                watching[kept] = id;
                kept += 1;
                continue;
            }
            let replacement =
                (start + 2..end).find(|&j| self.value(self.literals[j]) != Value::False);
            if let Some(j) = replacement {
                self.literals.swap(start + 1, j);
                let watch = self.literals[start + 1];
                self.watches[watch.code()].push(id);
                continue;
            }
            watching[kept] = id;
            kept += 1;
            consistent = self.assign(other, Reason::Long(id));
            if !consistent {
                self.falsified = Some(Falsified::Long(id));
            }
        }
        watching.truncate(kept);
        self.watches[falsified.code()] = watching;
        consistent
    }
}

/// [`Propagator::assign`] on the propagator's fields (its values, reasons and trail).
#[inline]
fn assign_to(
    value: &mut [u8],
    reasons: &mut [Reason],
    trail: &mut Vec<SatLit>,
    lit: SatLit,
    reason: Reason,
) -> bool {
    let var = lit.var() as usize;
    match value[var] {
        0 => {
            value[var] = if lit.is_positive() { 1 } else { 2 };
            reasons[var] = reason;
            trail.push(lit);
            true
        }
        v => (v == 1) == lit.is_positive(),
    }
}

#[cfg(test)]
mod tests;
