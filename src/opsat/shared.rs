//! Conflicts shared between OPSAT searches that assume the same literals.
//!
//! A conflict is a set of literals `x = v` that cannot hold together with the theory and the
//! per-problem assumptions. That is a fact about the theory and the assumptions alone: it holds
//! in every OCSP with those assumptions, whatever values its decision variables may take and at
//! whatever costs. TimedME asks one OCSP per source state, all under the same observation, which
//! differ only in each component's allowed next modes and their costs; each used to relearn,
//! with SAT calls, the conflicts the other sources had already paid for. A [`ConflictStore`]
//! holds them at the literal level, and every search that assumes exactly the store's
//! assumptions reads them, translated into its own (member, choice) pairs where they apply.
//!
//! # Why sharing is exact
//! A conflict `K` applies to a search when every literal of `K` is one of its members taking a
//! value its domain allows; a conflict naming a value the domain lacks can never be contained in
//! a candidate there and is skipped. An applicable `K` is a conflict of that search's OCSP, so
//! pruning with it removes only inconsistent assignments: each search still enumerates exactly
//! the feasible assignments of its OCSP, each once (`search.rs`), cheapest first. Solutions come
//! out in a canonical order — cost, then the assignment's choice indices compared from the last
//! member back — that the conflicts known cannot change (`search.rs`, "Order"), so every
//! search's sequence of solutions, and therefore everything computed from it (the merge, the
//! κ cut, the belief), is the same with and without sharing, bit for bit.

use super::theory::Literal;

/// Conflicts learned under one list of assumptions, in the order they were learned. The
/// default store is one for no assumptions ([`ConflictStore::assume`] makes it another's).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ConflictStore {
    assumptions: Vec<Literal>,
    conflicts: Vec<Box<[Literal]>>,
}

impl ConflictStore {
    /// Past this many conflicts the store starts afresh, so that translating it into a new
    /// search stays cheap (conflicts only speed a search up; dropping them changes no answer).
    const LIMIT: usize = 4096;

    /// Makes the store one for `assumptions`: kept if it already is (and not too large),
    /// emptied otherwise. Call between searches, never while an enumeration reading the store
    /// is still to be resumed.
    pub fn assume(&mut self, assumptions: &[Literal]) {
        if self.assumptions != assumptions {
            self.assumptions.clear();
            self.assumptions.extend_from_slice(assumptions);
            self.conflicts.clear();
        } else if self.conflicts.len() > Self::LIMIT {
            self.conflicts.clear();
        }
    }

    /// The assumptions every conflict here is a conflict under.
    pub fn assumptions(&self) -> &[Literal] {
        &self.assumptions
    }

    /// How many conflicts the store holds.
    pub(crate) fn len(&self) -> usize {
        self.conflicts.len()
    }

    /// The conflicts from the `from`-th on (a search reads each once).
    pub(crate) fn since(&self, from: usize) -> &[Box<[Literal]>] {
        self.conflicts.get(from..).unwrap_or_default()
    }

    /// Records a conflict learned under the store's assumptions.
    pub(crate) fn learn(&mut self, conflict: impl IntoIterator<Item = Literal>) {
        self.conflicts.push(conflict.into_iter().collect());
    }
}
