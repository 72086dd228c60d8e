//! Deciding the sequencer's conditions: "is this formula entailed by ŝ and ω?" (thesis §5.3,
//! Figure 5-3 steps 2, 7 and 8).
//!
//! A formula's clock atoms are grounded with the clock values ω(i) (an atom on a clock not yet
//! started stays open and the formula must be entailed whatever its truth,
//! [`entailed_in_every_case`]); what remains is asked of the [`Entailment`] oracle about one
//! estimate. Within a half cycle each formula is asked at most once.
//!
//! # Answers kept across cycles ([`Memo`])
//!
//! A quiet cycle asks the same few questions as the cycle before (is the marked goal achieved,
//! does the watched condition hold, is the guard entailed) about the same estimate, with clocks
//! that have advanced by one period. The answer is a function of three things only: the
//! formula, the truth values its clock atoms take under ω (true, false, or open for a clock not
//! started — the grounding sees nothing else of ω), and what the oracle entails about the
//! estimate. When the oracle names the estimate with a revision ([`Entailment::revision`]: the
//! same revision, the same answers), an answer is kept with the revision and the clock atoms'
//! truth values it was computed under, and given again while both are unchanged. That is exact:
//! the grounded formula is the same formula, and the oracle would give the same answer about it.
//! An oracle without revisions gets every question, as before.
//!
//! Measured on the nominal Mars EDL's quiet cruise cycle (three questions a cycle, callgrind):
//! about 560 instructions a question before (grounding allocates a formula, the oracle's own
//! cache hashes it); a kept answer costs the comparison of a revision and a few clock bounds
//! (the sequencer's whole saving is in `step.rs`).

use super::oracle::{Entailment, entailed_in_every_case};
use super::thca::{Condition, FormulaId, Sense, Thca};
use crate::logic::{Atom, ClockId, CmpOp};

/// A formula's clock atoms that fit in a [`Truths`] code; more, and its answers are not kept.
const MAX_CLOCK_ATOMS: usize = 32;

/// The truth values of a formula's clock atoms under ω, two bits each (0 open, 1 false,
/// 2 true), in the order of [`Memo::clock_atoms`].
type Truths = u64;

/// An answer and what it was computed under.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Kept {
    revision: u64,
    truths: Truths,
    answer: bool,
}

/// Answers kept across half cycles, per formula (see the module documentation). Holds no state
/// that decides the sequencer's future: dropping it changes no answer.
#[derive(Debug, Clone, Default)]
pub(super) struct Memo {
    /// Per formula, its clock atoms (`None`: too many to keep its answers).
    clock_atoms: Vec<Option<Vec<(ClockId, CmpOp, f64)>>>,
    /// Per formula, the last answer kept.
    kept: Vec<Option<Kept>>,
}

impl Memo {
    /// An empty memo for the formulas of `thca`.
    pub(super) fn new(thca: &Thca) -> Self {
        let clock_atoms = (thca.formulas().iter())
            .map(|formula| {
                let atoms: Vec<(ClockId, CmpOp, f64)> = (formula.atoms().into_iter())
                    .filter_map(|atom| match atom {
                        Atom::Clock { clock, op, seconds } => Some((*clock, *op, seconds.0)),
                        _ => None,
                    })
                    .collect();
                (atoms.len() <= MAX_CLOCK_ATOMS).then_some(atoms)
            })
            .collect();
        Memo {
            clock_atoms,
            kept: vec![None; thca.formula_count()],
        }
    }

    /// The truth values of formula `id`'s clock atoms under `clocks`, as the grounding decides
    /// them; `None` when its answers are not kept.
    fn truths(&self, id: FormulaId, clocks: &[Option<f64>]) -> Option<Truths> {
        let atoms = self.clock_atoms.get(id.index())?.as_ref()?;
        let mut truths: Truths = 0;
        for (k, &(clock, op, seconds)) in atoms.iter().enumerate() {
            let value = clock_value(clocks, clock);
            let code = match value.map(|v| op.holds(v, seconds)) {
                None => 0,
                Some(false) => 1,
                Some(true) => 2,
            };
            truths |= code << (2 * k);
        }
        Some(truths)
    }
}

/// ω's value of `clock` (`None`: not started).
fn clock_value(clocks: &[Option<f64>], clock: ClockId) -> Option<f64> {
    clocks.get(clock.index()).copied().flatten()
}

/// Answers "does this condition hold?" for one half cycle: clocks ground with ω(i), the rest is
/// asked of the oracle about one estimate, and each formula is asked at most once.
pub(super) struct Evaluator<'a, E: Entailment> {
    thca: &'a Thca,
    clocks: &'a [Option<f64>],
    estimate: &'a E::Estimate,
    oracle: &'a mut E,
    /// The oracle's name for the estimate's answers (`None`: nothing is kept across cycles).
    revision: Option<u64>,
    /// Per formula, its answer once asked (the sequencer's buffer, reset here).
    entailed: &'a mut Vec<Option<bool>>,
    memo: &'a mut Memo,
}

impl<'a, E: Entailment> Evaluator<'a, E> {
    /// An evaluator of `thca`'s formulas with ω = `clocks` and ŝ = `estimate`.
    pub(super) fn new(
        thca: &'a Thca,
        clocks: &'a [Option<f64>],
        estimate: &'a E::Estimate,
        oracle: &'a mut E,
        (entailed, memo): (&'a mut Vec<Option<bool>>, &'a mut Memo),
    ) -> Self {
        entailed.clear();
        entailed.resize(thca.formula_count(), None);
        let revision = oracle.revision(estimate);
        Evaluator {
            thca,
            clocks,
            estimate,
            oracle,
            revision,
            entailed,
            memo,
        }
    }

    /// Is the formula entailed by the estimate and the clock values? A bound on a clock that has
    /// not been started is unknown: the formula must be entailed whatever its truth.
    pub(super) fn entailed(&mut self, id: FormulaId) -> bool {
        if let Some(known) = self.entailed[id.index()] {
            return known;
        }
        let key = self
            .revision
            .and_then(|revision| Some((revision, self.memo.truths(id, self.clocks)?)));
        let kept = self.memo.kept.get(id.index()).copied().flatten();
        let answer = match (key, kept) {
            (Some((revision, truths)), Some(kept))
                if kept.revision == revision && kept.truths == truths =>
            {
                kept.answer
            }
            _ => self.ask(id),
        };
        if let (Some((revision, truths)), Some(slot)) = (key, self.memo.kept.get_mut(id.index())) {
            *slot = Some(Kept {
                revision,
                truths,
                answer,
            });
        }
        self.entailed[id.index()] = Some(answer);
        answer
    }

    /// The oracle's answer about formula `id` grounded with ω.
    fn ask(&mut self, id: FormulaId) -> bool {
        let clocks = self.clocks;
        let grounded = self.thca.formula(id).ground(&mut |atom| match atom {
            Atom::Clock { clock, op, seconds } => {
                clock_value(clocks, *clock).map(|value| op.holds(value, seconds.0))
            }
            _ => None,
        });
        let (oracle, estimate) = (&mut *self.oracle, self.estimate);
        entailed_in_every_case(
            &grounded,
            &|atom| matches!(atom, Atom::Clock { .. }),
            &mut |formula| oracle.entailed(estimate, formula),
        )
    }

    /// Does the maintenance condition or guard hold?
    pub(super) fn holds(&mut self, condition: &Condition) -> bool {
        let entailed = self.entailed(condition.formula);
        match condition.sense {
            Sense::Entailed => entailed,
            Sense::NotEntailed => !entailed,
        }
    }

    /// Does the guard hold (no guard: **True**)?
    pub(super) fn guard(&mut self, guard: Option<&Condition>) -> bool {
        guard.is_none_or(|condition| self.holds(condition))
    }
}
