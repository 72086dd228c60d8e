//! The sequencer's oracle in the executive: the plant's one theory, with answers kept while the
//! estimate does not change.
//!
//! Most cycles of a mission are quiescent — the estimate is the same as the cycle before — and
//! the sequencer asks the same questions every cycle (are the marked goals achieved? are the
//! guards entailed?). Entailment by the model and ŝ depends only on ŝ, so answers are cached
//! per estimate *version*, which the executive bumps whenever ŝ (or a belief the program's
//! confidence atoms read) changes. Consistency of goals with the model never changes.
//!
//! The same version is the sequencer's [`Entailment::revision`]: it keeps its answers across
//! cycles too, and skips even this cache's look-up (hashing the grounded formula) while the
//! version and the clock atoms' truth values stay the same (`sequencer/evaluate.rs`).

use rustc_hash::FxHashMap;

use crate::logic::Formula;
use crate::opsat::Theory;
use crate::sequencer::{Entailment, StateEstimate, TheoryOracle};

/// ŝ as the sequencer sees it, with a version that changes whenever it does.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct VersionedEstimate {
    pub(crate) version: u64,
    pub(crate) state: StateEstimate,
}

/// Answers kept across cycles. Fx-hashed: a quiet cycle looks up a few formulas, and SipHash
/// over a formula tree cost more than the answer saved; the maps are never iterated.
#[derive(Debug, Clone, Default)]
pub(crate) struct AnswerCache {
    version: u64,
    entailed: FxHashMap<Formula, bool>,
    consistent: FxHashMap<Formula, bool>,
}

/// [`TheoryOracle`] with an [`AnswerCache`].
pub(crate) struct CachedOracle<'a> {
    pub(crate) theory: &'a mut Theory,
    pub(crate) cache: &'a mut AnswerCache,
}

impl Entailment for CachedOracle<'_> {
    type Estimate = VersionedEstimate;

    fn entailed(&mut self, estimate: &VersionedEstimate, formula: &Formula) -> bool {
        if self.cache.version != estimate.version {
            self.cache.version = estimate.version;
            self.cache.entailed.clear();
        }
        if let Some(&answer) = self.cache.entailed.get(formula) {
            return answer;
        }
        let answer = TheoryOracle::new(self.theory).entailed(&estimate.state, formula);
        self.cache.entailed.insert(formula.clone(), answer);
        answer
    }

    fn consistent(&mut self, formula: &Formula) -> bool {
        if let Some(&answer) = self.cache.consistent.get(formula) {
            return answer;
        }
        let answer = TheoryOracle::new(self.theory).consistent(formula);
        self.cache.consistent.insert(formula.clone(), answer);
        answer
    }

    /// The version: the executive bumps it whenever ŝ or a belief the program reads changes,
    /// and never reuses one, so one version means one estimate, hence the same answers.
    fn revision(&self, estimate: &VersionedEstimate) -> Option<u64> {
        Some(estimate.version)
    }
}
