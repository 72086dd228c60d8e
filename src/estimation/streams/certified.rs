//! The certified list of one stream, served lazily (the streams are [`super`]'s).
//!
//! A stream serves its certified solutions — the known ones costing at most `bound − Δ` (all of
//! them for a complete shape) — cheapest first, ties to the one known last ([`Waiting`]; the
//! order `replay.rs` reproduces). Costing every known solution of every source's shape for that
//! (`cost_at`: a sum over the components) was a seventh of an 8κ step on Livingstone 2's breaker
//! log, while the merge takes three or four solutions of a source that knows fifteen. So each
//! shape keeps its known solutions in serving order under *reference* choices (a source's of
//! that shape, renewed when a stream's drift from them passes [`REBASE`]), with their costs
//! ([`Reference`]), brought up to date when an expansion first meets the shape (never during
//! one: a stream walks the solutions known when it was taken, as the whole list did). Then:
//! - a stream whose choices cost what the reference ones do, bit for bit ([`same_costs`]),
//!   has the very costs `cost_at` would give, in the very order: it is served from the
//!   reference order as it stands, nothing costed, up to its limit;
//! - otherwise, with `D` the drift from the reference choices over the modes a feasible solution
//!   may take (as far as decided: no SAT call; an undecided mode counts), a solution of reference
//!   cost `r` costs at least `floor(r, D)` ([`floor`]: `r − D` less a rounding margin, and
//!   non-decreasing in `r`). The stream costs solutions in reference order into a heap and
//!   serves the heap's first only once the next uncosted one's floor is strictly above it: every
//!   uncosted solution then costs strictly more, so none can come first, ties included. The
//!   first solution past the limit ends it as the whole list's filter did.
//!
//! Either way the stream serves the same solutions with the same costs in the same order as the
//! whole list (`the_lazy_certified_list_serves_as_the_whole_heap` checks it against that list on
//! random shapes), and the theory is asked exactly what it was: beliefs and SAT calls are
//! byte-identical. Measured on the 15-breaker log (1,600 steps, callgrind, whole process):
//! κ = 10 9.048 G → 8.208 G instructions, κ = 5 4.392 G → 4.027 G; CPU time 0.80 / 0.91 of
//! before (`farm-bench --vs`, 5 pairs, medians). Every stream there had its reference's costs:
//! the heap alone (no same-cost path) costed three quarters of the list all the same — the
//! symmetric breakers' plateaus of equal cost — and saved 1 % of the instructions.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::Arc;

use super::super::expand::Choices;
use super::cost_at;

/// A certified known solution waiting to be served, by index into its shape's solutions, with
/// its cost. The greatest is served first: the cheapest (by [`f64::total_cmp`]) and, among equal
/// costs, the one known last — the order in which a list of them sorted dearest first, stably
/// over the known solutions' order, is served from its back (the order `replay.rs` reproduces).
/// Indices are distinct, so no two compare equal and the order is total. A heap gives it without
/// sorting the whole list: the merge takes a few solutions of a source that may know hundreds,
/// and sorting them all was most of an expansion's sorting.
#[derive(Debug, Clone, Copy)]
pub(super) struct Waiting {
    pub(super) index: usize,
    pub(super) cost: f64,
}

impl Ord for Waiting {
    fn cmp(&self, other: &Self) -> Ordering {
        (other.cost.total_cmp(&self.cost)).then(self.index.cmp(&other.index))
    }
}

impl PartialOrd for Waiting {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Waiting {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Waiting {}

/// The known solutions of one shape in the order of their costs under reference choices
/// ("The certified list, lazily" in the module documentation).
#[derive(Default)]
pub(super) struct Reference {
    /// The reference choices (a source's of this shape); `None` before the first use.
    pub(super) choices: Option<Arc<Choices>>,
    /// (cost under `choices`, index into the shape's solutions) in [`Waiting`]'s serving
    /// order: ascending by cost ([`f64::total_cmp`]), then descending by index; solutions with
    /// an absent position are left out.
    pub(super) order: Vec<(f64, usize)>,
    /// How many of the shape's known solutions `order` has taken in.
    pub(super) covered: usize,
}

/// Past this drift (in nats) of a stream's choices from the reference ones, the reference is
/// renewed from that stream's choices before the shape's streams of an expansion walk it: the
/// drift widens the window of solutions a stream must cost.
const REBASE: f64 = 1.0;

/// The rounding margin of a lower bound from the reference order, relative to the costs
/// compared: a cost is a sum of a few dozen non-negative terms, whose rounding error is under
/// 1e-14 relative; the margin is far wider (`replay.rs` makes the same argument).
const ROUNDING: f64 = 1e-9;

impl Reference {
    /// Brings the order up to date with `positions` (the shape's known solutions): renewed
    /// from `choices` when there is no reference yet or `drift` from it exceeds [`REBASE`];
    /// otherwise the solutions learned since are costed under the reference choices and
    /// merged in.
    pub(super) fn refresh(
        &mut self,
        positions: &[Vec<u32>],
        choices: &Arc<Choices>,
        drift: impl FnOnce(&Choices) -> f64,
    ) {
        let renew = self
            .choices
            .as_ref()
            .is_none_or(|reference| drift(reference) > REBASE);
        if renew {
            self.choices = Some(Arc::clone(choices));
            self.order.clear();
            self.covered = 0;
        }
        if self.covered == positions.len() {
            return;
        }
        let Some(reference) = &self.choices else {
            return;
        };
        let fresh = self.order.len();
        let learned = positions.iter().enumerate().skip(self.covered);
        self.order
            .extend(learned.filter_map(|(index, at)| Some((cost_at(reference, at)?, index))));
        self.covered = positions.len();
        if fresh > 0 {
            // Both runs are sorted when the new one is: a stable sort merges them cheaply.
            self.order[fresh..].sort_unstable_by(serving_order);
            self.order.sort_by(serving_order);
        } else {
            self.order.sort_unstable_by(serving_order);
        }
    }
}

/// [`Waiting`]'s order, first served first, for (cost, index) pairs.
fn serving_order(a: &(f64, usize), b: &(f64, usize)) -> Ordering {
    a.0.total_cmp(&b.0).then(b.1.cmp(&a.1))
}

/// Whether every next mode costs the same, bit for bit, in `a` and `b` (of one shape): then
/// `cost_at` gives every solution the same cost under both.
pub(super) fn same_costs(a: &Choices, b: &Choices) -> bool {
    a.iter().zip(b).all(|(x, y)| {
        Arc::ptr_eq(x, y)
            || x.iter()
                .zip(y.iter())
                .all(|(m, n)| m.cost.to_bits() == n.cost.to_bits())
    })
}

/// A lower bound on the cost under a stream's choices of a known solution whose cost under the
/// reference choices is `reference`, when the stream's drift from them is `drift`: the exact
/// difference is at most `drift`, and the margin covers both sums' rounding. Non-decreasing in
/// `reference` (products by positive constants and subtraction of a constant round
/// monotonically), so the bound of the next solution in the reference order bounds every one
/// after it; infinite when `reference` is and `drift` is not, −∞ or NaN (never above
/// anything) when `drift` is infinite.
pub(super) fn floor(reference: f64, drift: f64) -> f64 {
    let shrunk = if reference >= 0.0 {
        reference * (1.0 - ROUNDING)
    } else {
        reference * (1.0 + ROUNDING)
    };
    shrunk - (drift * (1.0 + ROUNDING) + ROUNDING)
}

/// One stream's certified known solutions, served in [`Waiting`]'s order from the shape's
/// reference order: costed under the stream's choices only as far as serving needs
/// ("The certified list, lazily").
#[derive(Default)]
pub(super) struct Certified {
    /// Serve only solutions costing at most this (the certificate's bound less its drift;
    /// ∞ for a complete shape).
    pub(super) limit: f64,
    /// The stream's drift from the reference choices.
    pub(super) drift: f64,
    /// The stream's choices cost what the reference ones do (see [`same_costs`]): the
    /// reference order is the serving order, with the very costs, and nothing is costed.
    pub(super) same: bool,
    /// The next position in the reference order to cost; past its end once nothing is left
    /// (a stream with nothing certified starts there).
    pub(super) next: usize,
    /// Costed certified solutions not served yet.
    pub(super) waiting: BinaryHeap<Waiting>,
}

impl Certified {
    /// Nothing certified.
    pub(super) fn none() -> Certified {
        Certified {
            next: usize::MAX,
            ..Certified::default()
        }
    }

    /// The next certified solution in [`Waiting`]'s order, if any: the greatest of those
    /// costed, once the next in the reference order (and so every later one) is bound to cost
    /// strictly more — no uncosted solution can then come first, ties included.
    pub(super) fn pop(
        &mut self,
        order: &[(f64, usize)],
        positions: &[Vec<u32>],
        choices: &Choices,
    ) -> Option<Waiting> {
        if self.same {
            let &(cost, index) = order.get(self.next)?;
            if cost <= self.limit {
                self.next += 1;
                return Some(Waiting { index, cost });
            }
            self.next = usize::MAX;
            return None;
        }
        while let Some(&(reference, index)) = order.get(self.next) {
            let bound = floor(reference, self.drift);
            match self.waiting.peek() {
                Some(first) if bound > first.cost => break,
                None if bound > self.limit => {
                    self.next = usize::MAX;
                    break;
                }
                _ => {}
            }
            self.next += 1;
            if let Some(cost) = cost_at(choices, &positions[index])
                && cost <= self.limit
            {
                self.waiting.push(Waiting { index, cost });
            }
        }
        self.waiting.pop()
    }
}
