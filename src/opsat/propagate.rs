//! Unit propagation over the theory's compiled clauses: the fast path in front of the SAT solver
//! (issue 15, direction 4; Livingstone's truth maintenance answers most of its queries the same
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

use super::sat::{Outcome, RecordedSolver, SatLit, SatSolver};

/// The SAT solver and a [`Propagator`] that is given every clause the solver is.
#[derive(Clone)]
pub(crate) struct Solver {
    /// The complete backstop.
    pub(crate) sat: RecordedSolver,
    /// The fast path.
    pub(crate) propagator: Propagator,
}

impl SatSolver for Solver {
    fn new_var(&mut self) -> SatLit {
        self.sat.new_var()
    }

    fn add_clause(&mut self, clause: &[SatLit]) {
        self.sat.add_clause(clause);
        self.propagator.add_clause(clause);
    }

    fn solve(&mut self, assumptions: &[SatLit]) -> Outcome {
        let outcome = self.sat.solve(assumptions);
        if let Outcome::Satisfiable = outcome {
            self.propagator.model = Some(self.sat.model());
        }
        outcome
    }

    fn model(&self) -> Vec<bool> {
        self.sat.model()
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
    /// Per literal code `l`, the literals a binary clause `(l ∨ m)` forces once `l` is false.
    implied: Vec<Vec<SatLit>>,
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
    /// Makes room for the variable of `lit`.
    fn grow(&mut self, lit: SatLit) {
        let vars = lit.var() as usize + 1;
        if self.value.len() < vars {
            self.value.resize(vars, 0);
            self.reasons.resize(vars, Reason::Unit);
            self.visited.resize(vars, false);
            self.watches.resize_with(2 * vars, Vec::new);
            self.occurs.resize_with(2 * vars, Vec::new);
            self.implied.resize_with(2 * vars, Vec::new);
        }
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
    pub(crate) fn closure_of(&mut self, assumptions: &[SatLit]) -> bool {
        if !self.started {
            self.clear();
            self.started = true;
            self.closure_assumptions.clear();
            self.levels.clear();
            let units = std::mem::take(&mut self.units);
            self.conflict = self.empty
                || !(units.iter().all(|&u| self.assign(u, Reason::Unit)) && self.propagate(0));
            self.units = units;
            // A conflict among the units involves no assumption.
            self.closure_falsified = None;
            self.levels.push(self.trail.len());
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
        for &lit in &assumptions[common..] {
            self.closure_assumptions.push(lit);
            let head = self.trail.len();
            self.grow(lit);
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

    /// Unassigns everything.
    fn clear(&mut self) {
        self.started = false;
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
        let Some(model) = &self.model else {
            return false;
        };
        let mut flipped = std::mem::take(&mut self.flipped);
        flipped.clear();
        flipped.extend(
            self.trail
                .iter()
                .filter(|lit| model.get(lit.var() as usize).copied() != Some(lit.is_positive())),
        );
        let holds = |lit: SatLit| match self.value(lit) {
            Value::True => true,
            Value::False => false,
            Value::Unassigned => model.get(lit.var() as usize).copied() == Some(lit.is_positive()),
        };
        let satisfied = flipped.iter().all(|&lit| {
            let falsified = !lit;
            self.implied[falsified.code()].iter().all(|&m| holds(m))
                && self.occurs[falsified.code()].iter().all(|&id| {
                    let span = self.long[id as usize];
                    let (start, end) = (span.start as usize, (span.start + span.len) as usize);
                    self.literals[start..end].iter().any(|&m| holds(m))
                })
        });
        if satisfied && let Some(model) = &mut self.model {
            for lit in &flipped {
                model[lit.var() as usize] = lit.is_positive();
            }
        }
        self.flipped = flipped;
        satisfied
    }

    /// The current trail length, to undo to with [`Propagator::undo`].
    pub(crate) fn mark(&self) -> usize {
        self.trail.len()
    }

    /// Unassigns what was assigned after `mark`.
    pub(crate) fn undo(&mut self, mark: usize) {
        for lit in self.trail.drain(mark..) {
            self.value[lit.var() as usize] = 0;
        }
    }

    /// Assumes `lit` on top of the current assignment and propagates; false on a conflict.
    /// [`Propagator::undo`] to the previous [`Propagator::mark`] takes it back.
    pub(crate) fn extend(&mut self, lit: SatLit) -> bool {
        let head = self.trail.len();
        self.grow(lit);
        self.assign(lit, Reason::Assumed) && self.propagate(head)
    }

    /// Makes `lit` true for `reason`; false if it is already false. Its variable has room: it is
    /// in a clause, or an assumption (grown for by the caller: this runs for every literal
    /// propagated, and checking there was 7 % of a breaker tree's busy step).
    fn assign(&mut self, lit: SatLit, reason: Reason) -> bool {
        match self.value(lit) {
            Value::True => true,
            Value::False => false,
            Value::Unassigned => {
                self.value[lit.var() as usize] = if lit.is_positive() { 1 } else { 2 };
                self.reasons[lit.var() as usize] = reason;
                self.trail.push(lit);
                true
            }
        }
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
            for i in 0..self.implied[falsified.code()].len() {
                let forced = self.implied[falsified.code()][i];
                if !self.assign(forced, Reason::Binary(falsified)) {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn lit(var: u32, positive: bool) -> SatLit {
        SatLit::new(var, positive)
    }

    #[test]
    fn chains_of_binary_and_long_clauses_propagate() {
        let mut p = Propagator::default();
        let (a, b, c, d) = (lit(0, true), lit(1, true), lit(2, true), lit(3, true));
        p.add_clause(&[!a, b]); // a => b
        p.add_clause(&[!b, !c, d]); // b and c => d
        assert!(p.closure_of(&[a]));
        assert_eq!(p.value(b), Value::True);
        assert_eq!(p.value(d), Value::Unassigned);
        let mark = p.mark();
        assert!(p.extend(c));
        assert_eq!(p.value(d), Value::True);
        p.undo(mark);
        assert_eq!(p.value(d), Value::Unassigned);
        assert!(!p.extend(!d) || p.value(c) == Value::False);
        assert!(!p.closure_of(&[a, c, !d]));
    }

    #[test]
    fn units_and_empty_clauses_hold_in_every_propagation() {
        let mut p = Propagator::default();
        let (a, b) = (lit(0, true), lit(1, true));
        p.add_clause(&[a]);
        p.add_clause(&[!a, b]);
        assert!(p.closure_of(&[]));
        assert_eq!(p.value(b), Value::True);
        assert!(!p.closure_of(&[!b]));
        p.add_clause(&[]);
        assert!(!p.closure_of(&[]));
    }

    #[test]
    fn a_conflict_names_the_assumptions_it_was_derived_from() {
        // a => b, (b and c) => d, e => not d; e and f are unrelated to each other.
        let mut p = Propagator::default();
        let (a, b, c, d, e, f) = (
            lit(0, true),
            lit(1, true),
            lit(2, true),
            lit(3, true),
            lit(4, true),
            lit(5, true),
        );
        p.add_clause(&[!a, b]);
        p.add_clause(&[!b, !c, d]);
        p.add_clause(&[!e, !d]);
        // The conflict arises in a long clause's propagation: f plays no part.
        assert!(!p.closure_of(&[f, e, a, c]));
        let mut core = p.conflict_assumptions();
        core.sort_unstable();
        assert_eq!(core, vec![a, c, e]);
        // An assumption already false: it and what made it false.
        assert!(!p.closure_of(&[a, c, f, !d]));
        let mut core = p.conflict_assumptions();
        core.sort_unstable();
        assert_eq!(core, vec![a, c, !d]);
        // An extension after a closure does not disturb that closure's conflict.
        assert!(p.closure_of(&[a]));
        assert!(!p.extend(!b));
        assert!(!p.in_conflict());
        // A conflict among the units names no assumption.
        p.add_clause(&[f]);
        p.add_clause(&[!f]);
        assert!(!p.closure_of(&[a]));
        assert!(p.conflict_assumptions().is_empty());
    }
}
